//! The spec's networks, layer for layer: the CNN classifier of Table 4.1 (architectures "base",
//! "cls" and "unet" of 4.1) and the U-Net of Tables 4.2-4.3. The code has no backend parameter:
//! the device a model is built on decides where it runs.

use crate::kernels::conv::conv3x3;
use crate::kernels::pool::max_pool2x2;
use crate::upsample::upsample2x;
use burn::module::{Module, ModuleVisitor, Param};
use burn::nn::conv::{Conv2d, Conv2dConfig};
use burn::nn::{BatchNorm, BatchNormConfig, Linear, LinearConfig, PaddingConfig2d, Relu};
use burn::tensor::{activation, Device, Tensor};
use std::sync::Mutex;
pub use wakelab_schema::architecture::ClassifierHead;
pub use wakelab_schema::results::Architecture;

/// Side of the feature map after one (Conv2d 3x3, valid -> MaxPool 2) stage of Table 4.1.
fn stage_output(size: usize) -> usize {
    (size - 2) / 2
}

pub use wakelab_schema::results::{MIN_CLASSIFIER_SIZE, UNET_SIZE_MULTIPLE};

/// Channels of Table 4.1's last stage: what the pooled head reads, one value each.
pub const LAST_STAGE_CHANNELS: usize = 30;

/// Flatten size after the three stages (erratum 1: computed from the input size, 476,280 for
/// 1024 x 1024, not the printed 47,628).
pub fn flatten_size(input_size: usize) -> usize {
    let side = stage_output(stage_output(stage_output(input_size)));
    LAST_STAGE_CHANNELS * side * side
}

/// Features the head's first linear layer reads: the flattened map of [`flatten_size`], or one
/// per channel of the last stage when the map is pooled.
pub fn head_inputs(head: ClassifierHead, input_size: usize) -> usize {
    match head {
        ClassifierHead::Flatten => flatten_size(input_size),
        ClassifierHead::GlobalMax => LAST_STAGE_CHANNELS,
    }
}

/// The CNN classifier of Table 4.1: three (Conv2d 3x3 -> BatchNorm2d -> ReLU -> MaxPool2d 2)
/// stages with 10, 20 and 30 channels, a flatten, and Linear 70 -> 30 -> 1. Table 4.1 lists no
/// activation between the three linear layers, and none is added here. `forward` returns the
/// logit; the sigmoid of 4.1 is `probability`. With [`ClassifierHead::GlobalMax`] each channel's
/// largest response over the last map replaces the flatten (Linear 30 -> 70 -> 30 -> 1 after it).
#[derive(Module, Debug)]
pub struct WakeClassifier {
    conv1: Conv2d,
    norm1: BatchNorm,
    conv2: Conv2d,
    norm2: BatchNorm,
    conv3: Conv2d,
    norm3: BatchNorm,
    relu: Relu,
    linear1: Linear,
    linear2: Linear,
    linear3: Linear,
    #[module(skip)]
    head: ClassifierHead,
}

impl WakeClassifier {
    /// A freshly initialised classifier of Table 4.1 for `channels` x `input_size` x
    /// `input_size` inputs (PyTorch's default initialisation: Kaiming-uniform with gain
    /// 1/sqrt(3)).
    pub fn new(channels: usize, input_size: usize, device: &Device) -> Self {
        Self::with_head(channels, input_size, ClassifierHead::Flatten, device)
    }

    /// The same stages with `head` after them.
    pub fn with_head(channels: usize, input_size: usize, head: ClassifierHead, device: &Device) -> Self {
        assert!(
            input_size >= MIN_CLASSIFIER_SIZE,
            "input size {input_size} below {MIN_CLASSIFIER_SIZE}"
        );
        let conv = |i, o| Conv2dConfig::new([i, o], [3, 3]).init(device);
        Self {
            conv1: conv(channels, 10),
            norm1: BatchNormConfig::new(10).init(device),
            conv2: conv(10, 20),
            norm2: BatchNormConfig::new(20).init(device),
            conv3: conv(20, LAST_STAGE_CHANNELS),
            norm3: BatchNormConfig::new(LAST_STAGE_CHANNELS).init(device),
            relu: Relu::new(),
            linear1: LinearConfig::new(head_inputs(head, input_size), 70).init(device),
            linear2: LinearConfig::new(70, 30).init(device),
            linear3: LinearConfig::new(30, 1).init(device),
            head,
        }
    }

    /// The head after the stages.
    pub fn head(&self) -> ClassifierHead {
        self.head
    }

    /// Logits, shape [batch].
    pub fn forward(&self, images: Tensor<4>) -> Tensor<1> {
        let stage =
            |x, conv: &Conv2d, norm: &BatchNorm| max_pool2x2(self.relu.forward(norm.forward(conv3x3(conv, x, 0))));
        let x = stage(images, &self.conv1, &self.norm1);
        let x = stage(x, &self.conv2, &self.norm2);
        let x = stage(x, &self.conv3, &self.norm3);
        let x: Tensor<2> = match self.head {
            ClassifierHead::Flatten => x.flatten(1, 3),
            ClassifierHead::GlobalMax => x.flatten::<3>(2, 3).max_dim(2).flatten(1, 2),
        };
        let x = self.linear3.forward(self.linear2.forward(self.linear1.forward(x)));
        x.flatten(0, 1)
    }

    /// The wake probability o_i of 4.1 (sigmoid of the logit).
    pub fn probability(&self, images: Tensor<4>) -> Tensor<1> {
        activation::sigmoid(self.forward(images))
    }
}

/// Table 4.3: Conv2d 3x3 (padding 1) -> ReLU -> Conv2d 3x3 (padding 1) -> ReLU.
#[derive(Module, Debug)]
pub struct DoubleConv {
    first: Conv2d,
    second: Conv2d,
    relu: Relu,
}

impl DoubleConv {
    fn new(input: usize, output: usize, device: &Device) -> Self {
        let conv = |i, o| {
            Conv2dConfig::new([i, o], [3, 3])
                .with_padding(PaddingConfig2d::Explicit(1, 1, 1, 1))
                .init(device)
        };
        Self {
            first: conv(input, output),
            second: conv(output, output),
            relu: Relu::new(),
        }
    }

    fn forward(&self, x: Tensor<4>) -> Tensor<4> {
        let x = self.relu.forward(conv3x3(&self.first, x, 1));
        self.relu.forward(conv3x3(&self.second, x, 1))
    }
}

/// The U-Net of Table 4.2: 64-128-256-512 double convolutions with max pooling down, bilinear
/// upsampling (scale 2, aligned corners) and skip concatenations up, and a 1x1 output
/// convolution. Returns logits (Table 4.2 has no sigmoid); `mask` applies it.
#[derive(Module, Debug)]
pub struct UNet {
    down0: DoubleConv,
    down1: DoubleConv,
    down2: DoubleConv,
    bottom: DoubleConv,
    up2: DoubleConv,
    up1: DoubleConv,
    up0: DoubleConv,
    output: Conv2d,
}

/// Channels of the U-Net's first level in Table 4.2; the levels below double it.
pub const UNET_WIDTH: usize = wakelab_schema::recipe::UNET_WIDTH;

impl UNet {
    /// Table 4.2's U-Net.
    pub fn new(channels: usize, device: &Device) -> Self {
        Self::with_width(channels, UNET_WIDTH, device)
    }

    /// The same U-Net with `width` channels on its first level (w-2w-4w-8w); Table 4.2 is
    /// width 64. Narrower ones are for the quick default study on a laptop (FLOPs scale with
    /// width squared).
    pub fn with_width(channels: usize, width: usize, device: &Device) -> Self {
        let w = width;
        Self {
            down0: DoubleConv::new(channels, w, device),
            down1: DoubleConv::new(w, 2 * w, device),
            down2: DoubleConv::new(2 * w, 4 * w, device),
            bottom: DoubleConv::new(4 * w, 8 * w, device),
            up2: DoubleConv::new(8 * w + 4 * w, 4 * w, device),
            up1: DoubleConv::new(4 * w + 2 * w, 2 * w, device),
            up0: DoubleConv::new(2 * w + w, w, device),
            output: Conv2dConfig::new([w, 1], [1, 1]).init(device),
        }
    }

    /// Per-pixel logits, shape [batch, 1, h, w].
    pub fn forward(&self, images: Tensor<4>) -> Tensor<4> {
        let l0 = self.down0.forward(images);
        let l1 = self.down1.forward(max_pool2x2(l0.clone()));
        let l2 = self.down2.forward(max_pool2x2(l1.clone()));
        let x = self.bottom.forward(max_pool2x2(l2.clone()));
        let x = self.up2.forward(Tensor::cat(vec![upsample2x(x), l2], 1));
        let x = self.up1.forward(Tensor::cat(vec![upsample2x(x), l1], 1));
        let x = self.up0.forward(Tensor::cat(vec![upsample2x(x), l0], 1));
        self.output.forward(x)
    }

    /// The wake mask: per-pixel probabilities in [0, 1].
    pub fn mask(&self, images: Tensor<4>) -> Tensor<4> {
        activation::sigmoid(self.forward(images))
    }
}

/// burn's random initialisation draws from one process-wide generator per backend; this lock
/// makes "seed, then initialise" atomic when several models are built at once (tests, threads).
static INIT_LOCK: Mutex<()> = Mutex::new(());

/// Touches every parameter so that lazily initialised ones draw their values now.
struct Materialise;

impl ModuleVisitor for Materialise {
    fn visit_float<const D: usize>(&mut self, param: &Param<Tensor<D>>) {
        let _ = param.val();
    }
}

/// Build a module with its random initial weights drawn from `seed`: the same seed gives the
/// same weights, bit for bit.
pub fn init_seeded<M: Module>(seed: u64, device: &Device, build: impl FnOnce(&Device) -> M) -> M {
    let _guard = INIT_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    device.seed(seed);
    let module = build(device);
    module.visit(&mut Materialise);
    module
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flatten_size_follows_the_input_size_as_in_erratum_1() {
        // 1024 -> 1022 -> 511 -> 509 -> 254 -> 252 -> 126: 30 x 126 x 126
        assert_eq!(flatten_size(1024), 476_280);
        assert_eq!(flatten_size(128), 30 * 14 * 14);
        assert_eq!(flatten_size(MIN_CLASSIFIER_SIZE), 30);
    }

    /// The pooled head sees a feature wherever it lies: moved by 8 pixels (the three stages'
    /// pooling) within a blank window, a spot gives the same logit bit for bit; Table 4.1's
    /// flatten gives another, having learnt each place apart.
    #[test]
    fn the_pooled_head_answers_the_same_wherever_the_feature_lies() {
        let device = Device::flex();
        let spot = |row: usize, col: usize| {
            let mut v = vec![0.0f32; 64 * 64];
            for (r, c) in [(0, 0), (0, 1), (1, 0), (1, 1), (2, 2)] {
                v[(row + r) * 64 + col + c] = 3.0;
            }
            Tensor::<4>::from_data(burn::tensor::TensorData::new(v, [1, 1, 64, 64]), &device)
        };
        let logit = |model: &WakeClassifier, row, col| -> f32 {
            model.forward(spot(row, col)).into_data().try_to_vec::<f32>().unwrap()[0]
        };
        let pooled = init_seeded(5, &device, |d| {
            WakeClassifier::with_head(1, 64, ClassifierHead::GlobalMax, d)
        });
        let flat = init_seeded(5, &device, |d| WakeClassifier::new(1, 64, d));
        assert_eq!(pooled.head(), ClassifierHead::GlobalMax);
        assert_eq!(logit(&pooled, 16, 16), logit(&pooled, 24, 32));
        assert_ne!(logit(&flat, 16, 16), logit(&flat, 24, 32));
    }

    #[test]
    fn outputs_have_the_expected_shapes() {
        let device = Device::flex();
        let classifier = WakeClassifier::new(2, 32, &device);
        let x = Tensor::<4>::zeros([3, 2, 32, 32], &device);
        assert_eq!(classifier.forward(x).dims(), [3]);
        let unet = UNet::new(1, &device);
        let x = Tensor::<4>::zeros([2, 1, 16, 16], &device);
        assert_eq!(unet.forward(x).dims(), [2, 1, 16, 16]);
    }

    #[test]
    fn parameter_counts_match_the_tables() {
        let device = Device::flex();
        // Table 4.1 with one input channel at 128 x 128; each BatchNorm2d(n) holds gamma, beta
        // and the running mean and variance (PyTorch's buffers): 4 n values
        let conv = |i: usize, o: usize| o * i * 9 + o;
        let expected =
            conv(1, 10) + 40 + conv(10, 20) + 80 + conv(20, 30) + 120 + (5880 * 70 + 70) + (70 * 30 + 30) + 31;
        assert_eq!(WakeClassifier::new(1, 128, &device).num_params(), expected);
        // the pooled head reads one value per channel of the last stage: Linear 30 -> 70
        let pooled = WakeClassifier::with_head(1, 128, ClassifierHead::GlobalMax, &device);
        assert_eq!(pooled.num_params(), expected - 5880 * 70 + 30 * 70);
        // Tables 4.2-4.3: the usual 7.76 M parameters of this U-Net with one input channel
        let double = |i: usize, o: usize| conv(i, o) + conv(o, o);
        let expected = double(1, 64)
            + double(64, 128)
            + double(128, 256)
            + double(256, 512)
            + double(768, 256)
            + double(384, 128)
            + double(192, 64)
            + 65;
        assert_eq!(UNet::new(1, &device).num_params(), expected);
    }
}

//! Arithmetic of the networks of Tables 4.1-4.3: floating-point operations per image, layer by
//! layer, so that a step timed at one image size can be carried to another and to another
//! machine (`wakelab run --dry-run`).

use crate::models::flatten_size;
use crate::train::{ClassifierTrainer, Recipe, UNetTrainer};
use burn::tensor::{Device, Int, Tensor, TensorData};
use std::time::Instant;

/// One layer that multiplies: `inputs` x `outputs` weights of `kernel` x `kernel`, applied at
/// `positions` output positions per image (1 for a dense layer).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Layer {
    inputs: usize,
    outputs: usize,
    kernel: usize,
    positions: usize,
}

impl Layer {
    fn weights(&self) -> usize {
        self.inputs * self.outputs * self.kernel * self.kernel
    }

    fn multiply_adds(&self) -> f64 {
        self.weights() as f64 * self.positions as f64
    }
}

/// The classifier of Table 4.1 on `channels` x `size` x `size`: three valid 3 x 3 convolutions,
/// each followed by 2 x 2 pooling, then three dense layers.
fn classifier_layers(channels: usize, size: usize) -> Vec<Layer> {
    let conv = |inputs, outputs, input_side: usize| Layer {
        inputs,
        outputs,
        kernel: 3,
        positions: (input_side - 2) * (input_side - 2),
    };
    let pooled = |side: usize| (side - 2) / 2;
    let (s1, s2) = (pooled(size), pooled(pooled(size)));
    let dense = |inputs, outputs| Layer {
        inputs,
        outputs,
        kernel: 1,
        positions: 1,
    };
    vec![
        conv(channels, 10, size),
        conv(10, 20, s1),
        conv(20, 30, s2),
        dense(flatten_size(size), 70),
        dense(70, 30),
        dense(30, 1),
    ]
}

/// The U-Net of Tables 4.2-4.3 of first-level width `width`: padded 3 x 3 double convolutions at
/// four scales, the decoder's inputs concatenated with the encoder's, and a 1 x 1 output.
fn unet_layers(channels: usize, width: usize, size: usize) -> Vec<Layer> {
    let w = width;
    let double = |inputs, outputs, level: u32| {
        let side = size >> level;
        let at = |i, o| Layer {
            inputs: i,
            outputs: o,
            kernel: 3,
            positions: side * side,
        };
        [at(inputs, outputs), at(outputs, outputs)]
    };
    let mut layers = Vec::new();
    layers.extend(double(channels, w, 0));
    layers.extend(double(w, 2 * w, 1));
    layers.extend(double(2 * w, 4 * w, 2));
    layers.extend(double(4 * w, 8 * w, 3));
    layers.extend(double(12 * w, 4 * w, 2));
    layers.extend(double(6 * w, 2 * w, 1));
    layers.extend(double(3 * w, w, 0));
    layers.push(Layer {
        inputs: w,
        outputs: 1,
        kernel: 1,
        positions: size * size,
    });
    layers
}

/// Forward-pass floating-point operations of the classifier on one image (2 per multiply-add).
pub fn classifier_flops(channels: usize, size: usize) -> f64 {
    2.0 * classifier_layers(channels, size)
        .iter()
        .map(Layer::multiply_adds)
        .sum::<f64>()
}

/// Forward-pass floating-point operations of the U-Net on one image (2 per multiply-add).
pub fn unet_flops(channels: usize, width: usize, size: usize) -> f64 {
    2.0 * unet_layers(channels, width, size)
        .iter()
        .map(Layer::multiply_adds)
        .sum::<f64>()
}

/// Parameters of the U-Net (weights and biases): what its optimiser keeps two moments of.
pub fn unet_parameters(channels: usize, width: usize) -> usize {
    unet_layers(channels, width, 8)
        .iter()
        .map(|l| l.weights() + l.outputs)
        .sum()
}

/// A training step costs about three forward passes: the forward itself, and the backward pass's
/// two products per layer (the input's gradient and the weights').
pub const TRAINING_PASSES: f64 = 3.0;

/// Which network a timed step trains.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimedNetwork {
    Classifier,
    UNet { width: usize },
}

/// One training step timed on `device`: seconds per step (the least of `repeats` steps after one
/// warm-up), the training FLOP per second that makes, and the peak resident memory of the steps
/// above what the process held before them, where the operating system tells it.
#[derive(Debug, Clone, Copy)]
pub struct TimedStep {
    pub seconds: f64,
    pub flop_per_second: f64,
    pub peak_bytes: Option<f64>,
}

/// Time `network`'s training step on a batch of `batch` one-channel `side` x `side` images.
pub fn time_training_step(
    network: TimedNetwork,
    side: usize,
    batch: usize,
    repeats: usize,
    device: &Device,
) -> TimedStep {
    let pattern = |n: usize, phase: f32| (0..n).map(|i| ((i as f32) * 0.618 + phase).sin()).collect::<Vec<f32>>();
    let shape = [batch, 1, side, side];
    crate::device::release_freed_pages();
    let before = wakelab_core::memory::reset_peak();
    let mut times = Vec::new();
    let flops = match network {
        TimedNetwork::Classifier => {
            let mut trainer = ClassifierTrainer::new(1, side, &Recipe::classifier(), 0, device);
            let images = Tensor::<4>::from_data(
                TensorData::new(pattern(batch * side * side, 0.3), shape),
                trainer.device(),
            );
            let labels: Vec<i64> = (0..batch as i64).map(|i| i % 2).collect();
            for _ in 0..=repeats {
                let t = Instant::now();
                trainer.step(images.clone(), &labels);
                times.push(t.elapsed().as_secs_f64());
            }
            classifier_flops(1, side)
        }
        TimedNetwork::UNet { width } => {
            let recipe = Recipe {
                width,
                ..Recipe::unet()
            };
            let mut trainer = UNetTrainer::new(1, &recipe, 0, device);
            let images = Tensor::<4>::from_data(
                TensorData::new(pattern(batch * side * side, 0.7), shape),
                trainer.device(),
            );
            let masks: Vec<i64> = pattern(batch * side * side, 1.1)
                .iter()
                .map(|&v| i64::from(v > 0.8))
                .collect();
            let masks = Tensor::<4, Int>::from_data(TensorData::new(masks, shape), trainer.device());
            for _ in 0..=repeats {
                let t = Instant::now();
                trainer.step(images.clone(), masks.clone());
                times.push(t.elapsed().as_secs_f64());
            }
            unet_flops(1, width, side)
        }
    };
    let seconds = times[1..].iter().copied().fold(f64::INFINITY, f64::min);
    let peak_bytes = before.and_then(wakelab_core::memory::peak_since);
    TimedStep {
        seconds,
        flop_per_second: TRAINING_PASSES * flops * batch as f64 / seconds,
        peak_bytes,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::{UNet, WakeClassifier};
    use burn::module::Module;

    /// The layer lists hold every weight of the networks as burn builds them: the parameter
    /// count less the biases and the batch norms' four values per channel.
    #[test]
    fn the_layer_lists_hold_every_weight_of_the_networks() {
        let device = Device::flex();
        for (channels, size) in [(1, 128), (3, 64), (2, 256)] {
            let layers = classifier_layers(channels, size);
            let biases: usize = layers.iter().map(|l| l.outputs).sum();
            let norms = 4 * (10 + 20 + 30);
            let weights: usize = layers.iter().map(Layer::weights).sum();
            let model = WakeClassifier::new(channels, size, &device).num_params();
            assert_eq!(weights + biases + norms, model, "classifier {channels} x {size}");
        }
        for (channels, width) in [(1, 64), (2, 16)] {
            let layers = unet_layers(channels, width, 64);
            let biases: usize = layers.iter().map(|l| l.outputs).sum();
            let weights: usize = layers.iter().map(Layer::weights).sum();
            let model = UNet::with_width(channels, width, &device).num_params();
            assert_eq!(weights + biases, model, "U-Net {channels} channels, width {width}");
            assert_eq!(unet_parameters(channels, width), model);
        }
    }

    /// Convolutions cost in proportion to the pixels: the U-Net's count grows 4 times when the
    /// side doubles; the first convolution of the classifier at 32 x 32 is 30^2 positions of 9
    /// weights.
    #[test]
    fn costs_scale_with_the_image() {
        let ratio = unet_flops(1, 64, 256) / unet_flops(1, 64, 128);
        assert!((ratio - 4.0).abs() < 1e-12, "{ratio}");
        let first = classifier_layers(1, 32)[0];
        assert_eq!(first.multiply_adds(), (30.0 * 30.0) * 9.0 * 10.0);
    }
}

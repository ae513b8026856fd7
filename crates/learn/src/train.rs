//! Training (spec 4.1, "Training and Experiment"): the classifiers by SGD (lr 1e-3, L2 0.1) on
//! binary cross entropy, the U-Net by Adam (lr 1e-4, weight decay 1e-4) on 0.7 BCE + 0.3 log-Dice
//! (Eq. (4.1), erratum 9; the BCE class-balanced here, see [`unet_loss`]), both with inputs varied by their recipe's augmentation ([`crate::augment`]).
//! A recipe may name another optimiser ([`Optimiser`]): a shortened study trains its classifiers
//! by the spec's Adam, since plain SGD barely moves in a few hundred steps.

use crate::augment::Pose;
use crate::line_sums::network_input;
use crate::models::{init_seeded, UNet, WakeClassifier};
use burn::module::Module;
use burn::optim::decay::WeightDecayConfig;
use burn::optim::{AdamConfig, GradientsParams, ModuleOptimizer, SgdConfig};
use burn::tensor::{Device, Int, Tensor, TensorData};
use ndarray::{Array2, Array3, Axis};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::time::Instant;
use wakelab_core::WakelabError;
use wakelab_schema::architecture::{ClassifierHead, InputForm};
use wakelab_schema::recipe;
use wakelab_schema::recipe::{Augmentation, Optimiser};

use crate::loss::scalar;
pub use crate::loss::{balanced_bce_with_logits, bce_with_logits, unet_loss};

/// One training or test input: `channels` x h x w (already normalised), its label and, for the
/// U-Net, its wake mask (0 or 1 per pixel).
#[derive(Debug, Clone)]
pub struct Example {
    pub image: Array3<f32>,
    pub label: u8,
    pub mask: Option<Array2<f32>>,
}

impl Example {
    pub fn channels(&self) -> usize {
        self.image.shape()[0]
    }
    pub fn size(&self) -> usize {
        self.image.shape()[1]
    }
}

/// The training recipe of one network.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Recipe {
    pub epochs: usize,
    pub batch_size: usize,
    pub learning_rate: f64,
    /// The update rule (4.1: SGD for the classifiers, Adam for the U-Net).
    pub optimiser: Optimiser,
    /// L2 penalty added to the gradient (PyTorch's `weight_decay`).
    pub weight_decay: f64,
    /// How training inputs vary from epoch to epoch.
    pub augmentation: Augmentation,
    /// First-level channels of the U-Net (Table 4.2: 64); the classifiers ignore it.
    pub width: usize,
    /// What the classifier reads of each input (the U-Net always reads the pixels).
    #[serde(default)]
    pub input: InputForm,
    /// How the classifier decides from its last feature map (Table 4.1: flatten).
    #[serde(default)]
    pub head: ClassifierHead,
}

impl Recipe {
    /// The classifiers' recipe of 4.1: SGD, lr 1e-3, L2 0.1, 60 epochs (batch size not given in
    /// the spec: 8).
    pub fn classifier() -> Self {
        Self {
            epochs: recipe::CLASSIFIER_EPOCHS,
            batch_size: recipe::CLASSIFIER_BATCH_SIZE,
            learning_rate: recipe::CLASSIFIER_LEARNING_RATE,
            optimiser: recipe::CLASSIFIER_OPTIMISER,
            weight_decay: recipe::CLASSIFIER_WEIGHT_DECAY,
            augmentation: Augmentation::QuarterTurns,
            width: recipe::UNET_WIDTH,
            input: InputForm::Pixels,
            head: ClassifierHead::Flatten,
        }
    }

    /// The U-Net's recipe of 4.1: Adam, lr 1e-4, weight decay 1e-4, 60 epochs (batch size 4).
    pub fn unet() -> Self {
        Self {
            epochs: recipe::UNET_EPOCHS,
            batch_size: recipe::UNET_BATCH_SIZE,
            learning_rate: recipe::UNET_LEARNING_RATE,
            optimiser: Optimiser::Adam,
            weight_decay: recipe::UNET_WEIGHT_DECAY,
            augmentation: Augmentation::QuarterTurns,
            width: recipe::UNET_WIDTH,
            input: InputForm::Pixels,
            head: ClassifierHead::Flatten,
        }
    }
}

/// What one epoch did.
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct EpochRecord {
    pub epoch: usize,
    pub loss: f64,
    /// Share of training inputs classified right during the epoch (classifiers; pixels for the
    /// U-Net) at threshold 0.5.
    pub accuracy: f64,
    pub images_per_second: f64,
    pub seconds: f64,
}

impl EpochRecord {
    /// "epoch 3 loss 0.412 acc 81% 95.0 img/s", for progress bars.
    pub fn describe(&self) -> String {
        let (e, l, a, r) = (self.epoch, self.loss, 100.0 * self.accuracy, self.images_per_second);
        format!("epoch {e} loss {l:.3} acc {a:.0}% {r:.1} img/s")
    }
}

/// A stack of examples as one [batch, channels, h, w] tensor, each in its pose, then read in
/// `form` (the line sums of the turned window: a turn must move the wake's line, so it comes
/// first). The examples are made ready side by side.
pub fn batch_images(examples: &[&Example], poses: &[Pose], form: InputForm, device: &Device) -> Tensor<4> {
    let (c, n) = (examples[0].channels(), examples[0].size());
    let ready: Vec<Vec<f32>> = examples
        .par_iter()
        .zip(poses)
        .map(|(e, pose)| {
            let mut data = Vec::with_capacity(c * n * n);
            for channel in e.image.outer_iter() {
                let posed = if *pose == Pose::IDENTITY {
                    channel.to_owned()
                } else {
                    pose.apply(&channel.to_owned())
                };
                data.extend(network_input(form, posed).iter().copied());
            }
            data
        })
        .collect();
    Tensor::from_data(TensorData::new(ready.concat(), [examples.len(), c, n, n]), device)
}

pub fn batch_masks(examples: &[&Example], poses: &[Pose], device: &Device) -> Tensor<4, Int> {
    let n = examples[0].size();
    let mut data: Vec<i64> = Vec::with_capacity(examples.len() * n * n);
    for (e, pose) in examples.iter().zip(poses) {
        let zeros;
        let mask = match &e.mask {
            Some(m) => m,
            None => {
                zeros = Array2::zeros((n, n));
                &zeros
            }
        };
        data.extend(pose.apply(mask).iter().map(|&v| (v > 0.5) as i64));
    }
    Tensor::from_data(TensorData::new(data, [examples.len(), 1, n, n]), device)
}

fn check_examples(examples: &[Example]) -> (usize, usize) {
    assert!(!examples.is_empty(), "no training examples");
    let (c, n) = (examples[0].channels(), examples[0].size());
    assert!(
        examples
            .iter()
            .all(|e| e.channels() == c && e.size() == n && e.image.shape()[2] == n),
        "training examples differ in shape"
    );
    (c, n)
}

/// The order and poses of one epoch, drawn from the recipe's seed.
fn epoch_plan(
    count: usize,
    size: usize,
    seed: u64,
    epoch: usize,
    augmentation: Augmentation,
) -> (Vec<usize>, Vec<Pose>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ (epoch as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15));
    let mut order: Vec<usize> = (0..count).collect();
    for i in (1..count).rev() {
        order.swap(i, rng.random_range(0..=i));
    }
    let poses = (0..count).map(|_| Pose::draw(augmentation, size, &mut rng)).collect();
    (order, poses)
}

/// The recipe's update rule with its weight decay; Adam with PyTorch's epsilon 1e-8, as the
/// spec's training had.
fn optimiser(recipe: &Recipe) -> ModuleOptimizer {
    let decay = Some(WeightDecayConfig::new(recipe.weight_decay as f32));
    match recipe.optimiser {
        Optimiser::Sgd => SgdConfig::new().with_weight_decay(decay).init(),
        Optimiser::Adam => AdamConfig::new().with_epsilon(1e-8).with_weight_decay(decay).init(),
    }
}

/// A network being trained on the autodiff form of a device: one optimiser step per batch.
pub struct Trainer<M: Module> {
    model: Option<M>,
    optimiser: ModuleOptimizer,
    learning_rate: f64,
    device: Device,
}

/// A classifier being trained (4.1: by SGD).
pub type ClassifierTrainer = Trainer<WakeClassifier>;
/// The U-Net being trained (4.1: by Adam).
pub type UNetTrainer = Trainer<UNet>;

impl<M: Module> Trainer<M> {
    fn with(device: &Device, seed: u64, recipe: &Recipe, build: impl FnOnce(&Device) -> M) -> Self {
        let device = device.clone().autodiff();
        Self {
            model: Some(init_seeded(seed, &device, build)),
            optimiser: optimiser(recipe),
            learning_rate: recipe.learning_rate,
            device,
        }
    }

    /// A trainer that goes on from `model`'s weights, wherever they are, with a fresh optimiser
    /// of `recipe` on `device`: the same weights trained on two backends (the GPU parity test).
    pub fn from_model(model: M, recipe: &Recipe, device: &Device) -> Self {
        let device = device.clone().autodiff();
        Self {
            model: Some(model.fork(&device).train()),
            optimiser: optimiser(recipe),
            learning_rate: recipe.learning_rate,
            device,
        }
    }

    /// The device batches must be on.
    pub fn device(&self) -> &Device {
        &self.device
    }

    /// One optimiser step on the loss `forward` computes (which also returns how many items it
    /// got right, as a tensor); returns the batch's mean loss and that count.
    ///
    /// Nothing of the graph is read before the backward pass: on burn 0.22's fusion backends
    /// (wgpu, CUDA) reading the logits and the loss first changed the gradients, up to their
    /// sign (found by `tests/gpu_parity.rs` on lavapipe). On the CPU the order changes nothing.
    fn optimise(&mut self, forward: impl FnOnce(&M) -> (Tensor<1>, Tensor<1>)) -> (f64, f64) {
        let model = self.model.take().expect("model present between steps");
        let (loss, right) = forward(&model);
        let grads = GradientsParams::from_grads(loss.clone().backward(), &model);
        let (value, right) = (scalar(loss), scalar(right));
        self.model = Some(self.optimiser.step(self.learning_rate, model, grads));
        (value, right)
    }

    /// The trained network, for inference.
    pub fn finish(self) -> M {
        self.model.expect("model present").valid()
    }
}

/// How many logits fall on their target's side of 0 (images for a classifier, pixels for the
/// U-Net), as a tensor: read after the backward pass ([`Trainer::optimise`]).
fn right_count<const D: usize>(logits: Tensor<D>, targets: Tensor<D, Int>) -> Tensor<1> {
    logits.greater_elem(0.0).int().equal(targets).float().sum()
}

impl Trainer<WakeClassifier> {
    /// A fresh classifier with its recipe's optimiser (4.1: SGD with L2), its weights drawn from
    /// `seed`.
    pub fn new(channels: usize, size: usize, recipe: &Recipe, seed: u64, device: &Device) -> Self {
        Self::with(device, seed, recipe, |d| {
            WakeClassifier::with_head(channels, size, recipe.head, d)
        })
    }

    /// One optimiser step on BCE; returns the batch's mean loss and how many it classified right.
    pub fn step(&mut self, images: Tensor<4>, labels: &[i64]) -> (f64, f64) {
        let targets = Tensor::<1, Int>::from_data(TensorData::new(labels.to_vec(), [labels.len()]), &self.device);
        self.optimise(|model| {
            let logits = model.forward(images);
            let right = right_count(logits.clone(), targets.clone());
            (bce_with_logits(logits, targets), right)
        })
    }
}

impl Trainer<UNet> {
    /// A fresh U-Net with its recipe's optimiser (4.1: Adam with weight decay).
    pub fn new(channels: usize, recipe: &Recipe, seed: u64, device: &Device) -> Self {
        Self::with(device, seed, recipe, |d| UNet::with_width(channels, recipe.width, d))
    }

    /// One optimiser step on the U-Net loss; returns the batch's mean loss and how many pixels it
    /// classified right.
    pub fn step(&mut self, images: Tensor<4>, masks: Tensor<4, Int>) -> (f64, f64) {
        self.optimise(|model| {
            let logits = model.forward(images);
            let agree = right_count(logits.clone(), masks.clone());
            (unet_loss(logits, masks), agree)
        })
    }
}

/// The epochs of a recipe: batches in the seeded order with the seeded rotations, `step` on
/// each; `units` is what accuracy counts per example (1 image, or its pixels). A NaN or
/// infinite loss stops the training with an error: a diverged network must not be saved.
fn train_epochs<M: Module>(
    trainer: &mut Trainer<M>,
    examples: &[Example],
    recipe: &Recipe,
    seed: u64,
    units: f64,
    on_epoch: &mut dyn FnMut(&EpochRecord),
    step: impl Fn(&mut Trainer<M>, &[&Example], &[Pose]) -> (f64, f64),
) -> Result<(), WakelabError> {
    for epoch in 0..recipe.epochs {
        let start = Instant::now();
        let (order, poses) = epoch_plan(examples.len(), examples[0].size(), seed, epoch, recipe.augmentation);
        let (mut loss_sum, mut right) = (0.0, 0.0);
        for chunk in order.chunks(recipe.batch_size.max(1)) {
            let batch: Vec<&Example> = chunk.iter().map(|&i| &examples[i]).collect();
            let poses: Vec<Pose> = chunk.iter().map(|&i| poses[i]).collect();
            let (loss, r) = step(trainer, &batch, &poses);
            if !loss.is_finite() {
                return Err(WakelabError::Training(format!(
                    "the loss became {loss} in epoch {} (learning rate {}): the training diverged; lower the learning rate",
                    epoch + 1,
                    recipe.learning_rate
                )));
            }
            loss_sum += loss * batch.len() as f64;
            right += r;
        }
        let seconds = start.elapsed().as_secs_f64();
        on_epoch(&EpochRecord {
            epoch: epoch + 1,
            loss: loss_sum / examples.len() as f64,
            accuracy: right / (examples.len() as f64 * units),
            images_per_second: examples.len() as f64 / seconds.max(1e-9),
            seconds,
        });
    }
    Ok(())
}

/// Train a classifier (Table 4.1) on `examples` with its recipe (4.1: SGD); `seed` fixes the initial
/// weights, the order of the batches and the rotations. `device` is a plain device; training
/// runs on its autodiff form. `on_epoch` sees every epoch's record.
pub fn train_classifier(
    examples: &[Example],
    recipe: &Recipe,
    seed: u64,
    device: &Device,
    on_epoch: &mut dyn FnMut(&EpochRecord),
) -> Result<WakeClassifier, WakelabError> {
    let (channels, size) = check_examples(examples);
    let mut trainer = ClassifierTrainer::new(channels, size, recipe, seed, device);
    train_epochs(
        &mut trainer,
        examples,
        recipe,
        seed,
        1.0,
        on_epoch,
        |t, batch, poses| {
            let labels: Vec<i64> = batch.iter().map(|e| e.label as i64).collect();
            let images = batch_images(batch, poses, recipe.input, t.device());
            t.step(images, &labels)
        },
    )?;
    Ok(trainer.finish())
}

/// Train the U-Net (Tables 4.2-4.3) on the examples' masks with the Adam recipe.
pub fn train_unet(
    examples: &[Example],
    recipe: &Recipe,
    seed: u64,
    device: &Device,
    on_epoch: &mut dyn FnMut(&EpochRecord),
) -> Result<UNet, WakelabError> {
    let (channels, size) = check_examples(examples);
    let mut trainer = UNetTrainer::new(channels, recipe, seed, device);
    train_epochs(
        &mut trainer,
        examples,
        recipe,
        seed,
        (size * size) as f64,
        on_epoch,
        |t, batch, poses| {
            let images = batch_images(batch, poses, InputForm::Pixels, t.device());
            let masks = batch_masks(batch, poses, t.device());
            t.step(images, masks)
        },
    )?;
    Ok(trainer.finish())
}

/// Wake probabilities o_i of a trained classifier reading its inputs in `form`, in the
/// examples' order.
pub fn classify(
    model: &WakeClassifier,
    examples: &[Example],
    form: InputForm,
    batch_size: usize,
    device: &Device,
) -> Vec<f64> {
    let all: Vec<&Example> = examples.iter().collect();
    let mut out = Vec::with_capacity(examples.len());
    for chunk in all.chunks(batch_size.max(1)) {
        let images = batch_images(chunk, &vec![Pose::IDENTITY; chunk.len()], form, device);
        let p = model
            .probability(images)
            .into_data()
            .try_to_vec::<f32>()
            .expect("f32 outputs");
        out.extend(p.into_iter().map(|v| v as f64));
    }
    out
}

/// The U-Net's wake masks (probabilities per pixel) for every example.
pub fn segment(model: &UNet, examples: &[Example], batch_size: usize, device: &Device) -> Vec<Array2<f32>> {
    let all: Vec<&Example> = examples.iter().collect();
    let mut out = Vec::with_capacity(examples.len());
    for chunk in all.chunks(batch_size.max(1)) {
        let n = chunk[0].size();
        let images = batch_images(chunk, &vec![Pose::IDENTITY; chunk.len()], InputForm::Pixels, device);
        let p = model.mask(images).into_data().try_to_vec::<f32>().expect("f32 outputs");
        for image in p.chunks(n * n) {
            out.push(Array2::from_shape_vec((n, n), image.to_vec()).expect("n x n"));
        }
    }
    out
}

/// Inputs of the "unet" classifier (4.1): the bands' images followed by the U-Net's mask.
pub fn with_masks(examples: &[Example], masks: &[Array2<f32>]) -> Vec<Example> {
    examples
        .iter()
        .zip(masks)
        .map(|(e, m)| Example {
            image: ndarray::concatenate(Axis(0), &[e.image.view(), m.view().insert_axis(Axis(0))]).expect("same size"),
            label: e.label,
            mask: e.mask.clone(),
        })
        .collect()
}

/// Inputs of the "cls" control: the bands' images followed by a copy of the first (4.1, 5.2).
pub fn duplicated(examples: &[Example]) -> Vec<Example> {
    examples
        .iter()
        .map(|e| Example {
            image: ndarray::concatenate(Axis(0), &[e.image.view(), e.image.slice(ndarray::s![0..1, .., ..])])
                .expect("same size"),
            label: e.label,
            mask: e.mask.clone(),
        })
        .collect()
}

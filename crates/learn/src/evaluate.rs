//! Algorithm 2 (spec 4.2): for each repetition, Monte Carlo sample a balanced train/test split,
//! train, evaluate on the test images and keep every output o_i with its scene id; the metrics
//! (Eq. (4.3) and beyond) are computed from the kept outputs, per band set and architecture, as in
//! Tables 4.4-4.6 (and 5.1 for several bands as channels).

use crate::data::{balanced_split, Dataset};
use crate::robustness::Perturbation;
use crate::store::{Detector, ModelInfo};
use crate::train::{
    classify, duplicated, segment, train_classifier, train_unet, with_masks, EpochRecord, Example, Recipe,
};
use burn::tensor::Device;
use ndarray::{Array3, Axis};
use serde::{Deserialize, Serialize};
use wakelab_core::{ConfigError, WakelabError};
use wakelab_schema::results::Architecture;
pub use wakelab_schema::results::{band_set_name, summarise, summarise_split, Output, Summary};

/// The paper's split: 135 training and 14 test images per band (4.2), i.e. this share of the
/// images used is held out for testing.
pub const PAPER_TEST_FRACTION: f64 = 14.0 / 149.0;

/// What to evaluate and how.
#[derive(Debug, Clone)]
pub struct EvalOptions {
    pub architectures: Vec<Architecture>,
    /// Each entry one input: a single band, or several bands as channels (feature-level fusion).
    pub band_sets: Vec<Vec<String>>,
    /// Repetitions of Algorithm 2 (5 in the spec).
    pub repetitions: usize,
    /// Share of each class held out for testing in each repetition.
    pub test_fraction: f64,
    pub classifier: Recipe,
    pub unet: Recipe,
    pub threshold: f64,
    pub seed: u64,
    /// Perturbed copies of each repetition's test images the detectors are also run on
    /// (robustness, spec 6.2); their outputs are kept with split `test:<name>`.
    pub perturbations: Vec<Perturbation>,
}

impl EvalOptions {
    /// The spec's experiment on the given bands, one at a time.
    pub fn spec(bands: &[String]) -> Self {
        Self {
            architectures: Architecture::ALL.to_vec(),
            band_sets: bands.iter().map(|b| vec![b.clone()]).collect(),
            repetitions: 5,
            test_fraction: PAPER_TEST_FRACTION,
            classifier: Recipe::classifier(),
            unet: Recipe::unet(),
            threshold: 0.5,
            seed: 0,
            perturbations: Vec::new(),
        }
    }

    /// Epochs of a network as `train_detector` names it ("segmenter" is the U-Net).
    pub fn epochs_of(&self, network: &str) -> usize {
        match network {
            "segmenter" => self.unet.epochs,
            _ => self.classifier.epochs,
        }
    }

    pub fn validate(&self) -> Result<(), WakelabError> {
        let err = |f: &str, v: String, a: &str| Err(ConfigError::new(f, v, a).into());
        if self.repetitions == 0 || self.repetitions > 1000 {
            return err("repetitions", self.repetitions.to_string(), "an integer in [1, 1000]");
        }
        if !(self.test_fraction > 0.0 && self.test_fraction < 1.0) {
            return err("test_fraction", self.test_fraction.to_string(), "in (0, 1)");
        }
        if !(0.0..=1.0).contains(&self.threshold) {
            return err("threshold", self.threshold.to_string(), "in [0, 1]");
        }
        if !(4..=256).contains(&self.unet.width) {
            return err("unet_width", self.unet.width.to_string(), "an integer in [4, 256]");
        }
        for (name, r) in [("classifier", &self.classifier), ("unet", &self.unet)] {
            if r.epochs == 0 || r.epochs > 10_000 {
                return err(
                    &format!("{name}.epochs"),
                    r.epochs.to_string(),
                    "an integer in [1, 10000]",
                );
            }
            if r.batch_size == 0 || r.batch_size > 4096 {
                return err(
                    &format!("{name}.batch_size"),
                    r.batch_size.to_string(),
                    "an integer in [1, 4096]",
                );
            }
            if !(r.learning_rate > 0.0 && r.learning_rate <= 10.0) {
                return err(
                    &format!("{name}.learning_rate"),
                    r.learning_rate.to_string(),
                    "in (0, 10]",
                );
            }
            if !(0.0..=10.0).contains(&r.weight_decay) {
                return err(
                    &format!("{name}.weight_decay"),
                    r.weight_decay.to_string(),
                    "in [0, 10]",
                );
            }
        }
        if self.architectures.is_empty() || self.band_sets.is_empty() || self.band_sets.iter().any(|s| s.is_empty()) {
            return err(
                "bands/architectures",
                "empty".into(),
                "at least one band and one architecture",
            );
        }
        Ok(())
    }
}

/// One training curve point.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CurvePoint {
    pub bands: String,
    /// "base", "cls", "unet", or "segmenter" for the U-Net itself.
    pub network: String,
    pub repetition: usize,
    #[serde(flatten)]
    pub epoch: EpochRecord,
}

/// Progress of an evaluation, for a progress display.
#[derive(Debug, Clone)]
pub struct EvalProgress<'a> {
    pub bands: &'a str,
    pub network: &'a str,
    pub repetition: usize,
    pub epoch: &'a EpochRecord,
    pub epochs: usize,
}

impl EvalProgress<'_> {
    /// "S base rep 1/5 epoch 3/60 loss 0.412 118.0 img/s", of `repetitions` in all.
    pub fn describe(&self, repetitions: usize) -> String {
        format!(
            "{} {} rep {}/{repetitions} epoch {}/{} loss {:.3} {:.1} img/s",
            self.bands,
            self.network,
            self.repetition + 1,
            self.epoch.epoch,
            self.epochs,
            self.epoch.loss,
            self.epoch.images_per_second
        )
    }
}

/// Everything Algorithm 2 produced.
pub struct Evaluation {
    pub outputs: Vec<Output>,
    pub curves: Vec<CurvePoint>,
    pub summaries: Vec<Summary>,
    /// The detector of the last repetition of each band set and architecture.
    pub detectors: Vec<(Detector, ModelInfo)>,
}

/// Images of `bands` stacked as channels, with the label for that band set and the mask of the
/// first band.
pub fn load_examples(dataset: &Dataset, bands: &[String], scenes: &[usize]) -> Result<Vec<Example>, WakelabError> {
    scenes
        .iter()
        .map(|&i| {
            let images = bands
                .iter()
                .map(|b| dataset.image(i, b))
                .collect::<Result<Vec<_>, _>>()?;
            let views: Vec<_> = images.iter().map(|a| a.view().insert_axis(Axis(0))).collect();
            let image: Array3<f32> = ndarray::concatenate(Axis(0), &views).map_err(|e| WakelabError::Image {
                path: dataset.dir.display().to_string(),
                message: format!("bands {bands:?} of scene {} differ in size: {e}", dataset.records[i].id),
            })?;
            Ok(Example {
                image,
                label: dataset.label(i, bands),
                mask: Some(dataset.mask(i, &bands[0])?),
            })
        })
        .collect()
}

/// Train a detector of `architecture` on `train` (the U-Net first for "unet"); every epoch is
/// reported to `on_epoch` with the network's name.
pub fn train_detector(
    architecture: Architecture,
    train: &[Example],
    options: &EvalOptions,
    seed: u64,
    device: &Device,
    on_epoch: &mut dyn FnMut(&str, &EpochRecord),
) -> Detector {
    match architecture {
        Architecture::Base => Detector {
            classifier: train_classifier(train, &options.classifier, seed, device, &mut |e| on_epoch("base", e)),
            segmenter: None,
        },
        Architecture::Cls => Detector {
            classifier: train_classifier(&duplicated(train), &options.classifier, seed, device, &mut |e| {
                on_epoch("cls", e)
            }),
            segmenter: None,
        },
        Architecture::Unet => {
            let unet = train_unet(train, &options.unet, seed ^ 0x5555, device, &mut |e| {
                on_epoch("segmenter", e)
            });
            let masks = segment(&unet, train, options.unet.batch_size, device);
            let classifier = train_classifier(
                &with_masks(train, &masks),
                &options.classifier,
                seed,
                device,
                &mut |e| on_epoch("unet", e),
            );
            Detector {
                classifier,
                segmenter: Some(unet),
            }
        }
    }
}

/// Wake probabilities of a detector on examples (the image channels only; the "cls" copy and the
/// "unet" mask are made here).
pub fn detect(detector: &Detector, architecture: Architecture, examples: &[Example], device: &Device) -> Vec<f64> {
    let batch = 8;
    match (architecture, &detector.segmenter) {
        (Architecture::Base, _) => classify(&detector.classifier, examples, batch, device),
        (Architecture::Cls, _) => classify(&detector.classifier, &duplicated(examples), batch, device),
        (Architecture::Unet, Some(unet)) => {
            let masks = segment(unet, examples, 4, device);
            classify(&detector.classifier, &with_masks(examples, &masks), batch, device)
        }
        (Architecture::Unet, None) => panic!("a \"unet\" detector without its U-Net"),
    }
}

/// Run Algorithm 2 on a dataset.
pub fn evaluate(
    dataset: &Dataset,
    options: &EvalOptions,
    device: &Device,
    progress: &mut dyn FnMut(&EvalProgress),
) -> Result<Evaluation, WakelabError> {
    options.validate()?;
    let available = dataset.bands();
    let mut outputs = Vec::new();
    let mut curves = Vec::new();
    let mut detectors = Vec::new();
    for bands in &options.band_sets {
        if let Some(b) = bands.iter().find(|b| !available.contains(b)) {
            return Err(ConfigError::new("bands", b, format!("one of the dataset's bands {available:?}")).into());
        }
        let name = band_set_name(bands);
        // split on whether a ship is in the scene, so that every band set of a repetition sees
        // the same scenes (decision-level fusion needs them); metrics use each band's label
        let labels: Vec<u8> = dataset.records.iter().map(|r| r.label).collect();
        let per_class = labels
            .iter()
            .filter(|&&l| l == 1)
            .count()
            .min(labels.iter().filter(|&&l| l == 0).count());
        let test_per_class = ((per_class as f64 * options.test_fraction).round() as usize).max(1);
        if per_class < test_per_class + 1 {
            return Err(ConfigError::new(
                "dataset",
                format!("{per_class} scenes of the rarer class in bands {name}"),
                "at least 2 of each class (wake and no wake)",
            )
            .into());
        }
        let train_per_class = per_class - test_per_class;
        for repetition in 0..options.repetitions {
            let seed = options.seed.wrapping_add(1000 * repetition as u64);
            let (train_idx, test_idx) = balanced_split(&labels, train_per_class, test_per_class, seed)?;
            let train = load_examples(dataset, bands, &train_idx)?;
            let test = load_examples(dataset, bands, &test_idx)?;
            for &architecture in &options.architectures {
                let detector = train_detector(architecture, &train, options, seed, device, &mut |network, e| {
                    progress(&EvalProgress {
                        bands: &name,
                        network,
                        repetition,
                        epoch: e,
                        epochs: options.epochs_of(network),
                    });
                    curves.push(CurvePoint {
                        bands: name.clone(),
                        network: network.to_string(),
                        repetition,
                        epoch: e.clone(),
                    });
                });
                let mut splits = vec![("train".to_string(), train.clone()), ("test".to_string(), test.clone())];
                for (k, p) in options.perturbations.iter().enumerate() {
                    let perturbed = p.apply(&test, seed.wrapping_add(k as u64 + 1));
                    splits.push((format!("test:{}", p.name()), perturbed));
                }
                for (split, examples) in &splits {
                    let idx = if split == "train" { &train_idx } else { &test_idx };
                    let o = detect(&detector, architecture, examples, device);
                    outputs.extend(idx.iter().zip(examples.iter()).zip(o).map(|((&i, e), output)| Output {
                        bands: name.clone(),
                        architecture,
                        repetition,
                        split: split.clone(),
                        scene: dataset.records[i].id.clone(),
                        label: e.label,
                        output,
                    }));
                }
                if repetition + 1 == options.repetitions {
                    let size = train[0].size();
                    detectors.push((
                        detector,
                        ModelInfo {
                            architecture,
                            bands: bands.clone(),
                            input_size: size,
                            threshold: options.threshold,
                            unet_width: options.unet.width,
                        },
                    ));
                }
            }
        }
    }
    let summaries = summarise(&outputs, options.threshold);
    Ok(Evaluation {
        outputs,
        curves,
        summaries,
        detectors,
    })
}

/// Environments held out of training (robustness, spec 6.2): for each group of scenes, train on
/// every other scene and test on the group. Outputs are kept with split `held_out` and the
/// group's index as `repetition`, so `summarise_split(.., "held_out", ..)` averages over groups.
pub fn evaluate_held_out(
    dataset: &Dataset,
    options: &EvalOptions,
    groups: &[Vec<usize>],
    device: &Device,
    progress: &mut dyn FnMut(&EvalProgress),
) -> Result<Vec<Output>, WakelabError> {
    options.validate()?;
    let mut outputs = Vec::new();
    for bands in &options.band_sets {
        let name = band_set_name(bands);
        for (g, test_idx) in groups.iter().enumerate() {
            let train_idx: Vec<usize> = (0..dataset.records.len()).filter(|i| !test_idx.contains(i)).collect();
            if train_idx.is_empty() || test_idx.is_empty() {
                continue;
            }
            let train = load_examples(dataset, bands, &train_idx)?;
            let test = load_examples(dataset, bands, test_idx)?;
            let seed = options.seed.wrapping_add(7919 * (g as u64 + 1));
            for &architecture in &options.architectures {
                let detector = train_detector(architecture, &train, options, seed, device, &mut |network, e| {
                    progress(&EvalProgress {
                        bands: &name,
                        network,
                        repetition: g,
                        epoch: e,
                        epochs: options.epochs_of(network),
                    })
                });
                let o = detect(&detector, architecture, &test, device);
                outputs.extend(test_idx.iter().zip(&test).zip(o).map(|((&i, e), output)| Output {
                    bands: name.clone(),
                    architecture,
                    repetition: g,
                    split: "held_out".to_string(),
                    scene: dataset.records[i].id.clone(),
                    label: e.label,
                    output,
                }));
            }
        }
    }
    Ok(outputs)
}

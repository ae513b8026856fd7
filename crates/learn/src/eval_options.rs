//! What Algorithm 2 evaluates and how (spec 4.2): architectures, inputs, repetitions, the test
//! share, the two training recipes, the threshold, the seed and the perturbed test images.

use crate::robustness::Perturbation;
use crate::store::ModelInfo;
use crate::train::Recipe;
use wakelab_core::{ConfigError, WakelabError};
use wakelab_schema::band::{Band, Input};
use wakelab_schema::results::Architecture;
use wakelab_schema::split::Network;

pub use crate::data::PAPER_TEST_FRACTION;

/// What to evaluate and how.
#[derive(Debug, Clone)]
pub struct EvalOptions {
    pub architectures: Vec<Architecture>,
    /// Each entry one input: a single band, or several bands as channels (feature-level fusion).
    pub band_sets: Vec<Input>,
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
    /// What a detector of `architecture` trained with these options on `bands` of `dataset`
    /// records beside its weights: the network, and the imagery it learned (input size, pixel
    /// spacing, looks, scale), which `detect` matches an input to.
    pub fn model_info(&self, architecture: Architecture, bands: &Input, dataset: &crate::data::Dataset) -> ModelInfo {
        let (pixel_spacing, looks) = dataset.imagery();
        ModelInfo {
            architecture,
            bands: bands.clone(),
            input_size: dataset.image_size(),
            threshold: self.threshold,
            unet_width: self.unet.width,
            pixel_spacing,
            looks,
            input_scale: Some("linear".into()),
            calibration: None,
            input_form: self.classifier.input,
            head: self.classifier.head,
        }
    }

    /// The spec's experiment on the given bands, one at a time.
    pub fn spec(bands: &[Band]) -> Self {
        Self {
            architectures: Architecture::ALL.to_vec(),
            band_sets: bands.iter().map(|&b| Input::single(b)).collect(),
            repetitions: 5,
            test_fraction: PAPER_TEST_FRACTION,
            classifier: Recipe::classifier(),
            unet: Recipe::unet(),
            threshold: 0.5,
            seed: 0,
            perturbations: Vec::new(),
        }
    }

    /// Epochs of a network.
    pub fn epochs_of(&self, network: Network) -> usize {
        match network {
            Network::Segmenter => self.unet.epochs,
            Network::Classifier(_) => self.classifier.epochs,
        }
    }

    /// Whether every architecture takes the dataset's images, checked before any training.
    pub fn check_dataset(&self, dataset: &crate::data::Dataset) -> Result<(), WakelabError> {
        let size = dataset.image_size();
        for a in &self.architectures {
            a.accepts_input_size(size).map_err(|allowed| {
                ConfigError::new(
                    "image_size",
                    format!("{size} (the images of {})", dataset.dir.display()),
                    allowed,
                )
            })?;
        }
        Ok(())
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
        if self.architectures.is_empty() || self.band_sets.is_empty() {
            return err(
                "bands/architectures",
                "empty".into(),
                "at least one band and one architecture",
            );
        }
        Ok(())
    }
}

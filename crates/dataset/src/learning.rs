//! The `[learning]` table of a study file: how `wakelab run` trains, evaluates and stresses the
//! detectors on the study's dataset (spec 4.1-4.2, 5.1-5.2 and the future work of 6.2). Its
//! defaults are the spec's recipe; the embedded default study shortens it to fit a laptop.

use serde::{Deserialize, Serialize};
use wakelab_core::{ConfigError, WakelabError};
use wakelab_schema::band::{Band, Input};
use wakelab_schema::recipe;
use wakelab_schema::recipe::{Augmentation, Optimiser};

/// Training, evaluation and robustness settings of a study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LearningPlan {
    /// Repetitions of Algorithm 2 (spec 4.2: 5).
    pub repetitions: usize,
    /// Classifier epochs (4.1: 60).
    pub epochs: usize,
    /// Classifier learning rate (4.1: 1e-3).
    pub learning_rate: f64,
    /// Classifier optimiser: `sgd` (4.1) or `adam`.
    pub optimiser: Optimiser,
    /// Classifier L2 weight decay, added to the gradient (4.1: 0.1).
    pub weight_decay: f64,
    /// Classifier batch size (not in the spec).
    pub batch_size: usize,
    /// U-Net epochs (4.1: 60).
    pub unet_epochs: usize,
    /// U-Net batch size (4.1: 4).
    pub unet_batch_size: usize,
    /// U-Net Adam learning rate (4.1: 1e-4).
    pub unet_learning_rate: f64,
    /// First-level channels of the U-Net (Table 4.2: 64).
    pub unet_width: usize,
    /// Decision threshold on the wake probability (4.2: 0.5).
    pub threshold: f64,
    /// Seed of weights, splits, batch order, rotations and perturbations.
    pub seed: u64,
    /// Feature-level fusions: bands joined by `+` as channels of one input (5.1's "SX").
    /// Default: S+X (5.1) and C+LWIR (SAR with IR, 5.4), those of them the study renders.
    pub fused_inputs: Option<Vec<Input>>,
    /// How training inputs vary from epoch to epoch: `quarter_turns` (4.2) or `geometric`
    /// (any angle, flips, shifts).
    pub augmentation: Augmentation,
    /// Robustness: test images rotated by these angles (degrees, not multiples of 90).
    pub rotations: Vec<f64>,
    /// Robustness: square patches dropped (set to the image mean) from each test image.
    pub dropped_patches: usize,
    /// Side of a dropped patch as a share of the image side.
    pub patch_fraction: f64,
    /// Robustness: Gaussian noise added to the normalised test images (standard deviations).
    pub noise: f64,
    /// Robustness: test images (and masks) moved by this share of the image side in a seeded
    /// direction; 0 for none.
    pub shift: f64,
    /// Robustness: the study axis whose values are held out of training one at a time
    /// (`wind_speed`, `swell_direction`, `stratification`, ...); empty for none.
    pub held_out: String,
    /// Robustness: a continuous geometry axis (`heading`, `along_track`, `cross_track`,
    /// `incidence`) whose values are binned and each bin held out of training in turn ("base"
    /// only); empty for none.
    pub held_out_geometry: String,
    /// Bins of `held_out_geometry`: sectors of the circle for `heading`, equal ranges otherwise.
    pub geometry_groups: usize,
}

impl Default for LearningPlan {
    fn default() -> Self {
        Self {
            repetitions: recipe::REPETITIONS,
            epochs: recipe::CLASSIFIER_EPOCHS,
            learning_rate: recipe::CLASSIFIER_LEARNING_RATE,
            optimiser: recipe::CLASSIFIER_OPTIMISER,
            weight_decay: recipe::CLASSIFIER_WEIGHT_DECAY,
            batch_size: recipe::CLASSIFIER_BATCH_SIZE,
            unet_epochs: recipe::UNET_EPOCHS,
            unet_batch_size: recipe::UNET_BATCH_SIZE,
            unet_learning_rate: recipe::UNET_LEARNING_RATE,
            unet_width: recipe::UNET_WIDTH,
            threshold: recipe::THRESHOLD,
            seed: 0,
            fused_inputs: None,
            augmentation: Augmentation::QuarterTurns,
            rotations: vec![30.0, 45.0],
            dropped_patches: 4,
            patch_fraction: 0.125,
            noise: 0.5,
            shift: 0.25,
            held_out: "wind_speed".into(),
            held_out_geometry: "heading".into(),
            geometry_groups: 4,
        }
    }
}

impl LearningPlan {
    /// The feature-level fusions to train, each a list of bands.
    pub fn fused_inputs(&self, bands: &[Band]) -> Vec<Input> {
        match &self.fused_inputs {
            Some(list) => list.clone(),
            None => [[Band::S, Band::X], [Band::C, Band::Lwir]]
                .into_iter()
                .filter(|set| set.iter().all(|b| bands.contains(b)))
                .filter_map(|set| Input::new(set.to_vec()))
                .collect(),
        }
    }

    /// Check every value's range; `bands` are the study's bands.
    pub fn validate(&self, bands: &[Band]) -> Result<(), WakelabError> {
        let err = |f: &str, v: String, a: &str| -> Result<(), WakelabError> {
            Err(ConfigError::new(format!("learning.{f}"), v, a).into())
        };
        for (name, v, hi) in [
            ("repetitions", self.repetitions, 1000),
            ("epochs", self.epochs, 10_000),
            ("batch_size", self.batch_size, 4096),
            ("unet_epochs", self.unet_epochs, 10_000),
            ("unet_batch_size", self.unet_batch_size, 4096),
            ("dropped_patches", self.dropped_patches.max(1), 1000),
        ] {
            if v == 0 || v > hi {
                return err(name, v.to_string(), &format!("an integer in [1, {hi}]"));
            }
        }
        if !(4..=256).contains(&self.unet_width) {
            return err("unet_width", self.unet_width.to_string(), "an integer in [4, 256]");
        }
        for (name, v) in [
            ("learning_rate", self.learning_rate),
            ("unet_learning_rate", self.unet_learning_rate),
        ] {
            if !(v > 0.0 && v <= 10.0) {
                return err(name, v.to_string(), "in (0, 10]");
            }
        }
        if !(0.0..=10.0).contains(&self.weight_decay) {
            return err("weight_decay", self.weight_decay.to_string(), "in [0, 10]");
        }
        if !(0.0..=1.0).contains(&self.threshold) {
            return err("threshold", self.threshold.to_string(), "in [0, 1]");
        }
        if !(self.patch_fraction > 0.0 && self.patch_fraction <= 0.5) {
            return err("patch_fraction", self.patch_fraction.to_string(), "in (0, 0.5]");
        }
        if !(0.0..=100.0).contains(&self.noise) {
            return err("noise", self.noise.to_string(), "in [0, 100]");
        }
        let geometry = wakelab_schema::axes::held_out_geometry_axes();
        if !self.held_out_geometry.is_empty() && !geometry.contains(&self.held_out_geometry.as_str()) {
            return err(
                "held_out_geometry",
                self.held_out_geometry.clone(),
                &format!("empty, or one of {geometry:?}"),
            );
        }
        if !(2..=36).contains(&self.geometry_groups) {
            return err("geometry_groups", self.geometry_groups.to_string(), "in [2, 36]");
        }
        if !(0.0..=0.5).contains(&self.shift) {
            return err(
                "shift",
                self.shift.to_string(),
                "in [0, 0.5] (a share of the image side)",
            );
        }
        if let Some(a) = self.rotations.iter().find(|a| !a.is_finite() || a.abs() > 360.0) {
            return err("rotations", a.to_string(), "angles in [-360, 360] degrees");
        }
        for input in self.fused_inputs.iter().flatten() {
            if !input.is_fused() || input.bands().iter().any(|b| !bands.contains(b)) {
                let names: Vec<&str> = bands.iter().map(|b| b.name()).collect();
                return err(
                    "fused_inputs",
                    input.to_string(),
                    &format!("two or more of the study's bands {names:?} joined by +"),
                );
            }
        }
        let axes = wakelab_schema::axes::held_out_axes();
        if !self.held_out.is_empty() && !axes.contains(&self.held_out.as_str()) {
            return err("held_out", self.held_out.clone(), &format!("empty, or one of {axes:?}"));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bands() -> Vec<Band> {
        Band::ALL.to_vec()
    }

    #[test]
    fn the_defaults_are_the_spec_recipe_and_valid() {
        let p = LearningPlan::default();
        assert_eq!((p.repetitions, p.epochs, p.unet_epochs, p.unet_width), (5, 60, 60, 64));
        assert_eq!((p.learning_rate, p.unet_learning_rate, p.threshold), (1e-3, 1e-4, 0.5));
        assert_eq!((p.optimiser, p.weight_decay), (Optimiser::Sgd, 0.1));
        p.validate(&bands()).unwrap();
        assert_eq!(p.fused_inputs(&bands()).len(), 2);
        assert_eq!(p.fused_inputs(&[Band::C, Band::Lwir]), vec!["C+LWIR".parse().unwrap()]);
    }

    #[test]
    fn bad_values_name_their_field() {
        type Change = fn(&mut LearningPlan);
        let cases: [(Change, &str); 6] = [
            (|p| p.epochs = 0, "learning.epochs"),
            (|p| p.unet_width = 2, "learning.unet_width"),
            (
                |p| p.fused_inputs = Some(vec!["S".parse().unwrap()]),
                "learning.fused_inputs",
            ),
            (|p| p.held_out = "colour".into(), "learning.held_out"),
            (|p| p.rotations = vec![f64::NAN], "learning.rotations"),
            (|p| p.weight_decay = -0.1, "learning.weight_decay"),
        ];
        for (change, field) in cases {
            let mut p = LearningPlan::default();
            change(&mut p);
            let e = p.validate(&bands()).unwrap_err().to_string();
            assert!(e.contains(field), "{e}");
        }
    }
}

//! The study file: the axes of a parametric study (spec chapter 4 opening, Fig. 4.3) and the
//! scenes they span.
//!
//! ```toml
//! [study]
//! name = "default"
//! combine = "product"      # every combination of the axes, or "zip": the i-th value of each
//! seeds = 2                # random sea surfaces per combination
//! test_fraction = 0.25     # share of wake/no-wake pairs in the test split
//! grouped_split = false    # true: no environment on both sides of the split
//! min_visibility = 0.0     # label policy: a wake scene counts as "wake" in a band only above it
//!
//! [axes]                   # each axis a list; a missing axis keeps the base configuration's value
//! wind_speed = [5.0, 8.0]
//! swell_direction = ["following", "calm"]
//! along_track = { from = 2000.0, to = 4000.0, count = 3 }   # a numeric axis may be a range
//! ...
//!
//! [draws]                  # continuous axes each pair draws uniformly in [low, high) from its
//! heading = [0.0, 360.0]   # seed and index (reproducible), instead of a list of values
//!
//! [base]                   # any wakelab configuration table (grid, time, sea, sar, ...)
//! preset = "quick"
//! ```

use serde::{Deserialize, Serialize};
use wakelab_core::config::{NamedDirection, ProfileKind, SwellDirection, WakelabConfig};
use wakelab_core::{ConfigError, WakelabError};
use wakelab_schema::axes::axis_of_config_field;
pub use wakelab_schema::axes::{Axes, Combination, Combine};
pub use wakelab_schema::band::Band;
pub use wakelab_schema::dataset::BANDS;
use wakelab_schema::results::Architecture;

/// The `[study]` table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StudyOptions {
    pub name: String,
    pub combine: Combine,
    pub seeds: usize,
    pub test_fraction: f64,
    pub grouped_split: bool,
    pub min_visibility: f64,
    /// Depth of the mixed layer of the `mixed_layer` stratification (m).
    pub mixed_layer_depth: f64,
    /// Bands rendered (a subset of S, C, X, MWIR, LWIR).
    pub bands: Vec<Band>,
}

/// A study file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Study {
    pub study: StudyOptions,
    #[serde(default)]
    pub axes: Axes,
    /// Continuous axes drawn per pair, uniformly in [low, high).
    #[serde(default)]
    pub draws: std::collections::BTreeMap<String, [f64; 2]>,
    /// The base wakelab configuration, as a TOML table.
    #[serde(default)]
    pub base: toml::Table,
    /// How `wakelab run` trains and evaluates on the dataset (default: the spec's recipe).
    #[serde(default)]
    pub learning: crate::learning::LearningPlan,
    /// Detectors for real images (issue 38): a study with this table trains them instead of the
    /// chip study (`wakelab run --study transfer`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transfer: Option<crate::transfer::TransferPlan>,
}

/// A wake scene and its matching no-wake scene: the same environment, platform and seed.
#[derive(Debug, Clone)]
pub struct ScenePair {
    /// Index in the study's enumeration.
    pub index: usize,
    pub combination: Combination,
    pub seed: u64,
    /// The configuration of both scenes (the no-wake scene ignores the ship).
    pub config: WakelabConfig,
}

impl ScenePair {
    /// Scene ids: `<index>-w` (wake) and `<index>-n` (no wake).
    pub fn ids(&self) -> (String, String) {
        (format!("{:06}-w", self.index), format!("{:06}-n", self.index))
    }

    /// The environment, for grouped splits: everything but the seed and the platform.
    pub fn environment_key(&self) -> String {
        self.combination.environment_key()
    }
}

/// The embedded default study: 3 x 2 x 2 combinations x 16 seeds = 192 pairs (384 scenes) of
/// 32 x 32 pixels of 10 m on the `quick` wake, with a shortened training recipe: the whole
/// `wakelab run` in about 11 minutes on a 2-core machine (docs/results.md).
pub const DEFAULT_STUDY: &str = include_str!("../../../configs/study/default.toml");
/// The spec's scale: 180 pairs of 1024 x 1024 images on the `paper` grid.
pub const PAPER_STUDY: &str = include_str!("../../../configs/study/paper.toml");
/// Detectors for real images (issue 38): kilometre windows, domain randomisation, look-alikes.
pub const TRANSFER_STUDY: &str = include_str!("../../../configs/study/transfer.toml");

fn study_error(field: &str, value: impl ToString, allowed: &str) -> WakelabError {
    ConfigError::new(field, value, allowed).into()
}

impl Study {
    /// Parse and validate a study file's text (`origin` names it in errors).
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Self, WakelabError> {
        let study: Study = toml::from_str(text).map_err(|e| WakelabError::Parse {
            path: origin.to_string(),
            message: e.to_string(),
        })?;
        study.pairs()?;
        study.learning.validate(&study.study.bands)?;
        if let Some(plan) = &study.transfer {
            plan.validate()?;
        }
        Ok(study)
    }

    /// Read a study file.
    pub fn from_file(path: &std::path::Path) -> Result<Self, WakelabError> {
        let text = std::fs::read_to_string(path).map_err(|e| WakelabError::io(path, e))?;
        Self::from_toml_str(&text, &path.display().to_string())
    }

    /// The base configuration.
    pub fn base_config(&self) -> Result<WakelabConfig, WakelabError> {
        let text = toml::to_string(&self.base).expect("a TOML table serialises");
        WakelabConfig::from_toml_str_unvalidated(&text, "[base] of the study", None)
    }

    /// Every scene pair, in a fixed order; every value is validated before any work starts.
    pub fn pairs(&self) -> Result<Vec<ScenePair>, WakelabError> {
        let o = &self.study;
        if o.seeds == 0 || o.seeds > 10_000 {
            return Err(study_error("study.seeds", o.seeds, "an integer in [1, 10000]"));
        }
        if !(0.0..1.0).contains(&o.test_fraction) {
            return Err(study_error("study.test_fraction", o.test_fraction, "must be in [0, 1)"));
        }
        if !(0.0..=1000.0).contains(&o.min_visibility) {
            return Err(study_error(
                "study.min_visibility",
                o.min_visibility,
                "must be in [0, 1000]",
            ));
        }
        if o.bands.is_empty() {
            return Err(study_error(
                "study.bands",
                "[]",
                "a non-empty list of S, C, X, MWIR, LWIR",
            ));
        }
        let base = self.base_config()?;
        let combinations = self.axes.combinations(&Combination::from_config(&base), o.combine)?;
        self.validate_image_sizes(&combinations)?;
        self.validate_draws(&base, &combinations[0])?;
        let mut pairs = Vec::with_capacity(combinations.len() * o.seeds);
        for combination in combinations {
            for s in 0..o.seeds {
                let index = pairs.len();
                let seed = base.seed.wrapping_add(s as u64);
                let combination = self.drawn(&combination, base.seed, index);
                let config = self.scene_config(&base, &combination, seed)?;
                pairs.push(ScenePair {
                    index,
                    combination: combination.clone(),
                    seed,
                    config,
                });
            }
        }
        Ok(pairs)
    }

    /// `wakelab run` trains every architecture on the images, so each image side must suit the
    /// strictest of them (the U-Net's); checked before any scene is rendered.
    fn validate_image_sizes(&self, combinations: &[Combination]) -> Result<(), WakelabError> {
        let listed = serde_json::to_value(&self.axes).expect("serialisable");
        let field = if listed.get("image_size").is_some_and(|v| !v.is_null()) {
            "axes.image_size"
        } else {
            "base.scene.size"
        };
        for c in combinations {
            Architecture::Unet
                .accepts_input_size(c.image_size)
                .map_err(|allowed| study_error(field, c.image_size, &allowed))?;
        }
        Ok(())
    }

    /// Every `[draws]` entry names a continuous axis not also listed in `[axes]`, with
    /// low <= high, both valid values of the axis (with the first combination's other values).
    fn validate_draws(&self, config: &WakelabConfig, base: &Combination) -> Result<(), WakelabError> {
        let listed = serde_json::to_value(&self.axes).expect("serialisable");
        for (name, [lo, hi]) in &self.draws {
            let field = format!("draws.{name}");
            if !base.is_continuous(name) {
                let continuous: Vec<&str> = wakelab_schema::axes::AXES
                    .iter()
                    .map(|a| a.name)
                    .filter(|a| base.is_continuous(a))
                    .collect();
                return Err(study_error(
                    &field,
                    name,
                    &format!("a continuous axis: one of {}", continuous.join(", ")),
                ));
            }
            if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
                return Err(study_error(
                    &field,
                    format!("[{lo}, {hi}]"),
                    "[low, high] with low <= high",
                ));
            }
            if listed.get(name).is_some_and(|v| !v.is_null()) {
                return Err(study_error(&field, name, "an axis in [axes] or in [draws], not both"));
            }
            for end in [lo, hi] {
                let c = base.with_value(name, *end).expect("continuous");
                self.scene_config(config, &c, config.seed)?;
            }
        }
        Ok(())
    }

    /// `combination` with each drawn axis set from pair `index`'s own random stream.
    fn drawn(&self, combination: &Combination, seed: u64, index: usize) -> Combination {
        use rand::{RngExt, SeedableRng};
        let mut c = combination.clone();
        for (name, [lo, hi]) in &self.draws {
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(crate::fnv(format!("{seed}/{index}/{name}")));
            let u: f64 = rng.random();
            c = c.with_value(name, lo + (hi - lo) * u).expect("validated as continuous");
        }
        c
    }

    /// The configuration of one combination and seed, validated (the error names the axis).
    fn scene_config(&self, base: &WakelabConfig, c: &Combination, seed: u64) -> Result<WakelabConfig, WakelabError> {
        let mut cfg = base.clone();
        cfg.seed = seed;
        c.apply_to(&mut cfg);
        if matches!(c.swell_direction, SwellDirection::Named(NamedDirection::Calm)) {
            cfg.environment.swell.amplitude = 0.0;
        }
        if c.stratification == ProfileKind::MixedLayer {
            cfg.environment.temperature.mixed_layer_depth = self.study.mixed_layer_depth;
        }
        cfg.sea.window = cfg.sea.window.min(c.image_size - c.image_size % 2);
        cfg.validate().map_err(|e| {
            let axis = match axis_of_config_field(&e.field) {
                Some(a) if a.name == "along_track" => {
                    "axes.along_track (or axes.image_size, axes.pixel_spacing)".to_string()
                }
                Some(a) if self.draws.contains_key(a.name) => format!("draws.{}", a.name),
                Some(a) => format!("axes.{}", a.name),
                None => e.field.clone(),
            };
            WakelabError::from(ConfigError::new(axis, e.value, e.allowed))
        })?;
        Ok(cfg)
    }
}

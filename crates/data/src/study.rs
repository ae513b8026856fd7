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
//! ...
//!
//! [base]                   # any wakelab configuration table (grid, time, sea, sar, ...)
//! preset = "quick"
//! ```

use serde::{Deserialize, Serialize};
use wakelab_core::config::{NamedDirection, Polarisation, ProfileKind, SwellDirection, WakelabConfig};
use wakelab_core::{ConfigError, WakelabError};
pub use wakelab_schema::dataset::{Combination, BANDS};

/// How the axes combine into scenes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Combine {
    Product,
    Zip,
}

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
    pub bands: Vec<String>,
}

/// The `[axes]` table: every axis a list of values.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Axes {
    pub wind_speed: Option<Vec<f64>>,
    pub wind_direction: Option<Vec<f64>>,
    pub swell_amplitude: Option<Vec<f64>>,
    pub swell_wavelength: Option<Vec<f64>>,
    pub swell_direction: Option<Vec<SwellDirection>>,
    /// "linear" or "mixed_layer".
    pub stratification: Option<Vec<ProfileKind>>,
    pub ship_speed: Option<Vec<f64>>,
    /// Distance of the scene centre behind the stern (m).
    pub along_track: Option<Vec<f64>>,
    pub incidence: Option<Vec<f64>>,
    pub look_direction: Option<Vec<f64>>,
    pub polarisation: Option<Vec<Polarisation>>,
    pub pixel_spacing: Option<Vec<f64>>,
    pub image_size: Option<Vec<usize>>,
}

/// A study file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Study {
    pub study: StudyOptions,
    #[serde(default)]
    pub axes: Axes,
    /// The base wakelab configuration, as a TOML table.
    #[serde(default)]
    pub base: toml::Table,
    /// How `wakelab run` trains and evaluates on the dataset (default: the spec's recipe).
    #[serde(default)]
    pub learning: crate::learning::LearningPlan,
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
        let c = &self.combination;
        format!(
            "wind={}/{} swell={}/{}/{:?} strat={:?} ship={}",
            c.wind_speed,
            c.wind_direction,
            c.swell_amplitude,
            c.swell_wavelength,
            c.swell_direction,
            c.stratification,
            c.ship_speed
        )
    }
}

/// The embedded default study: 2 x 2 x 2 combinations x 2 seeds = 16 pairs (32 scenes) of
/// 64 x 64 pixels of 20 m on the `quick` wake, with a shortened training recipe: the whole
/// `wakelab run` in about ten minutes on a 2-core laptop.
pub const DEFAULT_STUDY: &str = include_str!("default_study.toml");
/// The spec's scale: 180 pairs of 1024 x 1024 images on the `paper` grid.
pub const PAPER_STUDY: &str = include_str!("paper_study.toml");

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
        for b in &o.bands {
            if !BANDS.contains(&b.as_str()) {
                return Err(study_error("study.bands", b, "each one of S, C, X, MWIR, LWIR"));
            }
        }
        let base = self.base_config()?;
        let a = &self.axes;
        macro_rules! axis {
            ($name:ident, $default:expr) => {
                match &a.$name {
                    Some(v) if v.is_empty() => {
                        return Err(study_error(
                            concat!("axes.", stringify!($name)),
                            "[]",
                            "a non-empty list",
                        ))
                    }
                    Some(v) => v.clone(),
                    None => vec![$default],
                }
            };
        }
        let env = &base.environment;
        let wind_speed = axis!(wind_speed, env.wind.speed);
        let wind_direction = axis!(wind_direction, env.wind.direction);
        let swell_amplitude = axis!(swell_amplitude, env.swell.amplitude);
        let swell_wavelength = axis!(swell_wavelength, env.swell.wavelength);
        let swell_direction = axis!(swell_direction, env.swell.direction);
        let stratification = axis!(stratification, env.temperature.kind);
        let ship_speed = axis!(ship_speed, base.ship.speed);
        let along_track = axis!(along_track, base.scene.along_track);
        let incidence = axis!(incidence, base.platform.incidence);
        let look_direction = axis!(look_direction, base.platform.look_direction);
        let polarisation = axis!(polarisation, base.sar.polarisation);
        let pixel_spacing = axis!(pixel_spacing, base.scene.pixel_spacing);
        let image_size = axis!(image_size, base.scene.size);
        let lengths = [
            wind_speed.len(),
            wind_direction.len(),
            swell_amplitude.len(),
            swell_wavelength.len(),
            swell_direction.len(),
            stratification.len(),
            ship_speed.len(),
            along_track.len(),
            incidence.len(),
            look_direction.len(),
            polarisation.len(),
            pixel_spacing.len(),
            image_size.len(),
        ];
        let combos: Vec<Vec<usize>> = match o.combine {
            Combine::Product => {
                let mut out = vec![vec![]];
                for &n in &lengths {
                    out = out
                        .into_iter()
                        .flat_map(|prefix| {
                            (0..n).map(move |i| {
                                let mut p = prefix.clone();
                                p.push(i);
                                p
                            })
                        })
                        .collect();
                }
                out
            }
            Combine::Zip => {
                let n = lengths.iter().copied().filter(|&l| l > 1).max().unwrap_or(1);
                if let Some(bad) = lengths.iter().position(|&l| l != 1 && l != n) {
                    return Err(study_error(
                        "axes",
                        format!("axis {bad} has {} values", lengths[bad]),
                        &format!("with combine = \"zip\" every axis has 1 or {n} values"),
                    ));
                }
                (0..n)
                    .map(|i| lengths.iter().map(|&l| if l == 1 { 0 } else { i }).collect())
                    .collect()
            }
        };
        let mut pairs = Vec::with_capacity(combos.len() * o.seeds);
        for idx in combos {
            let combination = Combination {
                wind_speed: wind_speed[idx[0]],
                wind_direction: wind_direction[idx[1]],
                swell_amplitude: swell_amplitude[idx[2]],
                swell_wavelength: swell_wavelength[idx[3]],
                swell_direction: swell_direction[idx[4]],
                stratification: stratification[idx[5]],
                ship_speed: ship_speed[idx[6]],
                along_track: along_track[idx[7]],
                incidence: incidence[idx[8]],
                look_direction: look_direction[idx[9]],
                polarisation: polarisation[idx[10]],
                pixel_spacing: pixel_spacing[idx[11]],
                image_size: image_size[idx[12]],
            };
            for s in 0..o.seeds {
                let index = pairs.len();
                let seed = base.seed.wrapping_add(s as u64);
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

    /// The configuration of one combination and seed, validated (the error names the axis).
    fn scene_config(&self, base: &WakelabConfig, c: &Combination, seed: u64) -> Result<WakelabConfig, WakelabError> {
        let mut cfg = base.clone();
        cfg.seed = seed;
        let env = &mut cfg.environment;
        env.wind.speed = c.wind_speed;
        env.wind.direction = c.wind_direction;
        env.swell.amplitude = c.swell_amplitude;
        env.swell.wavelength = c.swell_wavelength;
        env.swell.direction = c.swell_direction;
        if matches!(c.swell_direction, SwellDirection::Named(NamedDirection::Calm)) {
            env.swell.amplitude = 0.0;
        }
        env.temperature.kind = c.stratification;
        if c.stratification == ProfileKind::MixedLayer {
            env.temperature.mixed_layer_depth = self.study.mixed_layer_depth;
        }
        cfg.ship.speed = c.ship_speed;
        cfg.scene.along_track = c.along_track;
        cfg.scene.pixel_spacing = c.pixel_spacing;
        cfg.scene.size = c.image_size;
        cfg.sea.window = cfg.sea.window.min(c.image_size - c.image_size % 2);
        cfg.platform.incidence = c.incidence;
        cfg.platform.look_direction = c.look_direction;
        cfg.sar.polarisation = c.polarisation;
        cfg.validate().map_err(|e| {
            let axis = match e.field.as_str() {
                "environment.wind.speed" => "axes.wind_speed",
                "environment.wind.direction" => "axes.wind_direction",
                "environment.swell.amplitude" => "axes.swell_amplitude",
                "environment.swell.wavelength" => "axes.swell_wavelength",
                "ship.speed" => "axes.ship_speed",
                "scene.along_track" => "axes.along_track (or axes.image_size, axes.pixel_spacing)",
                "scene.size" => "axes.image_size",
                "scene.pixel_spacing" => "axes.pixel_spacing",
                "platform.incidence" => "axes.incidence",
                "platform.look_direction" => "axes.look_direction",
                other => other,
            }
            .to_string();
            WakelabError::from(ConfigError::new(axis, e.value, e.allowed))
        })?;
        Ok(cfg)
    }
}

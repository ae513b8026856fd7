//! The dataset's schema: one row of the manifest (a scene) and the study combination it was
//! rendered from.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use wakelab_core::config::{Polarisation, ProfileKind, SwellDirection};

/// Bands every scene is rendered in.
pub const BANDS: [&str; 5] = ["S", "C", "X", "MWIR", "LWIR"];

/// One combination of axis values (a wake/no-wake pair before the seed).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Combination {
    pub wind_speed: f64,
    pub wind_direction: f64,
    pub swell_amplitude: f64,
    pub swell_wavelength: f64,
    pub swell_direction: SwellDirection,
    pub stratification: ProfileKind,
    pub ship_speed: f64,
    pub along_track: f64,
    pub incidence: f64,
    pub look_direction: f64,
    pub polarisation: Polarisation,
    pub pixel_spacing: f64,
    pub image_size: usize,
}

/// One scene of the dataset (a row of the manifest).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct SceneRecord {
    pub id: String,
    pub pair: usize,
    /// 1: a ship wake is in the scene; 0: the matching scene without a ship.
    pub label: u8,
    /// The label under the study's `min_visibility` policy, per band.
    pub label_by_band: BTreeMap<String, u8>,
    /// Contrast-to-clutter ratio of the wake region per band (see `wakelab_data::render`).
    pub visibility: BTreeMap<String, f64>,
    pub seed: u64,
    pub environment: String,
    #[serde(flatten)]
    pub parameters: Combination,
    /// Paths relative to the dataset directory.
    pub images: BTreeMap<String, String>,
    pub masks: BTreeMap<String, String>,
    /// "train" or "test" (filled in by the manifest).
    #[serde(default)]
    pub split: String,
}

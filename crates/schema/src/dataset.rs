//! The dataset's schema: one row of the manifest (a scene) and the study combination it was
//! rendered from.

pub use crate::axes::Combination;
use crate::band::Band;
use crate::split::Split;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
pub use wakelab_core::grid::WakeGeometry;

/// Bands every scene can be rendered in.
pub const BANDS: [Band; 5] = Band::ALL;

/// One scene of the dataset (a row of the manifest).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct SceneRecord {
    pub id: String,
    pub pair: usize,
    /// 1: a ship wake is in the scene; 0: the matching scene without a ship.
    pub label: u8,
    /// The label under the study's `min_visibility` policy, per band.
    pub label_by_band: BTreeMap<Band, u8>,
    /// Contrast-to-clutter ratio of the wake region per band (see `wakelab_dataset::render`).
    pub visibility: BTreeMap<Band, f64>,
    pub seed: u64,
    pub environment: String,
    #[serde(flatten)]
    pub parameters: Combination,
    /// Paths relative to the dataset directory.
    pub images: BTreeMap<Band, String>,
    pub masks: BTreeMap<Band, String>,
    /// Where the wake lies in the image (its pixel-space track); none in a no-wake scene.
    #[serde(default)]
    pub geometry: Option<WakeGeometry>,
    /// Train or test (filled in by the manifest; none in a scene's own `scene.json`).
    #[serde(default, deserialize_with = "split_or_empty")]
    pub split: Option<Split>,
    /// The ship's Kelvin wake and own return, in a wake scene rendered with `kelvin.enabled`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kelvin: Option<KelvinRecord>,
    /// Where the scene's images lie: their grid and, where the study places the scene on the
    /// Earth (`scene.centre`), its centre and UTM zone (none in scenes written before).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub georeference: Option<SceneGeoreference>,
    /// Hash of everything the scene was rendered from (its configuration, the study's bands and
    /// label policy): a scene in the dataset directory counts as done only under the same key,
    /// so a changed study re-renders it instead of reusing it (empty in scenes written before).
    #[serde(default)]
    pub render_key: String,
}

/// The georeference of a scene's images (row 0 at the top; north up when placed on the Earth).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct SceneGeoreference {
    /// "EPSG:326zz" (WGS 84 / UTM, the centre's zone), or "local" for a grid not placed on the
    /// Earth (metres from the scene centre, x to the right, y up).
    pub crs: String,
    pub pixel_spacing_m: f64,
    pub rows: usize,
    pub cols: usize,
    /// The scene centre (WGS 84 degrees) where the study gives one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub centre: Option<wakelab_core::config::GeoPoint>,
}

impl SceneGeoreference {
    /// The georeference of a scene of `size` x `size` pixels of `spacing` m centred at `centre`.
    pub fn new(size: usize, spacing: f64, centre: Option<wakelab_core::config::GeoPoint>) -> Self {
        Self {
            crs: centre.map_or_else(|| "local".to_string(), |c| format!("EPSG:{}", c.utm_epsg())),
            pixel_spacing_m: spacing,
            rows: size,
            cols: size,
            centre,
        }
    }
}

/// What a wake scene's Kelvin wake was made with, and where its mask is.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct KelvinRecord {
    pub hull: wakelab_core::config::HullForm,
    /// The ship's radar cross section (m^2) per radar band.
    pub ship_rcs_m2: BTreeMap<Band, f64>,
    /// The Kelvin-arm mask (1 where the Kelvin waves' rms slope exceeds 0.01), relative to the
    /// dataset directory: one file for every band, apart from the wake masks.
    pub mask: String,
}

/// A scene's split as written, where an empty string (written before splits had a type) is none.
fn split_or_empty<'de, D: serde::Deserializer<'de>>(deserializer: D) -> Result<Option<Split>, D::Error> {
    let text = Option::<String>::deserialize(deserializer)?;
    match text.as_deref() {
        None | Some("") => Ok(None),
        Some(t) => t.parse().map(Some).map_err(serde::de::Error::custom),
    }
}

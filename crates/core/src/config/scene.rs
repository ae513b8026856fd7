//! `[scene]`: the imaged scene's grid and where the wakes lie in it, with each value's allowed
//! range.

use super::checks::{count, positive, range};
use crate::error::ConfigError;
use serde::{Deserialize, Serialize};

/// The scene imaged by the sensors: a square of `size` x `size` pixels on the sea surface.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneConfig {
    /// Pixel spacing (m).
    pub pixel_spacing: f64,
    /// Pixels per side.
    pub size: usize,
    /// Distance behind the stern of the scene centre (m).
    pub along_track: f64,
    /// Cross-track offset of the scene centre from the ship's track (m, positive to port).
    pub cross_track: f64,
    /// The ship's course in the image, degrees clockwise from up (a compass heading on a
    /// north-up image); 270 runs the ship to the left with its wake trailing to the right.
    pub heading: f64,
    /// Further wakes in the scene (`[[scene.other_wakes]]`): the same ship's wake placed again,
    /// as if other ships of its kind had passed; the scene's own placement above is the first.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub other_wakes: Vec<WakePlacement>,
}

/// Where a wake lies in the scene: the scene centre's distance behind that ship's stern (m), its
/// offset to port of that ship's track (m) and the ship's course in the image (degrees clockwise
/// from up), as in [`SceneConfig`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WakePlacement {
    pub along_track: f64,
    pub cross_track: f64,
    pub heading: f64,
}

impl SceneConfig {
    /// The placement of every wake in the scene, the scene's own first.
    pub fn wake_placements(&self) -> Vec<WakePlacement> {
        let own = WakePlacement {
            along_track: self.along_track,
            cross_track: self.cross_track,
            heading: self.heading,
        };
        std::iter::once(own).chain(self.other_wakes.iter().cloned()).collect()
    }

    /// This scene with its own wake placed at `placement` and no other.
    pub fn with_wake_at(&self, placement: &WakePlacement) -> SceneConfig {
        SceneConfig {
            along_track: placement.along_track,
            cross_track: placement.cross_track,
            heading: placement.heading,
            other_wakes: Vec::new(),
            ..self.clone()
        }
    }
}

impl SceneConfig {
    /// Check every value of `[scene]` (`sea_window`: `sea.window`, at most the scene; `wake_end`: how far astern the simulated wake reaches) against its allowed range; the error names the field.
    pub(super) fn validate(&self, sea_window: usize, wake_end: f64) -> Result<(), ConfigError> {
        let sc = self;
        positive("scene.pixel_spacing", sc.pixel_spacing, 0.1, 1000.0, "m")?;
        count("scene.size", sc.size, 16, 8192)?;
        if sea_window > sc.size {
            return Err(ConfigError::new(
                "sea.window",
                sea_window,
                format!("at most scene.size = {} pixels", sc.size),
            ));
        }
        for (i, w) in sc.wake_placements().iter().enumerate() {
            // the scene's own wake is named by its fields, the others by their index
            let field = |name: &str| match i {
                0 => format!("scene.{name}"),
                _ => format!("scene.other_wakes[{}].{name}", i - 1),
            };
            range(&field("heading"), w.heading, -360.0, 360.0, "degrees")?;
            let half = 0.5 * sc.size as f64 * sc.pixel_spacing;
            // how far astern of its centre the scene reaches along the track, at its heading
            let (sin, cos) = w.heading.to_radians().sin_cos();
            let reach = half * (sin.abs() + cos.abs());
            if w.along_track < 0.0 || w.along_track + reach > wake_end {
                return Err(ConfigError::new(
                    field("along_track"),
                    w.along_track,
                    format!(
                        "the scene (reaching {reach:.0} m astern of its centre at heading {}) must end within the \
                         simulated wake, 0..{wake_end:.0} m behind the stern: centre in [0, {:.0}] m",
                        w.heading,
                        wake_end - reach
                    ),
                ));
            }
            range(&field("cross_track"), w.cross_track, -20_000.0, 20_000.0, "m")?;
        }
        Ok(())
    }
}

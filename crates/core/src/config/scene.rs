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
    /// Where the scene's centre lies on the Earth (`[scene.centre]`, WGS 84 degrees): its images
    /// are then placed in the local UTM zone, north up. Without it the grid is local.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub centre: Option<GeoPoint>,
}

/// A point on the Earth: WGS 84 latitude and longitude (degrees).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GeoPoint {
    pub latitude: f64,
    pub longitude: f64,
}

impl GeoPoint {
    /// The UTM zone (1-60) of the point and whether it is north of the equator.
    pub fn utm_zone(&self) -> (u32, bool) {
        let zone = (((self.longitude + 180.0) / 6.0).floor() as i64).rem_euclid(60) + 1;
        (zone as u32, self.latitude >= 0.0)
    }

    /// The EPSG code of the point's WGS 84 / UTM zone (326zz north, 327zz south).
    pub fn utm_epsg(&self) -> u32 {
        let (zone, north) = self.utm_zone();
        if north {
            32600 + zone
        } else {
            32700 + zone
        }
    }
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
        if let Some(c) = sc.centre {
            // UTM's range (beyond it polar stereographic takes over)
            range("scene.centre.latitude", c.latitude, -80.0, 84.0, "degrees")?;
            range("scene.centre.longitude", c.longitude, -180.0, 180.0, "degrees")?;
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn utm_zones_follow_the_standard() {
        // NGA's UTM grid: zone 1 starts at 180 W, each 6 degrees wide
        let at = |latitude, longitude| GeoPoint { latitude, longitude };
        assert_eq!(at(54.3, 10.1).utm_epsg(), 32632); // Kiel
        assert_eq!(at(-33.9, 18.4).utm_epsg(), 32734); // Cape Town
        assert_eq!(at(0.0, -180.0).utm_zone(), (1, true));
        assert_eq!(at(0.0, 179.9).utm_zone(), (60, true));
    }
}

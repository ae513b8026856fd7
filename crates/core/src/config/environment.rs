//! `[environment]`: the water column (TEOS-10 profiles), the swell and the wind, with each
//! value's allowed range.

use super::checks::{positive, range};
use crate::error::ConfigError;
use serde::{Deserialize, Serialize};

/// The ocean the ship sails through.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EnvironmentConfig {
    /// Latitude (degrees north) for TEOS-10 pressure and gravity.
    pub latitude: f64,
    /// Longitude (degrees east, -180..360) for TEOS-10.
    pub longitude: f64,
    /// Gravitational acceleration g (m/s^2).
    pub gravity: f64,
    /// Molecular kinematic viscosity nu (m^2/s), Table 2.1.
    pub kinematic_viscosity: f64,
    /// Reference density rho_0 (kg/m^3), Table 2.1.
    pub reference_density: f64,
    /// Background in-situ temperature T_b(z) (deg C).
    pub temperature: Profile,
    /// Background practical salinity S_b(z) (PSU).
    pub salinity: Profile,
    pub swell: SwellConfig,
    pub wind: WindConfig,
    /// Ambient (background) turbulence kinetic energy (m^2/s^2).
    pub ambient_tke: f64,
    /// Ambient dissipation rate (m^2/s^3).
    pub ambient_dissipation: f64,
}

/// Shape of a background profile.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ProfileKind {
    /// `surface + depth_gradient * depth` everywhere.
    Linear,
    /// Uniform `surface` down to `mixed_layer_depth`, then the linear gradient below (Fig. 3.3).
    MixedLayer,
}

/// A background profile f_b(z) (Eq. (2.7)), constant in time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Profile {
    pub kind: ProfileKind,
    /// Value at the surface.
    pub surface: f64,
    /// Change per metre of depth (negative: decreasing downward).
    pub depth_gradient: f64,
    /// Depth of the mixed layer (m); used by `mixed_layer` only.
    pub mixed_layer_depth: f64,
}

impl Profile {
    /// Value at depth `depth` (m, positive down).
    pub fn at_depth(&self, depth: f64) -> f64 {
        let below = match self.kind {
            ProfileKind::Linear => depth,
            ProfileKind::MixedLayer => (depth - self.mixed_layer_depth).max(0.0),
        };
        self.surface + self.depth_gradient * below
    }
}

/// Swell direction relative to the ship's track: a name or degrees. Read by hand rather than as
/// an untagged enum, whose error ("did not match any variant") names no allowed value.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(untagged)]
pub enum SwellDirection {
    /// `calm`, `following`, `head` or `beam`.
    Named(NamedDirection),
    /// Direction of propagation in degrees from the ship's heading, counter-clockwise seen from
    /// above (0 = following, 90 = towards port, the +y side, 180 = head).
    Degrees(f64),
}

impl<'de> Deserialize<'de> for SwellDirection {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Visitor;
        const ALLOWED: &str = "calm, following, head, beam, or degrees from the heading (a number)";
        impl serde::de::Visitor<'_> for Visitor {
            type Value = SwellDirection;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                write!(f, "a swell direction: {ALLOWED}")
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<SwellDirection, E> {
                let named = match v {
                    "calm" => NamedDirection::Calm,
                    "following" => NamedDirection::Following,
                    "head" => NamedDirection::Head,
                    "beam" => NamedDirection::Beam,
                    _ => {
                        return Err(E::custom(format!(
                            "unknown swell direction \"{v}\"; allowed: {ALLOWED}"
                        )))
                    }
                };
                Ok(SwellDirection::Named(named))
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<SwellDirection, E> {
                Ok(SwellDirection::Degrees(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<SwellDirection, E> {
                Ok(SwellDirection::Degrees(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<SwellDirection, E> {
                Ok(SwellDirection::Degrees(v as f64))
            }
        }
        deserializer.deserialize_any(Visitor)
    }
}

/// The named swell directions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum NamedDirection {
    Calm,
    Following,
    Head,
    Beam,
}

/// The swell whose Stokes drift (Eq. (2.1)) drives the vortex force (Eq. (2.6)).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SwellConfig {
    /// Amplitude a_s (m).
    pub amplitude: f64,
    /// Wavelength lambda (m).
    pub wavelength: f64,
    /// Direction of propagation relative to the track.
    pub direction: SwellDirection,
}

impl SwellConfig {
    /// Propagation angle from the ship's heading (radians), or `None` for a calm sea.
    pub fn angle(&self) -> Option<f64> {
        match self.direction {
            SwellDirection::Named(NamedDirection::Calm) => None,
            _ if self.amplitude == 0.0 => None,
            SwellDirection::Named(NamedDirection::Following) => Some(0.0),
            SwellDirection::Named(NamedDirection::Beam) => Some(std::f64::consts::FRAC_PI_2),
            SwellDirection::Named(NamedDirection::Head) => Some(std::f64::consts::PI),
            SwellDirection::Degrees(d) => Some(d.to_radians()),
        }
    }
}

/// The wind over the scene (used by the surface stage).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WindConfig {
    /// Wind speed at 10 m (m/s).
    pub speed: f64,
    /// Direction the wind blows towards, degrees from the ship's heading.
    pub direction: f64,
    /// Relative standard deviation of the wind speed over the scene (0: uniform); its low-wind
    /// patches are dark in SAR like slicks.
    pub variability: f64,
    /// Correlation length of the wind speed's variation over the scene (m).
    pub gust_length: f64,
}

impl EnvironmentConfig {
    /// Check every value of `[environment]` (`depth`: the grid's, where the profiles end) against its allowed range; the error names the field.
    pub(super) fn validate(&self, depth: f64) -> Result<(), ConfigError> {
        let e = self;
        range("environment.latitude", e.latitude, -90.0, 90.0, "degrees")?;
        range("environment.longitude", e.longitude, -180.0, 360.0, "degrees")?;
        positive("environment.gravity", e.gravity, 9.7, 9.9, "m/s^2")?;
        positive(
            "environment.kinematic_viscosity",
            e.kinematic_viscosity,
            1e-7,
            1e-4,
            "m^2/s",
        )?;
        positive(
            "environment.reference_density",
            e.reference_density,
            990.0,
            1060.0,
            "kg/m^3",
        )?;
        e.temperature.validate("environment.temperature", -2.0, 40.0, depth)?;
        e.salinity.validate("environment.salinity", 2.0, 42.0, depth)?;
        range("environment.swell.amplitude", e.swell.amplitude, 0.0, 10.0, "m")?;
        positive("environment.swell.wavelength", e.swell.wavelength, 5.0, 1000.0, "m")?;
        if e.swell.amplitude > 0.0 {
            let steepness = e.swell.amplitude * 2.0 * std::f64::consts::PI / e.swell.wavelength;
            if steepness > 0.3 {
                return Err(ConfigError::new(
                    "environment.swell.amplitude",
                    e.swell.amplitude,
                    format!(
                        "steepness a k = {steepness:.3} must be at most 0.3 for a Stokes wave \
                         (amplitude at most {:.3} m for this wavelength)",
                        0.3 * e.swell.wavelength / (2.0 * std::f64::consts::PI)
                    ),
                ));
            }
        }
        if let SwellDirection::Degrees(d) = e.swell.direction {
            range(
                "environment.swell.direction",
                d,
                -360.0,
                360.0,
                "degrees, or calm/following/head/beam",
            )?;
        }
        range("environment.wind.speed", e.wind.speed, 0.0, 40.0, "m/s")?;
        range("environment.wind.direction", e.wind.direction, -360.0, 360.0, "degrees")?;
        range(
            "environment.wind.variability",
            e.wind.variability,
            0.0,
            0.5,
            "(relative standard deviation)",
        )?;
        positive("environment.wind.gust_length", e.wind.gust_length, 10.0, 1.0e5, "m")?;
        positive("environment.ambient_tke", e.ambient_tke, 1e-12, 1e-2, "m^2/s^2")?;
        positive(
            "environment.ambient_dissipation",
            e.ambient_dissipation,
            1e-15,
            1e-2,
            "m^2/s^3",
        )?;
        Ok(())
    }
}

impl Profile {
    /// Check the profile named `field`: its surface value and its value at
    /// every depth down to `depth` (the grid's) in lo..=hi.
    fn validate(&self, field: &str, lo: f64, hi: f64, depth: f64) -> Result<(), ConfigError> {
        let p = self;
        range(&format!("{field}.surface"), p.surface, lo, hi, "")?;
        range(
            &format!("{field}.depth_gradient"),
            p.depth_gradient,
            -1.0,
            1.0,
            "per metre of depth",
        )?;
        range(
            &format!("{field}.mixed_layer_depth"),
            p.mixed_layer_depth,
            0.0,
            depth,
            "m (0 to grid.depth)",
        )?;
        let bottom = p.at_depth(depth);
        if !(lo..=hi).contains(&bottom) {
            return Err(ConfigError::new(
                format!("{field}.depth_gradient"),
                p.depth_gradient,
                format!("the profile reaches {bottom:.3} at the bottom ({depth} m); it must stay in [{lo}, {hi}]"),
            ));
        }
        Ok(())
    }
}

//! `[platform]`, `[sar]` and `[ir]`: the sensors' geometry and settings (spec chapter 3), with
//! each value's allowed range.

use super::checks::range;
use crate::error::ConfigError;
use serde::{Deserialize, Serialize};

/// Viewing geometry of the imaging platform.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlatformConfig {
    /// Incidence angle at the scene centre (degrees).
    pub incidence: f64,
    /// Horizontal direction the sensor looks in, degrees counter-clockwise from the ship's heading
    /// (90: looking towards port, across the track).
    pub look_direction: f64,
}

/// SAR polarisation (transmit and receive alike).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Polarisation {
    Vv,
    Hh,
}

/// `vv` or `hh`, in either case.
impl std::str::FromStr for Polarisation {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "vv" => Ok(Self::Vv),
            "hh" => Ok(Self::Hh),
            _ => Err(format!("{s}: must be vv or hh")),
        }
    }
}

/// The SAR sensor (spec 3.1). With `looks = 0`, `noise_floor = false` and
/// `velocity_bunching = false` it is the spec's perfect SAR.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SarConfig {
    pub polarisation: Polarisation,
    /// Number of independent looks of the speckle; 0 for none.
    pub looks: u32,
    /// Resolution (m): the width of the impulse response, over which speckle and thermal noise
    /// are correlated; 0 for the pixel spacing.
    pub resolution: f64,
    /// Add thermal noise at the band's noise-equivalent sigma zero.
    pub noise_floor: bool,
    /// One noise-equivalent sigma zero for every band (dB); unset: each band's own below.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub nesz: Option<f64>,
    /// S-band NESZ (dB).
    pub nesz_s: f64,
    /// C-band NESZ (dB).
    pub nesz_c: f64,
    /// X-band NESZ (dB).
    pub nesz_x: f64,
    /// Displace scatterers in azimuth by their line-of-sight velocity times R/V (the ship too).
    pub velocity_bunching: bool,
    /// Slant range over platform speed R/V (s): Sentinel-1 about 115, TerraSAR-X about 75.
    pub range_to_velocity: f64,
}

impl SarConfig {
    /// The noise-equivalent sigma zero of `band` (dB).
    pub fn nesz_db(&self, band: crate::units::RadarBand) -> f64 {
        use crate::units::RadarBand::*;
        self.nesz.unwrap_or(match band {
            S => self.nesz_s,
            C => self.nesz_c,
            X => self.nesz_x,
        })
    }

    /// The resolution in pixels of `pixel_spacing` (1 when the resolution is the pixel).
    pub fn resolution_pixels(&self, pixel_spacing: f64) -> f64 {
        if self.resolution > 0.0 {
            self.resolution / pixel_spacing
        } else {
            1.0
        }
    }
}

/// The infrared sensor (spec 3.2, Eq. (3.5) and Algorithm 1).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IrConfig {
    /// Sun elevation above the horizon (degrees).
    pub sun_elevation: f64,
    /// Direction of the sun, degrees counter-clockwise from the ship's heading.
    pub sun_azimuth: f64,
    /// Brightness temperature of the sun's photosphere (K).
    pub sun_temperature: f64,
    /// Henyey-Greenstein asymmetry G of the sun's scattering lobe (Eq. (3.19)).
    pub sun_asymmetry: f64,
    /// Sky brightness temperature at the zenith (K), Eq. (3.20).
    pub sky_zenith_temperature: f64,
    /// Sky brightness temperature at the horizon (K), Eq. (3.20).
    pub sky_horizon_temperature: f64,
    /// Add the imager's noise, of standard deviation `netd`, to the brightness temperature.
    pub noise: bool,
    /// Noise-equivalent temperature difference (K).
    pub netd: f64,
    /// Full width at half maximum of the imager's point-spread function (m); 0: the pixel.
    pub resolution: f64,
}

impl PlatformConfig {
    /// Check every value of `[platform]` against its allowed range; the error names the field.
    pub(super) fn validate(&self) -> Result<(), ConfigError> {
        let p = self;
        range("platform.incidence", p.incidence, 15.0, 70.0, "degrees")?;
        range("platform.look_direction", p.look_direction, -360.0, 360.0, "degrees")?;
        Ok(())
    }
}

impl SarConfig {
    /// Check every value of `[sar]` against its allowed range; the error names the field.
    pub(super) fn validate(&self) -> Result<(), ConfigError> {
        let sar = self;
        if sar.looks > 1000 {
            return Err(ConfigError::new(
                "sar.looks",
                sar.looks,
                "an integer in [0, 1000] (0: no speckle)",
            ));
        }
        if let Some(nesz) = sar.nesz {
            range("sar.nesz", nesz, -60.0, 0.0, "dB")?;
        }
        range("sar.nesz_s", sar.nesz_s, -60.0, 0.0, "dB")?;
        range("sar.nesz_c", sar.nesz_c, -60.0, 0.0, "dB")?;
        range("sar.nesz_x", sar.nesz_x, -60.0, 0.0, "dB")?;
        range(
            "sar.resolution",
            sar.resolution,
            0.0,
            1000.0,
            "m (0: the pixel spacing)",
        )?;
        range("sar.range_to_velocity", sar.range_to_velocity, 0.0, 500.0, "s")?;
        Ok(())
    }
}

impl IrConfig {
    /// Check every value of `[ir]` against its allowed range; the error names the field.
    pub(super) fn validate(&self) -> Result<(), ConfigError> {
        let ir = self;
        range("ir.sun_elevation", ir.sun_elevation, -90.0, 90.0, "degrees")?;
        range("ir.sun_azimuth", ir.sun_azimuth, -360.0, 360.0, "degrees")?;
        range("ir.sun_temperature", ir.sun_temperature, 3000.0, 7000.0, "K")?;
        range("ir.sun_asymmetry", ir.sun_asymmetry, 0.0, 0.999, "")?;
        range("ir.netd", ir.netd, 0.0, 10.0, "K")?;
        range("ir.resolution", ir.resolution, 0.0, 10_000.0, "m (0: the pixel)")?;
        range(
            "ir.sky_zenith_temperature",
            ir.sky_zenith_temperature,
            150.0,
            320.0,
            "K",
        )?;
        range(
            "ir.sky_horizon_temperature",
            ir.sky_horizon_temperature,
            150.0,
            320.0,
            "K",
        )?;
        Ok(())
    }
}

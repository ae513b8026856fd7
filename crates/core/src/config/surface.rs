//! `[sea]`, `[slicks]` and `[kelvin]`: the sea's spectrum and films, natural slicks and the
//! ship's Kelvin wake and return, with each value's allowed range.

use super::checks::{positive, range};
use crate::error::ConfigError;
use serde::{Deserialize, Serialize};

/// Background wave spectrum models (spec 2.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SpectrumModel {
    /// Pierson-Moskowitz (Eq. (2.71)) for the long waves joined to the Lyzenga-Bennett power law
    /// B k^-c (Eq. (2.70)) for the short waves.
    PiersonMoskowitz,
    /// Elfouhaily et al. (1997) unified directional spectrum.
    Elfouhaily,
}

/// The ocean surface stage: wave spectrum, surface film and the random sea surface (spec 2.2-2.3).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SeaConfig {
    pub spectrum: SpectrumModel,
    /// Elfouhaily inverse wave age Omega_c (0.84: fully developed sea).
    pub inverse_wave_age: f64,
    /// Lyzenga-Bennett exponent c of the short-wave power law B k^-c of the 2D spectrum.
    pub short_wave_exponent: f64,
    /// Wavenumber where the power law takes over from Pierson-Moskowitz, in multiples of k_p.
    pub short_wave_join: f64,
    /// Relative spectral width (in k) of the swell component.
    pub swell_width: f64,
    /// Directional spread of the swell (degrees, standard deviation).
    pub swell_spread: f64,
    /// Dilational elasticity of the surface film at the reference concentration Gamma = 1 (N/m).
    pub film_elasticity: f64,
    /// Surface tension of clean sea water tau_w (N/m).
    pub surface_tension: f64,
    /// Side of the sampling window of the random surface (pixels, even; Eqs. (2.72)-(2.76)).
    pub window: usize,
}

/// Natural (biogenic) slicks on the open sea: patches and filaments of surface film, in wake and
/// no-wake scenes alike.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SlickConfig {
    /// Expected fraction of the scene under slicks (0: none).
    pub coverage: f64,
    /// Correlation length of the slick field across its filaments (m).
    pub length: f64,
    /// Length over width of the filaments, which run along the wind.
    pub elongation: f64,
    /// Reference dilational elasticity of a slick's film (N/m), in place of the open sea's
    /// `sea.film_elasticity`.
    pub elasticity: f64,
}

/// The ship's Kelvin wave pattern (linear thin-ship theory, Michell 1898) and the ship's own
/// radar and infrared return, in wake scenes (a no-wake scene has no ship).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KelvinConfig {
    /// Add the Kelvin wave field and the ship's return; false leaves scenes as without them.
    pub enabled: bool,
    /// The hull's form, scaled to `ship.length`, `ship.beam` and `ship.draft`.
    pub hull: HullForm,
    /// Radar cross section of the ship (m^2) in every band; unset: Skolnik's empirical
    /// sigma = 52 f^(1/2) D^(3/2) (f in MHz, D the displacement in kilotonnes) per band.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ship_rcs: Option<f64>,
    /// Temperature of the hull's sides above the sea surface's (K), for its infrared signature.
    pub hull_temperature_excess: f64,
    /// Emissivity of the hull's paint in the infrared.
    pub hull_emissivity: f64,
}

/// Hull forms of the thin-ship source distribution.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HullForm {
    /// Wigley's parabolic hull, y = (B/2) (1 - (2x/L)^2) (1 - (z/T)^2) (Wigley 1934).
    Wigley,
}

impl HullForm {
    /// The form's name as the configuration writes it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Wigley => "wigley",
        }
    }
}

impl SeaConfig {
    /// Check every value of `[sea]` against its allowed range; the error names the field.
    pub(super) fn validate(&self) -> Result<(), ConfigError> {
        let sea = self;
        positive("sea.inverse_wave_age", sea.inverse_wave_age, 0.84, 5.0, "")?;
        positive("sea.short_wave_exponent", sea.short_wave_exponent, 3.0, 5.0, "")?;
        positive(
            "sea.short_wave_join",
            sea.short_wave_join,
            1.5,
            1000.0,
            "multiples of k_p",
        )?;
        positive("sea.swell_width", sea.swell_width, 0.01, 0.5, "")?;
        positive("sea.swell_spread", sea.swell_spread, 1.0, 60.0, "degrees")?;
        range("sea.film_elasticity", sea.film_elasticity, 0.0, 0.08, "N/m")?;
        positive("sea.surface_tension", sea.surface_tension, 0.05, 0.08, "N/m")?;
        if !(16..=4096).contains(&sea.window) || sea.window % 2 != 0 {
            return Err(ConfigError::new(
                "sea.window",
                sea.window,
                "an even number of pixels in [16, 4096]",
            ));
        }
        Ok(())
    }
}

impl SlickConfig {
    /// Check every value of `[slicks]` against its allowed range; the error names the field.
    pub(super) fn validate(&self) -> Result<(), ConfigError> {
        let sl = self;
        range("slicks.coverage", sl.coverage, 0.0, 0.9, "(fraction of the scene)")?;
        positive("slicks.length", sl.length, 1.0, 1.0e5, "m")?;
        range("slicks.elongation", sl.elongation, 1.0, 50.0, "(length over width)")?;
        range("slicks.elasticity", sl.elasticity, 0.0, 0.1, "N/m")?;
        Ok(())
    }
}

impl KelvinConfig {
    /// Check every value of `[kelvin]` against its allowed range; the error names the field.
    pub(super) fn validate(&self) -> Result<(), ConfigError> {
        let k = self;
        if let Some(rcs) = k.ship_rcs {
            range("kelvin.ship_rcs", rcs, 0.0, 1.0e8, "m^2")?;
        }
        range(
            "kelvin.hull_temperature_excess",
            k.hull_temperature_excess,
            -20.0,
            100.0,
            "K",
        )?;
        range("kelvin.hull_emissivity", k.hull_emissivity, 0.0, 1.0, "")?;
        Ok(())
    }
}

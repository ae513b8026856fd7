//! What `wakelab sar sigma0` prints: the open sea's NRCS in one band, its parts, and CMOD5.N's
//! value beside it in C band.

use crate::gmf::cmod5n;
use crate::sar::{to_db, RadarSea};
use num_complex::Complex64;
use wakelab_core::config::Polarisation;
use wakelab_surface::short_waves::ShortWaves;
use wakelab_surface::spectrum::SeaSpectrum;

/// NRCS of the undisturbed sea for a configuration's wind, band, polarisation, incidence and look
/// (what `wakelab sar sigma0` prints), at pixel spacing `dx` for the two-scale split.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Sigma0Report {
    pub band: &'static str,
    pub frequency_hz: f64,
    pub polarisation: String,
    pub incidence_deg: f64,
    pub wind_speed: f64,
    /// Wind direction relative to the look direction (degrees; 0 = the radar looks down-wind).
    pub wind_relative_to_look_deg: f64,
    pub permittivity_real: f64,
    pub permittivity_imag: f64,
    pub bragg_wavenumber: f64,
    /// Side of the cell the sea is seen in (m): waves longer than it are resolved, shorter ones
    /// tilt the Bragg facets.
    pub cell_size_m: f64,
    /// Two-scale Bragg part, before the (1 - q) of the breakers.
    pub sigma0_bragg: f64,
    /// Specular part, before the (1 - q) of the breakers.
    pub sigma0_specular: f64,
    /// NRCS of the breaking zones times their fraction q.
    pub sigma0_breaking: f64,
    /// The breakers' surface fraction q.
    pub breaking_fraction: f64,
    pub sigma0: f64,
    pub sigma0_db: f64,
    /// CMOD5.N (Hersbach 2010) for the same wind, incidence and direction: C band only (its
    /// VV; null in S and X band).
    pub cmod5n: Option<f64>,
    pub cmod5n_db: Option<f64>,
}

/// The [`Sigma0Report`] of a configuration's sea (its wind, swell and water) in `band`, looking
/// `look_from_wind_deg` degrees from the wind direction (0: down-wind), with the configured
/// polarisation and incidence, seen in cells of side `cell` (m; the scene's pixel spacing for an
/// image's background, [`crate::gmf::CELL_SIZE`] for CMOD5.N's; None: the pixel spacing): what
/// `wakelab sar sigma0` prints. A cell outside 0.1 m-1000 km is refused naming `--cell`.
pub fn sigma0_of_config(
    cfg: &wakelab_core::WakelabConfig,
    band: wakelab_core::units::RadarBand,
    look_from_wind_deg: f64,
    cell: Option<f64>,
) -> Result<Sigma0Report, wakelab_core::ConfigError> {
    let cell = cell.unwrap_or(cfg.scene.pixel_spacing);
    if !(0.1..=1e6).contains(&cell) {
        return Err(wakelab_core::ConfigError::new("--cell", cell, "in [0.1, 1000000] m"));
    }
    let env = &cfg.environment;
    Ok(sigma0_of_sea(
        &wakelab_surface::background_spectrum(cfg),
        band,
        crate::sar_image::surface_permittivity(cfg, band),
        cfg.sar.polarisation,
        (env.wind.direction - look_from_wind_deg).to_radians(),
        cfg.platform.incidence,
        cell,
    ))
}

/// Compute the [`Sigma0Report`] of the undisturbed sea.
pub fn sigma0_of_sea(
    spectrum: &SeaSpectrum,
    band: wakelab_core::units::RadarBand,
    permittivity: Complex64,
    polarisation: Polarisation,
    look: f64,
    incidence_deg: f64,
    dx: f64,
) -> Sigma0Report {
    let theta = incidence_deg.to_radians();
    let short_waves = ShortWaves::new(spectrum);
    let radar = RadarSea::new(
        spectrum,
        &short_waves,
        band.wavenumber(),
        permittivity,
        polarisation,
        look,
        theta,
        dx,
    );
    let parts = radar.parts(theta);
    let total = parts.total();
    let relative = (spectrum.wind_direction - look).to_degrees();
    // CMOD5.N's direction is 0 looking up-wind, ours 0 looking down-wind
    let cmod = (band == wakelab_core::units::RadarBand::C)
        .then(|| cmod5n(spectrum.wind_speed, incidence_deg, 180.0 - relative));
    Sigma0Report {
        band: band.name(),
        frequency_hz: band.frequency(),
        polarisation: format!("{polarisation:?}").to_uppercase(),
        incidence_deg,
        wind_speed: spectrum.wind_speed,
        wind_relative_to_look_deg: relative,
        permittivity_real: permittivity.re,
        permittivity_imag: permittivity.im,
        bragg_wavenumber: band.bragg_wavenumber(incidence_deg),
        cell_size_m: dx,
        sigma0_bragg: parts.bragg,
        sigma0_specular: parts.specular,
        sigma0_breaking: parts.fraction * parts.breaking,
        breaking_fraction: parts.fraction,
        sigma0: total,
        sigma0_db: to_db(total),
        cmod5n: cmod,
        cmod5n_db: cmod.map(to_db),
    }
}

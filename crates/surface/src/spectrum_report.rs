//! What `wakelab spectrum` prints: the background spectrum of a configuration (spec 2.3) and
//! its densities at the Bragg wavenumbers of S, C and X band (Eq. (3.1)'s k_B).

use wakelab_core::config::WakelabConfig;

/// What `wakelab spectrum` reports: the spectrum's summary and its Bragg-scale densities.
#[derive(serde::Serialize)]
pub struct SpectrumReport {
    pub model: wakelab_core::config::SpectrumModel,
    pub wind_speed: f64,
    pub wind_direction_deg: f64,
    pub swell_amplitude: f64,
    pub swell_wavelength: f64,
    #[serde(flatten)]
    pub summary: crate::spectrum::SpectrumSummary,
    pub incidence_deg: f64,
    pub look_direction_deg: f64,
    pub bragg: Vec<BraggReport>,
}

/// The spectrum at one band's Bragg wavenumber, for the configured incidence and look, as the
/// radar sees it (Elfouhaily's revised in the decimetre range: [`crate::bragg_scale`]).
#[derive(serde::Serialize)]
pub struct BraggReport {
    pub band: &'static str,
    pub frequency_hz: f64,
    pub bragg_wavenumber: f64,
    pub bragg_wavelength_m: f64,
    /// F(k_B) towards the sensor (m^4).
    pub density_towards: f64,
    /// F(-k_B) away from the sensor (m^4).
    pub density_away: f64,
    /// Omnidirectional Psi(k_B) (m^3).
    pub omnidirectional: f64,
}

/// The background spectrum of a configuration (its wind, swell and spectrum model): its
/// integrated properties and the spectral densities at each radar band's Bragg wavenumber.
pub fn spectrum_report(cfg: &WakelabConfig) -> SpectrumReport {
    let sea = crate::background_spectrum(cfg);
    let bragg = wakelab_core::units::RadarBand::ALL
        .iter()
        .map(|&band| {
            let (t, a) = crate::bragg_vectors(cfg, band);
            let k = t.magnitude();
            BraggReport {
                band: band.name(),
                frequency_hz: band.frequency(),
                bragg_wavenumber: k,
                bragg_wavelength_m: 2.0 * std::f64::consts::PI / k,
                density_towards: sea.bragg_density(t.kx, t.ky),
                density_away: sea.bragg_density(a.kx, a.ky),
                omnidirectional: sea.bragg_omni(k),
            }
        })
        .collect();
    let env = &cfg.environment;
    SpectrumReport {
        model: cfg.sea.spectrum,
        wind_speed: env.wind.speed,
        wind_direction_deg: env.wind.direction,
        swell_amplitude: if env.swell.angle().is_some() {
            env.swell.amplitude
        } else {
            0.0
        },
        swell_wavelength: env.swell.wavelength,
        // slopes of all waves longer than 6 mm (k < 1000 rad/m, the gravity-capillary range)
        summary: sea.summary(1000.0),
        incidence_deg: cfg.platform.incidence,
        look_direction_deg: cfg.platform.look_direction,
        bragg,
    }
}

//! SAR images of a scene: the perfect SAR of spec Eq. (3.3) and, switchable, the speckle,
//! thermal noise (see [`crate::image_formation`]) and velocity bunching of a real instrument.
//!
//! Per pixel, with the band's Bragg waves modulated by the wake (N/N0 = m from the surface stage),
//! its breakers' fraction q by m_b (N/N0 of the breaking waves, same balance), and the resolved
//! long-wave slope s towards the radar tilting the local incidence to theta - psi,
//! psi = atan(s) (Eq. (3.3), to first order in psi; each part X is X(theta) - psi X'(theta)):
//!   sigma0 = (1 - m_b q) (m sigma_B + sigma_S) + m_b q sigma_wb   (KHCC03 Eq. 1).
//! Incidence is taken as constant over the scene (a distant platform).

use crate::image_formation::{form_sar_image, SarFormation};
use crate::permittivity::seawater_permittivity;
use crate::sar::RadarSea;
use ndarray::Array2;
use num_complex::Complex64;
use serde::Serialize;
use wakelab_core::units::RadarBand;
use wakelab_core::WakelabConfig;
use wakelab_surface::spectrum::angular_frequency;
use wakelab_surface::SurfaceScene;

/// One band's image and what it was made from.
#[derive(Debug, Clone)]
pub struct SarImage {
    pub band: RadarBand,
    /// Normalised radar cross section, linear, (rows, cols) like the scene.
    pub sigma0: Array2<f64>,
    pub info: SarInfo,
}

/// Scalars of a SAR image, for its metadata.
#[derive(Debug, Clone, Serialize)]
pub struct SarInfo {
    pub band: &'static str,
    pub frequency_hz: f64,
    pub polarisation: String,
    pub incidence_deg: f64,
    pub look_direction_deg: f64,
    pub permittivity_real: f64,
    pub permittivity_imag: f64,
    pub background_bragg: f64,
    pub background_specular: f64,
    /// NRCS of the breaking zones (before their fraction q).
    pub background_breaking: f64,
    /// Surface fraction q of the breakers.
    pub breaking_fraction: f64,
    pub looks: u32,
    pub nesz_db: Option<f64>,
    pub range_to_velocity_s: Option<f64>,
}

/// Permittivity of the undisturbed sea's surface water (its temperature and salinity at z = 0)
/// at a band's frequency (Klein & Swift 1977).
pub fn surface_permittivity(config: &WakelabConfig, band: RadarBand) -> Complex64 {
    let env = &config.environment;
    seawater_permittivity(
        band.frequency(),
        env.temperature.at_depth(0.0),
        env.salinity.at_depth(0.0),
    )
}

/// The radar view of the background sea for one band.
pub fn radar_sea<'a>(config: &WakelabConfig, scene: &'a SurfaceScene, band: RadarBand) -> RadarSea<'a> {
    RadarSea::new(
        &scene.spectrum,
        &scene.short_waves,
        band.wavenumber(),
        surface_permittivity(config, band),
        config.sar.polarisation,
        config.platform.look_direction.to_radians(),
        config.platform.incidence.to_radians(),
        scene.grid.pixel_spacing,
    )
}

/// Render one band's SAR image of `scene`.
pub fn render_sar(config: &WakelabConfig, scene: &SurfaceScene, band: RadarBand) -> SarImage {
    let radar = radar_sea(config, scene, band);
    let theta = config.platform.incidence.to_radians();
    let h = 1e-3;
    let part = |t: f64| radar.parts(t);
    let (at, lo, hi) = (part(theta), part(theta - h), part(theta + h));
    let slope = |f: fn(&crate::sar::Sigma0Parts) -> f64| (f(&hi) - f(&lo)) / (2.0 * h);
    let (bragg, specular, breaking) = (at.bragg, at.specular, at.breaking);
    let bragg_slope = slope(|p| p.bragg);
    let specular_slope = slope(|p| p.specular);
    let breaking_slope = slope(|p| p.breaking);
    let q = at.fraction;
    let waves = scene
        .bragg
        .iter()
        .find(|b| b.band == band)
        .expect("the surface stage covers every band");
    let phi = radar.look;
    let surface = &scene.surface;
    let mut sigma0 = Array2::zeros(waves.modulation.raw_dim());
    ndarray::Zip::from(&mut sigma0)
        .and(&waves.modulation)
        .and(&waves.breaking)
        .and(&surface.slope_x)
        .and(&surface.slope_y)
        .par_for_each(|out, &m, &mb, &sx, &sy| {
            // slope rising towards the radar: minus the gradient along the look direction; the
            // scene's x runs astern (-x heading), its slope_y along +y
            let towards = sx * phi.cos() - sy * phi.sin();
            let psi = towards.atan();
            let qm = (q * mb).min(1.0);
            let rough = m * (bragg - psi * bragg_slope) + specular - psi * specular_slope;
            *out = ((1.0 - qm) * rough + qm * (breaking - psi * breaking_slope)).max(0.0);
        });
    let sar = &config.sar;
    if sar.velocity_bunching {
        sigma0 = velocity_bunching(config, scene, &sigma0);
    }
    if sar.looks > 0 || sar.noise_floor {
        let formation = SarFormation {
            looks: sar.looks,
            resolution_pixels: sar.resolution_pixels(scene.grid.pixel_spacing),
            nesz: if sar.noise_floor {
                10f64.powf(sar.nesz_db(band) / 10.0)
            } else {
                0.0
            },
        };
        sigma0 = form_sar_image(&sigma0, formation, config.seed ^ (0x5A5A_0000 + band as u64));
    }
    let eps: Complex64 = radar.permittivity;
    SarImage {
        band,
        sigma0,
        info: SarInfo {
            band: band.name(),
            frequency_hz: band.frequency(),
            polarisation: format!("{:?}", sar.polarisation).to_uppercase(),
            incidence_deg: config.platform.incidence,
            look_direction_deg: config.platform.look_direction,
            permittivity_real: eps.re,
            permittivity_imag: eps.im,
            background_bragg: bragg,
            background_specular: specular,
            background_breaking: breaking,
            breaking_fraction: q,
            looks: sar.looks,
            nesz_db: sar.noise_floor.then_some(sar.nesz_db(band)),
            range_to_velocity_s: sar.velocity_bunching.then_some(sar.range_to_velocity),
        },
    }
}

/// Velocity bunching (Alpers & Rufenach 1979): each scatterer appears shifted in azimuth by
/// (R/V) v_r, v_r its line-of-sight orbital velocity. v_r comes from the scene's long-wave
/// elevation by linear wave theory, each Fourier component taken to travel down-wind; the
/// intensity is moved with bilinear weights, so the image's total is conserved.
pub fn velocity_bunching(config: &WakelabConfig, scene: &SurfaceScene, sigma0: &Array2<f64>) -> Array2<f64> {
    let n = sigma0.nrows();
    let dx = scene.grid.pixel_spacing;
    let theta = config.platform.incidence.to_radians();
    let look = config.platform.look_direction.to_radians();
    let wind = config.environment.wind.direction.to_radians();
    let v = crate::spectral::line_of_sight_velocity(&scene.surface.elevation, dx, theta, look, wind, |k| {
        angular_frequency(k, scene.spectrum.gravity, scene.spectrum.tension)
    });
    // azimuth (flight) direction: the look direction turned by +90 degrees; in scene pixels a
    // heading-frame vector (a, b) is (-a / dx) columns and (-b / dx) rows
    let (az_x, az_y) = (
        (look + std::f64::consts::FRAC_PI_2).cos(),
        (look + std::f64::consts::FRAC_PI_2).sin(),
    );
    let rv = config.sar.range_to_velocity;
    let mut out = Array2::zeros((n, n));
    for r in 0..n {
        for c in 0..n {
            let shift = rv * v[[r, c]];
            let col = c as f64 - az_x * shift / dx;
            let row = r as f64 - az_y * shift / dx;
            let (c0, r0) = (col.floor(), row.floor());
            let (fc, fr) = (col - c0, row - r0);
            for (dr, wr) in [(0.0, 1.0 - fr), (1.0, fr)] {
                for (dc, wc) in [(0.0, 1.0 - fc), (1.0, fc)] {
                    let (rr, cc) = (r0 + dr, c0 + dc);
                    if rr >= 0.0 && cc >= 0.0 && (rr as usize) < n && (cc as usize) < n {
                        out[[rr as usize, cc as usize]] += sigma0[[r, c]] * wr * wc;
                    }
                }
            }
        }
    }
    out
}

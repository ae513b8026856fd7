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
use crate::sar::{RadarSea, Sigma0Parts};
use ndarray::Array2;
use num_complex::Complex64;
use rayon::prelude::*;
use serde::Serialize;
use wakelab_core::units::RadarBand;
use wakelab_core::WakelabConfig;
use wakelab_surface::kelvin::ThinShip;
use wakelab_surface::scene::SceneGrid;
use wakelab_surface::short_waves::ShortWaves;
use wakelab_surface::spectrum::{angular_frequency, SeaSpectrum};
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
    radar_sea_of(
        config,
        &scene.spectrum,
        &scene.short_waves,
        scene.grid.pixel_spacing,
        band,
    )
}

/// The background sea's NRCS parts at the scene's incidence and their derivatives in incidence
/// (for the tilt of Eq. (3.3)).
#[derive(Debug, Clone, Copy)]
struct Background {
    at: Sigma0Parts,
    slope: Sigma0Parts,
}

impl Background {
    fn of(radar: &RadarSea, theta: f64) -> Self {
        let h = 1e-3;
        let (at, lo, hi) = (radar.parts(theta), radar.parts(theta - h), radar.parts(theta + h));
        let d = |f: fn(&Sigma0Parts) -> f64| (f(&hi) - f(&lo)) / (2.0 * h);
        Self {
            at,
            slope: Sigma0Parts {
                bragg: d(|p| p.bragg),
                specular: d(|p| p.specular),
                breaking: d(|p| p.breaking),
                fraction: 0.0,
            },
        }
    }

    /// Linear interpolation between two backgrounds.
    fn mix(&self, other: &Self, t: f64) -> Self {
        let lerp = |a: &Sigma0Parts, b: &Sigma0Parts| Sigma0Parts {
            bragg: a.bragg + t * (b.bragg - a.bragg),
            specular: a.specular + t * (b.specular - a.specular),
            breaking: a.breaking + t * (b.breaking - a.breaking),
            fraction: a.fraction + t * (b.fraction - a.fraction),
        };
        Self {
            at: lerp(&self.at, &other.at),
            slope: lerp(&self.slope, &other.slope),
        }
    }

    /// NRCS of a pixel whose Bragg waves are at N/N0 = m, breakers at m_b, tilted by psi towards
    /// the radar (module doc).
    fn sigma0(&self, m: f64, mb: f64, psi: f64) -> f64 {
        let (a, s) = (&self.at, &self.slope);
        let qm = (a.fraction * mb).min(1.0);
        let rough = m * (a.bragg - psi * s.bragg) + a.specular - psi * s.specular;
        ((1.0 - qm) * rough + qm * (a.breaking - psi * s.breaking)).max(0.0)
    }
}

/// Backgrounds over the range of a scene's local wind speeds, for its low-wind patches: each
/// pixel's background is that of its own wind (the sea's spectrum and short-wave balance at that
/// wind), interpolated linearly between `WIND_NODES` speeds (within 1 % of the exact sigma0
/// between the nodes: `wind_table_interpolates_within_one_percent`).
struct WindTable {
    speeds: Vec<f64>,
    backgrounds: Vec<Background>,
}

const WIND_NODES: usize = 8;

impl WindTable {
    fn new(config: &WakelabConfig, scene: &SurfaceScene, band: RadarBand, winds: &Array2<f64>) -> Self {
        let (lo, hi) = winds
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), &w| (a.min(w), b.max(w)));
        let nodes = if hi - lo < 1e-6 { 1 } else { WIND_NODES };
        let speeds: Vec<f64> = (0..nodes)
            .map(|i| lo + (hi - lo) * i as f64 / (nodes.max(2) - 1) as f64)
            .collect();
        let env = &config.environment;
        let backgrounds = speeds
            .par_iter()
            .map(|&speed| {
                let spectrum = SeaSpectrum::new(&config.sea, speed, env.wind.direction, &env.swell, env.gravity);
                let short_waves = ShortWaves::new(&spectrum);
                let radar = radar_sea_of(config, &spectrum, &short_waves, scene.grid.pixel_spacing, band);
                Background::of(&radar, config.platform.incidence.to_radians())
            })
            .collect();
        Self { speeds, backgrounds }
    }

    fn at(&self, speed: f64) -> Background {
        let n = self.speeds.len();
        if n == 1 {
            return self.backgrounds[0];
        }
        let step = self.speeds[1] - self.speeds[0];
        let t = ((speed - self.speeds[0]) / step).clamp(0.0, (n - 1) as f64);
        let i = (t.floor() as usize).min(n - 2);
        self.backgrounds[i].mix(&self.backgrounds[i + 1], t - i as f64)
    }
}

fn radar_sea_of<'a>(
    config: &WakelabConfig,
    spectrum: &'a SeaSpectrum,
    short_waves: &'a ShortWaves,
    dx: f64,
    band: RadarBand,
) -> RadarSea<'a> {
    RadarSea::new(
        spectrum,
        short_waves,
        band.wavenumber(),
        surface_permittivity(config, band),
        config.sar.polarisation,
        config.platform.look_direction.to_radians(),
        config.platform.incidence.to_radians(),
        dx,
    )
}

/// Render one band's SAR image of `scene` (for several bands, [`SarScene`] shares their work).
pub fn render_sar(config: &WakelabConfig, scene: &SurfaceScene, band: RadarBand) -> SarImage {
    SarScene::new(config, scene).render(band)
}

/// The field of `band` in a per-band list.
fn band_field(fields: &[(RadarBand, Array2<f64>)], band: RadarBand) -> Option<&Array2<f64>> {
    fields.iter().find(|(b, _)| *b == band).map(|(_, f)| f)
}

/// A scene as the SAR sees it in every band: the bands share the long waves' line-of-sight
/// velocity for velocity bunching.
pub type SarScene<'a> = crate::SensorScene<'a, Array2<f64>>;

impl SarScene<'_> {
    /// One band's image.
    pub fn render(&self, band: RadarBand) -> SarImage {
        let (config, scene) = (self.config, self.scene);
        let radar = radar_sea(config, scene, band);
        let theta = config.platform.incidence.to_radians();
        let background = Background::of(&radar, theta);
        let Sigma0Parts {
            bragg,
            specular,
            breaking,
            fraction: q,
        } = background.at;
        let waves = scene
            .bragg
            .iter()
            .find(|b| b.band == band)
            .expect("the surface stage covers every band");
        // the horizontal look direction in the image (east, north)
        let (look_e, look_n) = scene.grid.scene_frame(radar.look.cos(), radar.look.sin());
        let surface = &scene.surface;
        let psi_of = |sx: f64, sy: f64| {
            // slope rising towards the radar: minus the gradient along the look direction
            (-(sx * look_e + sy * look_n)).atan()
        };
        // the Kelvin waves' currents strain the Bragg waves too: N/N0 = m (1 + delta)
        // and their own short waves add the narrow-V: N/N0 = m (1 + delta + nu)
        let kelvin_change = scene
            .kelvin
            .as_ref()
            .and_then(|k| band_field(&k.bragg_change, band).zip(band_field(&k.narrow_v, band)));
        let modulation = match kelvin_change {
            Some((delta, nu)) => std::borrow::Cow::Owned(
                ndarray::Zip::from(&waves.modulation)
                    .and(delta)
                    .and(nu)
                    .par_map_collect(|&m, &d, &v| m * (1.0 + d + v).max(0.0)),
            ),
            None => std::borrow::Cow::Borrowed(&waves.modulation),
        };
        let mut sigma0 = Array2::zeros(waves.modulation.raw_dim());
        match &scene.wind_speed {
            None => ndarray::Zip::from(&mut sigma0)
                .and(modulation.as_ref())
                .and(&waves.breaking)
                .and(&surface.slope_x)
                .and(&surface.slope_y)
                .par_for_each(|out, &m, &mb, &sx, &sy| *out = background.sigma0(m, mb, psi_of(sx, sy))),
            Some(winds) => {
                let table = WindTable::new(config, scene, band, winds);
                ndarray::Zip::from(&mut sigma0)
                    .and(modulation.as_ref())
                    .and(&waves.breaking)
                    .and(&surface.slope_x)
                    .and(&surface.slope_y)
                    .and(winds)
                    .par_for_each(|out, &m, &mb, &sx, &sy, &w| *out = table.at(w).sigma0(m, mb, psi_of(sx, sy)))
            }
        }
        let sar = &config.sar;
        // the hull hides the sea under it and returns its own cross section
        let hull = scene.kelvin.as_ref().and_then(|k| k.hull_cover.as_ref());
        let ship = hull.map(|cover| {
            sigma0.zip_mut_with(cover, |s, &c| *s *= 1.0 - c);
            let ship = ThinShip::new(&config.ship, config.kelvin.hull, config.environment.gravity);
            let area = scene.grid.pixel_spacing.powi(2);
            let per_cover = ship_cross_section(config, &ship, band) / (ship.waterplane_area().max(area));
            cover.mapv(|c| c * per_cover)
        });
        if sar.velocity_bunching {
            let v = self.shared.get_or_init(|| line_of_sight_velocity(config, scene));
            sigma0 = velocity_bunching(config, &scene.grid, v, &sigma0);
        }
        if let Some(mut ship) = ship {
            if sar.velocity_bunching {
                // the ship's own motion along the line of sight moves it off its wake in azimuth
                let (st, _) = config.platform.incidence.to_radians().sin_cos();
                let v = config.ship.speed * config.platform.look_direction.to_radians().cos() * st;
                ship = velocity_bunching(config, &scene.grid, &Array2::from_elem(ship.raw_dim(), v), &ship);
            }
            sigma0 += &ship;
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
}

/// Radar cross section (m^2) of the ship in `band`: `kelvin.ship_rcs`, or
/// [`skolnik_cross_section`] of its displacement.
pub fn ship_cross_section(config: &WakelabConfig, ship: &ThinShip, band: RadarBand) -> f64 {
    config.kelvin.ship_rcs.unwrap_or_else(|| {
        let kilotonnes = ship.displacement_volume() * config.environment.reference_density / 1e6;
        skolnik_cross_section(band, kilotonnes)
    })
}

/// Skolnik's (1980) empirical radar cross section (m^2) of a ship of `kilotonnes`
/// displacement in `band`: sigma = 52 f^(1/2) D^(3/2) for f in MHz and D in kilotonnes.
pub fn skolnik_cross_section(band: RadarBand, kilotonnes: f64) -> f64 {
    52.0 * (band.frequency() / 1e6).sqrt() * kilotonnes.powf(1.5)
}

/// The long waves' line-of-sight velocity (m/s, away from the radar) on the scene, from its
/// elevation by linear wave theory (see [`crate::spectral::line_of_sight_velocity`]); the Kelvin
/// waves, which run with the ship and not with the wind, with their own velocity.
fn line_of_sight_velocity(config: &WakelabConfig, scene: &SurfaceScene) -> Array2<f64> {
    let sea = match &scene.kelvin {
        Some(k) => std::borrow::Cow::Owned(&scene.surface.elevation - &k.elevation),
        None => std::borrow::Cow::Borrowed(&scene.surface.elevation),
    };
    let mut v = crate::spectral::line_of_sight_velocity(
        sea.as_ref(),
        &scene.grid,
        config.platform.incidence.to_radians(),
        config.platform.look_direction.to_radians(),
        config.environment.wind.direction.to_radians(),
        |k| angular_frequency(k, scene.spectrum.gravity, scene.spectrum.tension),
    );
    if let Some(k) = &scene.kelvin {
        v += &k.line_of_sight_velocity;
    }
    v
}

/// Velocity bunching (Alpers & Rufenach 1979): each scatterer appears shifted in azimuth by
/// -(R/V) v_r, v_r its line-of-sight velocity `v` away from the radar: a scatterer approaching
/// the radar adds Doppler, which the processor places where the platform had passed it, ahead
/// in the flight direction (Raney 1971); one receding, behind. The intensity is moved with
/// bilinear weights across the scene's periodic edges (its sea is synthesised by FFT), so the
/// image's total is conserved.
pub fn velocity_bunching(
    config: &WakelabConfig,
    grid: &SceneGrid,
    v: &Array2<f64>,
    sigma0: &Array2<f64>,
) -> Array2<f64> {
    let n = sigma0.nrows();
    let dx = grid.pixel_spacing;
    let look = config.platform.look_direction.to_radians();
    // azimuth (flight) direction: the look direction turned by +90 degrees, in the image
    let azimuth = look + std::f64::consts::FRAC_PI_2;
    let (az_e, az_n) = grid.scene_frame(azimuth.cos(), azimuth.sin());
    let rv = config.sar.range_to_velocity;
    // where each source pixel lands: column and row, fractional
    let target = |r: usize, c: usize| {
        let shift = -rv * v[[r, c]];
        (r as f64 - az_n * shift / dx, c as f64 + az_e * shift / dx)
    };
    // how many rows any pixel moves at most: a band of output rows gathers from its own rows
    // and that many beyond each edge (the result does not depend on the bands' height)
    let reach = v.iter().fold(0.0f64, |m, &x| m.max((az_n * rv * x / dx).abs())).ceil() as usize + 1;
    // bands several reaches high, so that few rows are visited twice, and enough of them to share
    let band_rows = (4 * reach).max(n / 16).max(1);
    let mut out = Array2::zeros((n, n));
    // output rows in bands, in parallel; each pixel receives its sources in row-major order, as
    // a serial scatter would, so the bytes do not depend on the threads
    out.axis_chunks_iter_mut(ndarray::Axis(0), band_rows)
        .into_par_iter()
        .enumerate()
        .for_each(|(band, mut rows)| {
            let first = band * band_rows;
            let last = first + rows.nrows();
            // the scene is periodic (its random sea is synthesised by FFT): what leaves one edge
            // enters the other, so the scene's mean is kept; source row k stands for row k mod n
            let (first_k, last_k) = (first as i64 - reach as i64, (last + reach) as i64);
            for k in first_k..last_k {
                let r = k.rem_euclid(n as i64) as usize;
                for c in 0..n {
                    let (row, col) = target(r, c);
                    let row = row + (k - r as i64) as f64;
                    let (r0, c0) = (row.floor(), col.floor());
                    let (fr, fc) = (row - r0, col - c0);
                    for (dr, wr) in [(0.0, 1.0 - fr), (1.0, fr)] {
                        let rr = r0 + dr;
                        // (written so that a NaN shift lands nowhere)
                        if !(rr >= first as f64 && rr < last as f64) {
                            continue;
                        }
                        for (dc, wc) in [(0.0, 1.0 - fc), (1.0, fc)] {
                            let cc = (c0 + dc).rem_euclid(n as f64);
                            if cc.is_finite() {
                                rows[[rr as usize - first, cc as usize]] += sigma0[[r, c]] * wr * wc;
                            }
                        }
                    }
                }
            }
        });
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Halfway between the table's nodes (the worst place for linear interpolation), the
    /// background NRCS is within 1 % of its exact value at that wind, in every band.
    #[test]
    fn wind_table_interpolates_within_one_percent() {
        let config = WakelabConfig::from_toml_str(
            "[scene]\nsize = 64\nalong_track = 2000.0\n[sea]\nwindow = 32\n[environment.wind]\nvariability = 0.3\n",
            "test",
        )
        .unwrap();
        let scene = wakelab_surface::simulate_surface(&config, None);
        let winds = scene.wind_speed.clone().unwrap();
        let env = &config.environment;
        for band in RadarBand::ALL {
            let table = WindTable::new(&config, &scene, band, &winds);
            for pair in table.speeds.windows(2) {
                let speed = 0.5 * (pair[0] + pair[1]);
                let spectrum = SeaSpectrum::new(&config.sea, speed, env.wind.direction, &env.swell, env.gravity);
                let short_waves = ShortWaves::new(&spectrum);
                let radar = radar_sea_of(&config, &spectrum, &short_waves, scene.grid.pixel_spacing, band);
                let exact = Background::of(&radar, config.platform.incidence.to_radians()).sigma0(1.0, 1.0, 0.0);
                let interpolated = table.at(speed).sigma0(1.0, 1.0, 0.0);
                let error = (interpolated / exact - 1.0).abs();
                assert!(error < 0.01, "{band:?} at {speed:.2} m/s: {error:.4}");
            }
        }
    }
}

//! wakelab-surface: stage 2 of the pipeline (spec 2.2-2.3). From the hydro stage's surface map it
//! computes the surfactant concentration (Eq. (2.66)), the wake's modulation of the short (Bragg)
//! waves through the wave action balance (Eqs. (2.67)-(2.69)), the background spectrum
//! (Eqs. (2.70)-(2.71) or Elfouhaily et al. 1997) and a random sea surface (Eqs. (2.72)-(2.76)), all on
//! the scene the sensors image.
//!
//! [`simulate_surface`] is the stage's function: config and (optional) wake in, [`SurfaceScene`]
//! out. Without a wake it returns the undisturbed sea of the same environment and seed.

pub mod action;
pub mod bragg_scale;
pub mod constants;
pub mod film;
pub mod fourier;
pub mod kelvin;
pub mod kelvin_scene;
pub mod narrow_v;
pub mod natural;
pub mod output;
pub mod scene;
pub mod short_waves;
pub mod spectrum;
pub mod spectrum_report;
pub mod surfactant;
pub mod synthesis;

use action::{extra_damping, relax_short_waves, Relaxation, WaveVector};
use film::Film;
use film::WakeDamping;
use kelvin::ThinShip;
use kelvin_scene::{kelvin_scene, BraggWaves, KelvinScene, RadarView};
use ndarray::Array2;
use rayon::prelude::*;
use scene::{resample, MapField, SceneGrid};
use short_waves::ShortWaves;
use spectrum::SeaSpectrum;
use surfactant::{redistribute_surfactant, SurfactantField};
use synthesis::{synthesise_surface, RandomSurface};
use wakelab_core::units::RadarBand;
use wakelab_core::WakelabConfig;
use wakelab_hydro::SurfaceMap;

/// The wake's modulation of one band's Bragg waves on the scene.
#[derive(Debug, Clone)]
pub struct BraggModulation {
    pub band: RadarBand,
    /// Bragg wavenumber 2 k_0 sin(theta) (rad/m).
    pub wavenumber: f64,
    /// Background 2D spectral density at +k_B and -k_B (towards and away from the sensor), m^4.
    pub density: (f64, f64),
    /// N / N_0 of the Bragg spectral density F(k_B) + F(-k_B), on the scene (rows, cols).
    pub modulation: Array2<f64>,
    /// N / N_0 of the breaking waves this band sees (k0 / 10, running with the wind): the
    /// modulation of their surface fraction q.
    pub breaking: Array2<f64>,
}

/// Everything the sensors need about the sea surface of one scene.
#[derive(Debug, Clone)]
pub struct SurfaceScene {
    pub grid: SceneGrid,
    /// Surfactant concentration Gamma relative to the ambient film (the wake's redistribution).
    pub surfactant: Array2<f64>,
    pub bragg: Vec<BraggModulation>,
    /// Long-wave surface (elevation and slopes) at the scene's pixels.
    pub surface: RandomSurface,
    /// Sea-surface temperature perturbation dT (K) from the hydro stage.
    pub temperature_anomaly: Array2<f64>,
    pub spectrum: SeaSpectrum,
    /// The Bragg-scale waves' balance (KHCC03) of the same wind.
    pub short_waves: ShortWaves,
    /// The local 10-m wind speed (m/s) where the wind varies over the scene; None if uniform.
    pub wind_speed: Option<Array2<f64>>,
    /// 1 where a natural slick covers the sea; None without slicks.
    pub slick_mask: Option<Array2<u8>>,
    /// The ship's Kelvin waves and hull, in a wake scene with `kelvin.enabled`; their elevation
    /// and slopes are in `surface` too.
    pub kelvin: Option<KelvinScene>,
}

/// The background spectrum of a configuration.
pub fn background_spectrum(config: &WakelabConfig) -> SeaSpectrum {
    let env = &config.environment;
    SeaSpectrum::new(&config.sea, env.wind.speed, env.wind.direction, &env.swell, env.gravity)
}

/// Bragg wave vectors (towards and away from the sensor) of a band, heading frame.
pub fn bragg_vectors(config: &WakelabConfig, band: RadarBand) -> (WaveVector, WaveVector) {
    let kb = band.bragg_wavenumber(config.platform.incidence);
    let phi = config.platform.look_direction.to_radians();
    // the resonant waves run along the look direction, towards (+) and away from the sensor
    let towards = WaveVector {
        kx: -kb * phi.cos(),
        ky: -kb * phi.sin(),
    };
    let away = WaveVector {
        kx: -towards.kx,
        ky: -towards.ky,
    };
    (towards, away)
}

/// A map field on the scene, resampled with its ambient value, once per wake (`wakes`: the
/// scene's grid as each wake's ship sees it) and combined as independent modulations: a ratio
/// field (ambient 1: N/N0, Gamma) as the product of the wakes' ratios, an anomaly (ambient 0: dT)
/// as their sum. Exact where the wakes do not overlap; where they cross, a first-order guess.
fn to_scene(wakes: &[SceneGrid], map: &SurfaceMap, values: &[f64], ambient: f64) -> Array2<f64> {
    let field = MapField {
        x: &map.x,
        y: &map.y,
        values,
    };
    let mut each = wakes.iter().map(|grid| resample(grid, &field, ambient));
    let first = each.next().expect("the scene's own wake");
    each.fold(first, |total, next| {
        if ambient == 0.0 {
            total + next
        } else {
            total * next / ambient
        }
    })
}

/// N/N0 of one wave vector on the scene: the wake's, and where a slick lies its film's damping
/// d_s on top, 1/r = 1/r_wake + d_s / mu (the steady state of the relaxation equation with both
/// dampings, exact where the wake's waves are in equilibrium). A slick thinner than the open
/// sea's film (d_s < 0) is bounded as the wake's converging currents are: r <= 1 / SATURATION.
fn with_slicks(wake: Array2<f64>, slick_damping: Option<&Array2<f64>>, mu: f64) -> Array2<f64> {
    match slick_damping {
        None => wake,
        Some(d) => {
            let mut r = wake;
            ndarray::Zip::from(&mut r).and(d).for_each(|r, &d| {
                if d != 0.0 {
                    *r = 1.0 / (1.0 / *r + d / mu).max(action::SATURATION);
                }
            });
            r
        }
    }
}

/// Stage 2: the sea surface of the configured scene, with the wake of `map` or without a wake;
/// natural slicks and the wind's variation (see [`natural`]) in both.
pub fn simulate_surface(config: &WakelabConfig, map: Option<&SurfaceMap>) -> SurfaceScene {
    let grid = SceneGrid::new(&config.scene);
    // the scene as each wake's ship sees it: its own placement first, then the others'
    let wakes: Vec<SceneGrid> = config
        .scene
        .wake_placements()
        .iter()
        .map(|w| SceneGrid::new(&config.scene.with_wake_at(w)))
        .collect();
    let n = grid.size();
    let spectrum = background_spectrum(config);
    let short_waves = ShortWaves::new(&spectrum);
    let wake_damping = wake_damping(config, &spectrum);
    let speed = config.ship.speed;
    let wind = &config.environment.wind;
    // the sea, the natural fields and the Kelvin waves are independent: made side by side
    let ((mut surface, kelvin), (slicks, wind_speed)) = rayon::join(
        || {
            rayon::join(
                || {
                    synthesise_surface(
                        &spectrum,
                        n,
                        grid.pixel_spacing,
                        grid.heading,
                        config.sea.window,
                        config.seed,
                    )
                },
                || {
                    (map.is_some() && config.kelvin.enabled)
                        .then(|| kelvin_on_scene(config, &grid, &spectrum, &short_waves))
                },
            )
        },
        || {
            rayon::join(
                || {
                    natural::natural_slicks(
                        &grid,
                        &config.slicks,
                        config.sea.film_elasticity,
                        wind.direction,
                        config.seed,
                    )
                },
                || natural::local_wind(&grid, wind, config.seed),
            )
        },
    );
    // the slicks' film damping over the open sea's (Eq. (2.69)) at a wavenumber, on the scene
    let slick_damping = |k: f64| {
        slicks.as_ref().map(|s| {
            let film_of = |e: f64| {
                let f = Film {
                    reference_elasticity: e,
                };
                film::film_damping(
                    k,
                    f.elasticity(1.0),
                    f.pressure(1.0),
                    spectrum.tension,
                    spectrum.gravity,
                )
            };
            let open_sea = film_of(config.sea.film_elasticity);
            ndarray::Zip::from(&s.elasticity).par_map_collect(|&e| {
                if e == config.sea.film_elasticity {
                    0.0
                } else {
                    film_of(e) - open_sea
                }
            })
        })
    };
    let farthest = wakes.iter().map(SceneGrid::farthest_astern).fold(f64::MIN, f64::max);
    let map = map.map(|m| crop_rows(m, farthest + grid.pixel_spacing));
    let gamma: Option<SurfactantField> = map.as_ref().map(|m| redistribute_surfactant(m, speed));
    let ones = || Array2::from_elem((n, n), 1.0);
    let bragg = RadarBand::ALL
        .par_iter()
        .map(|&band| {
            let (towards, away) = bragg_vectors(config, band);
            let breakers = breaking_vector(&spectrum, band);
            let relax = |k: WaveVector| Relaxation::new(k, &spectrum, &short_waves);
            let (rel_t, rel_a, rel_b) = (relax(towards), relax(away), relax(breakers));
            // the wake's extra damping at the Bragg and the breakers' wavenumbers (both Bragg
            // vectors share one), then N/N0 of each wave vector on the scene
            let damping = |k: f64| match (&map, &gamma) {
                (Some(map), Some(gamma)) => Some((map, extra_damping(map, gamma, k, &spectrum, &wake_damping))),
                _ => None,
            };
            let (at_bragg, at_breaking) =
                rayon::join(|| damping(towards.magnitude()), || damping(breakers.magnitude()));
            let wake = |rel: &Relaxation, damping: &Option<(&SurfaceMap, Vec<f64>)>| match damping {
                Some((map, d)) => to_scene(&wakes, map, &relax_short_waves(map, d, rel, speed), 1.0)
                    .mapv_into(|r| r.min(1.0 / action::SATURATION)),
                None => ones(),
            };
            let ((r_t, r_a), r_b) = rayon::join(
                || rayon::join(|| wake(&rel_t, &at_bragg), || wake(&rel_a, &at_bragg)),
                || wake(&rel_b, &at_breaking),
            );
            let (d_bragg, d_breaking) = rayon::join(
                || slick_damping(towards.magnitude()),
                || slick_damping(breakers.magnitude()),
            );
            let r_t = with_slicks(r_t, d_bragg.as_ref(), rel_t.rate);
            let r_a = with_slicks(r_a, d_bragg.as_ref(), rel_a.rate);
            let (f_t, f_a) = (
                spectrum.bragg_density(towards.kx, towards.ky),
                spectrum.bragg_density(away.kx, away.ky),
            );
            let mut modulation = r_t;
            ndarray::Zip::from(&mut modulation)
                .and(&r_a)
                .for_each(|t, &a| *t = (f_t * *t + f_a * a) / (f_t + f_a));
            BraggModulation {
                band,
                wavenumber: towards.magnitude(),
                density: (f_t, f_a),
                modulation,
                breaking: with_slicks(r_b, d_breaking.as_ref(), rel_b.rate),
            }
        })
        .collect();
    let (surfactant, temperature_anomaly) = match (&map, &gamma) {
        (Some(map), Some(gamma)) => {
            let dt: Vec<f64> = map
                .field(wakelab_hydro::SliceField::DT)
                .iter()
                .map(|&v| v as f64)
                .collect();
            (
                to_scene(&wakes, map, &gamma.gamma, 1.0),
                to_scene(&wakes, map, &dt, 0.0),
            )
        }
        _ => (ones(), Array2::zeros((n, n))),
    };
    if let Some(k) = &kelvin {
        surface.elevation += &k.elevation;
        surface.slope_x += &k.slope_x;
        surface.slope_y += &k.slope_y;
    }
    SurfaceScene {
        grid,
        surfactant,
        bragg,
        surface,
        temperature_anomaly,
        short_waves,
        spectrum,
        wind_speed,
        slick_mask: slicks.map(|s| s.mask),
        kelvin,
    }
}

/// The Kelvin waves and hull of the configured ship on the scene, with every band's Bragg waves.
pub fn kelvin_on_scene(
    config: &WakelabConfig,
    grid: &SceneGrid,
    spectrum: &SeaSpectrum,
    short_waves: &ShortWaves,
) -> KelvinScene {
    let ship = ThinShip::new(&config.ship, config.kelvin.hull, config.environment.gravity);
    let bands: Vec<BraggWaves> = RadarBand::ALL
        .iter()
        .map(|&band| {
            let (towards, away) = bragg_vectors(config, band);
            BraggWaves {
                band,
                towards: Relaxation::new(towards, spectrum, short_waves),
                away: Relaxation::new(away, spectrum, short_waves),
                density: (
                    spectrum.bragg_density(towards.kx, towards.ky),
                    spectrum.bragg_density(away.kx, away.ky),
                ),
                // the waves the two-scale model tilts by: longer than its cut, k_B / 4
                spread: {
                    let kb = towards.magnitude();
                    let (along, across) = spectrum.slope_variances(towards.ky.atan2(towards.kx), 1e-3, 0.25 * kb);
                    kb * (along + across).sqrt()
                },
            }
        })
        .collect();
    let view = RadarView {
        incidence: config.platform.incidence.to_radians(),
        look: config.platform.look_direction.to_radians(),
    };
    kelvin_scene(ship, grid, view, &bands, config.environment.kinematic_viscosity)
}

/// The wave vector of the breakers a band sees: k0 / 10 along the wind.
fn breaking_vector(spectrum: &SeaSpectrum, band: RadarBand) -> WaveVector {
    let k = short_waves::breaking_wavenumber(band.wavenumber());
    WaveVector {
        kx: k * spectrum.wind_direction.cos(),
        ky: k * spectrum.wind_direction.sin(),
    }
}

/// The wake's extra damping over the sea of `config`: its film, and its turbulence over the
/// wind-driven surface layer at the depth of the hydro grid's top cell (where the map's eps is).
pub fn wake_damping(config: &WakelabConfig, spectrum: &SeaSpectrum) -> WakeDamping {
    let depth = 0.5 * wakelab_core::grid::CrossGrid::new(&config.grid).dz;
    WakeDamping {
        film: Film {
            reference_elasticity: config.sea.film_elasticity,
        },
        ambient_dissipation: film::surface_layer_dissipation(spectrum.friction_velocity(), depth),
        model_ambient_dissipation: config.environment.ambient_dissipation,
    }
}

/// The rows of `map` up to distance `x_end` behind the stern (the march needs nothing beyond).
fn crop_rows(map: &SurfaceMap, x_end: f64) -> SurfaceMap {
    let rows = (map.x.iter().take_while(|&&x| x <= x_end).count() + 1).clamp(2, map.x.len());
    let cols = map.y.len();
    SurfaceMap {
        x: map.x[..rows].to_vec(),
        y: map.y.clone(),
        fields: map.fields.iter().map(|f| f[..rows * cols].to_vec()).collect(),
    }
}

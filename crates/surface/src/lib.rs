//! wakelab-surface: stage 2 of the pipeline (spec 2.2-2.3). From the hydro stage's surface map it
//! computes the surfactant concentration (Eq. (2.66)), the wake's modulation of the short (Bragg)
//! waves through the wave action balance (Eqs. (2.67)-(2.69)), the background spectrum
//! (Eqs. (2.70)-(2.71) or Elfouhaily et al. 1997) and a random sea surface (Eqs. (2.72)-(2.76)), all on
//! the scene the sensors image.
//!
//! [`simulate_surface`] is the stage's function: config and (optional) wake in, [`SurfaceScene`]
//! out. Without a wake it returns the undisturbed sea of the same environment and seed.

pub mod action;
pub mod film;
pub mod fourier;
pub mod output;
pub mod scene;
pub mod short_waves;
pub mod spectrum;
pub mod spectrum_report;
pub mod surfactant;
pub mod synthesis;

use action::{modulate_short_waves, Relaxation, WaveVector};
use film::Film;
use film::WakeDamping;
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
    /// Surfactant concentration Gamma relative to the ambient film.
    pub surfactant: Array2<f64>,
    pub bragg: Vec<BraggModulation>,
    /// Long-wave surface (elevation and slopes) at the scene's pixels.
    pub surface: RandomSurface,
    /// Sea-surface temperature perturbation dT (K) from the hydro stage.
    pub temperature_anomaly: Array2<f64>,
    pub spectrum: SeaSpectrum,
    /// The Bragg-scale waves' balance (KHCC03) of the same wind.
    pub short_waves: ShortWaves,
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

/// Map fields needed on the scene, resampled with their ambient values.
fn to_scene(grid: &SceneGrid, map: &SurfaceMap, values: &[f64], ambient: f64) -> Array2<f64> {
    resample(
        grid,
        &MapField {
            x: &map.x,
            y: &map.y,
            values,
        },
        ambient,
    )
}

/// Stage 2: the sea surface of the configured scene, with the wake of `map` or without a wake.
pub fn simulate_surface(config: &WakelabConfig, map: Option<&SurfaceMap>) -> SurfaceScene {
    let grid = SceneGrid::new(&config.scene);
    let n = grid.size();
    let spectrum = background_spectrum(config);
    let short_waves = ShortWaves::new(&spectrum);
    let wake_damping = wake_damping(config, &spectrum);
    let speed = config.ship.speed;
    let surface = synthesise_surface(&spectrum, n, grid.pixel_spacing, config.sea.window, config.seed);

    let (surfactant, bragg, temperature_anomaly) = match map {
        None => (
            Array2::from_elem((n, n), 1.0),
            RadarBand::ALL
                .iter()
                .map(|&band| undisturbed_band(config, band, &spectrum, n))
                .collect(),
            Array2::zeros((n, n)),
        ),
        Some(map) => {
            let map = crop_rows(map, grid.x[n - 1] + grid.pixel_spacing);
            let gamma: SurfactantField = redistribute_surfactant(&map, speed);
            let bragg = RadarBand::ALL
                .par_iter()
                .map(|&band| {
                    let (towards, away) = bragg_vectors(config, band);
                    let ratio = |k: WaveVector| {
                        let relax = Relaxation::new(k, &spectrum, &short_waves);
                        modulate_short_waves(&map, &gamma, &relax, &spectrum, &wake_damping, speed)
                    };
                    let (f_t, f_a) = (
                        spectrum.directional(towards.kx, towards.ky),
                        spectrum.directional(away.kx, away.ky),
                    );
                    let ((r_t, r_a), r_b) = rayon::join(
                        || rayon::join(|| ratio(towards), || ratio(away)),
                        || ratio(breaking_vector(&spectrum, band)),
                    );
                    let combined: Vec<f64> = r_t
                        .iter()
                        .zip(&r_a)
                        .map(|(a, b)| (f_t * a + f_a * b) / (f_t + f_a))
                        .collect();
                    BraggModulation {
                        band,
                        wavenumber: towards.magnitude(),
                        density: (f_t, f_a),
                        modulation: to_scene(&grid, &map, &combined, 1.0),
                        breaking: to_scene(&grid, &map, &r_b, 1.0),
                    }
                })
                .collect();
            let dt: Vec<f64> = map
                .field(wakelab_hydro::SliceField::DT)
                .iter()
                .map(|&v| v as f64)
                .collect();
            (
                to_scene(&grid, &map, &gamma.gamma, 1.0),
                bragg,
                to_scene(&grid, &map, &dt, 0.0),
            )
        }
    };
    SurfaceScene {
        grid,
        surfactant,
        bragg,
        surface,
        temperature_anomaly,
        short_waves,
        spectrum,
    }
}

fn undisturbed_band(config: &WakelabConfig, band: RadarBand, spectrum: &SeaSpectrum, n: usize) -> BraggModulation {
    let (towards, away) = bragg_vectors(config, band);
    BraggModulation {
        band,
        wavenumber: towards.magnitude(),
        density: (
            spectrum.directional(towards.kx, towards.ky),
            spectrum.directional(away.kx, away.ky),
        ),
        modulation: Array2::from_elem((n, n), 1.0),
        breaking: Array2::from_elem((n, n), 1.0),
    }
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

//! The environments step of `wakelab run`: the spec's environments (its Figs. 3.1-3.2): is the
//! persistent wake bright or dark in S, C and X band without swell, with head swell and with
//! following swell? And the open sea's C-band VV sigma0 of the study's base sea against CMOD5.N.
//! It writes `environments/environments.json`, which the report renders beside the spec's
//! figures.
//!
//! A wake brightens the Bragg waves only where its converging currents refract energy into them
//! faster than its film and excess turbulence damp them: in the relaxation form of the action
//! balance ([`wakelab_surface::action`]) the steady state mu / (mu + d - R) exceeds 1 only where
//! the refraction source R exceeds the extra damping d. So beside each contrast the table gives
//! the largest R across the wake at its age, and d and the relaxation rate mu where R is largest.

use super::context::{fnv_hex, step_time, write_results};
use crate::{Result, StepTime};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::time::Instant;
use wakelab_core::config::Polarisation;
use wakelab_core::config::{NamedDirection, SwellDirection};
use wakelab_core::units::RadarBand;
use wakelab_core::WakelabConfig;
use wakelab_core::WakelabError;
use wakelab_dataset::study::Study;
use wakelab_hydro::SurfaceMap;
use wakelab_sensors::sar_image::surface_permittivity;
use wakelab_sensors::sigma0_report::sigma0_of_sea;
use wakelab_surface::action::{current_gradient, extra_damping, Relaxation};
use wakelab_surface::short_waves::ShortWaves;
use wakelab_surface::surfactant::redistribute_surfactant;
use wakelab_surface::{background_spectrum, bragg_vectors, simulate_surface, wake_damping};

/// The spec's environments: Fig. 3.2's calm, head and following seas.
pub const ENVIRONMENTS: [NamedDirection; 3] = [NamedDirection::Calm, NamedDirection::Head, NamedDirection::Following];
/// The wake's age as distance behind the stern (m), at most; the scene's side (pixels) and
/// pixel spacing (m): enough to hold the wake and the open sea beside it.
const ALONG_TRACK: f64 = 4000.0;
const SIDE: usize = 128;
const SPACING: f64 = 10.0;
/// A wake is called bright or dark where its brightest or darkest row departs by more than this
/// (dB); nearer than that it is "none".
pub const VISIBLE_DB: f64 = 0.5;

/// One band's wake in one environment.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EnvironmentContrast {
    pub environment: NamedDirection,
    pub band: RadarBand,
    /// The darkest and the brightest row across the wake, wake scene over no-wake scene (dB).
    pub darkest_db: f64,
    pub brightest_db: f64,
    /// The largest refraction source R across the wake at its age (1/s), and the extra damping
    /// d and relaxation rate mu of the Bragg waves where it is largest.
    pub refraction: f64,
    pub damping: f64,
    pub relaxation: f64,
}

impl EnvironmentContrast {
    /// "bright", "dark" or "none": whichever extreme departs more, if by over [`VISIBLE_DB`].
    pub fn verdict(&self) -> &'static str {
        if self.brightest_db.max(-self.darkest_db) <= VISIBLE_DB {
            "none"
        } else if self.brightest_db > -self.darkest_db {
            "bright"
        } else {
            "dark"
        }
    }
}

/// The configuration of one environment: `base`'s sea, wind, ship and sensors with the swell
/// of `environment` (the base's amplitude and wavelength; the default's 1 m and 100 m where the
/// base has none), a perfect SAR (no speckle, noise or bunching: the table compares means), no
/// natural slicks, and a [`SIDE`]-pixel scene of [`SPACING`] m centred [`ALONG_TRACK`] m (or
/// halfway along a shorter wake) behind the stern, the ship running to the left.
pub fn environment_config(base: &WakelabConfig, environment: NamedDirection) -> WakelabConfig {
    let mut c = base.clone();
    if c.environment.swell.amplitude <= 0.0 {
        let default = WakelabConfig::default().environment.swell;
        c.environment.swell.amplitude = default.amplitude;
        c.environment.swell.wavelength = default.wavelength;
    }
    c.environment.swell.direction = SwellDirection::Named(environment);
    c.sar.looks = 0;
    c.sar.noise_floor = false;
    c.sar.velocity_bunching = false;
    c.slicks.coverage = 0.0;
    let halfway = 0.5 * c.wake_end();
    c.scene.size = SIDE;
    c.scene.pixel_spacing = SPACING;
    c.scene.along_track = ALONG_TRACK.min(halfway);
    c.scene.cross_track = 0.0;
    c.scene.heading = 270.0;
    c.scene.other_wakes.clear();
    c
}

/// The wake of every radar band in every environment of [`ENVIRONMENTS`]; the hydro maps come
/// from (and go to) the dataset's cache in `cache_dir`.
pub fn spec_environments(base: &WakelabConfig, cache_dir: &std::path::Path) -> Result<Vec<EnvironmentContrast>> {
    let mut out = Vec::new();
    for environment in ENVIRONMENTS {
        let c = environment_config(base, environment);
        c.validate()?;
        let map = wakelab_dataset::hydro_map(cache_dir, &c)?;
        let (with, without) = rayon::join(|| simulate_surface(&c, Some(&map)), || simulate_surface(&c, None));
        for band in RadarBand::ALL {
            let (darkest_db, brightest_db) = row_extremes(
                &wakelab_sensors::render_sar(&c, &with, band).sigma0,
                &wakelab_sensors::render_sar(&c, &without, band).sigma0,
            );
            let (refraction, damping, relaxation) = refraction_against_damping(&c, &map, band);
            out.push(EnvironmentContrast {
                environment,
                band,
                darkest_db,
                brightest_db,
                refraction,
                damping,
                relaxation,
            });
        }
    }
    Ok(out)
}

/// The darkest and brightest row (the ship runs along the rows) of `with` over `without`, each
/// row's mean along the wake (dB).
fn row_extremes(with: &ndarray::Array2<f64>, without: &ndarray::Array2<f64>) -> (f64, f64) {
    with.rows()
        .into_iter()
        .zip(without.rows())
        .map(|(a, b)| 10.0 * (a.sum() / b.sum()).log10())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)))
}

/// On the surface map's row nearest the scene centre's age: the largest refraction source R of
/// `band`'s Bragg waves (towards the radar) across the wake, with the extra damping d and the
/// relaxation rate mu there (all 1/s).
fn refraction_against_damping(c: &WakelabConfig, map: &SurfaceMap, band: RadarBand) -> (f64, f64, f64) {
    let spectrum = background_spectrum(c);
    let short_waves = ShortWaves::new(&spectrum);
    let (towards, _) = bragg_vectors(c, band);
    let relaxation = Relaxation::new(towards, &spectrum, &short_waves);
    let gamma = redistribute_surfactant(map, c.ship.speed);
    let damping = extra_damping(map, &gamma, towards.magnitude(), &spectrum, &wake_damping(c, &spectrum));
    let cols = map.y.len();
    let row = map
        .x
        .iter()
        .position(|&x| x >= c.scene.along_track)
        .unwrap_or(map.x.len() - 1)
        .max(1);
    // the same gradients the action balance's march uses on that row
    let (mut largest, mut there) = (f64::NEG_INFINITY, 0);
    for j in 0..cols {
        let r = relaxation.refraction(current_gradient(map, row, j));
        if r > largest {
            (largest, there) = (r, j);
        }
    }
    (largest, damping[row * cols + there], relaxation.rate)
}

/// The open sea's C-band VV sigma0 at one wind and look, wakelab's and CMOD5.N's (dB), over
/// incidence (degrees).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sigma0Curve {
    /// "up-wind" or "cross-wind".
    pub look: String,
    pub wind: f64,
    pub incidence: Vec<f64>,
    pub wakelab_db: Vec<f64>,
    /// None where CMOD5.N has no value.
    pub cmod5n_db: Vec<Option<f64>>,
}

/// Looking up-wind and cross-wind: wakelab's C-band VV sigma0 and CMOD5.N's over incidence
/// 20-50 degrees for winds of 5, 10 and 15 m/s, for the sea of `base` without swell, in
/// CMOD5.N's 25 km cell ([`wakelab_sensors::gmf::CELL_SIZE`]: every wave tilts).
pub fn sigma0_against_cmod5n(base: &WakelabConfig) -> Vec<Sigma0Curve> {
    let eps = surface_permittivity(base, RadarBand::C);
    let mut sea = base.clone();
    sea.environment.swell.amplitude = 0.0;
    let mut curves = Vec::new();
    for (look_name, look) in [
        ("up-wind", std::f64::consts::PI),
        ("cross-wind", std::f64::consts::FRAC_PI_2),
    ] {
        for wind in [5.0, 10.0, 15.0] {
            sea.environment.wind.speed = wind;
            sea.environment.wind.direction = 0.0;
            let spectrum = background_spectrum(&sea);
            let reports: Vec<_> = (0..=12)
                .map(|i| {
                    let inc = 20.0 + 2.5 * i as f64;
                    let cell = wakelab_sensors::gmf::CELL_SIZE;
                    sigma0_of_sea(&spectrum, RadarBand::C, eps, Polarisation::Vv, look, inc, cell)
                })
                .collect();
            curves.push(Sigma0Curve {
                look: look_name.into(),
                wind,
                incidence: reports.iter().map(|r| r.incidence_deg).collect(),
                wakelab_db: reports.iter().map(|r| r.sigma0_db).collect(),
                cmod5n_db: reports.iter().map(|r| r.cmod5n_db).collect(),
            });
        }
    }
    curves
}

/// What the environments step wrote: its key, the seconds it took, the wake's age in the
/// environments (m behind the stern), the contrasts and the sigma0 curves.
#[derive(Serialize, Deserialize)]
pub struct Environments {
    key: String,
    seconds: f64,
    pub along_track: f64,
    pub contrasts: Vec<EnvironmentContrast>,
    pub sigma0: Vec<Sigma0Curve>,
}

/// `environments/environments.json` in a run directory.
fn environments_file(run_dir: &Path) -> std::path::PathBuf {
    run_dir.join("environments").join("environments.json")
}

/// The environments step: the spec's environments and the sigma0 curves of the study's base
/// configuration (reused when that configuration and wakelab's version are unchanged). The hydro
/// maps come from (and go to) the dataset's cache.
pub fn environments_step(run_dir: &Path, study: &Study) -> Result<StepTime> {
    let start = Instant::now();
    let base = study.base_config()?;
    let key = fnv_hex(&format!("{base:?} {}", env!("CARGO_PKG_VERSION")));
    let file = environments_file(run_dir);
    if let Ok(found) = load_environments(run_dir) {
        if found.key == key {
            return Ok(step_time("environments", start, Some(found.seconds)));
        }
    }
    let contrasts = spec_environments(&base, &run_dir.join("dataset"))?;
    let sigma0 = sigma0_against_cmod5n(&base);
    let environments = Environments {
        key,
        seconds: start.elapsed().as_secs_f64(),
        along_track: environment_config(&base, NamedDirection::Calm).scene.along_track,
        contrasts,
        sigma0,
    };
    write_results(&file, &environments)?;
    Ok(step_time("environments", start, None))
}

/// What the environments step wrote into `run_dir`.
pub fn load_environments(run_dir: &Path) -> Result<Environments> {
    let file = environments_file(run_dir);
    let text = std::fs::read_to_string(&file).map_err(|e| WakelabError::io(&file, e))?;
    serde_json::from_str(&text).map_err(|e| anyhow::anyhow!("{}: {e}", file.display()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use wakelab_hydro::SliceField;

    fn contrast(darkest_db: f64, brightest_db: f64) -> EnvironmentContrast {
        EnvironmentContrast {
            environment: NamedDirection::Head,
            band: RadarBand::C,
            darkest_db,
            brightest_db,
            refraction: 0.0,
            damping: 0.0,
            relaxation: 0.1,
        }
    }

    #[test]
    fn the_verdict_follows_the_larger_departure() {
        assert_eq!(contrast(-4.0, 0.1).verdict(), "dark");
        assert_eq!(contrast(-0.6, 1.5).verdict(), "bright");
        assert_eq!(contrast(-0.4, 0.3).verdict(), "none");
    }

    /// The table's refraction source against its closed form. On a uniformly converging current
    /// V = -a y over a Pierson-Moskowitz sea whose short waves follow the power law F ~ k^-c
    /// (Eq. (2.70)), with the wind 45 degrees off the Bragg waves (where the spreading does not
    /// change with k), N = rho omega F / k gives k d ln N / dk = d ln omega / d ln k - c - 1, so
    /// for Bragg waves across the track R = (k d ln N / dk) dV/dy = (c + 1 - d ln omega / d ln k) a,
    /// with d ln omega / d ln k = (g + 3 tau k^2 / rho) / (2 (g + tau k^2 / rho)).
    #[test]
    fn the_refraction_source_is_the_closed_form_on_a_converging_current() {
        let c = WakelabConfig::from_toml_str(
            "[sea]\nspectrum = \"pierson_moskowitz\"\n[environment.wind]\ndirection = 45.0\n\
             [environment.swell]\ndirection = \"calm\"\n",
            "test",
        )
        .unwrap();
        let a = 1e-3;
        let x: Vec<f64> = (0..=50).map(|i| 100.0 * i as f64).collect();
        let y: Vec<f64> = (-20..=20).map(|j| 10.0 * j as f64).collect();
        let cells = x.len() * y.len();
        let mut fields = vec![vec![0f32; cells]; SliceField::ALL.len()];
        for (i, v) in fields[SliceField::V as usize].iter_mut().enumerate() {
            *v = (-a * y[i % y.len()]) as f32;
        }
        fields[SliceField::Eps as usize] = vec![c.environment.ambient_dissipation as f32; cells];
        fields[SliceField::NuT as usize] = vec![1e-4; cells];
        let map = SurfaceMap { x, y, fields };
        let sea = background_spectrum(&c);
        let (g, tau) = (sea.gravity, sea.tension);
        for band in RadarBand::ALL {
            let (refraction, _, _) = refraction_against_damping(&c, &map, band);
            let k = bragg_vectors(&c, band).0.magnitude();
            let rho = wakelab_surface::constants::RHO_WATER;
            let dln_omega = (g + 3.0 * tau * k * k / rho) / (2.0 * (g + tau * k * k / rho));
            let closed = (c.sea.short_wave_exponent + 1.0 - dln_omega) * a;
            assert!(
                (refraction / closed - 1.0).abs() < 1e-3,
                "{band:?}: R {refraction} vs {closed}"
            );
        }
    }

    /// Each environment's configuration is valid for the default study's base and differs from
    /// it only in the swell's direction among the physics; a calm base sea still gets its swell.
    #[test]
    fn environment_configs_set_the_swell_and_a_perfect_sar() {
        let mut base = WakelabConfig::default();
        base.environment.swell.amplitude = 0.0;
        for environment in ENVIRONMENTS {
            let c = environment_config(&base, environment);
            c.validate().unwrap();
            assert_eq!(c.environment.swell.direction, SwellDirection::Named(environment));
            assert!(c.environment.swell.amplitude > 0.0);
            assert_eq!(c.environment.wind.speed, base.environment.wind.speed);
            assert_eq!((c.sar.looks, c.sar.noise_floor), (0, false));
            assert_eq!(c.scene.along_track, ALONG_TRACK);
        }
        assert!(environment_config(&base, NamedDirection::Calm)
            .environment
            .swell
            .angle()
            .is_none());
    }
}

//! The report's table of the spec's environments (its Figs. 3.1-3.2; issue 12): is the
//! persistent wake bright or dark in S, C and X band without swell, with head swell and with
//! following swell, beside what those figures show?
//!
//! A wake brightens the Bragg waves only where its converging currents refract energy into them
//! faster than its film and excess turbulence damp them: in the relaxation form of the action
//! balance ([`wakelab_surface::action`]) the steady state mu / (mu + d - R) exceeds 1 only where
//! the refraction source R exceeds the extra damping d. So beside each contrast the table gives
//! the largest R across the wake at its age, and d and the relaxation rate mu where R is largest.

use crate::report::Table;
use crate::Result;
use wakelab_core::config::{NamedDirection, SwellDirection};
use wakelab_core::units::RadarBand;
use wakelab_core::WakelabConfig;
use wakelab_hydro::SurfaceMap;
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
const VISIBLE_DB: f64 = 0.5;

/// One band's wake in one environment.
#[derive(Debug, Clone, PartialEq)]
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

/// What the spec's figures show for `band` in `environment` (Fig. 3.2 is C band only; Fig. 3.1,
/// the three bands, does not state its swell).
pub fn spec_figure(environment: NamedDirection, band: RadarBand) -> &'static str {
    match (band, environment) {
        (RadarBand::C, NamedDirection::Calm) => "Fig. 3.2: no noticeable persistent wake",
        (RadarBand::C, _) => "Fig. 3.2: wake visible; Fig. 3.1: bright streak",
        (RadarBand::S, _) => "Fig. 3.1 (swell not stated): bright, with a dark outline",
        (RadarBand::X, _) => "Fig. 3.1 (swell not stated): bright streak",
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

/// The report's table of [`spec_environments`].
pub fn environment_table(rows: &[EnvironmentContrast], along_track: f64) -> Table {
    Table {
        id: "spec_environments".into(),
        title: "The spec's environments: bright or dark".into(),
        caption: format!(
            "The study's base sea, wind, ship and sensors (a perfect SAR, no slicks) without swell, with head \
             swell and with following swell (the spec's Fig. 3.2), {along_track:.0} m behind the stern: the \
             darkest and brightest row across the wake, wake scene over no-wake scene. A wake brightens \
             where its converging currents' refraction source R beats its extra damping d (steady state \
             mu / (mu + d - R) > 1): R is the largest across the wake, d and the Bragg waves' relaxation \
             rate mu are where R is largest. \"none\": within {VISIBLE_DB} dB."
        ),
        header: [
            "environment",
            "band",
            "darkest (dB)",
            "brightest (dB)",
            "wakelab",
            "spec",
            "R (1/s)",
            "d (1/s)",
            "mu (1/s)",
        ]
        .map(String::from)
        .to_vec(),
        rows: rows
            .iter()
            .map(|r| {
                vec![
                    format!("{:?}", r.environment).to_lowercase(),
                    r.band.name().to_string(),
                    format!("{:+.2}", r.darkest_db),
                    format!("{:+.2}", r.brightest_db),
                    r.verdict().to_string(),
                    spec_figure(r.environment, r.band).to_string(),
                    format!("{:.1e}", r.refraction),
                    format!("{:.1e}", r.damping),
                    format!("{:.1e}", r.relaxation),
                ]
            })
            .collect(),
    }
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

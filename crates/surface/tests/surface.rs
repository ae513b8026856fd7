//! Checks of the surface stage against analytic equilibria, conservation laws and the input
//! spectrum.

use wakelab_core::WakelabConfig;
use wakelab_hydro::{SurfaceMap, SLICE_FIELDS};
use wakelab_surface::action::{modulate_short_waves, Relaxation, WaveVector};
use wakelab_surface::film::{Film, WakeDamping};
use wakelab_surface::short_waves::ShortWaves;
use wakelab_surface::surfactant::{redistribute_surfactant, row_fluxes, SurfactantField};
use wakelab_surface::synthesis::{resolved_variance, synthesise_surface};
use wakelab_surface::{background_spectrum, simulate_surface};

const AMBIENT_EPS: f64 = 1e-10;

/// A synthetic surface map: rows every `dx` from 71 m, columns every `dy` across +-`half`, fields
/// from `f(x, y) -> (U, V, nu_t, eps)`.
fn synthetic_map(rows: usize, dx: f64, half: f64, dy: f64, f: impl Fn(f64, f64) -> (f64, f64, f64, f64)) -> SurfaceMap {
    let x: Vec<f64> = (0..rows).map(|i| 71.0 + i as f64 * dx).collect();
    let cols = (2.0 * half / dy).round() as usize + 1;
    let y: Vec<f64> = (0..cols).map(|j| -half + j as f64 * dy).collect();
    let mut fields = vec![Vec::with_capacity(rows * cols); SLICE_FIELDS.len()];
    for &xi in &x {
        for &yj in &y {
            let (u, v, nut, eps) = f(xi, yj);
            let values = [u, v, 0.0, 1e-7, eps, nut, 0.0, 0.0, 0.0];
            for (o, val) in fields.iter_mut().zip(values) {
                o.push(val as f32);
            }
        }
    }
    SurfaceMap { x, y, fields }
}

fn film(c: &WakelabConfig) -> Film {
    Film {
        reference_elasticity: c.sea.film_elasticity,
    }
}

/// The wake's damping over a sea whose own near-surface dissipation is 1e-6 m^2/s^3.
fn wake_damping(c: &WakelabConfig) -> WakeDamping {
    WakeDamping {
        film: film(c),
        ambient_dissipation: 1e-6,
        model_ambient_dissipation: AMBIENT_EPS,
    }
}

#[test]
fn no_ship_means_no_modulation_and_an_ambient_film() {
    let c = WakelabConfig::default();
    let map = synthetic_map(60, 25.0, 300.0, 3.0, |_, _| (0.0, 0.0, 9e-5, AMBIENT_EPS));
    let gamma = redistribute_surfactant(&map, c.ship.speed);
    assert!(gamma.gamma.iter().all(|g| (g - 1.0).abs() < 1e-12));
    let sea = background_spectrum(&c);
    let k = WaveVector { kx: 0.0, ky: 127.0 };
    let relax = Relaxation::new(k, &sea, &ShortWaves::new(&sea));
    let r = modulate_short_waves(&map, &gamma, &relax, &sea, &wake_damping(&c), c.ship.speed);
    let worst = r.iter().fold(0.0f64, |m, x| m.max((x - 1.0).abs()));
    // the map stores f32, so the ambient eps read back differs from the f64 one by rounding
    assert!(worst < 1e-8, "N/N0 departs from 1 by {worst:e} with no ship");
    // and the stage's own no-wake scene
    let scene = simulate_surface(&c, None);
    assert!(scene.surfactant.iter().all(|&g| g == 1.0));
    assert!(scene.bragg.iter().all(|b| b.modulation.iter().all(|&r| r == 1.0)));
}

/// Constant extra damping d relaxes N/N0 to mu / (mu + d), with e-folding time 1 / (mu + d)
/// (the closed form of the relaxation equation), and never to zero however strong d is.
#[test]
fn constant_extra_damping_relaxes_to_mu_over_mu_plus_d() {
    let c = WakelabConfig::default();
    let sea = background_spectrum(&c);
    let k = WaveVector { kx: 0.0, ky: 127.0 };
    let relax = Relaxation::new(k, &sea, &ShortWaves::new(&sea));
    let mu = relax.rate;
    let dx = 0.5;
    let travel = c.ship.speed - relax.group_velocity.0;
    for eps in [1e-6, 1e-5, 1e-3] {
        // turbulence everywhere: a uniform extra damping d
        let map = synthetic_map(1200, dx, 60.0, 3.0, |_, _| (0.0, 0.0, 9e-5, eps));
        let gamma = redistribute_surfactant(&map, c.ship.speed);
        let wake = wake_damping(&c);
        let r = modulate_short_waves(&map, &gamma, &relax, &sea, &wake, c.ship.speed);
        let d = wake.extra(127.0, 1.0, eps, sea.tension, sea.gravity);
        let steady = mu / (mu + d);
        let cols = map.y.len();
        let centre = |row: usize| r[row * cols + cols / 2];
        let last = centre(map.x.len() - 1);
        eprintln!("eps {eps:e}: d = {d:.4} 1/s, mu = {mu:.4} 1/s: N/N0 {last:.6} vs mu/(mu+d) {steady:.6}");
        assert!(d > 0.0 && last > 0.0);
        assert!((last - steady).abs() < 1e-6 * steady.max(1e-3));
        // after one e-folding time the departure from the steady state is 1/e of the start's
        let rows = ((1.0 / (mu + d)) * travel / dx).round() as usize;
        if rows >= 4 {
            let t = rows as f64 * dx / travel;
            let expected = steady + (1.0 - steady) * (-(mu + d) * t).exp();
            let got = centre(rows);
            assert!(
                (got - expected).abs() < 0.01 * (1.0 - steady),
                "e-folding: {got} vs {expected}"
            );
        }
    }
}

#[test]
fn surfactant_flux_is_the_same_through_every_cross_section() {
    let c = WakelabConfig::default();
    // converging and diverging cross-track currents, a slower along-track band, wake turbulence
    let map = synthetic_map(300, 25.0, 200.0, 2.0, |x, y| {
        let v = -0.02 * (y / 40.0) * (-(y * y) / 3200.0).exp() * (x / 3000.0).sin();
        let u = 0.05 * (-(y * y) / 800.0).exp();
        let nut = 9e-5 + 0.01 * (-(y * y) / 400.0).exp() / (1.0 + x / 1000.0);
        (u, v, nut, AMBIENT_EPS)
    });
    let gamma = redistribute_surfactant(&map, c.ship.speed);
    let flux = row_fluxes(&map, &gamma, c.ship.speed);
    let inflow = flux[0];
    let worst = flux.iter().fold(0.0f64, |m, f| m.max(((f - inflow) / inflow).abs()));
    let gmax = gamma.gamma.iter().fold(0.0f64, |m, &g| m.max(g));
    eprintln!("surfactant: max Gamma {gmax:.4}, worst relative flux change {worst:e}");
    assert!(gmax > 1.01, "the converging flow did not gather any film");
    assert!(worst < 1e-10);
}

#[test]
fn converging_currents_raise_and_diverging_currents_lower_short_waves() {
    let c = WakelabConfig::default();
    let sea = background_spectrum(&c);
    // the radar's Bragg wave along the heading; an along-track current u = s (x - x0) behind the
    // stern is converging for s > 0 (du/dx_heading = -s < 0)
    let k = WaveVector { kx: 127.0, ky: 0.0 };
    let relax = Relaxation::new(k, &sea, &ShortWaves::new(&sea));
    let tau = 1.0 / relax.rate;
    // the spectrum's own slope m = -d ln N0 / d ln k along k (independent finite difference)
    let h = 1e-3;
    let m = -((sea.action(127.0 * (1.0 + h), 0.0) / sea.action(127.0 * (1.0 - h), 0.0)).ln()) / (2.0 * h);
    for s in [2e-4, -2e-4] {
        let map = synthetic_map(400, 25.0, 30.0, 3.0, |x, _| (s * (x - 71.0), 0.0, 9e-5, AMBIENT_EPS));
        // a uniform film, so that only refraction acts (a converging current also gathers film)
        let gamma = SurfactantField {
            gamma: vec![1.0; map.x.len() * map.y.len()],
            rows: map.x.len(),
            cols: map.y.len(),
        };
        let r = modulate_short_waves(&map, &gamma, &relax, &sea, &wake_damping(&c), c.ship.speed);
        let got = r[r.len() - 1] - 1.0;
        // relaxation-time estimate: dr = -m tau du/dx_heading = m tau s
        let estimate = m * tau * s;
        eprintln!(
            "strain {s:+e}: N/N0 - 1 = {got:+.5e}, relaxation estimate {estimate:+.5e} (m = {m:.3}, tau = {tau:.3} s)"
        );
        assert!(got.signum() == s.signum(), "wrong sign");
        assert!((got / estimate - 1.0).abs() < 0.1);
    }
}

#[test]
fn realised_surface_matches_its_spectrum_and_its_seed() {
    let c = WakelabConfig::default();
    let sea = background_spectrum(&c);
    let (size, dx, window) = (1024, 2.0, 128);
    let a = synthesise_surface(&sea, size, dx, 0.0, window, 7);
    let expected = resolved_variance(&sea, dx, 0.0, window);
    let n = (size * size) as f64;
    let mean = a.elevation.iter().sum::<f64>() / n;
    let variance = a.elevation.iter().map(|z| (z - mean).powi(2)).sum::<f64>() / n;
    eprintln!("surface variance {variance:.5e} m^2 vs resolved spectrum {expected:.5e}");
    assert!((variance / expected - 1.0).abs() < 0.1);
    let b = synthesise_surface(&sea, size, dx, 0.0, window, 7);
    assert!(
        a.elevation == b.elevation && a.slope_x == b.slope_x,
        "same seed, different surface"
    );
    let other = synthesise_surface(&sea, size, dx, 0.0, window, 8);
    assert!(a.elevation != other.elevation);
}

#[test]
fn periodogram_of_the_realised_surface_follows_the_input_spectrum() {
    use rustfft::num_complex::Complex64;
    use std::f64::consts::PI;
    let c = WakelabConfig::default();
    let sea = background_spectrum(&c);
    let (size, dx, window) = (1024usize, 10.0, 128usize);
    let z = synthesise_surface(&sea, size, dx, 0.0, window, 11).elevation;
    let mut data: Vec<Complex64> = z.iter().map(|&v| Complex64::new(v, 0.0)).collect();
    wakelab_surface::fourier::fft_2d(&mut data, size, false);
    let dk_scene = 2.0 * PI / (size as f64 * dx);
    let dk_window = 2.0 * PI / (window as f64 * dx);
    let freq = |i: usize| if i < size / 2 { i as f64 } else { i as f64 - size as f64 };
    // octave rings in units of the window's wavenumber step
    // the swell (k = 12.8 dk), the gap before the wind sea, and the wind sea up to the Nyquist
    // wavenumber; the Hann windows leak a little of the swell into the gap
    let rings = [(8.0, 20.0), (20.0, 32.0), (32.0, 48.0), (48.0, 64.0)];
    let total = resolved_variance(&sea, dx, 0.0, window);
    let n4 = (size as f64).powi(4);
    for (lo, hi) in rings {
        let mut realised = 0.0;
        for i in 0..size {
            for j in 0..size {
                let k = (freq(i).hypot(freq(j))) * dk_scene / dk_window;
                if k >= lo && k < hi {
                    realised += data[i * size + j].norm_sqr() / n4;
                }
            }
        }
        let mut input = 0.0;
        for a in 1..window {
            for b in 1..window {
                let (ka, kb) = (a as f64 - (window / 2) as f64, b as f64 - (window / 2) as f64);
                let k = ka.hypot(kb);
                if k >= lo && k < hi {
                    input += sea.directional(kb * dk_window, ka * dk_window) * dk_window * dk_window;
                }
            }
        }
        eprintln!("ring {lo}-{hi} dk: periodogram {realised:.4e}, spectrum {input:.4e}");
        if lo == 20.0 {
            assert!(
                realised < 0.005 * total,
                "leakage into the gap: {realised:e} of {total:e}"
            );
        } else {
            assert!(
                (realised / input - 1.0).abs() < 0.1,
                "ring {lo}-{hi}: {realised:e} vs {input:e}"
            );
        }
    }
}

#[test]
fn a_simulated_wake_conserves_film_flux_and_darkens_its_bragg_waves() {
    let c = WakelabConfig::from_toml_str(
        "[time]\nduration = 1200.0\n[scene]\nsize = 256\npixel_spacing = 5.0\nalong_track = 3000.0\n",
        "test",
    )
    .unwrap();
    let map = wakelab_hydro::simulate_surface_map(&c).unwrap();
    let gamma = redistribute_surfactant(&map, c.ship.speed);
    let flux = row_fluxes(&map, &gamma, c.ship.speed);
    let worst = flux.iter().fold(0.0f64, |m, f| m.max(((f - flux[0]) / flux[0]).abs()));
    assert!(worst < 1e-10, "film flux changed by {worst:e}");
    let scene = simulate_surface(&c, Some(&map));
    for b in &scene.bragg {
        let min = b.modulation.iter().cloned().fold(f64::INFINITY, f64::min);
        // turbulence in the wake damps the short waves, boundedly; the far field is undisturbed
        assert!(min < 0.9 && min > 0.01, "{:?}: minimum N/N0 {min}", b.band);
        assert!((b.modulation[[0, 0]] - 1.0).abs() < 1e-9);
    }
}

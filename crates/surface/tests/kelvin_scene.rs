//! The Kelvin waves on a scene: the same field as thin-ship theory's on the track, the hull's
//! waterplane, the relaxation MTF's published limit, and nothing changed when switched off.

use rustfft::num_complex::Complex64;
use std::f64::consts::PI;
use std::sync::OnceLock;
use wakelab_core::WakelabConfig;
use wakelab_hydro::SurfaceMap;
use wakelab_surface::action::{Relaxation, WaveVector};
use wakelab_surface::kelvin::{KelvinWaves, ThinShip};
use wakelab_surface::kelvin_scene::bragg_straining;
use wakelab_surface::simulate_surface;

/// A 256 x 256 scene of 5 m pixels centred `along` m behind the stern, the ship heading 30
/// degrees.
fn scene_config(along: f64, extra: &str) -> WakelabConfig {
    let base = format!(
        "[time]\nduration = 600.0\n[sea]\nwindow = 32\n[scene]\nsize = 256\npixel_spacing = 5.0\nalong_track = {along}\nheading = 30.0\n"
    );
    WakelabConfig::from_toml_str(&format!("{base}{extra}"), "test").unwrap()
}

fn config(extra: &str) -> WakelabConfig {
    scene_config(600.0, extra)
}

fn map() -> &'static SurfaceMap {
    static MAP: OnceLock<SurfaceMap> = OnceLock::new();
    MAP.get_or_init(|| wakelab_hydro::simulate_surface_map(&config("")).unwrap())
}

/// The scene's Kelvin elevation, interpolated from its track grid and turned to the heading,
/// equals thin-ship theory's evaluated at each pixel's own track position (on a fine grid
/// through it, same band of wavenumbers) within 5 % of the field's rms.
#[test]
fn the_scene_holds_the_thin_ship_field_at_every_pixel() {
    let c = config("");
    let scene = simulate_surface(&c, Some(map()));
    let kelvin = scene.kelvin.as_ref().expect("Kelvin waves in a wake scene");
    let waves = KelvinWaves::new(ThinShip::new(&c.ship, c.kelvin.hull, c.environment.gravity));
    let rms = (kelvin.elevation.iter().map(|v| v * v).sum::<f64>() / kelvin.elevation.len() as f64).sqrt();
    assert!(rms > 1e-3, "a visible field: rms {rms} m");
    let elevation = |_: f64, _: f64| Complex64::new(1.0, 0.0);
    let mut error = 0.0;
    let mut count = 0;
    for r in (3..253).step_by(25) {
        for col in (3..253).step_by(25) {
            let (x, y) = scene.grid.track_position(r, col);
            if x < 10.0 {
                continue;
            }
            // a 0.5-m-ish grid with a node on y
            let steps = (y.abs() / 0.5).ceil().max(1.0);
            let h = y.abs() / steps;
            let h = if h == 0.0 { 0.5 } else { h };
            let n = 16384;
            let f = waves.track_fields(&[x], n, h, 0.8 * PI / 5.0, &[&elevation]).field(0);
            let j = (n as f64 / 2.0 + y / h).round() as usize;
            error += (f[[0, j]] as f64 - kelvin.elevation[[r, col]]).powi(2);
            count += 1;
        }
    }
    let error = (error / count as f64).sqrt();
    eprintln!("rms error {error} m vs field rms {rms} m over {count} pixels");
    assert!(
        error < 0.05 * rms,
        "rms error {error} m vs field rms {rms} m over {count} pixels"
    );
}

/// The hull's footprint adds up to its waterplane, 2/3 L B for Wigley's hull (closed form),
/// within 2 %; a scene far astern holds no hull.
#[test]
fn the_hull_covers_its_waterplane() {
    let c = scene_config(300.0, "");
    let scene = simulate_surface(&c, Some(map()));
    let cover = scene
        .kelvin
        .as_ref()
        .unwrap()
        .hull_cover
        .as_ref()
        .expect("the ship is in the scene");
    let area = cover.sum() * 25.0;
    let want = 2.0 / 3.0 * c.ship.length * c.ship.beam;
    assert!((area / want - 1.0).abs() < 0.02, "{area} m^2 vs {want} m^2");
    let far = simulate_surface(&scene_config(2000.0, ""), Some(map()));
    assert!(far.kelvin.unwrap().hull_cover.is_none());
}

/// With `kelvin.enabled = false` a wake scene has no Kelvin waves and its surface is the one
/// with them minus their elevation and slopes (the sea's draws do not move).
#[test]
fn switched_off_the_scene_is_the_sea_without_them() {
    let on = simulate_surface(&config(""), Some(map()));
    let off = simulate_surface(&config("[kelvin]\nenabled = false\n"), Some(map()));
    assert!(off.kelvin.is_none());
    let k = on.kelvin.as_ref().unwrap();
    for (a, b, kk) in [
        (&on.surface.elevation, &off.surface.elevation, &k.elevation),
        (&on.surface.slope_x, &off.surface.slope_x, &k.slope_x),
        (&on.surface.slope_y, &off.surface.slope_y, &k.slope_y),
    ] {
        let worst = ndarray::Zip::from(a)
            .and(b)
            .and(kk)
            .fold(0.0f64, |m, &a, &b, &k| m.max((a - k - b).abs()));
        assert!(worst < 1e-12, "{worst}");
    }
    assert_eq!(
        on.bragg[1].modulation, off.bragg[1].modulation,
        "the turbulent wake's modulation"
    );
    // no ship, no Kelvin waves
    assert!(simulate_surface(&config(""), None).kelvin.is_none());
}

/// For an isotropic action spectrum N ~ k^-p without relaxation the straining reduces to the
/// hydrodynamic MTF of Keller & Wright (1975) / Alpers, Ross & Rufenach (1981), p q_l^2 / |q|
/// (q_l the wave vector along the Bragg waves), and relaxation mu scales it by
/// omega / sqrt(omega^2 + mu^2), omega = U |q_x| the wave's frequency.
#[test]
fn straining_is_the_relaxation_mtf() {
    let (u, g, p) = (7.0, 9.81, 4.5);
    let waves = KelvinWaves::new(ThinShip::new(
        &config("").ship,
        wakelab_core::config::HullForm::Wigley,
        g,
    ));
    for (kb, look) in [(100.0, 0.0), (30.0, 1.0), (200.0, 2.5)] {
        // Bragg wave vector in the heading frame; d ln N / dk = -p k / |k|^2
        let k = WaveVector {
            kx: kb * f64::cos(look),
            ky: kb * f64::sin(look),
        };
        for mu in [0.0, 0.3] {
            let bragg = Relaxation {
                k,
                rate: mu,
                dln_action_dk: (-p * k.kx / (kb * kb), -p * k.ky / (kb * kb)),
                group_velocity: (0.0, 0.0),
            };
            for qy in [0.0, 0.1, -0.25, 0.6] {
                let qx = waves.along_track_wavenumber(qy);
                let q = qx.hypot(qy);
                // the Bragg direction in the track frame (behind, port)
                let ql = -qx * f64::cos(look) + qy * f64::sin(look);
                let omega = u * qx;
                let want = p * ql * ql / q * omega / omega.hypot(mu);
                let got = bragg_straining(qx, qy, &bragg, u, g);
                assert!((got.norm() - want).abs() < 1e-9 * (1.0 + want), "{got} vs {want}");
                if mu == 0.0 {
                    assert!(got.im.abs() < 1e-9 * (1.0 + want), "real without relaxation: {got}");
                }
            }
        }
    }
}

/// The narrow-V on a scene: looking across the track (the default look), each band's brightest
/// narrow-V pixels lie on the rays of sqrt(g lambda_B / (8 pi)) / U within 20 % (median over the
/// pixels above half the band's peak); looking along the track nothing resonates: only the tails
/// of the spread reach the Bragg vector, below 1 % of the across-track peak.
#[test]
fn the_narrow_v_lies_on_its_rays_and_needs_a_look_across_the_track() {
    let c = config("");
    let scene = simulate_surface(&c, Some(map()));
    let along = simulate_surface(&config("[platform]\nlook_direction = 0.0\n"), Some(map()));
    let (k, k_along) = (scene.kelvin.as_ref().unwrap(), along.kelvin.as_ref().unwrap());
    for ((band, nu), (_, nu_along)) in k.narrow_v.iter().zip(&k_along.narrow_v) {
        let peak = nu.fold(0.0f64, |m, &v| m.max(v));
        let peak_along = nu_along.fold(0.0f64, |m, &v| m.max(v));
        let mut angles: Vec<f64> = nu
            .indexed_iter()
            .filter(|(_, &v)| v > 0.5 * peak)
            .map(|((r, col), _)| {
                let (x, y) = scene.grid.track_position(r, col);
                (y.abs() / x).atan()
            })
            .collect();
        angles.sort_by(f64::total_cmp);
        let median = angles[angles.len() / 2];
        let lambda = 2.0 * PI / band.bragg_wavenumber(c.platform.incidence);
        let published = (c.environment.gravity * lambda / (8.0 * PI)).sqrt() / c.ship.speed;
        eprintln!(
            "{} band: peak nu {peak:.3e} ({:.1} dB), median angle {:.3} deg of {} pixels vs {:.3} deg; along the track {peak_along:.2e}",
            band.name(),
            10.0 * (1.0 + peak).log10(),
            median.to_degrees(),
            angles.len(),
            published.to_degrees()
        );
        assert!(
            (median / published - 1.0).abs() < 0.2,
            "{band:?}: {median} vs {published}"
        );
        assert!(peak_along < 1e-2 * peak, "{band:?}: {peak_along} vs {peak}");
    }
}

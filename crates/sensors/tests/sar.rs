//! SAR images of a simulated scene with and without a wake.

use wakelab_core::units::RadarBand;
use wakelab_core::WakelabConfig;
use wakelab_sensors::render_sar;
use wakelab_surface::simulate_surface;

fn config(extra: &str) -> WakelabConfig {
    WakelabConfig::from_toml_str(
        &format!("[time]\nduration = 1200.0\n[scene]\nsize = 256\npixel_spacing = 5.0\nalong_track = 3000.0\n{extra}"),
        "test",
    )
    .unwrap()
}

/// Mean of rows with |y| < 40 m (the wake) and of rows with |y| > 300 m (open sea), and the
/// standard deviation of row means in the open sea.
fn strip_statistics(img: &ndarray::Array2<f64>, y: &[f64]) -> (f64, f64, f64) {
    let row_mean = |r: usize| img.row(r).mean().unwrap();
    let wake: Vec<f64> = (0..y.len()).filter(|&r| y[r].abs() < 40.0).map(row_mean).collect();
    let sea: Vec<f64> = (0..y.len()).filter(|&r| y[r].abs() > 300.0).map(row_mean).collect();
    let m = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let (mw, ms) = (m(&wake), m(&sea));
    let sd = (sea.iter().map(|x| (x - ms).powi(2)).sum::<f64>() / (sea.len() - 1) as f64).sqrt();
    (mw, ms, sd)
}

#[test]
fn a_wake_in_following_seas_shows_in_c_band_and_no_ship_shows_nothing() {
    let c = config("[environment.swell]\ndirection = \"following\"\n");
    let map = wakelab_hydro::simulate_surface_map(&c).unwrap();
    let with = simulate_surface(&c, Some(&map));
    let without = simulate_surface(&c, None);
    let y = with.grid.y.clone();
    let wake_img = render_sar(&c, &with, RadarBand::C).sigma0;
    let sea_img = render_sar(&c, &without, RadarBand::C).sigma0;
    let (w, s, sd) = strip_statistics(&wake_img, &y);
    let (w0, s0, sd0) = strip_statistics(&sea_img, &y);
    eprintln!(
        "C band, wake strip {w:.4e} vs sea {s:.4e} (row sd {sd:.2e}); no ship: {w0:.4e} vs {s0:.4e} (sd {sd0:.2e})"
    );
    // the wake stands out by many standard deviations of the sea's row-to-row variation ...
    assert!(
        (w - s).abs() > 5.0 * sd,
        "wake contrast {} vs noise {sd}",
        (w - s).abs()
    );
    // ... and without a ship the same strip is indistinguishable from the sea
    assert!(
        (w0 - s0).abs() < 3.0 * sd0,
        "no-ship contrast {} vs noise {sd0}",
        (w0 - s0).abs()
    );
    // the two scenes differ only where the wake reaches: identical outside the simulated
    // cross-section (|y| > 600 m), and by under 0.1 % in the open sea inside it
    for r in 0..y.len() {
        for col in 0..wake_img.ncols() {
            let (a, b) = (wake_img[[r, col]], sea_img[[r, col]]);
            if y[r].abs() > 610.0 {
                assert_eq!(a, b);
            } else if y[r].abs() > 300.0 {
                assert!(((a - b) / b).abs() < 1e-3, "y = {}: {a} vs {b}", y[r]);
            }
        }
    }
}

#[test]
fn speckle_has_the_statistics_of_its_looks() {
    // multiplicative speckle of L looks: the image's mean is unchanged and, on a uniform sea,
    // the normalised variance grows by about 1 / L
    let base = config("");
    let speckled = config("[sar]\nlooks = 4\n");
    let scene = simulate_surface(&base, None);
    let a = render_sar(&base, &scene, RadarBand::X).sigma0;
    let b = render_sar(&speckled, &scene, RadarBand::X).sigma0;
    let ratio: Vec<f64> = a.iter().zip(b.iter()).map(|(x, y)| y / x).collect();
    let n = ratio.len() as f64;
    let mean = ratio.iter().sum::<f64>() / n;
    let var = ratio.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / n;
    eprintln!("speckle ratio: mean {mean:.4}, variance {var:.4} (expected 1, 0.25)");
    assert!((mean - 1.0).abs() < 0.01);
    assert!((var - 0.25).abs() < 0.01);
}

#[test]
fn velocity_bunching_moves_intensity_without_creating_it() {
    let c = config("[environment.wind]\nspeed = 10.0\n");
    let scene = simulate_surface(&c, None);
    let plain = render_sar(&c, &scene, RadarBand::C).sigma0;
    let zero = config("[environment.wind]\nspeed = 10.0\n[sar]\nvelocity_bunching = true\nrange_to_velocity = 0.0\n");
    assert_eq!(
        render_sar(&zero, &scene, RadarBand::C).sigma0,
        plain,
        "R/V = 0 must change nothing"
    );
    let bunched_cfg =
        config("[environment.wind]\nspeed = 10.0\n[sar]\nvelocity_bunching = true\nrange_to_velocity = 40.0\n");
    let bunched = render_sar(&bunched_cfg, &scene, RadarBand::C).sigma0;
    let (a, b) = (plain.sum(), bunched.sum());
    let changed = plain
        .iter()
        .zip(bunched.iter())
        .filter(|(x, y)| (*x - *y).abs() > 1e-3 * *x)
        .count();
    eprintln!("velocity bunching: total {a:.6e} -> {b:.6e}, {changed} pixels changed by > 0.1 %");
    // only what is shifted across the scene's edges is lost
    assert!(b <= a && (a - b) / a < 0.03);
    assert!(changed > plain.len() / 10);
}

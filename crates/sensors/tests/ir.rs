//! Infrared images of a simulated wake.

use wakelab_core::WakelabConfig;
use wakelab_sensors::{render_ir, IrBand};
use wakelab_surface::simulate_surface;

#[test]
fn a_cold_surface_wake_is_dark_by_the_emissivity_times_its_temperature_drop() {
    let c = WakelabConfig::from_toml_str(
        "[time]\nduration = 1200.0\n[scene]\nsize = 256\npixel_spacing = 5.0\nalong_track = 3000.0\n",
        "test",
    )
    .unwrap();
    let map = wakelab_hydro::simulate_surface_map(&c).unwrap();
    let scene = simulate_surface(&c, Some(&map));
    let calm = simulate_surface(&c, None);
    let y = &scene.grid.y;
    let wake_rows: Vec<usize> = (0..y.len()).filter(|&r| y[r].abs() < 10.0).collect();
    let mean = |a: &ndarray::Array2<f64>, rows: &[usize]| {
        rows.iter().map(|&r| a.row(r).mean().unwrap()).sum::<f64>() / rows.len() as f64
    };
    let dt = mean(&scene.temperature_anomaly, &wake_rows);
    assert!(dt < -0.01, "the wake is not cold at the surface: dT = {dt}");
    for band in IrBand::ALL {
        let with = render_ir(&c, &scene, band);
        let without = render_ir(&c, &calm, band);
        // same surface and footprint: the brightness temperature changes by the surface dT times
        // the emissivity (radiance is linear in T over 0.1 K; the reflected sky and sun are the same)
        let dbt = mean(&with.brightness_temperature, &wake_rows) - mean(&without.brightness_temperature, &wake_rows);
        let eps = with.info.flat_sea.emissivity;
        eprintln!("{band:?}: wake dT {dt:.4} K, brightness-temperature drop {dbt:.4} K, emissivity {eps:.4}");
        assert!(dbt < 0.0, "{band:?}: the cold wake is not dark");
        assert!(
            (dbt / (eps * dt) - 1.0).abs() < 0.05,
            "{band:?}: {dbt} vs eps dT = {}",
            eps * dt
        );
    }
}

//! The surface stage on a 1024 x 1024 scene with the three Bragg wavenumbers (S, C, X), given
//! the hydro stage's surface map of the `quick` preset (computed once, not timed), and its parts;
//! and the Kelvin waves on a 1024 x 1024 scene.

use criterion::{criterion_group, criterion_main, Criterion};
use wakelab_core::WakelabConfig;
use wakelab_surface::{background_spectrum, simulate_surface};

fn surface(c: &mut Criterion) {
    let cfg = WakelabConfig::from_toml_str(
        "[scene]\nsize = 1024\npixel_spacing = 5.0\nalong_track = 6000.0\n",
        "bench",
    )
    .expect("valid");
    let map = wakelab_hydro::simulate_surface_map(&cfg).expect("wake");
    let mut g = c.benchmark_group("surface_stage_1024");
    g.sample_size(10);
    g.bench_function("whole_stage_with_wake", |b| {
        b.iter(|| simulate_surface(&cfg, Some(&map)))
    });
    g.bench_function("no_wake_scene", |b| b.iter(|| simulate_surface(&cfg, None)));
    let sea = background_spectrum(&cfg);
    g.bench_function("random_surface_only", |b| {
        b.iter(|| wakelab_surface::synthesis::synthesise_surface(&sea, 1024, 5.0, 0.0, cfg.sea.window, 1))
    });
    g.finish();
    // the Kelvin waves alone (goal: 0.3 s), on a scene that holds the ship, heading 30 deg
    let ship_near = WakelabConfig::from_toml_str(
        "[scene]\nsize = 1024\npixel_spacing = 5.0\nalong_track = 2000.0\nheading = 30.0\n",
        "bench",
    )
    .expect("valid");
    let grid = wakelab_surface::scene::SceneGrid::new(&ship_near.scene);
    let short_waves = wakelab_surface::short_waves::ShortWaves::new(&sea);
    let mut g = c.benchmark_group("kelvin_1024");
    g.sample_size(10);
    g.bench_function("kelvin_field", |b| {
        b.iter(|| wakelab_surface::kelvin_on_scene(&ship_near, &grid, &sea, &short_waves))
    });
    g.finish();
}

criterion_group!(benches, surface);
criterion_main!(benches);

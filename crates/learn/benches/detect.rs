//! What `wakelab detect`'s CNN costs, side by side in one run: the shipped 1.28 km detector
//! (64 x 64 windows at 20 m) scanning a scene of 25.6 x 25.6 km (1,280 x 1,280 pixels at 20 m,
//! windows half a window apart: 39 x 39 = 1,521 windows), against the same detector scoring
//! one window centred on each of 20 ships (`score_windows`, the ships' `cnn_probability`),
//! against the part of the scan that places each window's wake (`strongest_line` of the same
//! 1,521 normalised windows, done inside the scan), and against what `--real` adds to each
//! image: its peak's chance (`peak_by_chance` over the 1,521 windows, a target 500 m wide
//! across the scene).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use ndarray::Array2;
use std::path::Path;
use wakelab_learn::data::{detector_input, RadarScale};
use wakelab_learn::detect::{detect_image, score_windows, window_at, ScanOptions};
use wakelab_learn::peak_chance::peak_by_chance;
use wakelab_learn::store::load_detector;
use wakelab_learn::window_line::strongest_line;
use wakelab_schema::band::Band;

/// 4-look-like speckle around sigma0 0.01, deterministic.
fn sea(n: usize, seed: u64) -> Array2<f32> {
    let mut state = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    Array2::from_shape_fn((n, n), |_| {
        let mut s = 0.0f64;
        for _ in 0..4 {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let u = ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64;
            s -= u.ln();
        }
        (0.01 * s / 4.0) as f32
    })
}

fn detect_bench(c: &mut Criterion) {
    let device = burn::tensor::Device::flex();
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models/C_transfer_1280m.safetensors");
    let (detector, info) = load_detector(&path, None, &device).expect("the shipped detector");
    let options = ScanOptions {
        scale: RadarScale::Linear,
        ..ScanOptions::default()
    };
    let scene = sea(1280, 1);
    let side = info.input_size;
    let ships: Vec<Array2<f32>> = (0..20).map(|i| sea(side, 100 + i)).collect();

    let mut group = c.benchmark_group("detect");
    group.sample_size(10);
    group.throughput(Throughput::Elements(1521));
    group.bench_function("scan_655km2_1521_windows", |b| {
        b.iter(|| detect_image(&detector, &info, &scene, options, &device, &mut |_, _| {}).expect("scanned"))
    });
    let scan = detect_image(&detector, &info, &scene, options, &device, &mut |_, _| {}).expect("scanned");
    let n = scan.window;
    let windows: Vec<Array2<f32>> = scan
        .tiles
        .iter()
        .map(|t| {
            detector_input(
                window_at(scene.view(), (t.row as isize, t.col as isize), n),
                Band::C,
                options.scale,
            )
        })
        .collect();
    group.bench_function("strongest_line_1521_windows", |b| {
        b.iter(|| {
            windows
                .iter()
                .map(|w| strongest_line(w.view()))
                .filter(Option::is_some)
                .count()
        })
    });
    group.bench_function("peak_by_chance_1521_windows", |b| {
        b.iter(|| peak_by_chance(&scan.tiles, n, |_, c| (c - 640.0).abs() <= 12.5))
    });
    group.throughput(Throughput::Elements(20));
    group.bench_function("score_20_ship_windows", |b| {
        b.iter(|| score_windows(&detector, &info, &ships, options, &device).expect("scored"))
    });
    group.finish();
}

criterion_group!(benches, detect_bench);
criterion_main!(benches);

//! The products crate's kernels: one Sentinel-1 row calibrated and denoised at an IW GRD
//! product's width (25,931 pixels, 27 calibration and noise vectors as a real product has), and
//! area averaging of a 2048 x 2048 image by 2.5 (a 4 m product brought to a 10 m detector).

use criterion::{criterion_group, criterion_main, Criterion};
use ndarray::Array2;
use std::hint::black_box;
use wakelab_products::resample::area_average;
use wakelab_products::sentinel1::annotation::{AzimuthBlock, Noise};
use wakelab_products::sentinel1::lut::{LutVector, SparseLut};
use wakelab_products::sentinel1::Calibration;

const WIDTH: usize = 25_931;

/// 27 vectors over 16,854 lines, a knot every 40 pixels (a real IW GRD's calibration).
fn lut(base: f64) -> SparseLut {
    let pixels: Vec<f64> = (0..WIDTH).step_by(40).map(|p| p as f64).collect();
    SparseLut::new(
        (0..27)
            .map(|k| LutVector {
                line: k as f64 * 650.0,
                values: pixels.iter().map(|p| base + 0.01 * p + k as f64).collect(),
                pixels: pixels.clone(),
            })
            .collect(),
    )
    .unwrap()
}

fn bench(c: &mut Criterion) {
    let noise = Noise::RangeAzimuth {
        range: lut(1000.0),
        azimuth: (0..3)
            .map(|k| AzimuthBlock {
                first_line: 0,
                last_line: 16_853,
                first_sample: k * WIDTH / 3,
                last_sample: (k + 1) * WIDTH / 3 - 1,
                lines: vec![0.0, 16_853.0],
                values: vec![1.0, 1.2],
            })
            .collect(),
    };
    let calibration = Calibration::new(&lut(400.0), Some(&noise), WIDTH);
    let dn: Vec<u16> = (0..WIDTH)
        .map(|p| if p < 40 { 0 } else { 100 + (p % 300) as u16 })
        .collect();
    let mut out = vec![0.0f32; WIDTH];
    c.bench_function("calibrate_row/iw_grd_25931", |b| {
        b.iter(|| black_box(calibration.row(black_box(8000), &dn, &mut out)))
    });
    let image = Array2::from_shape_fn((2048, 2048), |(r, c)| 0.01 + 1e-5 * ((r * 7 + c * 13) % 101) as f32);
    c.bench_function("area_average/2048_by_2.5", |b| {
        b.iter(|| black_box(area_average(black_box(&image), 2.5, 2.5)))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);

//! The line sums of a window (the `line_sums` input form): one 64 x 64 window, the transfer
//! study's detectors' size, and a training batch of 16 made ready side by side as training makes
//! it (turned, then summed), against the same batch read as pixels.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use ndarray::Array2;
use wakelab_learn::augment::Pose;
use wakelab_learn::line_sums::line_sums;
use wakelab_learn::train::{batch_images, Example};
use wakelab_schema::architecture::InputForm;

fn window(n: usize, seed: f32) -> Array2<f32> {
    Array2::from_shape_fn((n, n), |(r, c)| ((r * n + c) as f32 * 0.618 + seed).sin() * 2.0)
}

fn line_sums_bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("line_sums");
    let one = window(64, 0.3);
    group.throughput(Throughput::Elements(1));
    group.bench_function("window_64", |b| b.iter(|| line_sums(&one)));

    let examples: Vec<Example> = (0..16)
        .map(|i| Example {
            image: window(64, i as f32).insert_axis(ndarray::Axis(0)),
            label: (i % 2) as u8,
            mask: None,
        })
        .collect();
    let batch: Vec<&Example> = examples.iter().collect();
    let poses: Vec<Pose> = (0..16)
        .map(|i| Pose {
            degrees: 22.5 * i as f64,
            flip: i % 2 == 0,
            shift: (1, -2),
        })
        .collect();
    let device = burn::tensor::Device::flex();
    group.throughput(Throughput::Elements(16));
    for form in InputForm::ALL {
        group.bench_function(format!("batch16_{}", form.name()), |b| {
            b.iter(|| batch_images(&batch, &poses, form, &device))
        });
    }
    group.finish();
}

criterion_group!(benches, line_sums_bench);
criterion_main!(benches);

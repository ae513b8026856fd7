//! Training-step throughput of the spec's networks on the CPU backend, at the sizes that were
//! asked for: "base" at 256 x 256 (batch 8) and the U-Net at 128 x 128 (batch 4). Compare with
//! PyTorch through `bench/learning_vs_pytorch.sh`, which runs both side by side.

use burn::tensor::{Device, Int, Tensor, TensorData};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::time::Duration;

// As in the `wakelab` binary: training allocates and frees large activation buffers every step,
// which glibc's allocator hands back to the kernel each time (page faults, zeroing).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;
use wakelab_learn::train::{ClassifierTrainer, Recipe, UNetTrainer};

fn pattern(n: usize, seed: f32) -> Vec<f32> {
    (0..n).map(|i| ((i as f32) * 0.618 + seed).sin()).collect()
}

fn training_steps(c: &mut Criterion) {
    wakelab_learn::device::keep_freed_pages();
    let device = Device::flex();
    let mut group = c.benchmark_group("train_step");
    group.sample_size(10).measurement_time(Duration::from_secs(20));

    let (batch, size) = (8, 256);
    let mut trainer = ClassifierTrainer::new(1, size, &Recipe::classifier(), 0, &device);
    let images = Tensor::<4>::from_data(
        TensorData::new(pattern(batch * size * size, 0.3), [batch, 1, size, size]),
        trainer.device(),
    );
    let labels: Vec<i64> = (0..batch as i64).map(|i| i % 2).collect();
    group.throughput(Throughput::Elements(batch as u64));
    group.bench_function("base_256_batch8", |b| b.iter(|| trainer.step(images.clone(), &labels)));

    let (batch, size) = (4, 128);
    let mut trainer = UNetTrainer::new(1, &Recipe::unet(), 0, &device);
    let images = Tensor::<4>::from_data(
        TensorData::new(pattern(batch * size * size, 0.7), [batch, 1, size, size]),
        trainer.device(),
    );
    let masks: Vec<i64> = pattern(batch * size * size, 1.1)
        .iter()
        .map(|&v| (v > 0.8) as i64)
        .collect();
    let masks = Tensor::<4, Int>::from_data(TensorData::new(masks, [batch, 1, size, size]), trainer.device());
    group.throughput(Throughput::Elements(batch as u64));
    group.bench_function("unet_128_batch4", |b| {
        b.iter(|| trainer.step(images.clone(), masks.clone()))
    });
    group.finish();
}

criterion_group!(benches, training_steps);
criterion_main!(benches);

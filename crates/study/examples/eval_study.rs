//! `wakelab eval --study STUDY --dataset DATASET --device DEVICE` without the `wakelab` binary:
//! Algorithm 2 with a study's `[learning]` table (spec 4.2) on a dataset rendered elsewhere
//! (`wakelab dataset --study STUDY`), for a GPU machine that lacks the GDAL and NetCDF libraries
//! the binary links. This program calls neither, so the linker leaves them out and it runs
//! wherever the GPU driver does (issue 41: the paper-shaped study trained on an NVIDIA H100).
//!
//! Build it beside a GPU backend and run it:
//! `cargo build --release -p wakelab -p wakelab-study --features wakelab/wgpu --example eval_study`, then
//! `target/release/examples/eval_study eval DATASET STUDY DEVICE OUT [ARCH,...]`, or time one
//! training step: `eval_study time DEVICE unet|classifier SIDE BATCH`.

use std::path::PathBuf;
use std::time::Instant;
use wakelab_learn::cost::{time_training_step, TimedNetwork};
use wakelab_learn::models::Architecture;
use wakelab_learn::train::Recipe;
use wakelab_study::learning::{eval_command, summary_table, LearnRequest};

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        Some("time") => time(&args[1..]),
        Some("eval") => eval(&args[1..]),
        _ => anyhow::bail!("usage: eval_study eval DATASET STUDY DEVICE OUT [ARCH,...] | eval_study time DEVICE unet|classifier SIDE BATCH"),
    }
}

/// One network's training step timed on a device (three steps after a warm-up that compiles and
/// tunes the kernels): what the dry run carries to a study's sizes.
fn time(args: &[String]) -> anyhow::Result<()> {
    let [device, network, side, batch] = args else {
        anyhow::bail!("usage: eval_study time DEVICE unet|classifier SIDE BATCH");
    };
    let network = match network.as_str() {
        "unet" => TimedNetwork::UNet { width: 64 },
        "classifier" => TimedNetwork::Classifier,
        other => anyhow::bail!("network {other}: one of unet, classifier"),
    };
    let multiple = wakelab_schema::results::UNET_SIZE_MULTIPLE;
    let side: usize = match side.parse() {
        Ok(n) if n >= multiple && n % multiple == 0 => n,
        _ => anyhow::bail!("SIDE {side}: a whole number of pixels, a positive multiple of {multiple}"),
    };
    let batch: usize = match batch.parse() {
        Ok(n) if n >= 1 => n,
        _ => anyhow::bail!("BATCH {batch}: a whole number of images, at least 1"),
    };
    let t = Instant::now();
    let step = time_training_step(network, side, batch, 3, &wakelab_learn::device::parse_device(device)?);
    println!(
        "{network:?} at {side} x {side} in batches of {batch}: {:.4} s per step, {:.2} TFLOP/s ({:.0} s with warm-up)",
        step.seconds,
        step.flop_per_second / 1e12,
        t.elapsed().as_secs_f64()
    );
    Ok(())
}

/// Algorithm 2 of the study's `[learning]` on the dataset, for the architectures named (default:
/// all three).
fn eval(args: &[String]) -> anyhow::Result<()> {
    let (dataset, study, device, out, which) = match args {
        [d, s, dev, o] => (d, s, dev, o, "base,cls,unet"),
        [d, s, dev, o, a] => (d, s, dev, o, a.as_str()),
        _ => anyhow::bail!("usage: eval_study eval DATASET STUDY DEVICE OUT [ARCH,...]"),
    };
    wakelab_learn::device::keep_freed_pages();
    let request = LearnRequest {
        dataset: PathBuf::from(dataset),
        bands: None,
        // the study's [learning] table replaces these, as in `wakelab eval --study`
        classifier: Recipe::classifier(),
        unet: Recipe::unet(),
        threshold: 0.5,
        seed: 0,
        device: device.clone(),
        out: Some(PathBuf::from(out)),
    };
    let architectures = which
        .split(',')
        .map(|a| match a {
            "base" => Ok(Architecture::Base),
            "cls" => Ok(Architecture::Cls),
            "unet" => Ok(Architecture::Unet),
            other => Err(anyhow::anyhow!("architecture {other}: one of base, cls, unet")),
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    let started = Instant::now();
    let mut last = Instant::now();
    let mut progress = |total: u64, message: String| {
        if last.elapsed().as_secs_f64() >= 10.0 {
            eprintln!(
                "[{:>6.0} s] {message} ({total} epochs in all)",
                started.elapsed().as_secs_f64()
            );
            last = Instant::now();
        }
    };
    let done = eval_command(&request, &architectures, 1, Some(study), &mut progress)?;
    print!("{}", summary_table(&done.evaluation.summaries));
    let ious: Vec<f64> = done.evaluation.mask_scores.iter().map(|m| m.iou).collect();
    if !ious.is_empty() {
        let mean = ious.iter().sum::<f64>() / ious.len() as f64;
        let best = ious.iter().copied().fold(0.0, f64::max);
        println!(
            "U-Net masks: mean IoU {mean:.3}, best {best:.3}, over {} test wake scenes",
            ious.len()
        );
    }
    println!(
        "learning on {} took {:.0} s; outputs in {}",
        wakelab_learn::device::describe_device(&wakelab_learn::device::parse_device(device)?),
        started.elapsed().as_secs_f64(),
        done.dir.display()
    );
    Ok(())
}

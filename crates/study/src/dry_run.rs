//! `wakelab run --dry-run`: a study's work stage by stage, and what it costs on this machine,
//! from short measurements (one wake's first two minutes, one scene, one training step of each
//! network) carried to the study's sizes by counting steps, pixels and floating-point
//! operations. Nothing is written. With `--device wgpu` or `cuda` the training steps are also
//! timed on that device, and its column is a measurement instead of an estimate.

use crate::Result;
use std::collections::BTreeSet;
use std::time::Instant;
use wakelab_core::{CrossGrid, WakelabConfig};
use wakelab_dataset::study::{ScenePair, Study};
use wakelab_hydro::WakeSolver;
use wakelab_learn::cost::{
    classifier_flops, time_training_step, unet_flops, unet_parameters, TimedNetwork, TRAINING_PASSES,
};
use wakelab_learn::device::Device;
use wakelab_schema::band::Input;

/// The GPU the dry run names when none is timed, and its training rates (FLOP/s of the
/// classifier's and the 64-wide U-Net's steps): an NVIDIA H100 80GB HBM3 (driver 580.159) through
/// wgpu on Vulkan, timed on 2026-11-26 at 256 x 256 with `crates/study/examples/eval_study.rs`
/// (docs/results.md, "GPU backends"). The classifier's small steps are bound by kernel launches
/// (0.17 TFLOP/s, about the 2-core CPU's); the U-Net reached 3.87 TFLOP/s, 6 % of the card's
/// 67 TFLOP/s of FP32. The CUDA backend was not timed: it could not be built here.
pub const MEASURED_GPU: (&str, f64, f64) = ("NVIDIA H100, wgpu", 0.17e12, 3.87e12);

/// The memory a study must fit in (the issue's bound for the paper study).
pub const MEMORY_BOUND_GIB: f64 = 24.0;

/// Largest side at which a network's step is timed on the CPU.
const MEASURED_SIDE: usize = 128;

/// Largest side at which a network's step is timed on a GPU: large enough that the card is busy
/// (a 128 x 128 step leaves a data-centre GPU mostly idle), small enough for any card (a U-Net
/// step at 512 x 512 in batches of 4 needs about 3 GiB).
const GPU_MEASURED_SIDE: usize = 512;

/// Timed training steps of the classifier and the U-Net on a GPU.
struct GpuTiming {
    side: usize,
    classifier: wakelab_learn::cost::TimedStep,
    unet: wakelab_learn::cost::TimedStep,
}

/// One stage of the dry run.
#[derive(Debug, Clone)]
pub struct StageEstimate {
    pub stage: &'static str,
    pub work: String,
    pub cpu_seconds: f64,
    /// On the GPU of [`DryRun::gpu`] (learning stages only).
    pub gpu_seconds: Option<f64>,
}

/// What `wakelab run --dry-run` prints.
#[derive(Debug, Clone)]
pub struct DryRun {
    pub headline: String,
    pub stages: Vec<StageEstimate>,
    /// The GPU column's heading: the device timed (`--device`), or [`MEASURED_GPU`].
    pub gpu: String,
    /// Peak memory of one U-Net training step at the study's size in its batch (bytes), and how
    /// it was found.
    pub unet_memory: (f64, String),
    /// Peak memory of one wake simulation (bytes).
    pub hydro_memory: f64,
    pub measured_seconds: f64,
    pub notes: Vec<String>,
}

/// Image-steps of each kind of training: (classifier steps by input channels, U-Net steps by
/// input channels).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TrainingWork {
    pub classifier: Vec<(usize, u64)>,
    pub unet: Vec<(usize, u64)>,
}

impl TrainingWork {
    fn add_classifier(&mut self, channels: usize, steps: u64) {
        add(&mut self.classifier, channels, steps);
    }
    fn add_unet(&mut self, channels: usize, steps: u64) {
        add(&mut self.unet, channels, steps);
    }
    pub fn classifier_steps(&self) -> u64 {
        self.classifier.iter().map(|c| c.1).sum()
    }
    pub fn unet_steps(&self) -> u64 {
        self.unet.iter().map(|c| c.1).sum()
    }
}

fn add(list: &mut Vec<(usize, u64)>, channels: usize, steps: u64) {
    match list.iter_mut().find(|(c, _)| *c == channels) {
        Some(entry) => entry.1 += steps,
        None => list.push((channels, steps)),
    }
}

/// The training work of the study's three learning stages (Algorithm 2 on every input; the
/// held-out environments with "base" and "cls"; the held-out geometry with "base"), as the steps
/// of `wakelab run` do it: "base" sees each input's channels, "cls" and the "unet" classifier one
/// channel more, the U-Net each input's channels. `pairs` are the study's scene pairs.
pub fn training_work(study: &Study, pairs: &[ScenePair]) -> [(&'static str, TrainingWork); 3] {
    let plan = &study.learning;
    let bands = &study.study.bands;
    let scenes = 2 * pairs.len();
    let mut inputs: Vec<Input> = bands.iter().map(|&b| Input::single(b)).collect();
    inputs.extend(plan.fused_inputs(bands));
    let train = ((1.0 - study.study.test_fraction) * scenes as f64).round() as u64;
    let (epochs, unet_epochs, runs) = (plan.epochs as u64, plan.unet_epochs as u64, plan.repetitions as u64);
    let mut learning = TrainingWork::default();
    for input in &inputs {
        let c = input.bands().len();
        learning.add_classifier(c, epochs * train * runs);
        learning.add_classifier(c + 1, 2 * epochs * train * runs);
        learning.add_unet(c, unet_epochs * train * runs);
    }
    let held_out = |groups: usize, with_cls: bool| {
        let mut work = TrainingWork::default();
        if groups >= 2 {
            let train = (scenes * (groups - 1) / groups) as u64;
            let steps = epochs * train * groups as u64 * bands.len() as u64;
            work.add_classifier(1, steps);
            if with_cls {
                work.add_classifier(2, steps);
            }
        }
        work
    };
    let geometry_groups = if plan.held_out_geometry.is_empty() {
        0
    } else {
        plan.geometry_groups
    };
    let environments: BTreeSet<String> = pairs
        .iter()
        .filter_map(|p| p.combination.value_text(&plan.held_out))
        .collect();
    [
        ("learning", learning),
        ("held-out environments", held_out(environments.len(), true)),
        ("held-out geometry", held_out(geometry_groups, false)),
    ]
}

/// One wake on `cfg`'s grid: its first two minutes run (the initial plane's adjustment, when the
/// steps are shortest), the rest counted at `time.max_dt` per step at the measured cost of a
/// step. Returns (seconds per wake, peak bytes, steps run).
fn time_one_wake(cfg: &WakelabConfig) -> Result<(f64, Option<f64>, usize)> {
    let first = cfg.time.duration.min(120.0);
    wakelab_learn::device::release_freed_pages();
    let start = wakelab_core::memory::reset_peak();
    let mut solver = WakeSolver::new(cfg);
    let t = Instant::now();
    solver.run_until(first)?;
    let seconds = t.elapsed().as_secs_f64();
    let steps = solver.steps().max(1);
    let peak = start.and_then(wakelab_core::memory::peak_since);
    let later = ((cfg.time.duration - first) / cfg.time.max_dt).ceil().max(0.0);
    Ok((seconds + later * seconds / steps as f64, peak, steps))
}

/// The side at which a network is timed: the study's, up to `largest`, a multiple of the
/// U-Net's.
fn measured_side(side: usize, largest: usize) -> usize {
    let m = wakelab_schema::results::UNET_SIZE_MULTIPLE;
    (side.min(largest) / m * m).max(m)
}

/// Seconds of the training `work` at side `side`, from the measured FLOP rates.
fn training_seconds(work: &TrainingWork, side: usize, width: usize, classifier_rate: f64, unet_rate: f64) -> f64 {
    let classifier: f64 = work
        .classifier
        .iter()
        .map(|&(c, n)| n as f64 * TRAINING_PASSES * classifier_flops(c, side) / classifier_rate)
        .sum();
    let unet: f64 = work
        .unet
        .iter()
        .map(|&(c, n)| n as f64 * TRAINING_PASSES * unet_flops(c, width, side) / unet_rate)
        .sum();
    classifier + unet
}

/// The dry run of `study` (see the module docs); unless `quiet`, says on stderr what it times.
pub fn dry_run(study: &Study, device: &Device, quiet: bool) -> Result<DryRun> {
    crate::chip_study_only(study, "--dry-run")?;
    let progress = |what: &str| {
        if !quiet {
            eprintln!("  dry run: {what}");
        }
    };
    let started = Instant::now();
    let pairs = study.pairs()?;
    let first = (pairs.first()).ok_or_else(|| anyhow::anyhow!("study {} has no scene pairs", study.study.name))?;
    let cfg = &first.config;
    let side = pairs
        .iter()
        .map(|p| p.config.scene.size)
        .max()
        .unwrap_or(cfg.scene.size);
    let bands = &study.study.bands;
    let plan = &study.learning;
    let wakes: BTreeSet<String> = pairs.iter().map(|p| wakelab_dataset::hydro_key(&p.config)).collect();
    let cells = CrossGrid::new(&cfg.grid).cells();

    progress("timing one wake's first two minutes");
    let (wake_seconds, hydro_memory, wake_steps) = time_one_wake(cfg)?;
    progress("timing one scene");
    let t = Instant::now();
    std::hint::black_box(wakelab_dataset::render::render_sea_scene(cfg, bands));
    let scene_seconds = t.elapsed().as_secs_f64();

    let m = measured_side(side, MEASURED_SIDE);
    progress("timing a training step of each network");
    let unet_network = TimedNetwork::UNet { width: plan.unet_width };
    let cpu = Device::flex();
    let unet = time_training_step(unet_network, m, plan.unet_batch_size, 1, &cpu);
    let classifier = time_training_step(TimedNetwork::Classifier, m, plan.batch_size, 2, &cpu);
    let gpu_timing = (!wakelab_learn::device::is_cpu(device)).then(|| {
        let g = measured_side(side, GPU_MEASURED_SIDE);
        progress(&format!(
            "timing a training step of each network on {}",
            wakelab_learn::device::describe_device(device)
        ));
        // three steps after the warm-up, which also compiles and tunes the kernels
        GpuTiming {
            side: g,
            unet: time_training_step(unet_network, g, plan.unet_batch_size, 3, device),
            classifier: time_training_step(TimedNetwork::Classifier, g, plan.batch_size, 3, device),
        }
    });
    // The U-Net's peak: its weights, gradients and two Adam moments do not grow with the image;
    // the activations (what the step's peak holds beyond those) grow with the pixels.
    let params = unet_parameters(1, plan.unet_width) as f64;
    let fixed = 4.0 * 4.0 * params;
    let (unet_memory, memory_how) = match unet.peak_bytes {
        Some(peak) => {
            let scale = (side * side) as f64 / (m * m) as f64;
            let activations = (peak - fixed).max(0.0);
            let how = if m == side {
                format!(
                    "measured: one training step at {side} x {side} in batches of {}",
                    plan.unet_batch_size
                )
            } else {
                format!(
                    "one step measured at {m} x {m} ({:.2} GiB), its activations ({:.2} GiB beyond {:.2} GiB of weights, gradients and Adam's moments) scaled by the pixels",
                    gib(peak),
                    gib(activations),
                    gib(fixed)
                )
            };
            (fixed + activations * scale, how)
        }
        None => (
            f64::NAN,
            "not measured: the operating system does not report peak memory".into(),
        ),
    };

    let scenes = 2 * pairs.len();
    let mut stages = vec![
        StageEstimate {
            stage: "dataset: wakes",
            work: format!(
                "{} wakes of {:.0} s on {} cells",
                wakes.len(),
                cfg.time.duration,
                thousands(cells as u64)
            ),
            cpu_seconds: wakes.len() as f64 * wake_seconds,
            gpu_seconds: None,
        },
        StageEstimate {
            stage: "dataset: scenes",
            work: format!(
                "{scenes} scenes ({} pairs) of {side} x {side} in {} bands",
                pairs.len(),
                bands.len()
            ),
            cpu_seconds: scenes as f64 * scene_seconds,
            gpu_seconds: None,
        },
    ];
    let (named_gpu, classifier_rate, unet_rate) = MEASURED_GPU;
    let width = plan.unet_width;
    for (stage, work) in training_work(study, &pairs) {
        let gpu_seconds = match &gpu_timing {
            Some(g) => training_seconds(&work, side, width, g.classifier.flop_per_second, g.unet.flop_per_second),
            None => training_seconds(&work, side, width, classifier_rate, unet_rate),
        };
        stages.push(StageEstimate {
            stage,
            work: format!(
                "{} classifier and {} U-Net image-steps at {side} x {side}",
                thousands(work.classifier_steps()),
                thousands(work.unet_steps())
            ),
            cpu_seconds: training_seconds(&work, side, width, classifier.flop_per_second, unet.flop_per_second),
            gpu_seconds: Some(gpu_seconds),
        });
    }
    let mut notes = vec![
        format!(
            "Wake: the first {:.0} s ran in {wake_steps} steps; the rest is counted at time.max_dt = {} s per step.",
            cfg.time.duration.min(120.0),
            cfg.time.max_dt
        ),
        format!(
            "Scenes: one scene without its wake timed ({scene_seconds:.2} s); a wake scene adds the wake's marches of the wave spectrum."
        ),
        format!(
            "Training: one step timed at {m} x {m} per network (\"base\" {:.3} s in batches of {}, U-Net {:.3} s in batches of {}: {:.1} and {:.1} GFLOP/s), carried to {side} x {side} and to each input's channels by the networks' floating-point operations; evaluation passes are not counted.",
            classifier.seconds,
            plan.batch_size,
            unet.seconds,
            plan.unet_batch_size,
            classifier.flop_per_second / 1e9,
            unet.flop_per_second / 1e9
        ),
        match &gpu_timing {
            Some(g) => format!(
                "{}: measured, one step timed at {s} x {s} per network (\"base\" {:.4} s, U-Net {:.4} s: {:.2} and {:.2} TFLOP/s), carried to {side} x {side} likewise.",
                wakelab_learn::device::describe_device(device),
                g.classifier.seconds,
                g.unet.seconds,
                g.classifier.flop_per_second / 1e12,
                g.unet.flop_per_second / 1e12,
                s = g.side
            ),
            None => format!(
                "{named_gpu}: the rates of its training steps measured at 256 x 256 on 2026-11-26 (\"base\" {:.2}, U-Net {:.2} TFLOP/s), carried to {side} x {side}; `--device wgpu` or `cuda` times this machine's GPU instead. On wgpu the U-Net's step at 1024 x 1024 in batches of 4 failed there (a 3 GiB buffer over the adapter's limit).",
                classifier_rate / 1e12,
                unet_rate / 1e12
            ),
        },
    ];
    let peak = unet_memory.max(hydro_memory.unwrap_or(0.0));
    notes.push(if peak.is_nan() {
        "Memory: not measured.".into()
    } else if gib(peak) <= MEMORY_BOUND_GIB {
        format!("Memory: the largest step needs {:.1} GiB, within {MEMORY_BOUND_GIB} GiB.", gib(peak))
    } else {
        format!(
            "Memory: the U-Net's training step at {side} x {side} in batches of {} needs {:.1} GiB, more than {MEMORY_BOUND_GIB} GiB: train it on a GPU with that much memory, or lower learning.unet_batch_size.",
            plan.unet_batch_size,
            gib(unet_memory)
        )
    });
    let headline = format!(
        "Dry run of study \"{}\": {} pairs ({scenes} scenes) of {side} x {side} pixels of {} m in {} bands, {} inputs, {} repetitions; measured here in {:.0} s, nothing written.",
        study.study.name,
        pairs.len(),
        cfg.scene.pixel_spacing,
        bands.len(),
        bands.len() + plan.fused_inputs(bands).len(),
        plan.repetitions,
        started.elapsed().as_secs_f64()
    );
    let gpu = match gpu_timing {
        Some(_) => format!("{} (measured)", wakelab_learn::device::describe_device(device)),
        None => format!("{named_gpu} (measured rates)"),
    };
    Ok(DryRun {
        headline,
        stages,
        gpu,
        unet_memory: (unet_memory, memory_how),
        hydro_memory: hydro_memory.unwrap_or(f64::NAN),
        measured_seconds: started.elapsed().as_secs_f64(),
        notes,
    })
}

fn gib(bytes: f64) -> f64 {
    bytes / (1u64 << 30) as f64
}

/// 1234567 as "1,234,567".
fn thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, ch) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(ch);
    }
    out
}

/// Days, hours, minutes or seconds, whichever reads best.
fn duration(seconds: f64) -> String {
    // a stage without work sums an empty list, which Rust's float sum starts at -0.0
    let seconds = seconds + 0.0;
    if seconds >= 4.0 * 86400.0 {
        format!(
            "{} h ({:.0} days)",
            thousands((seconds / 3600.0).round() as u64),
            seconds / 86400.0
        )
    } else if seconds >= 5400.0 {
        format!("{:.1} h", seconds / 3600.0)
    } else if seconds >= 90.0 {
        format!("{:.0} min", seconds / 60.0)
    } else {
        format!("{seconds:.0} s")
    }
}

impl DryRun {
    /// The table and notes `wakelab run --dry-run` prints.
    pub fn describe(&self) -> String {
        let mut out = format!("{}\n\n", self.headline);
        out += &format!("{:<22} {:<60} {:>20} {:>22}\n", "stage", "work", "this CPU", self.gpu);
        for s in &self.stages {
            let gpu = s.gpu_seconds.map_or("-".to_string(), duration);
            out += &format!(
                "{:<22} {:<60} {:>20} {:>22}\n",
                s.stage,
                s.work,
                duration(s.cpu_seconds),
                gpu
            );
        }
        let cpu: f64 = self.stages.iter().map(|s| s.cpu_seconds).sum();
        out += &format!("{:<22} {:<60} {:>20}\n\n", "total", "", duration(cpu));
        let (bytes, how) = &self.unet_memory;
        out += &format!("U-Net training step: peak {:.2} GiB ({how}).\n", gib(*bytes));
        out += &format!("One wake: peak {:.2} GiB.\n", gib(self.hydro_memory));
        for n in &self.notes {
            out += n;
            out.push('\n');
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small study whose work is counted by hand.
    const SMALL: &str = r#"
[study]
name = "small"
combine = "product"
seeds = 2
test_fraction = 0.25
grouped_split = false
min_visibility = 0.0
mixed_layer_depth = 20.0
bands = ["C"]

[axes]
wind_speed = [3.0, 6.0]
image_size = [32]

[draws]
heading = [0.0, 360.0]

[base]
preset = "quick"

[learning]
repetitions = 1
epochs = 2
unet_epochs = 3
unet_width = 8
batch_size = 4
held_out = "wind_speed"
held_out_geometry = "heading"
geometry_groups = 2
"#;

    #[test]
    fn the_training_work_is_what_the_steps_train() {
        let study = Study::from_toml_str(SMALL, "test").expect("valid study");
        let pairs = study.pairs().unwrap();
        assert_eq!(pairs.len(), 4);
        let [(_, learning), (_, environments), (_, geometry)] = training_work(&study, &pairs);
        // 8 scenes, 6 of them for training; C alone: "base" 2 epochs x 6 on one channel,
        // "cls" and the "unet" classifier 2 x 6 each on two, the U-Net 3 x 6 on one
        assert_eq!(learning.classifier, vec![(1, 12), (2, 24)]);
        assert_eq!(learning.unet, vec![(1, 18)]);
        // two wind speeds held out in turn, 4 scenes left for training each time, 2 epochs,
        // "base" and "cls"
        assert_eq!(environments.classifier, vec![(1, 16), (2, 16)]);
        assert_eq!(geometry.classifier, vec![(1, 16)]);
        assert!(geometry.unet.is_empty());
    }

    #[test]
    fn numbers_read_as_people_write_them() {
        assert_eq!(thousands(1_234_567), "1,234,567");
        assert_eq!(thousands(999), "999");
        assert_eq!(duration(30.0), "30 s");
        assert_eq!(duration(Vec::<f64>::new().iter().sum()), "0 s");
        assert_eq!(duration(600.0), "10 min");
        assert_eq!(duration(7200.0), "2.0 h");
        assert_eq!(duration(3600.0 * 14759.2), "14,759 h (615 days)");
        assert_eq!(measured_side(1024, MEASURED_SIDE), 128);
        assert_eq!(measured_side(32, MEASURED_SIDE), 32);
        assert_eq!(measured_side(1024, GPU_MEASURED_SIDE), 512);
        assert_eq!(measured_side(256, GPU_MEASURED_SIDE), 256);
    }
}

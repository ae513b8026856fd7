//! `wakelab train`, `wakelab eval` and `wakelab detect`: the learning stage on a dataset
//! directory and on a user's own image.

use crate::Result;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::Write;
use std::path::{Path, PathBuf};
use wakelab_core::io::write_atomically;
use wakelab_learn::data::Dataset;
use wakelab_learn::device::parse_device;
use wakelab_learn::evaluate::{
    band_set_name, detect, evaluate, load_examples, train_detector, CurvePoint, EvalOptions, Evaluation, Output,
    Summary,
};
use wakelab_learn::metrics::{roc_auc, Confusion};
use wakelab_learn::models::Architecture;
use wakelab_learn::store::{load_detector, save_detector, ModelInfo};
use wakelab_learn::train::Recipe;

/// Options shared by `train` and `eval`.
#[derive(clap::Args, Debug, Clone)]
pub struct LearnArgs {
    /// Dataset directory (written by `wakelab dataset`).
    pub dataset: PathBuf,
    /// Inputs, comma-separated; `S+X` is one input of two bands as channels (feature-level
    /// fusion). Default: every band of the dataset, one at a time.
    #[arg(long, value_name = "LIST")]
    pub bands: Option<String>,
    /// Classifier epochs (spec: 60).
    #[arg(long, default_value_t = 60)]
    pub epochs: usize,
    /// U-Net epochs (spec: 60).
    #[arg(long, default_value_t = 60)]
    pub unet_epochs: usize,
    /// First-level channels of the U-Net (Table 4.2: 64; narrower trains faster).
    #[arg(long, default_value_t = 64)]
    pub unet_width: usize,
    /// Classifier batch size.
    #[arg(long, default_value_t = 8)]
    pub batch_size: usize,
    /// Classifier learning rate (spec: 1e-3, SGD).
    #[arg(long, default_value_t = 1e-3)]
    pub learning_rate: f64,
    /// Decision threshold on the wake probability (spec 4.2: 0.5).
    #[arg(long, default_value_t = 0.5)]
    pub threshold: f64,
    /// Seed of the weights, splits, batch order and rotations.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Backend: cpu, or wgpu / cuda in builds with those features.
    #[arg(long, default_value = "cpu")]
    pub device: String,
    /// Output directory (default: DATASET/learn).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

fn parse_band_sets(text: Option<&str>, dataset: &Dataset) -> Vec<Vec<String>> {
    match text {
        None => dataset.bands().into_iter().map(|b| vec![b]).collect(),
        Some(t) => t
            .split(',')
            .filter(|s| !s.trim().is_empty())
            .map(|s| s.split('+').map(|b| b.trim().to_string()).collect())
            .collect(),
    }
}

fn parse_architectures(text: &str) -> Result<Vec<Architecture>> {
    text.split(',')
        .map(|a| {
            Architecture::parse(a.trim())
                .ok_or_else(|| anyhow::anyhow!("--arch {a}: must be base, cls or unet (comma-separated)"))
        })
        .collect()
}

impl LearnArgs {
    fn options(&self, dataset: &Dataset, architectures: Vec<Architecture>, repetitions: usize) -> EvalOptions {
        EvalOptions {
            architectures,
            band_sets: parse_band_sets(self.bands.as_deref(), dataset),
            repetitions,
            test_fraction: dataset.test_fraction(),
            classifier: Recipe {
                epochs: self.epochs,
                batch_size: self.batch_size,
                learning_rate: self.learning_rate,
                ..Recipe::classifier()
            },
            unet: Recipe {
                epochs: self.unet_epochs,
                width: self.unet_width,
                ..Recipe::unet()
            },
            threshold: self.threshold,
            seed: self.seed,
            perturbations: Vec::new(),
        }
    }

    fn out_dir(&self) -> PathBuf {
        self.out.clone().unwrap_or_else(|| self.dataset.join("learn"))
    }
}

fn epoch_bar(quiet: bool, total: u64) -> ProgressBar {
    let bar = if quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(total)
    };
    bar.set_style(
        ProgressStyle::with_template("{spinner} {msg} [{bar:30}] {pos}/{len} epochs | {elapsed_precise}, {eta} left")
            .expect("valid template")
            .progress_chars("=> "),
    );
    bar
}

/// Epochs one evaluation trains in all (for the progress bar).
fn total_epochs(o: &EvalOptions) -> u64 {
    let per_rep: usize = o
        .architectures
        .iter()
        .map(|a| o.classifier.epochs + if *a == Architecture::Unet { o.unet.epochs } else { 0 })
        .sum();
    (per_rep * o.repetitions * o.band_sets.len()) as u64
}

pub fn csv<T: serde::Serialize>(rows: &[T]) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    let values: Vec<serde_json::Value> = rows
        .iter()
        .map(serde_json::to_value)
        .collect::<std::result::Result<_, _>>()?;
    let Some(first) = values.first().and_then(|v| v.as_object()) else {
        return Ok(out);
    };
    let keys: Vec<String> = first.keys().cloned().collect();
    writeln!(out, "{}", keys.join(","))?;
    for v in &values {
        let cells: Vec<String> = keys
            .iter()
            .map(|k| match &v[k] {
                serde_json::Value::String(s) => s.clone(),
                serde_json::Value::Null => String::new(),
                other => other.to_string(),
            })
            .collect();
        writeln!(out, "{}", cells.join(","))?;
    }
    Ok(out)
}

/// Write an evaluation's files: outputs, metrics (CSV, JSON), curves and the detectors.
pub fn write_evaluation(dir: &Path, evaluation: &Evaluation) -> Result<()> {
    std::fs::create_dir_all(dir.join("models"))?;
    write_atomically(dir.join("outputs.csv"), &csv::<Output>(&evaluation.outputs)?)?;
    write_atomically(dir.join("metrics.csv"), &csv::<Summary>(&evaluation.summaries)?)?;
    write_atomically(
        dir.join("metrics.json"),
        serde_json::to_string_pretty(&evaluation.summaries)?.as_bytes(),
    )?;
    write_atomically(dir.join("curves.csv"), &csv::<CurvePoint>(&evaluation.curves)?)?;
    for (detector, info) in &evaluation.detectors {
        let name = format!("{}_{}.safetensors", band_set_name(&info.bands), info.architecture);
        save_detector(detector, info, &dir.join("models").join(name))?;
    }
    Ok(())
}

pub fn print_summaries(summaries: &[Summary]) {
    let w = summaries.iter().map(|s| s.bands.len()).max().unwrap_or(5).max(5);
    println!(
        "{:<w$} {:<5} {:>5} {:>14} {:>16} {:>6} {:>6}  TP/TN/FP/FN",
        "input", "arch", "reps", "MCC", "accuracy", "F1", "AUC"
    );
    for s in summaries {
        println!(
            "{:<w$} {:<5} {:>5} {:>7.2} ± {:<4.2} {:>8.1}% ± {:<4.1} {:>6.2} {:>6}  {}/{}/{}/{}",
            s.bands,
            s.architecture.name(),
            s.repetitions,
            s.mcc,
            s.mcc_spread,
            100.0 * s.accuracy,
            100.0 * s.accuracy_spread,
            s.f1,
            s.roc_auc.map(|a| format!("{a:.2}")).unwrap_or_else(|| "-".into()),
            s.tp,
            s.tn,
            s.fp,
            s.fn_
        );
    }
}

/// A fusion row of Tables 5.1-5.3 with Dempster-Shafer's mean conflict (0 for Bayes).
#[derive(serde::Serialize)]
struct FusionRow {
    #[serde(flatten)]
    summary: Summary,
    mean_conflict: f64,
}

/// `wakelab eval`: Algorithm 2 on a dataset.
pub fn run_eval(args: &LearnArgs, arch: &str, repetitions: usize, json: bool) -> Result<()> {
    let dataset = Dataset::open(&args.dataset)?;
    let device = parse_device(&args.device)?;
    let options = args.options(&dataset, parse_architectures(arch)?, repetitions);
    options.validate()?;
    let bar = epoch_bar(args.quiet, total_epochs(&options));
    let evaluation = evaluate(&dataset, &options, &device, &mut |p| {
        bar.inc(1);
        bar.set_message(format!(
            "{} {} rep {}/{} epoch {}/{} loss {:.3} {:.1} img/s",
            p.bands,
            p.network,
            p.repetition + 1,
            options.repetitions,
            p.epoch.epoch,
            p.epochs,
            p.epoch.loss,
            p.epoch.images_per_second
        ));
    })?;
    bar.finish_and_clear();
    let dir = args.out_dir();
    write_evaluation(&dir, &evaluation)?;
    // decision-level fusion of the single bands (spec 5.1-5.2, 5.4) from the kept outputs
    let (fused, fusion) = wakelab_fusion::decision::fuse_all(&evaluation.outputs, options.threshold);
    if !fused.is_empty() {
        write_atomically(dir.join("fusion_outputs.csv"), &csv(&fused)?)?;
        let rows: Vec<FusionRow> = fusion
            .iter()
            .map(|(s, k)| FusionRow {
                summary: s.clone(),
                mean_conflict: *k,
            })
            .collect();
        write_atomically(dir.join("fusion_metrics.csv"), &csv(&rows)?)?;
    }
    if json {
        println!("{}", serde_json::to_string_pretty(&evaluation.summaries)?);
    } else {
        print_summaries(&evaluation.summaries);
        if !fusion.is_empty() {
            println!("\ndecision-level fusion (Bayes weights from each source's training images):");
            print_summaries(&fusion.iter().map(|(s, _)| s.clone()).collect::<Vec<_>>());
        }
        eprintln!(
            "wrote outputs, metrics, curves, fusion and models into {}",
            dir.display()
        );
    }
    Ok(())
}

/// `wakelab train`: one detector on the dataset's training split, tested on its test split.
pub fn run_train(args: &LearnArgs, arch: &str, model: Option<&Path>) -> Result<()> {
    let dataset = Dataset::open(&args.dataset)?;
    let device = parse_device(&args.device)?;
    let architecture = parse_architectures(arch)?;
    let [architecture] = architecture[..] else {
        anyhow::bail!("--arch {arch}: `train` trains one architecture (base, cls or unet)");
    };
    let options = args.options(&dataset, vec![architecture], 1);
    options.validate()?;
    let [bands] = &options.band_sets[..] else {
        anyhow::bail!("--bands: `train` trains one input (a band, or bands joined by +)");
    };
    let split = |name: &str| -> Vec<usize> {
        (0..dataset.records.len())
            .filter(|&i| dataset.records[i].split == name)
            .collect()
    };
    let (train_idx, test_idx) = (split("train"), split("test"));
    if train_idx.is_empty() {
        anyhow::bail!("{}: no scenes in the training split", args.dataset.display());
    }
    let train = load_examples(&dataset, bands, &train_idx)?;
    let bar = epoch_bar(args.quiet, total_epochs(&options));
    let mut curves = Vec::new();
    let name = band_set_name(bands);
    let detector = train_detector(architecture, &train, &options, args.seed, &device, &mut |network, e| {
        bar.inc(1);
        bar.set_message(format!(
            "{name} {network} epoch {} loss {:.3} acc {:.0}% {:.1} img/s",
            e.epoch,
            e.loss,
            100.0 * e.accuracy,
            e.images_per_second
        ));
        curves.push(CurvePoint {
            bands: name.clone(),
            network: network.to_string(),
            repetition: 0,
            epoch: e.clone(),
        });
    });
    bar.finish_and_clear();
    let info = ModelInfo {
        architecture,
        bands: bands.clone(),
        input_size: train[0].size(),
        threshold: args.threshold,
        unet_width: options.unet.width,
    };
    let dir = args.out_dir();
    std::fs::create_dir_all(&dir)?;
    let path = model
        .map(Path::to_path_buf)
        .unwrap_or_else(|| dir.join(format!("{name}_{architecture}.safetensors")));
    let (path, export) = save_detector(&detector, &info, &path)?;
    write_atomically(dir.join(format!("{name}_{architecture}_curve.csv")), &csv(&curves)?)?;
    eprintln!("saved {} (PyTorch layout: {})", path.display(), export.display());
    if !test_idx.is_empty() {
        let test = load_examples(&dataset, bands, &test_idx)?;
        let outputs = detect(&detector, architecture, &test, &device);
        let labels: Vec<u8> = test.iter().map(|e| e.label).collect();
        let c = Confusion::from_outputs(&outputs, &labels, args.threshold);
        println!(
            "test split ({} scenes): MCC {:.3}, accuracy {:.1}%, TP/TN/FP/FN {}/{}/{}/{}, AUC {}",
            test.len(),
            c.mcc(),
            100.0 * c.accuracy(),
            c.tp,
            c.tn,
            c.fp,
            c.fn_,
            roc_auc(&outputs, &labels)
                .map(|a| format!("{a:.3}"))
                .unwrap_or_else(|| "-".into())
        );
    }
    Ok(())
}

/// `wakelab detect`: a saved single-band detector on a user's image.
pub fn run_detect(image: &Path, model: &Path, device: &str, mask: Option<&Path>, json: bool) -> Result<()> {
    let device = parse_device(device)?;
    let (detector, info) = load_detector(model, None, &device)?;
    let pixels = wakelab_learn::detect::read_single_band(image)?;
    let detection = wakelab_learn::detect::detect_image(&detector, &info, &pixels, &device)?;
    if let (Some(path), Some(m)) = (mask, &detection.mask) {
        let (h, w) = m.dim();
        let bytes: Vec<u8> = m.iter().map(|&v| (v.clamp(0.0, 1.0) * 255.0).round() as u8).collect();
        let png = image::GrayImage::from_raw(w as u32, h as u32, bytes).expect("h x w bytes");
        let mut buffer = std::io::Cursor::new(Vec::new());
        png.write_to(&mut buffer, image::ImageFormat::Png)?;
        write_atomically(path, buffer.get_ref())?;
    } else if mask.is_some() {
        eprintln!(
            "note: --mask needs a \"unet\" detector; {} is \"{}\"",
            model.display(),
            info.architecture
        );
    }
    if json {
        println!("{}", serde_json::to_string_pretty(&detection)?);
    } else {
        println!(
            "{}: wake probability {:.3} ({} at threshold {}), {} tile(s) of {} x {} px",
            image.display(),
            detection.probability,
            if detection.wake { "wake" } else { "no wake" },
            detection.threshold,
            detection.tiles.len(),
            info.input_size,
            info.input_size
        );
    }
    Ok(())
}

//! `wakelab train` and `wakelab eval`: the learning stage on a dataset directory.

use crate::cli::{EvalArgs, TrainArgs};
use crate::Result;
use indicatif::ProgressBar;
use std::path::PathBuf;
use wakelab_learn::data::Dataset;
use wakelab_learn::device::parse_device;
use wakelab_learn::evaluate::EvalOptions;
use wakelab_learn::models::Architecture;
use wakelab_learn::train::Recipe;
use wakelab_schema::recipe;
use wakelab_study::learning::{evaluate_into, summary_table, total_epochs, train_into};

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
    #[arg(long, default_value_t = recipe::CLASSIFIER_EPOCHS)]
    pub epochs: usize,
    /// U-Net epochs (spec: 60).
    #[arg(long, default_value_t = recipe::UNET_EPOCHS)]
    pub unet_epochs: usize,
    /// U-Net batch size (spec: 4).
    #[arg(long, default_value_t = recipe::UNET_BATCH_SIZE)]
    pub unet_batch_size: usize,
    /// First-level channels of the U-Net (Table 4.2: 64; narrower trains faster).
    #[arg(long, default_value_t = recipe::UNET_WIDTH)]
    pub unet_width: usize,
    /// Classifier batch size.
    #[arg(long, default_value_t = recipe::CLASSIFIER_BATCH_SIZE)]
    pub batch_size: usize,
    /// Classifier learning rate (spec: 1e-3, SGD).
    #[arg(long, default_value_t = recipe::CLASSIFIER_LEARNING_RATE, allow_negative_numbers = true)]
    pub learning_rate: f64,
    /// Classifier optimiser: sgd (spec 4.1) or adam (the spec's U-Net optimiser; learns in far
    /// fewer steps).
    #[arg(long, default_value = "sgd", value_name = "sgd|adam")]
    pub optimiser: wakelab_schema::recipe::Optimiser,
    /// Classifier L2 weight decay (spec: 0.1).
    #[arg(long, default_value_t = recipe::CLASSIFIER_WEIGHT_DECAY, allow_negative_numbers = true)]
    pub weight_decay: f64,
    /// Decision threshold on the wake probability (spec 4.2: 0.5).
    #[arg(long, default_value_t = recipe::THRESHOLD, allow_negative_numbers = true)]
    pub threshold: f64,
    /// Seed of the weights, splits, batch order and augmentation.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// How training inputs vary: quarter_turns (spec 4.2) or geometric (rotations by any angle,
    /// flips and shifts).
    #[arg(long, default_value = "quarter_turns", value_name = "quarter_turns|geometric")]
    pub augmentation: wakelab_schema::recipe::Augmentation,
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

impl LearnArgs {
    fn options(&self, dataset: &Dataset, architectures: Vec<Architecture>, repetitions: usize) -> Result<EvalOptions> {
        Ok(EvalOptions {
            architectures,
            band_sets: dataset.inputs(self.bands.as_deref())?,
            repetitions,
            test_fraction: dataset.test_fraction(),
            classifier: Recipe {
                epochs: self.epochs,
                batch_size: self.batch_size,
                learning_rate: self.learning_rate,
                optimiser: self.optimiser,
                weight_decay: self.weight_decay,
                augmentation: self.augmentation,
                ..Recipe::classifier()
            },
            unet: Recipe {
                epochs: self.unet_epochs,
                batch_size: self.unet_batch_size,
                width: self.unet_width,
                augmentation: self.augmentation,
                ..Recipe::unet()
            },
            threshold: self.threshold,
            seed: self.seed,
            perturbations: Vec::new(),
        })
    }

    fn out_dir(&self) -> PathBuf {
        self.out.clone().unwrap_or_else(|| self.dataset.join("learn"))
    }
}

fn epoch_bar(quiet: bool, total: u64) -> ProgressBar {
    let template = "{spinner} {msg} [{bar:30}] {pos}/{len} epochs | {elapsed_precise}, {eta} left";
    wakelab_study::progress_bar(quiet, total, template)
}

/// `wakelab eval`: Algorithm 2 on a dataset.
pub fn run_eval(eval: &EvalArgs) -> Result<()> {
    let (args, json) = (&eval.learn, eval.json);
    let dataset = Dataset::open(&args.dataset)?;
    let device = parse_device(&args.device)?;
    let options = match &eval.study {
        None => args.options(&dataset, eval.arch.clone(), eval.repetitions)?,
        Some(name) => wakelab_study::stages::study_eval_options(name, &dataset, &eval.arch, args.bands.as_deref())?,
    };
    options.validate()?;
    let bar = epoch_bar(args.quiet, total_epochs(&options));
    let dir = args.out_dir();
    let (evaluation, fusion) = evaluate_into(&dataset, &options, &dir, &device, &mut |p| {
        bar.inc(1);
        bar.set_message(p.describe(options.repetitions));
    })?;
    bar.finish_and_clear();
    if json {
        println!("{}", serde_json::to_string_pretty(&evaluation.summaries)?);
    } else {
        print!("{}", summary_table(&evaluation.summaries));
        if !fusion.is_empty() {
            println!("\ndecision-level fusion (Bayes weights from each source's training images):");
            print!(
                "{}",
                summary_table(&fusion.iter().map(|(s, _)| s.clone()).collect::<Vec<_>>())
            );
        }
        eprintln!(
            "wrote outputs, metrics, curves, fusion and models into {}",
            dir.display()
        );
    }
    Ok(())
}

/// `wakelab train`: one detector on the dataset's training split, tested on its test split.
pub fn run_train(train: &TrainArgs) -> Result<()> {
    let (args, architecture, model) = (&train.learn, train.arch, train.model.as_deref());
    let dataset = Dataset::open(&args.dataset)?;
    let device = parse_device(&args.device)?;
    let options = args.options(&dataset, vec![architecture], 1)?;
    options.validate()?;
    let [bands] = &options.band_sets[..] else {
        anyhow::bail!("--bands: `train` trains one input (a band, or bands joined by +)");
    };
    let bar = epoch_bar(args.quiet, total_epochs(&options));
    let trained = train_into(
        &dataset,
        architecture,
        bands,
        &options,
        &args.out_dir(),
        model,
        &device,
        &mut |network, e| {
            bar.inc(1);
            bar.set_message(format!("{bands} {network} {}", e.describe()));
        },
    )?;
    bar.finish_and_clear();
    eprintln!(
        "saved {} (PyTorch layout: {})",
        trained.path.display(),
        trained.export.display()
    );
    if let Some((n, c, auc)) = trained.test {
        let auc = auc.map(|a| format!("{a:.3}")).unwrap_or_else(|| "-".into());
        println!("test split ({n} scenes): {c}, AUC {auc}");
    }
    Ok(())
}

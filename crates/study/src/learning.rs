//! The learning commands' work on a dataset directory (`wakelab eval`, `wakelab train`): Algorithm
//! 2 with its files and the decision-level fusion of its outputs, one detector trained and
//! tested, and the U-Net mask of `wakelab detect` as a PNG.

use crate::output::{csv, write_evaluation};
use crate::Result;
use std::path::{Path, PathBuf};
use wakelab_core::io::write_atomically;
use wakelab_core::WakelabError;
use wakelab_learn::data::Dataset;
use wakelab_learn::device::Device;
use wakelab_learn::evaluate::{
    detect, evaluate, load_examples, train_detector, which_training, CurvePoint, EvalOptions, EvalProgress, Evaluation,
    Summary,
};
use wakelab_learn::metrics::{roc_auc, Confusion};
use wakelab_learn::models::Architecture;
use wakelab_learn::store::save_detector;
use wakelab_learn::train::EpochRecord;
use wakelab_schema::band::Input;
use wakelab_schema::split::{Network, Split};

/// Epochs one evaluation trains in all (for a progress bar).
pub fn total_epochs(o: &EvalOptions) -> u64 {
    let per_rep: usize = o
        .architectures
        .iter()
        .map(|a| o.classifier.epochs + if *a == Architecture::Unet { o.unet.epochs } else { 0 })
        .sum();
    (per_rep * o.repetitions * o.band_sets.len()) as u64
}

/// A fusion row of Tables 5.1-5.3 with Dempster-Shafer's mean conflict (0 for Bayes).
#[derive(serde::Serialize)]
struct FusionRow {
    #[serde(flatten)]
    summary: Summary,
    mean_conflict: f64,
}

/// Algorithm 2 on `dataset` with `options`, its files written into `dir`, and the decision-level
/// fusion of the single bands (spec 5.1-5.2, 5.4) from the kept outputs: the evaluation and the
/// fusion rows with their mean conflict.
pub fn evaluate_into(
    dataset: &Dataset,
    options: &EvalOptions,
    dir: &Path,
    device: &Device,
    progress: &mut (dyn FnMut(&EvalProgress) + Send),
) -> Result<(Evaluation, Vec<(Summary, f64)>)> {
    let evaluation = evaluate(dataset, options, device, progress)?;
    write_evaluation(dir, &evaluation)?;
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
    Ok((evaluation, fusion))
}

/// A trained detector's files and its score on the test split.
pub struct Trained {
    pub path: PathBuf,
    /// The same weights in PyTorch's layout.
    pub export: PathBuf,
    /// Test scenes, their confusion counts and ROC AUC (None without a test split).
    pub test: Option<(usize, Confusion, Option<f64>)>,
}

/// One detector of `architecture` on `input`, trained on the dataset's training split
/// and tested on its test split; saved at `model` (default `dir/<input>_<arch>.safetensors`)
/// with its training curve beside it.
#[allow(clippy::too_many_arguments)]
pub fn train_into(
    dataset: &Dataset,
    architecture: Architecture,
    input: &Input,
    options: &EvalOptions,
    dir: &Path,
    model: Option<&Path>,
    device: &Device,
    progress: &mut dyn FnMut(Network, &EpochRecord),
) -> Result<Trained> {
    let split = |split: Split| -> Vec<usize> {
        (0..dataset.records.len())
            .filter(|&i| dataset.records[i].split.as_ref() == Some(&split))
            .collect()
    };
    options.check_dataset(dataset)?;
    let (train_idx, test_idx) = (split(Split::Train), split(Split::Test));
    if train_idx.is_empty() {
        anyhow::bail!("{}: no scenes in the training split", dataset.dir.display());
    }
    let train = load_examples(dataset, input, &train_idx)?;
    // the test images are read before training too: a bad one refuses the run before any output
    let test_examples = load_examples(dataset, input, &test_idx)?;
    let mut curves = Vec::new();
    let name = input.name();
    let detector = train_detector(
        architecture,
        &train,
        options,
        options.seed,
        device,
        &mut |network, e| {
            progress(network, e);
            curves.push(CurvePoint {
                bands: input.clone(),
                network,
                repetition: 0,
                epoch: e.clone(),
            });
        },
    )
    .map_err(|e| which_training(e, input, architecture, 0))?;
    let info = options.model_info(architecture, input, dataset);
    std::fs::create_dir_all(dir).map_err(|e| WakelabError::io(dir, e))?;
    let path = model
        .map(Path::to_path_buf)
        .unwrap_or_else(|| dir.join(format!("{name}_{architecture}.safetensors")));
    let (path, export) = save_detector(&detector, &info, &path)?;
    write_atomically(dir.join(format!("{name}_{architecture}_curve.csv")), &csv(&curves)?)?;
    let test = if test_examples.is_empty() {
        None
    } else {
        let test = test_examples;
        let outputs = detect(&detector, architecture, &test, device);
        let labels: Vec<u8> = test.iter().map(|e| e.label).collect();
        let c = Confusion::from_outputs(&outputs, &labels, options.threshold);
        Some((test.len(), c, roc_auc(&outputs, &labels)))
    };
    Ok(Trained { path, export, test })
}

/// What `wakelab train` and `wakelab eval` are asked to do: the dataset, the inputs
/// (comma-separated; None: every band), both recipes, the threshold, the seed, the backend and
/// the output folder (None: `DATASET/learn`).
pub struct LearnRequest {
    pub dataset: PathBuf,
    pub bands: Option<String>,
    pub classifier: wakelab_learn::train::Recipe,
    pub unet: wakelab_learn::train::Recipe,
    pub threshold: f64,
    pub seed: u64,
    pub device: String,
    pub out: Option<PathBuf>,
}

impl LearnRequest {
    /// The evaluation options of this request for `architectures` and `repetitions`.
    fn options(&self, dataset: &Dataset, architectures: Vec<Architecture>, repetitions: usize) -> Result<EvalOptions> {
        let options = EvalOptions {
            architectures,
            band_sets: dataset.inputs(self.bands.as_deref())?,
            repetitions,
            test_fraction: dataset.test_fraction(),
            classifier: self.classifier.clone(),
            unet: self.unet.clone(),
            threshold: self.threshold,
            seed: self.seed,
            perturbations: Vec::new(),
        };
        options.validate()?;
        Ok(options)
    }

    fn out_dir(&self) -> PathBuf {
        self.out.clone().unwrap_or_else(|| self.dataset.join("learn"))
    }
}

/// A finished `wakelab eval`: the evaluation, the decision-level fusion rows with their mean
/// conflict, and the folder written.
pub struct Evaluated {
    pub evaluation: Evaluation,
    pub fusion: Vec<(Summary, f64)>,
    pub dir: PathBuf,
}

/// `wakelab eval`: Algorithm 2 on the request's dataset for `architectures` and `repetitions`
/// (or with the recipe of `study`'s `[learning]` table), its files written; `progress` hears
/// (epochs in all, what was just trained) after every epoch.
pub fn eval_command(
    request: &LearnRequest,
    architectures: &[Architecture],
    repetitions: usize,
    study: Option<&str>,
    progress: &mut (dyn FnMut(u64, String) + Send),
) -> Result<Evaluated> {
    let dataset = Dataset::open(&request.dataset)?;
    let device = wakelab_learn::device::parse_device(&request.device)?;
    let options = match study {
        None => request.options(&dataset, architectures.to_vec(), repetitions)?,
        Some(name) => {
            let options = crate::plan::study_eval_options(name, &dataset, architectures, request.bands.as_deref())?;
            options.validate()?;
            options
        }
    };
    let total = total_epochs(&options);
    let dir = request.out_dir();
    let (evaluation, fusion) = evaluate_into(&dataset, &options, &dir, &device, &mut |p| {
        progress(total, p.describe(options.repetitions))
    })?;
    Ok(Evaluated {
        evaluation,
        fusion,
        dir,
    })
}

/// `wakelab train`: one detector of `architecture` on the request's one input, saved at `model`
/// (None: in the output folder) and tested; `progress` hears (epochs in all, what was just
/// trained) after every epoch.
pub fn train_command(
    request: &LearnRequest,
    architecture: Architecture,
    model: Option<&Path>,
    progress: &mut dyn FnMut(u64, String),
) -> Result<Trained> {
    let dataset = Dataset::open(&request.dataset)?;
    let device = wakelab_learn::device::parse_device(&request.device)?;
    let options = request.options(&dataset, vec![architecture], 1)?;
    let [bands] = &options.band_sets[..] else {
        anyhow::bail!("--bands: `train` trains one input (a band, or bands joined by +)");
    };
    let total = total_epochs(&options);
    let dir = request.out_dir();
    train_into(
        &dataset,
        architecture,
        bands,
        &options,
        &dir,
        model,
        &device,
        &mut |network, e| progress(total, format!("{bands} {network} {}", e.describe())),
    )
}

/// A mask of values in [0, 1] as an 8-bit grey PNG (0 black, 1 white), written atomically.
pub fn write_mask_png(path: &Path, mask: &ndarray::Array2<f32>) -> Result<()> {
    let (h, w) = mask.dim();
    let values: Vec<f32> = mask.iter().copied().collect();
    wakelab_core::io::geotiff::write_quicklook(path, &values, h, w, 0.0, 1.0)?;
    Ok(())
}

/// Summaries as an aligned text table: input, architecture, repetitions, MCC and accuracy with
/// their spread, F1, ROC AUC and the confusion counts.
pub fn summary_table(summaries: &[Summary]) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let w = summaries
        .iter()
        .map(|s| s.bands.to_string().len())
        .max()
        .unwrap_or(5)
        .max(5);
    writeln!(
        out,
        "{:<w$} {:<5} {:>5} {:>14} {:>16} {:>6} {:>6}  TP/TN/FP/FN",
        "input", "arch", "reps", "MCC", "accuracy", "F1", "AUC"
    )
    .expect("writing to a string");
    for s in summaries {
        writeln!(
            out,
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
        )
        .expect("writing to a string");
    }
    out
}

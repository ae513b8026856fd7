//! The stages of `wakelab run`, each reused when its inputs have not changed.

use crate::held_out::held_out_stages;
use crate::output::{csv, write_evaluation};
pub use crate::plan::{eval_options, study_eval_options, study_inputs};
use crate::Result;
use crate::{Display, StageTime};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::time::Instant;
use wakelab_core::io::write_atomically;
use wakelab_core::WakelabError;
use wakelab_dataset::learning::LearningPlan;
use wakelab_dataset::study::Study;
use wakelab_fusion::decision::{fuse_all, FusedOutput};
use wakelab_learn::data::Dataset;
use wakelab_learn::evaluate::{evaluate, summarise, CurvePoint, EvalOptions, Output, Summary};
use wakelab_learn::masks::MaskScore;
use wakelab_learn::models::Architecture;
use wakelab_learn::robustness::Perturbation;
use wakelab_schema::band::Input;
use wakelab_schema::split::{Network, Split};

/// Everything a study run produced, for the report.
pub struct StudyRun {
    pub dataset: Dataset,
    pub plan: LearningPlan,
    /// Inputs evaluated: single bands, then the feature-level fusions.
    pub inputs: Vec<Input>,
    /// Kept outputs of every input: train, test and perturbed test splits.
    pub outputs: Vec<Output>,
    pub curves: Vec<CurvePoint>,
    /// The U-Net masks' IoU on the test wake scenes of every input.
    pub mask_scores: Vec<MaskScore>,
    /// Test metrics per input and architecture (Tables 4.4-4.6, 5.1's feature-level rows).
    pub summaries: Vec<Summary>,
    pub perturbations: Vec<Perturbation>,
    /// The held-out axis's values, one per group, and the held-out outputs.
    pub held_out_groups: Vec<String>,
    pub held_out: Vec<Output>,
    /// The held-out geometry bins ("heading in [0, 90)") and their outputs.
    pub held_out_geometry_groups: Vec<String>,
    pub held_out_geometry: Vec<Output>,
    /// Decision-level fusion: fused outputs and their metrics with the mean conflict.
    pub fused: Vec<FusedOutput>,
    pub fusion: Vec<(Summary, f64)>,
    pub times: Vec<StageTime>,
    /// When the run started (UTC) and the device it trained on, for the report's header.
    pub started: String,
    pub device: String,
}

/// A learning stage's results as cached beside its files.
#[derive(Serialize, Deserialize)]
pub(crate) struct CachedStage {
    pub key: String,
    pub seconds: f64,
    pub outputs: Vec<Output>,
    pub curves: Vec<CurvePoint>,
    /// Required: the key does not hash wakelab's code, so a cache written before mask scores
    /// existed must fail to read (and be recomputed) rather than give an empty IoU table.
    pub mask_scores: Vec<MaskScore>,
}

pub(crate) fn read_cache(path: &Path, key: &str) -> Option<CachedStage> {
    let text = std::fs::read_to_string(path).ok()?;
    let cached: CachedStage = serde_json::from_str(&text).ok()?;
    (cached.key == key).then_some(cached)
}

/// Relative cost of one U-Net image pass against one classifier image pass (measured at 64 x 64
/// on the CPU backend: width 16 about 40x), for the progress display's time left.
fn unet_cost(width: usize) -> u64 {
    (40 * width / 16).max(1) as u64
}

/// Work units of training `options` on `images` training images (for the progress display).
pub(crate) fn training_units(options: &EvalOptions, images: usize, runs: usize) -> u64 {
    let per_run: u64 = options
        .architectures
        .iter()
        .map(|a| {
            options.classifier.epochs as u64
                + match a {
                    Architecture::Unet => options.unet.epochs as u64 * unet_cost(options.unet.width),
                    _ => 0,
                }
        })
        .sum();
    per_run * (images * runs * options.band_sets.len()) as u64
}

pub(crate) fn stage_time(stage: &str, start: Instant, computed: Option<f64>) -> StageTime {
    let seconds = start.elapsed().as_secs_f64();
    StageTime {
        stage: stage.to_string(),
        seconds,
        computed_seconds: computed.unwrap_or(seconds),
        reused: computed.is_some(),
    }
}

/// Stage 1: the dataset (finished scenes are skipped).
fn dataset_stage(study: &Study, dir: &Path, display: &Display) -> Result<(Dataset, StageTime)> {
    let start = Instant::now();
    let pairs = study.pairs()?.len();
    display.stage(1, "dataset", 2 * pairs as u64);
    let times = wakelab_dataset::render_dataset(study, dir, None, None, &|p| match p {
        wakelab_dataset::Progress::Hydro { done, total } => display.set(0, format!("wake simulations {done}/{total}")),
        wakelab_dataset::Progress::Scene { done, total } => {
            display.set(2 * done as u64, format!("scene pairs {done}/{total}"))
        }
    })?;
    wakelab_dataset::write_manifest(study, dir)?;
    let reused = times.scenes_rendered == 0;
    let previous: Option<f64> = std::fs::read_to_string(dir.join("timing.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .and_then(|v| v["wall"].as_f64());
    let mut time = stage_time("dataset", start, if reused { previous } else { None });
    if reused && previous.is_none() {
        time.reused = true;
    }
    if !reused {
        let mut v = serde_json::to_value(&times)?;
        v["wall"] = time.seconds.into();
        write_atomically(dir.join("timing.json"), serde_json::to_string_pretty(&v)?.as_bytes())?;
    }
    display.println(format!(
        "dataset: {} scenes ({} rendered, {} reused) in {:.1} s",
        2 * pairs,
        times.scenes_rendered,
        times.scenes_skipped,
        time.seconds
    ));
    Ok((Dataset::open(dir)?, time))
}

/// What the learning stages share.
pub(crate) struct Context<'a> {
    pub dataset: &'a Dataset,
    options: &'a EvalOptions,
    /// Hash of the dataset's manifest (part of every stage key).
    manifest_hash: &'a str,
    device: &'a wakelab_learn::device::Device,
    display: &'a Display,
}

type ContextParts<'a> = (
    &'a Dataset,
    &'a EvalOptions,
    &'a str,
    &'a wakelab_learn::device::Device,
    &'a Display,
);

impl<'a> Context<'a> {
    fn new(
        dataset: &'a Dataset,
        options: &'a EvalOptions,
        manifest_hash: &'a str,
        device: &'a wakelab_learn::device::Device,
        display: &'a Display,
    ) -> Self {
        Self {
            dataset,
            options,
            manifest_hash,
            device,
            display,
        }
    }

    pub(crate) fn parts(&self) -> ContextParts<'a> {
        (
            self.dataset,
            self.options,
            self.manifest_hash,
            self.device,
            self.display,
        )
    }
}

/// What the learning stage gives the report: outputs, curves and mask scores of every input.
type Learned = (Vec<Output>, Vec<CurvePoint>, Vec<MaskScore>);

/// Stage 2: Algorithm 2 on every input, each input cached on its own.
fn learning_stage(cx: &Context, inputs: &[Input], dir: &Path) -> Result<(Learned, StageTime)> {
    let (dataset, options, manifest_hash, device, display) = cx.parts();
    let start = Instant::now();
    let train_images = ((1.0 - options.test_fraction) * dataset.records.len() as f64).round() as usize;
    let mut all = options.clone();
    all.band_sets = inputs.to_vec();
    display.stage(2, "learning", training_units(&all, train_images, options.repetitions));
    let (mut outputs, mut curves, mut mask_scores) = (Vec::new(), Vec::new(), Vec::new());
    let mut computed_seconds = 0.0;
    let mut all_reused = true;
    for input in inputs {
        let name = input.name();
        let mut one = options.clone();
        one.band_sets = vec![input.clone()];
        let units = training_units(&one, train_images, options.repetitions);
        let key = stage_key(manifest_hash, &one);
        let stage_dir = dir.join(&name);
        let cache = stage_dir.join("evaluation.json");
        if let Some(c) = read_cache(&cache, &key) {
            display.advance(units, format!("{name}: reused"));
            computed_seconds += c.seconds;
            outputs.extend(c.outputs);
            curves.extend(c.curves);
            mask_scores.extend(c.mask_scores);
            continue;
        }
        all_reused = false;
        let t = Instant::now();
        let unet = unet_cost(options.unet.width);
        let evaluation = evaluate(dataset, &one, device, &mut |p| {
            let per_image = if p.network == Network::Segmenter { unet } else { 1 };
            display.advance(per_image * train_images as u64, p.describe(options.repetitions));
        })?;
        write_evaluation(&stage_dir, &evaluation)?;
        let seconds = t.elapsed().as_secs_f64();
        computed_seconds += seconds;
        let cached = CachedStage {
            key,
            seconds,
            outputs: evaluation.outputs,
            curves: evaluation.curves,
            mask_scores: evaluation.mask_scores,
        };
        write_atomically(&cache, serde_json::to_string(&cached)?.as_bytes())?;
        display.println(format!("learning: {name} done in {seconds:.1} s"));
        outputs.extend(cached.outputs);
        curves.extend(cached.curves);
        mask_scores.extend(cached.mask_scores);
    }
    let time = stage_time("learning", start, all_reused.then_some(computed_seconds));
    Ok(((outputs, curves, mask_scores), time))
}

pub(crate) fn fnv_hex(text: &str) -> String {
    format!("{:016x}", wakelab_dataset::fnv(text))
}

/// What a learning stage's results depend on: the dataset's manifest, the options and wakelab.
pub(crate) fn stage_key(manifest_hash: &str, options: &EvalOptions) -> String {
    fnv_hex(&format!("{manifest_hash} {options:?} {}", env!("CARGO_PKG_VERSION")))
}

/// What the learning stages of `plan` on `dataset` need: the evaluation options, the inputs and
/// the manifest's hash.
fn learning_setup(plan: &LearningPlan, dataset: &Dataset) -> Result<(EvalOptions, Vec<Input>, String)> {
    Ok((
        eval_options(plan, dataset),
        study_inputs(plan, dataset),
        manifest_hash(dataset)?,
    ))
}

/// The hash of a dataset's manifest, part of every learning stage's key.
fn manifest_hash(dataset: &Dataset) -> Result<String> {
    let manifest_path = dataset.dir.join("manifest.json");
    let manifest = std::fs::read_to_string(&manifest_path).map_err(|e| WakelabError::io(&manifest_path, e))?;
    Ok(fnv_hex(&manifest))
}

/// One learning stage of a study run on its own, on a dataset already rendered and merged (what
/// the jobs of `wakelab run --emit-slurm` run side by side); a plain `wakelab run` afterwards
/// reuses its results.
#[derive(Debug, Clone, PartialEq)]
pub enum OneStage {
    /// Algorithm 2 on one input (stage 2).
    Learning(Input),
    /// The held-out environment and geometry tests (stage 3).
    HeldOut,
}

impl OneStage {
    /// The stage that `wakelab run --stage learning|held-out [--input NAME]` names (`held_out`
    /// false: learning), or none without `--stage`; an error for a missing or misplaced input.
    pub fn from_flags(stage: Option<bool>, input: Option<&str>) -> Result<Option<Self>> {
        Ok(match (stage, input) {
            (None, None) => None,
            (None, Some(_)) => anyhow::bail!("--input names the input of `--stage learning`"),
            (Some(false), None) => anyhow::bail!("--stage learning needs --input NAME (e.g. S or S+X)"),
            (Some(false), Some(text)) => Some(OneStage::Learning(text.parse().map_err(|e| {
                anyhow::anyhow!("--input {text}: {e}; a band (S, C, X, MWIR, LWIR) or bands joined by +")
            })?)),
            (Some(true), None) => Some(OneStage::HeldOut),
            (Some(true), Some(_)) => anyhow::bail!("--input belongs to `--stage learning`, not held-out"),
        })
    }
}

/// Run `stage` of `study` in the run directory `dir` and cache its results there.
pub fn run_one_stage(
    study: &Study,
    dir: &Path,
    stage: &OneStage,
    device: &wakelab_learn::device::Device,
    display: &Display,
) -> Result<StageTime> {
    let dataset_dir = dir.join("dataset");
    if !dataset_dir.join("manifest.json").exists() {
        anyhow::bail!(
            "{}: no manifest.json; render and merge the dataset first (`wakelab dataset --study ... --out {} \
             [--shard K/N] [--merge]`)",
            dataset_dir.display(),
            dataset_dir.display()
        );
    }
    let dataset = Dataset::open(&dataset_dir)?;
    let plan = &study.learning;
    let (options, inputs, manifest_hash) = learning_setup(plan, &dataset)?;
    let cx = Context::new(&dataset, &options, &manifest_hash, device, display);
    Ok(match stage {
        OneStage::Learning(input) => {
            if !inputs.contains(input) {
                let names: Vec<String> = inputs.iter().map(Input::name).collect();
                anyhow::bail!(
                    "--input {}: not an input of study \"{}\"; its inputs are {}",
                    input.name(),
                    study.study.name,
                    names.join(", ")
                );
            }
            learning_stage(&cx, std::slice::from_ref(input), &dir.join("learn"))?.1
        }
        OneStage::HeldOut => {
            let singles: Vec<Input> = inputs.into_iter().filter(|i| !i.is_fused()).collect();
            let [environment, geometry] = held_out_stages(&cx, plan, &singles, &dir.join("learn"))?.2;
            StageTime {
                stage: "held-out".into(),
                seconds: environment.seconds + geometry.seconds,
                computed_seconds: environment.computed_seconds + geometry.computed_seconds,
                reused: environment.reused && geometry.reused,
            }
        }
    })
}

/// Run stages 1-4.
pub fn run_stages(
    study: &Study,
    dir: &Path,
    device: &wakelab_learn::device::Device,
    display: &Display,
) -> Result<StudyRun> {
    let (dataset, dataset_time) = dataset_stage(study, &dir.join("dataset"), display)?;
    let plan = study.learning.clone();
    let (options, inputs, manifest_hash) = learning_setup(&plan, &dataset)?;
    let singles: Vec<Input> = inputs.iter().filter(|i| !i.is_fused()).cloned().collect();
    let cx = Context::new(&dataset, &options, &manifest_hash, device, display);
    let ((outputs, curves, mask_scores), learning_time) = learning_stage(&cx, &inputs, &dir.join("learn"))?;
    let ((held_out_groups, held_out), (held_out_geometry_groups, held_out_geometry), [held_out_time, geometry_time]) =
        held_out_stages(&cx, &plan, &singles, &dir.join("learn"))?;
    let start = Instant::now();
    display.stage(4, "fusion", 1);
    let single_outputs: Vec<Output> = outputs
        .iter()
        .filter(|o| !o.bands.is_fused() && matches!(o.split, Split::Train | Split::Test))
        .cloned()
        .collect();
    let (fused, fusion) = fuse_all(&single_outputs, plan.threshold);
    let fusion_dir = dir.join("fusion");
    std::fs::create_dir_all(&fusion_dir).map_err(|e| WakelabError::io(&fusion_dir, e))?;
    write_atomically(fusion_dir.join("fusion_outputs.csv"), &csv(&fused)?)?;
    let fusion_time = stage_time("fusion", start, None);
    let summaries = summarise(&outputs, plan.threshold);
    Ok(StudyRun {
        dataset,
        plan,
        inputs,
        outputs,
        curves,
        mask_scores,
        summaries,
        perturbations: options.perturbations,
        held_out_groups,
        held_out,
        held_out_geometry_groups,
        held_out_geometry,
        fused,
        fusion,
        times: vec![dataset_time, learning_time, held_out_time, geometry_time, fusion_time],
        started: String::new(),
        device: String::new(),
    })
}

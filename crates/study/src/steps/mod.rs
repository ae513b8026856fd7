//! The named steps of `wakelab run` (dataset, learning, held-out, fusion, scan, environments, ships,
//! calibration; the report renders what they wrote), each reused when its inputs have not changed.

pub mod calibration;
pub(crate) mod context;
pub mod environments;
mod held_out;
pub(crate) mod open_sea;
pub mod ship_windows;
pub mod ships;
mod study_run;
pub mod whole_scene;

pub use study_run::StudyRun;

use crate::output::{csv, write_evaluation};
pub use crate::plan::{eval_options, study_eval_options, study_inputs};
use crate::Result;
use crate::{Display, StepTime};
use context::{fnv_hex, read_cache, step_key, step_time, training_units, unet_cost, CachedStep, Context};
use held_out::held_out_steps;
use std::path::Path;
use std::time::Instant;
use wakelab_core::io::write_atomically;
use wakelab_core::WakelabError;
use wakelab_dataset::learning::LearningPlan;
use wakelab_dataset::study::Study;
use wakelab_fusion::decision::fuse_all;
use wakelab_learn::data::Dataset;
use wakelab_learn::evaluate::{evaluate, summarise, CurvePoint, EvalOptions, Output};
use wakelab_learn::masks::MaskScore;
use wakelab_schema::band::Input;
use wakelab_schema::split::{Network, Split};

/// The dataset step (finished scenes are skipped).
fn dataset_step(study: &Study, dir: &Path, display: &Display) -> Result<(Dataset, StepTime)> {
    let start = Instant::now();
    let pairs = study.pairs()?.len();
    display.step(1, "dataset", pairs as u64, "pairs");
    display.set(0, "simulating the study's wakes".into());
    let times = wakelab_dataset::render_dataset(study, dir, None, None, &|p| match p {
        wakelab_dataset::Progress::Hydro { done, total } => {
            display.phase("wakes", done as u64, total as u64, "wakes simulated".into())
        }
        wakelab_dataset::Progress::Scene { done, total } => {
            display.phase("pairs", done as u64, total as u64, "scene pairs rendered".into())
        }
    })?;
    wakelab_dataset::write_manifest(study, dir)?;
    let reused = times.scenes_rendered == 0;
    let previous: Option<f64> = std::fs::read_to_string(dir.join("timing.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .and_then(|v| v["wall"].as_f64());
    let mut time = step_time("dataset", start, if reused { previous } else { None });
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

/// What the learning step gives the report: outputs, curves and mask scores of every input.
type Learned = (Vec<Output>, Vec<CurvePoint>, Vec<MaskScore>);

/// The learning step: Algorithm 2 on every input, each input cached on its own.
fn learning_step(cx: &Context, inputs: &[Input], dir: &Path) -> Result<(Learned, StepTime)> {
    let (dataset, options, manifest_hash, device, display) = cx.parts();
    let start = Instant::now();
    let train_images = ((1.0 - options.test_fraction) * dataset.records.len() as f64).round() as usize;
    let mut all = options.clone();
    all.band_sets = inputs.to_vec();
    display.step(
        2,
        "learning",
        training_units(&all, train_images, options.repetitions),
        "image-epochs",
    );
    let (mut outputs, mut curves, mut mask_scores) = (Vec::new(), Vec::new(), Vec::new());
    let mut computed_seconds = 0.0;
    let mut all_reused = true;
    for input in inputs {
        let name = input.name();
        let mut one = options.clone();
        one.band_sets = vec![input.clone()];
        let units = training_units(&one, train_images, options.repetitions);
        let key = step_key(manifest_hash, &one);
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
        let cached = CachedStep {
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
    let time = step_time("learning", start, all_reused.then_some(computed_seconds));
    Ok(((outputs, curves, mask_scores), time))
}

/// What the learning steps of `plan` on `dataset` need: the evaluation options, the inputs and
/// the manifest's hash.
fn learning_setup(plan: &LearningPlan, dataset: &Dataset) -> Result<(EvalOptions, Vec<Input>, String)> {
    Ok((
        eval_options(plan, dataset),
        study_inputs(plan, dataset),
        manifest_hash(dataset)?,
    ))
}

/// The hash of a dataset's manifest, part of every learning step's key.
fn manifest_hash(dataset: &Dataset) -> Result<String> {
    let manifest_path = dataset.dir.join("manifest.json");
    let manifest = std::fs::read_to_string(&manifest_path).map_err(|e| WakelabError::io(&manifest_path, e))?;
    Ok(fnv_hex(&manifest))
}

/// One learning step of a study run on its own, on a dataset already rendered and merged (what
/// the jobs of `wakelab run --emit-slurm` run side by side); a plain `wakelab run` afterwards
/// reuses its results.
#[derive(Debug, Clone, PartialEq)]
pub enum OneStep {
    /// Algorithm 2 on one input (the learning step).
    Learning(Input),
    /// The held-out environment and geometry tests (the held-out step).
    HeldOut,
}

impl OneStep {
    /// The step that `wakelab run --stage learning|held-out [--input NAME]` names (`held_out`
    /// false: learning), or none without `--stage`; an error for a missing or misplaced input.
    pub fn from_flags(stage: Option<bool>, input: Option<&str>) -> Result<Option<Self>> {
        Ok(match (stage, input) {
            (None, None) => None,
            (None, Some(_)) => anyhow::bail!("--input names the input of `--stage learning`"),
            (Some(false), None) => anyhow::bail!("--stage learning needs --input NAME (e.g. S or S+X)"),
            (Some(false), Some(text)) => Some(OneStep::Learning(text.parse().map_err(|e| {
                anyhow::anyhow!("--input {text}: {e}; a band (S, C, X, MWIR, LWIR) or bands joined by +")
            })?)),
            (Some(true), None) => Some(OneStep::HeldOut),
            (Some(true), Some(_)) => anyhow::bail!("--input belongs to `--stage learning`, not held-out"),
        })
    }
}

/// Run `step` of `study` in the run directory `dir` and cache its results there.
pub fn run_one_step(
    study: &Study,
    dir: &Path,
    step: &OneStep,
    device: &wakelab_learn::device::Device,
    display: &Display,
) -> Result<StepTime> {
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
    Ok(match step {
        OneStep::Learning(input) => {
            if !inputs.contains(input) {
                let names: Vec<String> = inputs.iter().map(Input::name).collect();
                anyhow::bail!(
                    "--input {}: not an input of study \"{}\"; its inputs are {}",
                    input.name(),
                    study.study.name,
                    names.join(", ")
                );
            }
            learning_step(&cx, std::slice::from_ref(input), &dir.join("learn"))?.1
        }
        OneStep::HeldOut => {
            let singles: Vec<Input> = inputs.into_iter().filter(|i| !i.is_fused()).collect();
            let [environment, geometry] = held_out_steps(&cx, plan, &singles, &dir.join("learn"))?.2;
            StepTime {
                step: "held-out".into(),
                seconds: environment.seconds + geometry.seconds,
                computed_seconds: environment.computed_seconds + geometry.computed_seconds,
                reused: environment.reused && geometry.reused,
            }
        }
    })
}

/// Run every step but the report: dataset, learning, held-out, fusion, scan, environments,
/// ships and calibration.
pub fn run_steps(
    study: &Study,
    dir: &Path,
    device: &wakelab_learn::device::Device,
    display: &Display,
) -> Result<StudyRun> {
    let (dataset, dataset_time) = dataset_step(study, &dir.join("dataset"), display)?;
    let plan = study.learning.clone();
    let (options, inputs, manifest_hash) = learning_setup(&plan, &dataset)?;
    let singles: Vec<Input> = inputs.iter().filter(|i| !i.is_fused()).cloned().collect();
    let cx = Context::new(&dataset, &options, &manifest_hash, device, display);
    let ((outputs, curves, mask_scores), learning_time) = learning_step(&cx, &inputs, &dir.join("learn"))?;
    let ((held_out_groups, held_out), (held_out_geometry_groups, held_out_geometry), [held_out_time, geometry_time]) =
        held_out_steps(&cx, &plan, &singles, &dir.join("learn"))?;
    let start = Instant::now();
    display.step(4, "fusion", 1, "steps");
    let single_outputs: Vec<Output> = outputs
        .iter()
        .filter(|o| !o.bands.is_fused() && matches!(o.split, Split::Train | Split::Test))
        .cloned()
        .collect();
    let (fused, fusion) = fuse_all(&single_outputs, plan.threshold);
    let fusion_dir = dir.join("fusion");
    std::fs::create_dir_all(&fusion_dir).map_err(|e| WakelabError::io(&fusion_dir, e))?;
    write_atomically(fusion_dir.join("fusion_outputs.csv"), &csv(&fused)?)?;
    let fusion_time = step_time("fusion", start, None);
    let summaries = summarise(&outputs, plan.threshold);
    let mut run = StudyRun {
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
    };
    display.step(5, "scan", 1, "steps");
    let scan_time = whole_scene::scan_step(dir, study, &run, &manifest_hash)?;
    display.step(6, "environments", 1, "steps");
    let environments_time = environments::environments_step(dir, study)?;
    display.step(7, "ships", 1, "steps");
    let ships_time = ships::ships_step(dir, study)?;
    display.step(8, "calibration", 1, "steps");
    let calibration_time = calibration::calibration_step(dir, study, &run)?;
    run.times
        .extend([scan_time, environments_time, ships_time, calibration_time]);
    Ok(run)
}

//! The stages of `wakelab run`, each reused when its inputs have not changed.

use crate::output::{csv, write_evaluation};
use crate::Result;
use crate::{Display, StageTime};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;
use wakelab_core::io::write_atomically;
use wakelab_core::WakelabError;
use wakelab_data::learning::LearningPlan;
use wakelab_data::study::Study;
use wakelab_fusion::decision::{fuse_all, FusedOutput};
use wakelab_learn::data::Dataset;
use wakelab_learn::evaluate::{evaluate, evaluate_held_out, summarise, CurvePoint, EvalOptions, Output, Summary};
use wakelab_learn::models::Architecture;
use wakelab_learn::robustness::Perturbation;
use wakelab_learn::train::Recipe;
use wakelab_schema::axes::Combination;
use wakelab_schema::band::Input;
use wakelab_schema::split::{Network, Split};

/// Architectures trained with an environment held out: the two plain classifiers (the U-Net's
/// "unet" would double the stage's time; its robustness shows in the perturbed test images).
pub const HELD_OUT_ARCHITECTURES: [Architecture; 2] = [Architecture::Base, Architecture::Cls];

/// Everything a study run produced, for the report.
pub struct StudyRun {
    pub dataset: Dataset,
    pub plan: LearningPlan,
    /// Inputs evaluated: single bands, then the feature-level fusions.
    pub inputs: Vec<Input>,
    /// Kept outputs of every input: train, test and perturbed test splits.
    pub outputs: Vec<Output>,
    pub curves: Vec<CurvePoint>,
    /// Test metrics per input and architecture (Tables 4.4-4.6, 5.1's feature-level rows).
    pub summaries: Vec<Summary>,
    pub perturbations: Vec<Perturbation>,
    /// The held-out axis's values, one per group, and the held-out outputs.
    pub held_out_groups: Vec<String>,
    pub held_out: Vec<Output>,
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
struct CachedStage {
    key: String,
    seconds: f64,
    outputs: Vec<Output>,
    curves: Vec<CurvePoint>,
}

fn read_cache(path: &Path, key: &str) -> Option<CachedStage> {
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
fn training_units(options: &EvalOptions, images: usize, runs: usize) -> u64 {
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

/// The inputs a study's learning stage trains on: every band of the dataset alone, then the
/// plan's feature-level fusions.
pub fn study_inputs(plan: &LearningPlan, dataset: &Dataset) -> Vec<Input> {
    let bands = dataset.bands();
    let mut inputs: Vec<Input> = bands.iter().map(|&b| Input::single(b)).collect();
    inputs.extend(plan.fused_inputs(&bands));
    inputs
}

/// The evaluation options of a study's `[learning]` table.
pub fn eval_options(plan: &LearningPlan, dataset: &Dataset) -> EvalOptions {
    let mut perturbations: Vec<Perturbation> = plan
        .rotations
        .iter()
        .map(|&degrees| Perturbation::Rotate { degrees })
        .collect();
    if plan.dropped_patches > 0 {
        perturbations.push(Perturbation::DropPatches {
            patches: plan.dropped_patches,
            fraction: plan.patch_fraction,
        });
    }
    if plan.noise > 0.0 {
        perturbations.push(Perturbation::Noise { sigma: plan.noise });
    }
    EvalOptions {
        architectures: Architecture::ALL.to_vec(),
        band_sets: Vec::new(),
        repetitions: plan.repetitions,
        test_fraction: dataset.test_fraction(),
        classifier: Recipe {
            epochs: plan.epochs,
            batch_size: plan.batch_size,
            learning_rate: plan.learning_rate,
            optimiser: plan.optimiser,
            weight_decay: plan.weight_decay,
            augmentation: plan.augmentation,
            ..Recipe::classifier()
        },
        unet: Recipe {
            epochs: plan.unet_epochs,
            batch_size: plan.unet_batch_size,
            learning_rate: plan.unet_learning_rate,
            width: plan.unet_width,
            augmentation: plan.augmentation,
            ..Recipe::unet()
        },
        threshold: plan.threshold,
        seed: plan.seed,
        perturbations,
    }
}

fn stage_time(stage: &str, start: Instant, computed: Option<f64>) -> StageTime {
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
    let times = wakelab_data::run_study(study, dir, None, None, &|p| match p {
        wakelab_data::Progress::Hydro { done, total } => display.set(0, format!("wake simulations {done}/{total}")),
        wakelab_data::Progress::Scene { done, total } => {
            display.set(2 * done as u64, format!("scene pairs {done}/{total}"))
        }
    })?;
    wakelab_data::write_manifest(study, dir)?;
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
struct Context<'a> {
    dataset: &'a Dataset,
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
    fn parts(&self) -> ContextParts<'a> {
        (
            self.dataset,
            self.options,
            self.manifest_hash,
            self.device,
            self.display,
        )
    }
}

/// Stage 2: Algorithm 2 on every input, each input cached on its own.
fn learning_stage(cx: &Context, inputs: &[Input], dir: &Path) -> Result<(Vec<Output>, Vec<CurvePoint>, StageTime)> {
    let (dataset, options, manifest_hash, device, display) = cx.parts();
    let start = Instant::now();
    let train_images = ((1.0 - options.test_fraction) * dataset.records.len() as f64).round() as usize;
    let mut all = options.clone();
    all.band_sets = inputs.to_vec();
    display.stage(2, "learning", training_units(&all, train_images, options.repetitions));
    let (mut outputs, mut curves) = (Vec::new(), Vec::new());
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
        };
        write_atomically(&cache, serde_json::to_string(&cached)?.as_bytes())?;
        display.println(format!("learning: {name} done in {seconds:.1} s"));
        outputs.extend(cached.outputs);
        curves.extend(cached.curves);
    }
    let time = stage_time("learning", start, all_reused.then_some(computed_seconds));
    Ok((outputs, curves, time))
}

/// The scenes grouped by their value on the held-out axis, each value written as the manifest
/// writes it ([`Combination::value_text`]: "5", not "5.0"), numbers in numeric order.
fn held_out_groups(dataset: &Dataset, axis: &str) -> Vec<(String, Vec<usize>)> {
    group_by_value(dataset.records.iter().map(|r| &r.parameters), axis)
}

fn group_by_value<'a>(parameters: impl Iterator<Item = &'a Combination>, axis: &str) -> Vec<(String, Vec<usize>)> {
    let mut groups: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    for (i, p) in parameters.enumerate() {
        groups
            .entry(p.value_text(axis).unwrap_or_default())
            .or_default()
            .push(i);
    }
    let mut groups: Vec<(String, Vec<usize>)> = groups.into_iter().collect();
    // numbers by value (text order would put "10" before "5"), names as written
    groups.sort_by(|(a, _), (b, _)| match (a.parse::<f64>(), b.parse::<f64>()) {
        (Ok(x), Ok(y)) => x.total_cmp(&y),
        _ => a.cmp(b),
    });
    groups
}

/// Stage 3: the classifiers trained with one environment held out at a time.
fn held_out_stage(
    cx: &Context,
    plan: &LearningPlan,
    singles: &[Input],
    dir: &Path,
) -> Result<(Vec<String>, Vec<Output>, StageTime)> {
    let (dataset, options, manifest_hash, device, display) = cx.parts();
    let start = Instant::now();
    let groups = if plan.held_out.is_empty() {
        Vec::new()
    } else {
        held_out_groups(dataset, &plan.held_out)
    };
    let mut o = options.clone();
    o.architectures = HELD_OUT_ARCHITECTURES.to_vec();
    o.band_sets = singles.to_vec();
    o.perturbations = Vec::new();
    let names: Vec<String> = groups.iter().map(|(v, _)| format!("{} = {v}", plan.held_out)).collect();
    if groups.len() < 2 {
        display.println(format!(
            "held-out environments: skipped ({} has {} value(s) in this study)",
            plan.held_out,
            groups.len()
        ));
        return Ok((names, Vec::new(), stage_time("held-out environments", start, None)));
    }
    let train_images = dataset.records.len() * (groups.len() - 1) / groups.len();
    display.stage(3, "held-out", training_units(&o, train_images, groups.len()));
    let key = stage_key(manifest_hash, &o) + &fnv_hex(&format!("{names:?}"));
    let cache = dir.join("evaluation.json");
    if let Some(c) = read_cache(&cache, &key) {
        return Ok((
            names,
            c.outputs,
            stage_time("held-out environments", start, Some(c.seconds)),
        ));
    }
    let indices: Vec<Vec<usize>> = groups.into_iter().map(|(_, idx)| idx).collect();
    let outputs = evaluate_held_out(dataset, &o, &indices, device, &mut |p| {
        display.advance(train_images as u64, p.describe(indices.len()))
    })?;
    let seconds = start.elapsed().as_secs_f64();
    std::fs::create_dir_all(dir).map_err(|e| WakelabError::io(dir, e))?;
    write_atomically(dir.join("outputs.csv"), &csv(&outputs)?)?;
    let cached = CachedStage {
        key,
        seconds,
        outputs,
        curves: Vec::new(),
    };
    write_atomically(&cache, serde_json::to_string(&cached)?.as_bytes())?;
    Ok((names, cached.outputs, stage_time("held-out environments", start, None)))
}

fn fnv_hex(text: &str) -> String {
    format!("{:016x}", wakelab_data::fnv(text))
}

/// What a learning stage's results depend on: the dataset's manifest, the options and wakelab.
fn stage_key(manifest_hash: &str, options: &EvalOptions) -> String {
    fnv_hex(&format!("{manifest_hash} {options:?} {}", env!("CARGO_PKG_VERSION")))
}

/// Run stages 1-4.
pub fn run_stages(
    study: &Study,
    dir: &Path,
    device: &wakelab_learn::device::Device,
    display: &Display,
) -> Result<StudyRun> {
    let (dataset, dataset_time) = dataset_stage(study, &dir.join("dataset"), display)?;
    let manifest_path = dataset.dir.join("manifest.json");
    let manifest = std::fs::read_to_string(&manifest_path).map_err(|e| WakelabError::io(&manifest_path, e))?;
    let manifest_hash = fnv_hex(&manifest);
    let plan = study.learning.clone();
    let options = eval_options(&plan, &dataset);
    let inputs = study_inputs(&plan, &dataset);
    let singles: Vec<Input> = inputs.iter().filter(|i| !i.is_fused()).cloned().collect();
    let cx = Context {
        dataset: &dataset,
        options: &options,
        manifest_hash: &manifest_hash,
        device,
        display,
    };
    let (outputs, curves, learning_time) = learning_stage(&cx, &inputs, &dir.join("learn"))?;
    let (held_out_groups, held_out, held_out_time) =
        held_out_stage(&cx, &plan, &singles, &dir.join("learn").join("held_out"))?;
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
        summaries,
        perturbations: options.perturbations,
        held_out_groups,
        held_out,
        fused,
        fusion,
        times: vec![dataset_time, learning_time, held_out_time, fusion_time],
        started: String::new(),
        device: String::new(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use wakelab_core::WakelabConfig;

    /// Held-out groups are named as the manifest writes the values, in numeric order.
    #[test]
    fn held_out_groups_are_named_and_ordered_by_value() {
        let base = Combination::from_config(&WakelabConfig::default());
        let combos: Vec<Combination> = [3.0, 10.0, 5.0, 5.0, 7.5]
            .iter()
            .map(|&w| base.with_value("wind_speed", w).expect("a continuous axis"))
            .collect();
        let groups = group_by_value(combos.iter(), "wind_speed");
        let names: Vec<&str> = groups.iter().map(|(v, _)| v.as_str()).collect();
        assert_eq!(names, ["3", "5", "7.5", "10"]);
        assert_eq!(groups[1].1, [2, 3]);
    }
}

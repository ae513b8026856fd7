//! The held-out step of `wakelab run`: detectors trained with one group of scenes held out at a time and
//! tested on it; the groups are the values of an environment axis (`held_out`, e.g. each wind
//! speed) or bins of a geometry axis (`held_out_geometry`, e.g. thirds of the wake ages).

use super::context::{fnv_hex, read_cache, step_key, step_time, training_units, CachedStep, Context};
use crate::output::csv;
use crate::{Result, StepTime};
use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;
use wakelab_core::io::write_atomically;
use wakelab_core::WakelabError;
use wakelab_dataset::learning::LearningPlan;
use wakelab_learn::data::Dataset;
use wakelab_learn::evaluate::Output;
use wakelab_learn::held_out::evaluate_held_out;
use wakelab_learn::models::Architecture;
use wakelab_schema::axes::Combination;
use wakelab_schema::band::Input;

/// Architectures trained with an environment held out: the two plain classifiers (the U-Net's
/// "unet" would double the step's time; its robustness shows in the perturbed test images).
pub const HELD_OUT_ARCHITECTURES: [Architecture; 2] = [Architecture::Base, Architecture::Cls];

/// Architectures trained with a geometry bin held out: "base" alone, which keeps the default
/// study near its ten minutes.
pub const HELD_OUT_GEOMETRY_ARCHITECTURES: [Architecture; 1] = [Architecture::Base];

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

/// Scenes binned by their value on a continuous geometry axis: `heading` in `count` equal
/// sectors of the circle from 0 degrees, any other axis in `count` equal bins between its least
/// and largest value in the dataset; empty bins are dropped. Named "heading in [0, 90)".
fn geometry_groups<'a>(
    parameters: impl Iterator<Item = &'a Combination>,
    axis: &str,
    count: usize,
) -> Vec<(String, Vec<usize>)> {
    let values: Vec<f64> = parameters
        .map(|p| p.value_text(axis).and_then(|t| t.parse().ok()).unwrap_or(f64::NAN))
        .collect();
    if count == 0 || values.iter().any(|v| !v.is_finite()) {
        return Vec::new();
    }
    let (low, high, values) = if axis == "heading" {
        (
            0.0,
            360.0,
            values.iter().map(|v| v.rem_euclid(360.0)).collect::<Vec<f64>>(),
        )
    } else {
        let low = values.iter().copied().fold(f64::INFINITY, f64::min);
        let high = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        (low, high, values)
    };
    let width = (high - low) / count as f64;
    let mut bins: Vec<Vec<usize>> = vec![Vec::new(); count];
    for (i, v) in values.iter().enumerate() {
        let k = if width > 0.0 {
            ((v - low) / width).floor() as usize
        } else {
            0
        };
        bins[k.min(count - 1)].push(i);
    }
    bins.into_iter()
        .enumerate()
        .filter(|(_, idx)| !idx.is_empty())
        .map(|(k, idx)| {
            let (a, b) = (low + width * k as f64, low + width * (k + 1) as f64);
            let close = if k + 1 == count && axis != "heading" { ']' } else { ')' };
            (format!("{axis} in [{}, {}{close}", round_label(a), round_label(b)), idx)
        })
        .collect()
}

/// A bin edge as a label: at most one decimal.
fn round_label(v: f64) -> String {
    let r = (v * 10.0).round() / 10.0;
    format!("{r}")
}

/// One held-out test: scenes grouped, each group in turn tested on detectors trained without it.
struct HeldOutTest<'a> {
    /// The step's name in the wall-time table.
    stage: &'static str,
    /// What the groups are (for the skip message).
    what: String,
    groups: Vec<(String, Vec<usize>)>,
    architectures: &'a [Architecture],
}

/// The held-out step: detectors trained with one group of scenes held out at a time.
fn held_out_step(
    cx: &Context,
    test: HeldOutTest,
    singles: &[Input],
    dir: &Path,
) -> Result<(Vec<String>, Vec<Output>, StepTime)> {
    let (dataset, options, manifest_hash, device, display) = cx.parts();
    let start = Instant::now();
    let HeldOutTest {
        stage,
        what,
        groups,
        architectures,
    } = test;
    let mut o = options.clone();
    o.architectures = architectures.to_vec();
    o.band_sets = singles.to_vec();
    o.perturbations = Vec::new();
    let names: Vec<String> = groups.iter().map(|(v, _)| v.clone()).collect();
    if groups.len() < 2 {
        display.println(format!(
            "{stage}: skipped ({what} gives {} group(s) in this study)",
            groups.len()
        ));
        return Ok((names, Vec::new(), step_time(stage, start, None)));
    }
    let train_images = dataset.records.len() * (groups.len() - 1) / groups.len();
    display.step(3, stage, training_units(&o, train_images, groups.len()), "image-epochs");
    let key = step_key(manifest_hash, &o) + &fnv_hex(&format!("{groups:?}"));
    let cache = dir.join("evaluation.json");
    if let Some(c) = read_cache(&cache, &key) {
        return Ok((names, c.outputs, step_time(stage, start, Some(c.seconds))));
    }
    let indices: Vec<Vec<usize>> = groups.into_iter().map(|(_, idx)| idx).collect();
    let outputs = evaluate_held_out(dataset, &o, &indices, device, &mut |p| {
        display.advance(train_images as u64, p.describe(indices.len()))
    })?;
    let seconds = start.elapsed().as_secs_f64();
    std::fs::create_dir_all(dir).map_err(|e| WakelabError::io(dir, e))?;
    write_atomically(dir.join("outputs.csv"), &csv(&outputs)?)?;
    let cached = CachedStep {
        key,
        seconds,
        outputs,
        curves: Vec::new(),
        mask_scores: Vec::new(),
    };
    write_atomically(&cache, serde_json::to_string(&cached)?.as_bytes())?;
    Ok((names, cached.outputs, step_time(stage, start, None)))
}

/// The held-out environment test: one value of the plan's `held_out` axis at a time.
fn environment_test(dataset: &Dataset, plan: &LearningPlan) -> HeldOutTest<'static> {
    let groups = if plan.held_out.is_empty() {
        Vec::new()
    } else {
        held_out_groups(dataset, &plan.held_out)
            .into_iter()
            .map(|(v, idx)| (format!("{} = {v}", plan.held_out), idx))
            .collect()
    };
    HeldOutTest {
        stage: "held-out environments",
        what: format!("`{}`", plan.held_out),
        groups,
        architectures: &HELD_OUT_ARCHITECTURES,
    }
}

/// The held-out geometry test: one bin of the plan's `held_out_geometry` axis at a time.
fn geometry_test(dataset: &Dataset, plan: &LearningPlan) -> HeldOutTest<'static> {
    let groups = if plan.held_out_geometry.is_empty() {
        Vec::new()
    } else {
        let parameters = dataset.records.iter().map(|r| &r.parameters);
        geometry_groups(parameters, &plan.held_out_geometry, plan.geometry_groups)
    };
    HeldOutTest {
        stage: "held-out geometry",
        what: format!("`{}` in {} bins", plan.held_out_geometry, plan.geometry_groups),
        groups,
        architectures: &HELD_OUT_GEOMETRY_ARCHITECTURES,
    }
}

/// The held-out step, both tests: (group names, outputs) of each and their wall times.
#[allow(clippy::type_complexity)]
pub(crate) fn held_out_steps(
    cx: &Context,
    plan: &LearningPlan,
    singles: &[Input],
    dir: &Path,
) -> Result<((Vec<String>, Vec<Output>), (Vec<String>, Vec<Output>), [StepTime; 2])> {
    let (e_names, e_outputs, e_time) =
        held_out_step(cx, environment_test(cx.dataset, plan), singles, &dir.join("held_out"))?;
    let (g_names, g_outputs, g_time) = held_out_step(
        cx,
        geometry_test(cx.dataset, plan),
        singles,
        &dir.join("held_out_geometry"),
    )?;
    Ok(((e_names, e_outputs), (g_names, g_outputs), [e_time, g_time]))
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

    /// Headings fall into sectors of the circle (370 degrees is 10), other axes into equal bins
    /// between their extremes with the largest value in the last; empty bins are dropped.
    #[test]
    fn geometry_groups_bin_headings_by_sector_and_other_axes_by_range() {
        let base = Combination::from_config(&WakelabConfig::default());
        let with = |axis: &str, values: &[f64]| -> Vec<Combination> {
            values.iter().map(|&v| base.with_value(axis, v).unwrap()).collect()
        };
        let headings = with("heading", &[10.0, 95.0, 370.0, 359.9, 180.0]);
        let groups = geometry_groups(headings.iter(), "heading", 4);
        let names: Vec<&str> = groups.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(
            names,
            [
                "heading in [0, 90)",
                "heading in [90, 180)",
                "heading in [180, 270)",
                "heading in [270, 360)"
            ]
        );
        assert_eq!(groups[0].1, [0, 2]);
        assert_eq!(groups[3].1, [3]);
        let ages = with("along_track", &[2000.0, 6000.0, 2500.0]);
        let groups = geometry_groups(ages.iter(), "along_track", 4);
        let names: Vec<&str> = groups.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["along_track in [2000, 3000)", "along_track in [5000, 6000]"]);
        assert_eq!(groups[1].1, [1]);
        assert!(geometry_groups(ages.iter(), "along_track", 0).is_empty());
    }
}

//! `wakelab dataset`: a study rendered into a labelled dataset directory (its pairs or one
//! shard of them), a progress bar on the way and the stage's timing written beside it.

use crate::Result;
use std::path::{Path, PathBuf};
use std::time::Instant;
use wakelab_core::io::write_atomically;
use wakelab_dataset::study::Study;
use wakelab_dataset::{Progress, Shard};

/// Render the pairs of `study` (those of `shard`, or all) into `out`, skipping finished
/// scenes, and write `timing.json`; what it did, in one line.
pub fn render_dataset(study: &Study, out: &Path, shard: Option<Shard>, quiet: bool) -> Result<String> {
    let start = Instant::now();
    // the bar counts the phase it is in: the wakes simulated, then the scene pairs rendered
    let template = "{spinner} dataset: {msg} [{bar:40}] {pos}/{len} | {rate} | {elapsed_precise}, {eta} left";
    let bar = crate::progress_bar(quiet, 0, template);
    let phase = |name: &'static str, unit: &'static str, done: usize, total: usize| {
        if bar.message() != name {
            bar.set_message(name);
            bar.set_style(crate::style(template, unit));
            bar.reset();
        }
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    };
    let times = wakelab_dataset::render_dataset(study, out, shard, None, &|p| match p {
        Progress::Hydro { done, total } => phase("wakes simulated", "wakes", done, total),
        Progress::Scene { done, total } => phase("scene pairs rendered", "pairs", done, total),
    })?;
    bar.finish_and_clear();
    write_atomically(
        out.join("timing.json"),
        serde_json::to_string_pretty(&times)?.as_bytes(),
    )?;
    Ok(times.describe(start.elapsed().as_secs_f64()))
}

/// Gather the finished scenes of `out` into its manifest and splits; what it found, in one line.
pub fn merge_dataset(study: &Study, out: &Path) -> Result<String> {
    let records = wakelab_dataset::write_manifest(study, out)?;
    let expected = 2 * study.pairs()?.len();
    Ok(format!(
        "manifest: {} scenes ({expected} expected) in {}",
        records.len(),
        out.display()
    ))
}

/// Write the Slurm job-array script of the dataset stage (`tasks` tasks, at most one a pair)
/// into `out`; its path and what it holds, in one line.
pub fn emit_dataset_slurm(study: &Study, name: &str, out: &Path, tasks: usize) -> Result<(PathBuf, String)> {
    crate::slurm::check_tasks(tasks)?;
    let pairs = study.pairs()?.len();
    let tasks = tasks.min(pairs);
    let exe = std::env::current_exe()?.display().to_string();
    let path = wakelab_dataset::slurm::write_slurm_script(Path::new(name), out, tasks, &exe)?;
    let line = format!("wrote {} ({pairs} pairs over {tasks} tasks)", path.display());
    Ok((path, line))
}

/// `wakelab dataset`: the study named `name` written as a Slurm script of `slurm_tasks` array
/// tasks, or its pairs (shard `shard`, "K/N", of them) rendered into `out` and merged when whole
/// or when `merge` asks; what was done, a line each.
pub fn dataset_command(
    name: &str,
    out: &Path,
    shard: Option<&str>,
    merge: bool,
    slurm_tasks: Option<usize>,
    quiet: bool,
) -> Result<Vec<String>> {
    let study = crate::load_study(name)?;
    if let Some(tasks) = slurm_tasks {
        return Ok(vec![emit_dataset_slurm(&study, name, out, tasks)?.1]);
    }
    let shard: Option<Shard> = shard
        .map(|text| text.parse().map_err(|e| anyhow::anyhow!("--shard {text}: {e}")))
        .transpose()?;
    let mut said = Vec::new();
    if !merge {
        said.push(render_dataset(&study, out, shard, quiet)?);
    }
    if shard.is_none() || merge {
        said.push(merge_dataset(&study, out)?);
    }
    Ok(said)
}

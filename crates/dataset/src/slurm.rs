//! A Slurm job-array script for studies that outgrow one machine: task k of N renders the pairs
//! with index % N == k (`wakelab dataset --shard k/N`); a final job, started when every task has
//! succeeded, gathers the manifest (`wakelab dataset --merge`), which is the same code that ends
//! a single-machine run.

use std::path::{Path, PathBuf};
use wakelab_core::io::write_atomically;
use wakelab_core::WakelabError;

/// Write the script for `tasks` array tasks of 2 cores as `out/wakelab_dataset.slurm`, running
/// the `wakelab` executable at `wakelab`; its path.
pub fn write_slurm_script(study: &Path, out: &Path, tasks: usize, wakelab: &str) -> Result<PathBuf, WakelabError> {
    std::fs::create_dir_all(out).map_err(|e| WakelabError::io(out, e))?;
    let path = out.join("wakelab_dataset.slurm");
    write_atomically(&path, slurm_script(study, out, tasks, 2, wakelab).as_bytes())?;
    Ok(path)
}

/// The script, for `tasks` array tasks of `cpus` cores each.
pub fn slurm_script(study: &Path, out: &Path, tasks: usize, cpus: usize, wakelab: &str) -> String {
    let (study, out) = (study.display(), out.display());
    format!(
        r#"#!/bin/bash
# wakelab dataset as a Slurm job array: submit with `bash THIS_FILE` (it calls sbatch twice).
# Task k of {tasks} renders the wake/no-wake pairs whose index modulo {tasks} is k; each scene is
# written atomically and skipped when already done, so a failed task can simply be resubmitted.
# The merge job runs after every task has succeeded and writes manifest.json, manifest.csv and
# splits.json exactly as a single-machine run does.
set -euo pipefail
array_id=$(sbatch --parsable --job-name=wakelab-dataset --array=0-{last} \
  --cpus-per-task={cpus} --output={out}/slurm-%A_%a.log \
  --wrap="{wakelab} dataset --study {study} --out {out} --shard \$SLURM_ARRAY_TASK_ID/{tasks} --quiet")
sbatch --job-name=wakelab-merge --dependency=afterok:$array_id --cpus-per-task=1 \
  --output={out}/slurm-merge-%j.log \
  --wrap="{wakelab} dataset --study {study} --out {out} --merge --quiet"
echo "submitted array $array_id ({tasks} tasks) and its merge job"
"#,
        last = tasks.saturating_sub(1),
    )
}

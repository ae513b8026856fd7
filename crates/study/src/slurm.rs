//! `wakelab run --emit-slurm`: the whole study as Slurm jobs chained by their dependencies, for
//! studies that outgrow one machine (the paper study's 180 pairs of 1024 x 1024 pixels).
//!
//! 1. a job array renders the dataset in shards (`wakelab dataset --shard K/N`, as the dataset's
//!    own script does), then one job merges the manifest (`--merge`);
//! 2. one job per input of the learning stage (`wakelab run --stage learning --input NAME`) and one
//!    for the held-out environments (`--stage held-out`), each started when the merge succeeded;
//! 3. one job runs `wakelab run` when all of them have succeeded: it finds the dataset and every
//!    learning stage finished (their keys match), fuses and writes the report.
//!
//! Each job writes atomically and skips finished work, so a failed job can simply be resubmitted.

use crate::Result;
use std::path::{Path, PathBuf};
use wakelab_core::io::write_atomically;
use wakelab_dataset::study::Study;
use wakelab_schema::band::{Band, Input};

/// What the script runs: the study as the user named it (`default`, `paper` or an absolute path),
/// the absolute run directory, the `wakelab` executable, the training device and the shape of
/// the jobs.
pub struct SlurmRun {
    pub study: String,
    pub out: PathBuf,
    pub wakelab: PathBuf,
    pub device: String,
    /// Array tasks of the dataset stage.
    pub tasks: usize,
    /// Cores per job.
    pub cpus: usize,
}

/// `--tasks`, the array tasks of a dataset stage: 1 to 100000.
pub(crate) fn check_tasks(tasks: usize) -> Result<()> {
    if !(1..=100_000).contains(&tasks) {
        anyhow::bail!("--tasks {tasks}: must be in [1, 100000]");
    }
    Ok(())
}

impl SlurmRun {
    /// The run of `study` (named `name` by the user) into `dir` from this executable, with
    /// absolute paths so that jobs may start anywhere: `tasks` dataset tasks (default 16, at
    /// most one a pair) of `cpus` cores (default 2).
    pub fn new(
        name: &str,
        study: &Study,
        dir: &Path,
        device: &str,
        tasks: Option<usize>,
        cpus: Option<usize>,
    ) -> Result<Self> {
        crate::chip_study_only(study, "--emit-slurm")?;
        let (tasks, cpus) = (tasks.unwrap_or(16), cpus.unwrap_or(2));
        check_tasks(tasks)?;
        if !(1..=1024).contains(&cpus) {
            anyhow::bail!("--cpus {cpus}: must be in [1, 1024]");
        }
        let path = Path::new(name);
        Ok(Self {
            study: if path.exists() {
                std::path::absolute(path)?.display().to_string()
            } else {
                name.to_string()
            },
            out: std::path::absolute(dir)?,
            wakelab: std::env::current_exe()?,
            device: device.to_string(),
            tasks: tasks.min(study.pairs()?.len()),
            cpus,
        })
    }

    /// How many jobs the script chains after the dataset's: one per input, one for the
    /// held-out environments.
    pub fn learning_jobs(study: &Study) -> usize {
        slurm_inputs(study).len() + usize::from(!study.learning.held_out.is_empty())
    }
}

/// Characters that would end the double-quoted `--wrap` command or the single quotes around a path.
const UNQUOTABLE: [char; 5] = ['\'', '"', '$', '`', '\\'];

/// `text` in single quotes for the shell, or an error naming `what` when it holds a character
/// the script cannot carry through `sbatch --wrap="..."`.
fn quoted(what: &str, text: &str) -> Result<String> {
    if let Some(c) = text.chars().find(|c| UNQUOTABLE.contains(c) || c.is_control()) {
        anyhow::bail!("{what} {text:?}: the Slurm script cannot carry the character {c:?}; use a path without it");
    }
    Ok(format!("'{text}'"))
}

/// The inputs whose learning stages the script runs, in the order `wakelab run` trains them.
pub fn slurm_inputs(study: &Study) -> Vec<Input> {
    let bands: Vec<Band> = Band::ALL
        .into_iter()
        .filter(|b| study.study.bands.contains(b))
        .collect();
    let mut inputs: Vec<Input> = bands.iter().map(|&b| Input::single(b)).collect();
    inputs.extend(study.learning.fused_inputs(&bands));
    inputs
}

/// The script's text.
pub fn slurm_script(study: &Study, run: &SlurmRun) -> Result<String> {
    let out = run.out.display().to_string();
    let (w, s, o) = (
        quoted("the wakelab executable", &run.wakelab.display().to_string())?,
        quoted("--study", &run.study)?,
        quoted("--out", &out)?,
    );
    let device = quoted("--device", &run.device)?;
    let logs = quoted("--out", &format!("{out}/slurm"))?;
    let (tasks, cpus) = (run.tasks.max(1), run.cpus.max(1));
    let inputs: Vec<String> = slurm_inputs(study).iter().map(Input::name).collect();
    let held_out = if study.learning.held_out.is_empty() {
        String::new()
    } else {
        format!(
            "id=$(submit --job-name=wakelab-held-out --dependency=afterok:$merge --cpus-per-task={cpus} \\\n  \
             --output={logs}/held-out-%j.log \\\n  \
             --wrap=\"{w} run --study {s} --out {o} --stage held-out --device {device} --quiet\")\n\
             learning=\"$learning:$id\"\n"
        )
    };
    Ok(format!(
        r#"#!/bin/bash
# wakelab run of study "{name}" as Slurm jobs: submit with `bash THIS_FILE` (it calls sbatch).
# 1. {tasks} array tasks render the wake/no-wake pairs whose index modulo {tasks} is k, then one
#    job merges the manifest;
# 2. one job per input of the learning stage ({list}){held_out_note}, each
#    started once the merge succeeded;
# 3. a last job runs `wakelab run`: it reuses the dataset and every learning stage, fuses and
#    writes the report ({out}/report/report.html).
# Every job skips finished work, so a failed job (or the whole script) can simply be resubmitted.
# Logs: {out}/slurm/.
set -euo pipefail
mkdir -p {logs}
# sbatch --parsable prints "id" or "id;cluster"
submit() {{ local id; id=$(sbatch --parsable "$@"); echo "${{id%%;*}}"; }}
shards=$(submit --job-name=wakelab-dataset --array=0-{last} --cpus-per-task={cpus} \
  --output={logs}/dataset-%A_%a.log \
  --wrap="{w} dataset --study {s} --out {o}/dataset --shard \$SLURM_ARRAY_TASK_ID/{tasks} --quiet")
merge=$(submit --job-name=wakelab-merge --dependency=afterok:$shards --cpus-per-task=1 \
  --output={logs}/merge-%j.log \
  --wrap="{w} dataset --study {s} --out {o}/dataset --merge --quiet")
learning=""
for input in {list}; do
  id=$(submit --job-name="wakelab-learn-$input" --dependency=afterok:$merge --cpus-per-task={cpus} \
    --output={logs}/learn-$input-%j.log \
    --wrap="{w} run --study {s} --out {o} --stage learning --input $input --device {device} --quiet")
  learning="$learning:$id"
done
{held_out}report=$(submit --job-name=wakelab-report --dependency=afterok$learning --cpus-per-task={cpus} \
  --output={logs}/report-%j.log \
  --wrap="{w} run --study {s} --out {o} --device {device} --quiet")
echo "submitted: dataset array $shards ({tasks} tasks), merge $merge, learning${{learning//:/ }}, report $report"
"#,
        name = study.study.name,
        last = tasks - 1,
        list = inputs.join(" "),
        held_out_note = if held_out.is_empty() {
            ""
        } else {
            " and one for the held-out tests"
        },
    ))
}

/// Write the script as `DIR/wakelab_run.slurm` (and the study beside it as `study.toml`, as
/// `wakelab run` does); its path.
pub fn write_slurm_script(study: &Study, run: &SlurmRun) -> Result<PathBuf> {
    let script = slurm_script(study, run)?;
    let dir: &Path = &run.out;
    std::fs::create_dir_all(dir).map_err(|e| wakelab_core::WakelabError::io(dir, e))?;
    write_atomically(dir.join("study.toml"), toml::to_string(study)?.as_bytes())?;
    let path = dir.join("wakelab_run.slurm");
    write_atomically(&path, script.as_bytes())?;
    Ok(path)
}

/// `wakelab run --emit-slurm`: the script of `study` (named `name` by the user) into `dir`, and
/// a line saying what it holds and how to submit it.
pub fn emit_run_script(
    name: &str,
    study: &Study,
    dir: &Path,
    device: &str,
    tasks: Option<usize>,
    cpus: Option<usize>,
) -> Result<String> {
    let run = SlurmRun::new(name, study, dir, device, tasks, cpus)?;
    let script = write_slurm_script(study, &run)?;
    Ok(format!(
        "wrote {} ({} pairs over {} dataset tasks, {} learning jobs); submit it with `bash {}`",
        script.display(),
        study.pairs()?.len(),
        run.tasks,
        SlurmRun::learning_jobs(study),
        script.display()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use wakelab_dataset::study::DEFAULT_STUDY;

    fn run(out: &str) -> SlurmRun {
        SlurmRun {
            study: "default".into(),
            out: out.into(),
            wakelab: "/opt/wakelab".into(),
            device: "auto".into(),
            tasks: 8,
            cpus: 2,
        }
    }

    /// Task and core counts outside their ranges are refused naming the flag and the range; the
    /// tasks are capped at the study's pairs.
    #[test]
    fn a_bad_job_shape_is_refused() {
        let study = Study::from_toml_str(DEFAULT_STUDY, "default").unwrap();
        let dir = std::path::Path::new("/tmp/unused");
        for (tasks, cpus, needle) in [
            (Some(0), None, "--tasks 0: must be in [1, 100000]"),
            (Some(100_001), None, "--tasks 100001: must be in [1, 100000]"),
            (None, Some(0), "--cpus 0: must be in [1, 1024]"),
        ] {
            let e = SlurmRun::new("default", &study, dir, "cpu", tasks, cpus)
                .err()
                .expect("refused");
            assert!(e.to_string().contains(needle), "{e}");
        }
        let pairs = study.pairs().unwrap().len();
        let run = SlurmRun::new("default", &study, dir, "cpu", Some(100_000), None).unwrap();
        assert_eq!(run.tasks, pairs);
    }

    /// Every input of the default study gets its job, the report waits for all of them, and the
    /// learning jobs wait for the merge, which waits for the array.
    #[test]
    fn the_default_study_is_chained_by_afterok() {
        let study = Study::from_toml_str(DEFAULT_STUDY, "default").unwrap();
        let script = slurm_script(&study, &run("/scratch/run")).unwrap();
        assert!(
            script.contains("for input in S C X MWIR LWIR S+X C+LWIR; do"),
            "{script}"
        );
        assert!(script.contains("--array=0-7") && script.contains("\\$SLURM_ARRAY_TASK_ID/8"));
        assert!(script.contains("--dependency=afterok:$shards") && script.contains("--merge"));
        assert_eq!(
            script.matches("--dependency=afterok:$merge").count(),
            2,
            "inputs and held-out"
        );
        assert!(script.contains("--dependency=afterok$learning"));
        assert!(script.contains("--stage held-out") && script.contains("held-out-%j.log"));
        assert!(script.contains("--out '/scratch/run'/dataset"));
    }

    #[test]
    fn paths_the_script_cannot_quote_are_refused() {
        let study = Study::from_toml_str(DEFAULT_STUDY, "default").unwrap();
        let err = slurm_script(&study, &run("/scratch/it's")).unwrap_err().to_string();
        assert!(err.contains("--out") && err.contains("'\\''"), "{err}");
    }
}

//! `wakelab dataset`: a parametric study rendered into a labelled dataset.

use crate::cli::DatasetArgs;
use crate::Result;
use std::path::Path;
use std::time::Instant;
use wakelab_core::io::write_atomically;

pub fn run_dataset(args: &DatasetArgs) -> Result<()> {
    let (study_name, out, shard) = (args.study.as_str(), args.out.as_path(), args.shard.as_deref());
    let (merge, emit_slurm, tasks, quiet) = (args.merge, args.emit_slurm, args.tasks, args.quiet);
    let study = wakelab_study::load_study(study_name)?;
    let pairs = study.pairs()?.len();
    if emit_slurm {
        if tasks == 0 || tasks > 100_000 {
            anyhow::bail!("--tasks {tasks}: must be in [1, 100000]");
        }
        let exe = std::env::current_exe()?.display().to_string();
        let path = wakelab_data::slurm::write_slurm_script(Path::new(study_name), out, tasks.min(pairs), &exe)?;
        let tasks = tasks.min(pairs);
        eprintln!("wrote {} ({pairs} pairs over {tasks} tasks)", path.display());
        return Ok(());
    }
    let shard: Option<wakelab_data::Shard> = shard
        .map(|text| text.parse().map_err(|e| anyhow::anyhow!("--shard {text}: {e}")))
        .transpose()?;
    let start = Instant::now();
    if !merge {
        let template = "{spinner} {msg} [{bar:40}] {pos}/{len} | {per_sec} | {elapsed_precise}, {eta} left";
        let bar = wakelab_study::progress_bar(quiet, pairs as u64, template);
        bar.set_message("hydro");
        let times = wakelab_data::run_study(&study, out, shard, None, &|p| match p {
            wakelab_data::Progress::Hydro { done, total } => {
                bar.set_message(format!("hydro {done}/{total}"));
            }
            wakelab_data::Progress::Scene { done, total } => {
                bar.set_message("scene pairs");
                bar.set_length(total as u64);
                bar.set_position(done as u64);
            }
        })?;
        bar.finish_and_clear();
        let wall = start.elapsed().as_secs_f64();
        eprintln!("{}", times.describe(wall));
        write_atomically(
            out.join("timing.json"),
            serde_json::to_string_pretty(&times)?.as_bytes(),
        )?;
    }
    if shard.is_none() || merge {
        let records = wakelab_data::write_manifest(&study, out)?;
        let (n, dir) = (records.len(), out.display());
        eprintln!("manifest: {n} scenes ({} expected) in {dir}", 2 * pairs);
    }
    Ok(())
}

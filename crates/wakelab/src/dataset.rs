//! `wakelab dataset`: a parametric study rendered into a labelled dataset.

use crate::Result;
use indicatif::{ProgressBar, ProgressStyle};
use std::path::Path;
use std::time::Instant;
use wakelab_core::io::write_atomically;

pub fn load_study(name: &str) -> Result<wakelab_data::study::Study> {
    use wakelab_data::study::{Study, DEFAULT_STUDY, PAPER_STUDY};
    let path = Path::new(name);
    Ok(match name {
        _ if path.exists() => Study::from_file(path)?,
        "default" => Study::from_toml_str(DEFAULT_STUDY, "<embedded default study>")?,
        "paper" => Study::from_toml_str(PAPER_STUDY, "<embedded paper study>")?,
        _ => anyhow::bail!("--study {name}: no such file (or use `default` or `paper`)"),
    })
}

pub fn run_dataset(
    study_name: &str,
    out: &Path,
    shard: Option<&str>,
    merge: bool,
    emit_slurm: bool,
    tasks: usize,
    quiet: bool,
) -> Result<()> {
    let study = load_study(study_name)?;
    let pairs = study.pairs()?.len();
    if emit_slurm {
        if tasks == 0 || tasks > 100_000 {
            anyhow::bail!("--tasks {tasks}: must be in [1, 100000]");
        }
        let exe = std::env::current_exe()?.display().to_string();
        let script = wakelab_data::slurm::slurm_script(Path::new(study_name), out, tasks.min(pairs), 2, &exe);
        std::fs::create_dir_all(out)?;
        let path = out.join("wakelab_dataset.slurm");
        write_atomically(&path, script.as_bytes())?;
        eprintln!(
            "wrote {} ({} pairs over {} tasks)",
            path.display(),
            pairs,
            tasks.min(pairs)
        );
        return Ok(());
    }
    let shard = match shard {
        None => None,
        Some(text) => {
            let parsed = text
                .split_once('/')
                .and_then(|(k, n)| Some((k.parse::<usize>().ok()?, n.parse::<usize>().ok()?)))
                .filter(|&(k, n)| n > 0 && k < n);
            let Some((k, n)) = parsed else {
                anyhow::bail!("--shard {text}: must be K/N with 0 <= K < N");
            };
            Some(wakelab_data::Shard { shard: k, count: n })
        }
    };
    let start = Instant::now();
    if !merge {
        let bar = if quiet {
            ProgressBar::hidden()
        } else {
            ProgressBar::new(pairs as u64)
        };
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner} {msg} [{bar:40}] {pos}/{len} | {per_sec} | {elapsed_precise}, {eta} left",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
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
        eprintln!(
            "rendered {} scenes ({} already done) in {wall:.1} s: {:.1} scenes/min; hydro {:.1} s, then per core: surface {:.1} s, sensors {:.1} s, writing {:.1} s",
            times.scenes_rendered,
            times.scenes_skipped,
            times.scenes_rendered as f64 / wall * 60.0,
            times.hydro,
            times.surface,
            times.sensors,
            times.writing
        );
        write_atomically(
            out.join("timing.json"),
            serde_json::to_string_pretty(&times)?.as_bytes(),
        )?;
    }
    if shard.is_none() || merge {
        let records = wakelab_data::write_manifest(&study, out)?;
        eprintln!(
            "manifest: {} scenes ({} expected) in {}",
            records.len(),
            2 * pairs,
            out.display()
        );
    }
    Ok(())
}

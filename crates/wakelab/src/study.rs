//! `wakelab run`: the study's name and run directory from the arguments, the study itself from
//! `wakelab_study`, and what it did printed.

use crate::cli::{StageName, StudyArgs};
use crate::Result;
use std::path::PathBuf;
use wakelab_core::config::Preset;
use wakelab_study::slurm::{write_slurm_script, SlurmRun};
use wakelab_study::stages::OneStage;

/// The stage of `--stage` (and `--input`), if any.
fn one_stage(args: &StudyArgs) -> Result<Option<OneStage>> {
    Ok(match (args.stage, &args.input) {
        (None, None) => None,
        (None, Some(_)) => anyhow::bail!("--input names the input of `--stage learning`"),
        (Some(StageName::Learning), None) => anyhow::bail!("--stage learning needs --input NAME (e.g. S or S+X)"),
        (Some(StageName::Learning), Some(text)) => {
            Some(OneStage::Learning(text.parse().map_err(|e| {
                anyhow::anyhow!("--input {text}: {e}; a band (S, C, X, MWIR, LWIR) or bands joined by +")
            })?))
        }
        (Some(StageName::HeldOut), None) => Some(OneStage::HeldOut),
        (Some(StageName::HeldOut), Some(_)) => anyhow::bail!("--input belongs to `--stage learning`, not held-out"),
    })
}

/// `wakelab run --emit-slurm`: the script, with absolute paths so that jobs may start anywhere.
fn emit_slurm(args: &StudyArgs, name: &str, study: &wakelab_data::study::Study, dir: &std::path::Path) -> Result<()> {
    let pairs = study.pairs()?.len();
    let tasks = args.tasks.unwrap_or(16);
    let cpus = args.cpus.unwrap_or(2);
    if !(1..=100_000).contains(&tasks) {
        anyhow::bail!("--tasks {tasks}: must be in [1, 100000]");
    }
    if !(1..=1024).contains(&cpus) {
        anyhow::bail!("--cpus {cpus}: must be in [1, 1024]");
    }
    let path = std::path::Path::new(name);
    let run = SlurmRun {
        study: if path.exists() {
            std::path::absolute(path)?.display().to_string()
        } else {
            name.to_string()
        },
        out: std::path::absolute(dir)?,
        wakelab: std::env::current_exe()?,
        device: args.device.clone(),
        tasks: tasks.min(pairs),
        cpus,
    };
    let script = write_slurm_script(study, &run)?;
    eprintln!(
        "wrote {} ({pairs} pairs over {} dataset tasks, {} learning jobs); submit it with `bash {}`",
        script.display(),
        run.tasks,
        wakelab_study::slurm::slurm_inputs(study).len() + usize::from(!study.learning.held_out.is_empty()),
        script.display()
    );
    Ok(())
}

pub fn run_study_command(args: &StudyArgs) -> Result<()> {
    let name = match (&args.study, args.preset) {
        (Some(s), _) => s.clone(),
        (None, Some(Preset::Paper)) => "paper".to_string(),
        (None, _) => "default".to_string(),
    };
    let study = wakelab_study::load_study(&name)?;
    let dir = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("runs").join(&study.study.name));
    let stage = one_stage(args)?;
    if args.emit_slurm {
        if stage.is_some() || args.input.is_some() {
            anyhow::bail!("--emit-slurm writes the script of every stage: leave out --stage and --input");
        }
        return emit_slurm(args, &name, &study, &dir);
    }
    if args.tasks.is_some() || args.cpus.is_some() {
        anyhow::bail!("--tasks and --cpus shape the Slurm script: use them with --emit-slurm");
    }
    let device = wakelab_learn::device::parse_device(&args.device)?;
    if let Some(stage) = stage {
        let time = wakelab_study::run_one_stage(&study, &dir, &stage, &device, args.quiet)?;
        eprintln!("  {time}");
        return Ok(());
    }
    let outcome = wakelab_study::run_study(&study, &dir, &device, args.quiet)?;
    wakelab_study::report::print_summary(&outcome.run);
    for t in &outcome.run.times {
        eprintln!("  {t}");
    }
    eprintln!("study \"{}\" finished in {:.1} s", study.study.name, outcome.seconds);
    for f in outcome.files {
        eprintln!("wrote {}", f.display());
    }
    Ok(())
}

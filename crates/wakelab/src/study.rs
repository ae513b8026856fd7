//! `wakelab run`: the study's name and run directory from the arguments, the study itself from
//! `wakelab_study`, and what it did printed.

use crate::cli::{StageName, StudyArgs};
use crate::Result;
use std::path::PathBuf;
use wakelab_core::config::Preset;
use wakelab_study::slurm::{write_slurm_script, SlurmRun};
use wakelab_study::stages::OneStage;

/// `wakelab run --emit-slurm`.
fn emit_slurm(args: &StudyArgs, name: &str, study: &wakelab_dataset::study::Study, dir: &std::path::Path) -> Result<()> {
    let run = SlurmRun::new(name, study, dir, &args.device, args.tasks, args.cpus)?;
    let script = write_slurm_script(study, &run)?;
    eprintln!(
        "wrote {} ({} pairs over {} dataset tasks, {} learning jobs); submit it with `bash {}`",
        script.display(),
        study.pairs()?.len(),
        run.tasks,
        SlurmRun::learning_jobs(study),
        script.display()
    );
    Ok(())
}

pub fn run_study_command(args: &StudyArgs) -> Result<()> {
    let paper = args.preset == Some(Preset::Paper);
    let name = (args.study.clone()).unwrap_or_else(|| if paper { "paper" } else { "default" }.into());
    let study = wakelab_study::load_study(&name)?;
    let dir = (args.out.clone()).unwrap_or_else(|| PathBuf::from("runs").join(&study.study.name));
    let held_out = args.stage.map(|s| s == StageName::HeldOut);
    let stage = OneStage::from_flags(held_out, args.input.as_deref())?;
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
    eprintln!("{}", outcome.describe(&study.study.name));
    Ok(())
}

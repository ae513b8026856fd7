//! `wakelab run`: the study's name and run directory from the arguments, the study itself from
//! `wakelab_study`, and what it did printed.

use crate::cli::{StageName, StudyArgs};
use crate::Result;
use std::path::PathBuf;
use wakelab_core::config::Preset;
use wakelab_study::steps::OneStep;

pub fn run_study_command(args: &StudyArgs, quiet: bool) -> Result<()> {
    let paper = args.preset == Some(Preset::Paper);
    let name = (args.study.clone()).unwrap_or_else(|| if paper { "paper" } else { "default" }.into());
    let (sea, wakes) = (args.sea_images.as_deref(), args.wake_images.as_deref());
    let study = wakelab_study::with_real_images(wakelab_study::load_study(&name)?, sea, wakes)?;
    let dir = (args.out.clone()).unwrap_or_else(|| PathBuf::from("runs").join(&study.study.name));
    if args.emit_slurm {
        let script = wakelab_study::slurm::emit_run_script(&name, &study, &dir, &args.device, args.tasks, args.cpus)?;
        eprintln!("{script}");
        return Ok(());
    }
    let device = wakelab_learn::device::parse_device(&args.device)?;
    if args.dry_run {
        let estimate = wakelab_study::dry_run::dry_run(&study, &device, quiet)?;
        print!("{}", estimate.describe());
        return Ok(());
    }
    let step = OneStep::from_flags(args.stage.map(|s| s == StageName::HeldOut), args.input.as_deref())?;
    if let Some(step) = step {
        let done = wakelab_study::run_one_step(&study, &dir, &step, &device, quiet)?;
        eprintln!("  {done}");
        return Ok(());
    }
    let done = wakelab_study::run_and_describe(&study, &dir, &device, args.real.as_deref(), quiet)?;
    eprintln!("{done}");
    Ok(())
}

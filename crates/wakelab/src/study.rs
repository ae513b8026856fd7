//! `wakelab run`: the study's name and run directory from the arguments, the study itself from
//! `wakelab_study`, and what it did printed.

use crate::cli::StudyArgs;
use crate::Result;
use std::path::PathBuf;
use wakelab_core::config::Preset;

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
    let device = wakelab_learn::device::parse_device(&args.device)?;
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

//! `wakelab scene` and `wakelab wake`: the pipeline on one configuration.

use crate::cli::RunArgs;
use crate::Result;
use std::path::PathBuf;

/// `wakelab scene`: the wake, the sea surface of the configured scene and its five images.
pub fn run_pipeline(args: &RunArgs, quiet: bool) -> Result<()> {
    run(args, quiet, true)
}

/// `wakelab wake`: the hydro stage alone.
pub fn run_wake_only(args: &RunArgs, quiet: bool) -> Result<()> {
    run(args, quiet, false)
}

fn run(args: &RunArgs, quiet: bool, images: bool) -> Result<()> {
    let cfg = args.config.load()?;
    let dir = args.out.clone().unwrap_or_else(|| PathBuf::from(&cfg.output.dir));
    wakelab_study::scene::scene_command(&cfg, &dir, quiet, images, &mut |line| eprintln!("{line}"))
}

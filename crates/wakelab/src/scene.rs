//! `wakelab scene` and `wakelab wake`: the pipeline on one configuration.

use crate::cli::RunArgs;
use crate::Result;
use std::path::{Path, PathBuf};
use std::time::Instant;
use wakelab_core::config::WakelabConfig;

/// The wake, the sea surface of the configured scene and its five images.
pub fn run_pipeline(args: &RunArgs) -> Result<()> {
    let cfg = args.config.load()?;
    let dir = args.out.clone().unwrap_or_else(|| PathBuf::from(&cfg.output.dir));
    let start = Instant::now();
    let map = run_wake(&cfg, &dir, args.quiet)?;
    let rendered = wakelab_study::scene::render_scene(&cfg, &map, &dir)?;
    eprintln!("{}", rendered.describe(&cfg));
    for f in &rendered.files {
        eprintln!("wrote {}", f.display());
    }
    eprintln!(
        "study finished in {:.1} s; results in {}",
        start.elapsed().as_secs_f64(),
        dir.display()
    );
    Ok(())
}

/// The hydro stage alone.
pub fn run_wake_only(args: &RunArgs) -> Result<()> {
    let cfg = args.config.load()?;
    let dir = args.out.clone().unwrap_or_else(|| PathBuf::from(&cfg.output.dir));
    run_wake(&cfg, &dir, args.quiet).map(|_| ())
}

pub fn run_wake(cfg: &WakelabConfig, dir: &Path, quiet: bool) -> Result<wakelab_hydro::SurfaceMap> {
    let start = Instant::now();
    let wake = wakelab_study::scene::simulate_wake(cfg, dir, quiet)?;
    eprintln!("{}", wake.describe(cfg, start.elapsed().as_secs_f64()));
    for f in &wake.files {
        eprintln!("wrote {}", f.display());
    }
    Ok(wake.map)
}

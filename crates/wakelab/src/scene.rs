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
    eprintln!(
        "sea surface: {n} x {n} scene at {:.1} m, {:.1} s",
        cfg.scene.pixel_spacing,
        rendered.surface_seconds,
        n = cfg.scene.size
    );
    eprintln!(
        "SAR (S, C, X) and IR (MWIR, LWIR) images: {:.1} s",
        rendered.sensor_seconds
    );
    let files = rendered.files;
    for f in files {
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
    let duration = cfg.time.duration;
    eprintln!(
        "wake simulated: {:.0} s of wake ({:.1} km) in {} steps, {:.1} s wall",
        duration,
        cfg.ship.speed * duration / 1000.0,
        wake.steps,
        start.elapsed().as_secs_f64()
    );
    for f in &wake.files {
        eprintln!("wrote {}", f.display());
    }
    Ok(wake.map)
}

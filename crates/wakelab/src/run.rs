//! `wakelab run` and `wakelab wake`: the pipeline on one configuration.

use crate::cli::RunArgs;
use crate::Result;
use anyhow::Context;
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
use std::time::Instant;
use wakelab_core::config::WakelabConfig;
use wakelab_core::io::write_atomically;
use wakelab_core::units::RadarBand;

/// The wake, the sea surface of the configured scene and its five images.
pub fn run_pipeline(args: &RunArgs) -> Result<()> {
    let cfg = args.config.load()?;
    let dir = args.out.clone().unwrap_or_else(|| PathBuf::from(&cfg.output.dir));
    let start = Instant::now();
    let map = run_wake(&cfg, &dir, args.quiet)?;
    let t_surface = Instant::now();
    let scene = wakelab_surface::simulate_surface(&cfg, Some(&map));
    let mut files = wakelab_surface::output::write_surface_scene(&dir, &cfg, &scene)?;
    eprintln!(
        "sea surface: {n} x {n} scene at {:.1} m, {:.1} s",
        cfg.scene.pixel_spacing,
        t_surface.elapsed().as_secs_f64(),
        n = cfg.scene.size
    );
    let t_sensors = Instant::now();
    for band in RadarBand::ALL {
        let image = wakelab_sensors::render_sar(&cfg, &scene, band);
        files.extend(wakelab_sensors::output::write_sar(&dir, &cfg, &scene.grid, &image)?);
    }
    for band in wakelab_sensors::IrBand::ALL {
        let image = wakelab_sensors::render_ir(&cfg, &scene, band);
        files.extend(wakelab_sensors::output::write_ir(&dir, &cfg, &scene.grid, &image)?);
    }
    eprintln!(
        "SAR (S, C, X) and IR (MWIR, LWIR) images: {:.1} s",
        t_sensors.elapsed().as_secs_f64()
    );
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
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    write_atomically(dir.join("config.toml"), cfg.to_toml_string().as_bytes())?;
    let duration = cfg.time.duration;
    let bar = if quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(duration.ceil() as u64)
    };
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} wake [{bar:40}] {pos}/{len} s simulated | {msg} | {elapsed_precise} elapsed, {eta} left",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    let mut last_steps = (0usize, Instant::now());
    let mut rate = 0.0;
    let (run, outputs) = wakelab_hydro::output::run_hydro_stage(cfg, dir, &mut |t, steps| {
        let now = Instant::now();
        let dt = now.duration_since(last_steps.1).as_secs_f64();
        if dt > 0.5 {
            rate = (steps - last_steps.0) as f64 / dt;
            last_steps = (steps, now);
        }
        bar.set_position(t.floor() as u64);
        bar.set_message(format!("step {steps}, {rate:.1} steps/s"));
        Ok(())
    })?;
    bar.finish_and_clear();
    eprintln!(
        "wake simulated: {:.0} s of wake ({:.1} km) in {} steps, {:.1} s wall",
        duration,
        cfg.ship.speed * duration / 1000.0,
        outputs.steps,
        start.elapsed().as_secs_f64()
    );
    for f in &outputs.files {
        eprintln!("wrote {}", f.display());
    }
    Ok(run.surface_map(cfg, cfg.output.map_dx))
}

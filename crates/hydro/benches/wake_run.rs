//! Whole-run figures of the hydro stage (not criterion: each run is one long measurement).
//!
//! `cargo bench -p wakelab-hydro --bench wake_run` times one hour of wake on the `quick` preset
//! and the first 120 s on the `paper` grid; with WAKELAB_BENCH_PAPER=1 it runs the whole paper
//! hour (about 80 s here). It prints wall time, steps, and cell-updates per second
//! (cells x steps / wall time).

use std::time::Instant;
use wakelab_core::config::{Preset, WakelabConfig};
use wakelab_hydro::WakeSolver;

fn run(name: &str, cfg: &WakelabConfig, duration: f64) {
    let start = Instant::now();
    let mut solver = WakeSolver::new(cfg);
    let setup_s = start.elapsed().as_secs_f64();
    let t0 = Instant::now();
    solver.run_until(duration).expect("stable run");
    let wall = t0.elapsed().as_secs_f64();
    let cells = solver.setup.grid.cells();
    let steps = solver.steps();
    println!(
        "{name:<14} {cells:>9} cells  {duration:>6.0} s simulated  {steps:>6} steps  {wall:>8.2} s wall  \
         {:>7.1} ms/step  {:>6.2} M cell-updates/s  (setup {setup_s:.2} s)",
        1e3 * wall / steps as f64,
        cells as f64 * steps as f64 / wall / 1e6,
    );
}

fn main() {
    // `cargo bench` passes --bench; nothing else is expected.
    let quick = WakelabConfig::with_preset(Preset::Quick);
    run("quick", &quick, quick.time.duration);
    let paper = WakelabConfig::with_preset(Preset::Paper);
    if std::env::var("WAKELAB_BENCH_PAPER").is_ok_and(|v| v == "1") {
        run("paper", &paper, paper.time.duration);
    } else {
        run("paper (120 s)", &paper, 120.0);
    }
}

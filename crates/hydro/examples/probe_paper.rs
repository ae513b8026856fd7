use wakelab_core::{config::Preset, WakelabConfig};
use wakelab_hydro::WakeSolver;
fn main() {
    let cfg = WakelabConfig::with_preset(Preset::Paper);
    let mut s = WakeSolver::new(&cfg);
    let t0 = std::time::Instant::now();
    let mut last = 0.0;
    let end: f64 = std::env::args().nth(1).map(|a| a.parse().unwrap()).unwrap_or(600.0);
    while s.time() < end {
        let dt = s.step(end - s.time()).unwrap();
        if s.time() - last > 60.0 {
            last = s.time();
            let (d2, why) = s.stable_dt();
            println!("t {:.0} steps {} dt {:.3} next {:.3} {:?} wall {:.1}s", s.time(), s.steps(), dt, d2, why, t0.elapsed().as_secs_f64());
        }
    }
    println!("steps {} wall {:.2}s per step {:.3}s", s.steps(), t0.elapsed().as_secs_f64(), t0.elapsed().as_secs_f64()/s.steps() as f64);
}

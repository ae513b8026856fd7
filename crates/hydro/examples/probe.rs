use wakelab_core::WakelabConfig;
use wakelab_hydro::WakeSolver;
fn main() {
    let cfg = WakelabConfig::default();
    let mut s = WakeSolver::new(&cfg);
    println!("cells {} div0 {:e}", s.setup.grid.cells(), s.max_divergence());
    let t0 = std::time::Instant::now();
    let mut last = 0.0;
    while s.time() < 3600.0 {
        let dt = s.step(3600.0 - s.time()).unwrap();
        if s.time() - last > 300.0 || s.steps() < 3 {
            last = s.time();
            let st = s.state();
            let umax = st.u.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let vmax = st.v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let kmax = st.k.iter().fold(0.0f64, |m, x| m.max(*x));
            let tmax = st.temperature.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            println!("t {:.0} steps {} dt {:.3} |U| {:.4} |V| {:.4} k {:.2e} dT {:.4} div {:.1e} wall {:.1}s", s.time(), s.steps(), dt, umax, vmax, kmax, tmax, s.max_divergence(), t0.elapsed().as_secs_f64());
        }
    }
    println!("steps {} wall {:.2}s", s.steps(), t0.elapsed().as_secs_f64());
}

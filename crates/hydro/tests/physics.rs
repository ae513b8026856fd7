//! Physics checks of the hydro stage, each against a number from outside the solver: an analytic
//! solution, a conservation law, TEOS-10 through gsw, or a limit the equations must reach.

use wakelab_core::config::WakelabConfig;
use wakelab_hydro::setup::{Setup, RODI};
use wakelab_hydro::{WakeSolver, WakeState};

/// A configuration from TOML overrides of the embedded default.
fn config(toml: &str) -> WakelabConfig {
    WakelabConfig::from_toml_str(toml, "test").expect("valid test configuration")
}

/// A closed box: free-slip walls all round, no beaches.
const BOX: &str = r#"
[solver]
lateral_boundary = "wall"
beach_damping = 0.0
"#;

fn box_config(extra: &str, grid: &str) -> WakelabConfig {
    config(&format!("{BOX}\n{grid}\n{extra}"))
}

fn at_rest(cfg: &WakelabConfig) -> (Setup, WakeState) {
    let setup = Setup::new(cfg);
    let state = WakeState::at_rest(
        &setup.grid,
        cfg.environment.ambient_tke,
        cfg.environment.ambient_dissipation,
    );
    (setup, state)
}

/// A small deterministic pseudo-random sequence in [-1, 1] (64-bit LCG, Knuth's MMIX constants).
fn noise(seed: &mut u64) -> f64 {
    *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

#[test]
fn projection_makes_velocity_divergence_free() {
    for lateral in ["outlet", "wall"] {
        let cfg = config(&format!(
            "[solver]\nlateral_boundary = \"{lateral}\"\n[grid]\ncore_width = 200.0\ndepth = 40.0\ncore_cells = 100\ndepth_cells = 30\nbeach_width = 50.0\nbeach_cells = 8\n"
        ));
        let (setup, mut state) = at_rest(&cfg);
        let mut seed = 42;
        state.v.mapv_inplace(|_| noise(&mut seed));
        state.w.mapv_inplace(|_| noise(&mut seed));
        let nz = setup.nz;
        state.w.column_mut(0).fill(0.0);
        state.w.column_mut(nz).fill(0.0);
        let mut solver = WakeSolver::with_state(&cfg, setup, state);
        let before = solver.max_divergence();
        solver.project_state();
        let after = solver.max_divergence();
        // velocity of order 1 on cells of order 1 m: divergence of order 1 before
        assert!(before > 0.1, "{lateral}: {before}");
        assert!(after < 1e-11, "{lateral}: max |div u| = {after:e} after projection");
    }
    // and after every step of a real wake
    let cfg = config("[grid]\ncore_width = 300.0\ndepth = 40.0\ncore_cells = 150\ndepth_cells = 27\nbeach_width = 60.0\nbeach_cells = 10\n");
    let mut solver = WakeSolver::new(&cfg);
    for _ in 0..20 {
        solver.step(10.0).unwrap();
        assert!(solver.max_divergence() < 1e-11);
    }
}

#[test]
fn stratified_ocean_at_rest_stays_at_rest() {
    // Mixed layer over a thermocline, salinity gradient and a beam swell: no ship, no motion.
    let cfg = config(
        r#"
[grid]
core_width = 200.0
depth = 60.0
core_cells = 80
depth_cells = 40
beach_width = 50.0
beach_cells = 8
[environment.temperature]
kind = "mixed_layer"
surface = 20.0
mixed_layer_depth = 15.0
depth_gradient = -0.1
[environment.salinity]
kind = "linear"
surface = 34.0
depth_gradient = 0.01
[environment.swell]
direction = "beam"
"#,
    );
    let (setup, state) = at_rest(&cfg);
    let k_amb = cfg.environment.ambient_tke;
    let mut solver = WakeSolver::with_state(&cfg, setup, state);
    solver.run_until(1800.0).unwrap();
    let s = solver.state();
    let max = |a: &ndarray::Array2<f64>| a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    for (name, v) in [
        ("U", max(&s.u)),
        ("V", max(&s.v)),
        ("W", max(&s.w)),
        ("dT", max(&s.temperature)),
        ("dS", max(&s.salinity)),
    ] {
        assert!(v < 1e-14, "{name} grew to {v:e} in an ocean at rest");
    }
    let k_drift = s.k.iter().fold(0.0f64, |m, k| m.max((k - k_amb).abs() / k_amb));
    assert!(k_drift < 1e-9, "ambient k drifted by {k_drift:e}");
}

/// N from TEOS-10 through gsw, independently of the solver: N^2 = -(g / rho) d rho / dz at the
/// pressure of `z`, with the same SA and CT approximations as the solver documents.
fn buoyancy_frequency(t_surface: f64, gradient: f64, sp: f64, z: f64, lat: f64) -> f64 {
    let p = gsw::conversions::p_from_z(z, lat, Some(0.0), Some(0.0)).unwrap();
    let sa = gsw::conversions::sr_from_sp(sp);
    let rho = |zz: f64| {
        let t = t_surface + gradient * (-zz);
        gsw::volume::rho(sa, gsw::conversions::ct_from_pt(sa, t).unwrap(), p).unwrap()
    };
    let h = 0.5;
    (-(9.81 / rho(z)) * (rho(z + h) - rho(z - h)) / (2.0 * h)).sqrt()
}

#[test]
fn small_perturbation_oscillates_at_the_buoyancy_frequency() {
    let (width, depth, gradient) = (80.0, 100.0, -0.1);
    let cfg = box_config(
        &format!(
            "[environment.temperature]\nkind = \"linear\"\nsurface = 25.0\ndepth_gradient = {gradient}\n[environment.swell]\ndirection = \"calm\"\n[time]\nmax_dt = 2.0\n"
        ),
        &format!("[grid]\ncore_width = {width}\ndepth = {depth}\ncore_cells = 160\ndepth_cells = 50\nbeach_width = 0.0\nbeach_cells = 0\n"),
    );
    let (setup, mut state) = at_rest(&cfg);
    // Standing internal wave: dT = A cos(k_y (y + L/2)) sin(k_z (z + H)); walls at y = +-L/2.
    let ky = 8.0 * std::f64::consts::PI / width;
    let kz = std::f64::consts::PI / depth;
    for (j, &y) in setup.grid.y_centres.iter().enumerate() {
        for (k, &z) in setup.grid.z_centres.iter().enumerate() {
            state.temperature[[j, k]] = 1e-3 * (ky * (y + 0.5 * width)).cos() * (kz * (z + depth)).sin();
        }
    }
    let probe = (4usize, 25usize);
    let mut solver = WakeSolver::with_state(&cfg, setup, state);
    let mut series = vec![(0.0, solver.state().temperature[probe])];
    while solver.time() < 1200.0 {
        solver.step(1200.0 - solver.time()).unwrap();
        series.push((solver.time(), solver.state().temperature[probe]));
    }
    // zero crossings (either direction) are half a period apart
    let crossings: Vec<f64> = series
        .windows(2)
        .filter(|w| w[0].1 * w[1].1 < 0.0)
        .map(|w| w[0].0 + (w[1].0 - w[0].0) * w[0].1 / (w[0].1 - w[1].1))
        .collect();
    assert!(crossings.len() >= 4, "{} crossings", crossings.len());
    let half_period = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    let omega = std::f64::consts::PI / half_period;
    let n = buoyancy_frequency(25.0, gradient, 35.0, -50.0, cfg.environment.latitude);
    let omega_wave = n * ky / (ky * ky + kz * kz).sqrt();
    eprintln!("buoyancy oscillation: omega {omega:.6} rad/s, dispersion relation {omega_wave:.6}, N {n:.6}");
    assert!(
        (omega / omega_wave - 1.0).abs() < 0.02,
        "omega {omega} vs dispersion relation {omega_wave}"
    );
    assert!((omega / n - 1.0).abs() < 0.03, "omega {omega} vs N {n}");
}

#[test]
fn decaying_homogeneous_turbulence_follows_the_power_law() {
    let cfg = box_config(
        "[environment.temperature]\nkind = \"linear\"\nsurface = 15.0\ndepth_gradient = 0.0\n[environment.swell]\ndirection = \"calm\"\n[time]\nmax_dt = 2.0\n",
        "[grid]\ncore_width = 80.0\ndepth = 40.0\ncore_cells = 16\ndepth_cells = 8\nbeach_width = 0.0\nbeach_cells = 0\n",
    );
    let (setup, mut state) = at_rest(&cfg);
    let (k0, eps0) = (1e-3, 1e-5);
    state.k.fill(k0);
    state.eps.fill(eps0);
    let mut solver = WakeSolver::with_state(&cfg, setup, state);
    // dk/dt = -eps, deps/dt = -C2 eps^2 / k: k = k0 (1 + t / tau)^(-n), n = 1 / (C2 - 1), tau = n k0 / eps0
    let n = 1.0 / (RODI.c2 - 1.0);
    let tau = n * k0 / eps0;
    let mut samples = Vec::new();
    for t in [100.0, 300.0, 600.0, 1000.0, 1500.0] {
        solver.run_until(t).unwrap();
        let k = solver.state().k[[8, 4]];
        let exact = k0 * (1.0 + t / tau).powf(-n);
        eprintln!("decay t = {t}: k = {k:.6e}, analytic {exact:.6e}");
        assert!((k / exact - 1.0).abs() < 0.01, "t = {t}: k = {k:e}, analytic {exact:e}");
        samples.push((t, k));
    }
    // late-time exponent d ln k / d ln t -> -1 / (C2 - 1)
    let (t1, k1) = samples[3];
    let (t2, k2) = samples[4];
    let slope = (k2 / k1).ln() / ((tau + t2) / (tau + t1)).ln();
    assert!((slope + n).abs() < 0.02 * n, "exponent {slope} vs {}", -n);
}

#[test]
fn integral_of_temperature_perturbation_is_conserved_in_a_closed_box() {
    let cfg = box_config(
        "[environment.temperature]\nkind = \"linear\"\nsurface = 15.0\ndepth_gradient = 0.0\n",
        "[grid]\ncore_width = 120.0\ndepth = 30.0\ncore_cells = 120\ndepth_cells = 30\nbeach_width = 0.0\nbeach_cells = 0\n",
    );
    let mut solver = WakeSolver::new(&cfg);
    // a warm blob in the swirling, turbulent wake
    let grid = solver.setup.grid.clone();
    for (j, &y) in grid.y_centres.iter().enumerate() {
        for (k, &z) in grid.z_centres.iter().enumerate() {
            solver.state_mut().temperature[[j, k]] = 0.5 * (-((y - 3.0).powi(2) + (z + 6.0).powi(2)) / 20.0).exp();
        }
    }
    let integral = |s: &WakeState| -> f64 {
        let mut sum = 0.0;
        for (j, dy) in grid.dy.iter().enumerate() {
            for k in 0..grid.nz() {
                sum += s.temperature[[j, k]] * dy * grid.dz;
            }
        }
        sum
    };
    let before = integral(solver.state());
    solver.run_until(600.0).unwrap();
    let after = integral(solver.state());
    let spread = solver.state().temperature.iter().fold(0.0f64, |m, x| m.max(*x));
    assert!(spread < 0.45, "the blob did not mix: peak {spread}");
    eprintln!("integral of dT: {before:.15e} -> {after:.15e}");
    assert!(
        ((after - before) / before).abs() < 1e-12,
        "integral {before} -> {after}"
    );
}

/// Total excess TKE and the surface cross-track velocity after `seconds` for a test case.
fn wake_after(extra: &str, seconds: f64) -> (f64, Vec<f64>) {
    let cfg = config(&format!(
        "[grid]\ncore_width = 300.0\ndepth = 60.0\ncore_cells = 150\ndepth_cells = 40\nbeach_width = 100.0\nbeach_cells = 10\n{extra}"
    ));
    let mut solver = WakeSolver::new(&cfg);
    solver.run_until(seconds).unwrap();
    let s = solver.state();
    let k_amb = cfg.environment.ambient_tke;
    let tke = s.k.iter().map(|k| k - k_amb).sum::<f64>();
    let v_surface = (0..s.v.nrows()).map(|jf| s.v[[jf, 0]]).collect();
    (tke, v_surface)
}

#[test]
fn stable_stratification_lowers_the_wake_tke() {
    let calm = "[environment.swell]\ndirection = \"calm\"\n";
    let (neutral, _) = wake_after(
        &format!("{calm}[environment.temperature]\nkind = \"linear\"\nsurface = 15.0\ndepth_gradient = 0.0\n"),
        600.0,
    );
    let (stratified, _) = wake_after(
        &format!("{calm}[environment.temperature]\nkind = \"linear\"\nsurface = 20.0\ndepth_gradient = -0.1\n"),
        600.0,
    );
    eprintln!("wake TKE after 600 s: stratified {stratified:e}, neutral {neutral:e}");
    assert!(
        stratified < 0.9 * neutral,
        "stratified {stratified:e} vs neutral {neutral:e}"
    );
}

#[test]
fn swell_changes_the_surface_cross_flow_and_head_differs_from_following() {
    let run = |dir: &str| wake_after(&format!("[environment.swell]\ndirection = \"{dir}\"\n"), 900.0).1;
    let (calm, following, head) = (run("calm"), run("following"), run("head"));
    let norm = |a: &[f64]| a.iter().map(|x| x * x).sum::<f64>().sqrt();
    let diff = |a: &[f64], b: &[f64]| norm(&a.iter().zip(b).map(|(x, y)| x - y).collect::<Vec<_>>());
    eprintln!(
        "surface V norms: calm {:.3e}, following-calm {:.3e}, following-head {:.3e}",
        norm(&calm),
        diff(&following, &calm),
        diff(&following, &head)
    );
    assert!(
        diff(&following, &calm) > 0.2 * norm(&calm),
        "vortex force had no effect"
    );
    assert!(
        diff(&following, &head) > 0.2 * norm(&calm),
        "head and following seas gave the same wake"
    );
}

#[test]
fn a_blow_up_names_the_step_and_the_field() {
    let cfg = config("[grid]\ncore_width = 200.0\ndepth = 40.0\ncore_cells = 50\ndepth_cells = 20\nbeach_width = 50.0\nbeach_cells = 5\n");
    let mut solver = WakeSolver::new(&cfg);
    solver.step(1.0).unwrap();
    solver.state_mut().temperature[[20, 3]] = f64::NAN;
    let err = solver.step(1.0).unwrap_err().to_string();
    assert!(err.contains("step 2") && err.contains("dT"), "{err}");
}

/// Cross-plane velocity (V then W, cell-centred) over the central 400 m at the given times, after
/// a buoyant bump at the centre collapses and radiates internal waves towards the sides.
fn central_velocity_history(grid: &str, solver_opts: &str, times: &[f64]) -> Vec<Vec<f64>> {
    let cfg = config(&format!(
        r#"
{grid}
[solver]
{solver_opts}
[environment.temperature]
kind = "linear"
surface = 25.0
depth_gradient = -0.1
[environment.swell]
direction = "calm"
"#
    ));
    let (setup, mut state) = at_rest(&cfg);
    for (j, &y) in setup.grid.y_centres.iter().enumerate() {
        for (k, &z) in setup.grid.z_centres.iter().enumerate() {
            state.temperature[[j, k]] = 0.02 * (-(y * y / 400.0 + (z + 20.0).powi(2) / 100.0)).exp();
        }
    }
    let centre: Vec<usize> = (0..setup.ny)
        .filter(|&j| setup.grid.y_centres[j].abs() < 200.0)
        .collect();
    let mut solver = WakeSolver::with_state(&cfg, setup, state);
    times
        .iter()
        .map(|&t| {
            solver.run_until(t).unwrap();
            let s = solver.state();
            let nz = s.u.ncols();
            let mut out = Vec::new();
            for &j in &centre {
                for k in 0..nz {
                    out.push(0.5 * (s.v[[j, k]] + s.v[[j + 1, k]]));
                    out.push(0.5 * (s.w[[j, k]] + s.w[[j, k + 1]]));
                }
            }
            out
        })
        .collect()
}

#[test]
fn internal_waves_leave_through_the_beaches() {
    // Mode-1 waves travel at N H / pi = 0.3 m/s: from the 400 m core to the end of a 400 m beach
    // and back takes about 2000 s; on the 2400 m reference nothing returns within 6000 s.
    let times: Vec<f64> = (1..=30).map(|i| i as f64 * 200.0).collect();
    let narrow = "[grid]\ncore_width = 400.0\ndepth = 60.0\ncore_cells = 200\ndepth_cells = 30\nbeach_width = 400.0\nbeach_cells = 40";
    let beach = central_velocity_history(narrow, "lateral_boundary = \"outlet\"\nbeach_damping = 0.05", &times);
    let mirror = central_velocity_history(narrow, "lateral_boundary = \"wall\"\nbeach_damping = 0.0", &times);
    let wide = "[grid]\ncore_width = 2400.0\ndepth = 60.0\ncore_cells = 1200\ndepth_cells = 30\nbeach_width = 0.0\nbeach_cells = 0";
    let reference = central_velocity_history(wide, "lateral_boundary = \"wall\"\nbeach_damping = 0.0", &times);
    let norm = |a: &[f64]| a.iter().map(|x| x * x).sum::<f64>().sqrt();
    let outgoing = reference.iter().map(|r| norm(r)).fold(0.0, f64::max);
    // what came back = the difference from the unbounded reference (small-amplitude, linear)
    let returned = |run: &[Vec<f64>]| {
        run.iter()
            .zip(&reference)
            .map(|(a, r)| norm(&a.iter().zip(r).map(|(x, y)| x - y).collect::<Vec<_>>()))
            .fold(0.0, f64::max)
            / outgoing
    };
    let (back_beach, back_mirror) = (returned(&beach), returned(&mirror));
    eprintln!("returned amplitude fraction: beaches {back_beach:.4}, reflecting walls {back_mirror:.4}");
    assert!(
        back_mirror > 0.3,
        "control failed: reflecting walls returned only {back_mirror}"
    );
    assert!(back_beach < 0.05, "beaches let {back_beach} of the amplitude come back");
}

#[test]
fn somero_anisotropy_option_changes_the_near_surface_wake_only_when_on() {
    let run = |on: bool| {
        let cfg = config(&format!(
            "[solver]\nsomero_anisotropy = {on}\n[grid]\ncore_width = 200.0\ndepth = 40.0\ncore_cells = 100\ndepth_cells = 27\nbeach_width = 50.0\nbeach_cells = 6\n"
        ));
        let mut solver = WakeSolver::new(&cfg);
        solver.run_until(300.0).unwrap();
        solver.state().clone()
    };
    let (off, on) = (run(false), run(true));
    let diff = |k: usize| {
        (0..off.u.nrows())
            .map(|j| (off.u[[j, k]] - on.u[[j, k]]).abs())
            .fold(0.0, f64::max)
    };
    let scale = off.u.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    eprintln!(
        "Somero on vs off: max |dU| at the surface {:.3e}, at 30 m {:.3e}, |U| {scale:.3e}",
        diff(0),
        diff(20)
    );
    assert!(diff(0) > 1e-3 * scale, "the option had no effect at the surface");
    assert!(
        diff(20) < diff(0),
        "the correction acted more at depth than at the surface"
    );
}

/// The paper grid's resolution (0.5 m across, 1.5 m deep) on a narrower domain: the steps the
/// implicit cross-track diffusion allows (several seconds, against an explicit limit of about
/// 0.4 s) give the wake that steps held at 0.2 s give. The reference is the same equations
/// converged in time, so what is checked is the time-stepping error of the large steps.
#[test]
fn large_steps_with_implicit_cross_diffusion_match_small_steps() {
    let grid = "[grid]\ncore_width = 200.0\ndepth = 45.0\ncore_cells = 401\ndepth_cells = 31\nbeach_width = 50.0\nbeach_cells = 11\n";
    let run = |max_dt: f64| {
        let cfg = config(&format!("{grid}[time]\nmax_dt = {max_dt}\n"));
        let mut solver = WakeSolver::new(&cfg);
        solver.run_until(120.0).unwrap();
        (solver.steps(), solver.state().clone())
    };
    let (small_steps, reference) = run(0.2);
    let (large_steps, large) = run(10.0);
    let relative = |a: &ndarray::Array2<f64>, b: &ndarray::Array2<f64>, ambient: f64| {
        let num: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum();
        let den: f64 = b.iter().map(|y| (y - ambient).powi(2)).sum();
        (num / den).sqrt()
    };
    let (k_amb, e_amb) = (reference.k[[0, 20]], reference.eps[[0, 20]]);
    let errors = [
        ("U", relative(&large.u, &reference.u, 0.0)),
        ("V", relative(&large.v, &reference.v, 0.0)),
        ("W", relative(&large.w, &reference.w, 0.0)),
        ("k", relative(&large.k, &reference.k, k_amb)),
        ("eps", relative(&large.eps, &reference.eps, e_amb)),
        ("dT", relative(&large.temperature, &reference.temperature, 0.0)),
    ];
    eprintln!("120 s: {large_steps} large steps against {small_steps} of 0.2 s; relative L2 differences {errors:?}");
    assert!(
        large_steps * 5 < small_steps,
        "{large_steps} steps: the step is still held small"
    );
    for (name, e) in errors {
        assert!(e < 0.05, "{name} differs by {:.1} % from the small-step run", 100.0 * e);
    }
}

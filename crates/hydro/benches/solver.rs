//! Kernel benchmarks of the hydro solver on the spec's paper grid (4203 x 201 cells) and the
//! cost of one whole step at several grid sizes (how the cost grows with the number of cells).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use ndarray::Array2;
use wakelab_core::config::{Preset, WakelabConfig};
use wakelab_hydro::cross_diffusion::{diffuse_across, CrossDiffusionWork};
use wakelab_hydro::momentum::{v_tendency, w_tendency, CornerStress, MomentumInputs};
use wakelab_hydro::pressure::PressureSolver;
use wakelab_hydro::transport::{advect_diffuse, Diffusivity, Transported};
use wakelab_hydro::turbulence::Derived;
use wakelab_hydro::WakeSolver;

fn kernels(c: &mut Criterion) {
    let cfg = WakelabConfig::with_preset(Preset::Paper);
    let mut solver = WakeSolver::new(&cfg);
    for _ in 0..3 {
        solver.step(10.0).unwrap();
    }
    let s = solver.setup.clone();
    let state = solver.state().clone();
    let n = s.ny * s.nz;
    let mut g = c.benchmark_group("paper_grid_kernels");
    g.throughput(Throughput::Elements(n as u64));
    g.sample_size(10);
    let mut derived = Derived::new(n, false);
    g.bench_function("derived_fields", |b| b.iter(|| derived.update(&s, &state)));
    derived.update(&s, &state);
    let (u, v, w) = (
        state.u.as_slice().unwrap(),
        state.v.as_slice().unwrap(),
        state.w.as_slice().unwrap(),
    );
    let mut out = vec![0.0; n];
    let diff = Diffusivity {
        molecular: 1e-6,
        turbulent_factor: 1.0,
        eddy_viscosity: &derived.eddy_viscosity,
        vertical_factor: None,
    };
    let one = |values| Transported {
        values,
        diffusivity: diff,
        ambient: 0.0,
    };
    let five = [
        one(u),
        one(state.k.as_slice().unwrap()),
        one(state.eps.as_slice().unwrap()),
        one(u),
        one(u),
    ];
    let mut outs = vec![vec![0.0; n]; 4];
    g.bench_function("advect_diffuse_five_scalars", |b| {
        b.iter(|| {
            let [o1, o2, o3, o4] = &mut outs[..] else {
                unreachable!()
            };
            advect_diffuse(&s, &five, v, w, [&mut out, o1, o2, o3, o4])
        })
    });
    let mut corner = CornerStress::new(&s);
    g.bench_function("corner_shear", |b| {
        b.iter(|| corner.update(&s, v, w, &derived.viscosity, None))
    });
    let inputs = MomentumInputs {
        u,
        v,
        w,
        viscosity: &derived.viscosity,
        buoyancy: &derived.buoyancy,
        corner: &corner,
        normal_correction: None,
    };
    let mut vt = vec![0.0; (s.ny + 1) * s.nz];
    g.bench_function("v_tendency", |b| b.iter(|| v_tendency(&s, &inputs, &mut vt)));
    let mut wt = vec![0.0; s.ny * (s.nz + 1)];
    g.bench_function("w_tendency", |b| b.iter(|| w_tendency(&s, &inputs, &mut wt)));
    let ps = PressureSolver::new(&s.grid, s.lateral);
    let mut rhs = Array2::from_elem((s.ny, s.nz), 1e-3);
    let mut scratch = Array2::zeros((s.nz, s.ny));
    g.bench_function("pressure_solve", |b| b.iter(|| ps.solve(&mut rhs, &mut scratch)));
    let mut diffused = state.clone();
    let mut work = CrossDiffusionWork::default();
    g.bench_function("cross_diffusion_seven_fields", |b| {
        b.iter(|| diffuse_across(&s, &derived, &corner.viscosity, &mut diffused, 5.0, &mut work))
    });
    g.bench_function("whole_step", |b| b.iter(|| solver.step(0.5).unwrap()));
    g.finish();
}

fn step_scaling(c: &mut Criterion) {
    let mut g = c.benchmark_group("step_cost_vs_cells");
    g.sample_size(10);
    for (core_cells, depth_cells, beach) in [(501, 26, 13), (1001, 51, 26), (2001, 101, 51), (4001, 201, 101)] {
        let toml = format!(
            "preset = \"paper\"\n[grid]\ncore_cells = {core_cells}\ndepth_cells = {depth_cells}\nbeach_cells = {beach}\n"
        );
        let cfg = WakelabConfig::from_toml_str(&toml, "bench").unwrap();
        let mut solver = WakeSolver::new(&cfg);
        let cells = solver.setup.grid.cells();
        g.throughput(Throughput::Elements(cells as u64));
        g.bench_with_input(BenchmarkId::from_parameter(cells), &cells, |b, _| {
            b.iter(|| solver.step(0.5).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, kernels, step_scaling);
criterion_main!(benches);

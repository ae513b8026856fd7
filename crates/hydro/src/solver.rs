//! Time integration of the 2D+t wake: second-order strong-stability-preserving Runge-Kutta
//! (Heun) with a projection onto divergence-free velocity after each stage (Chorin's projection,
//! the explicit counterpart of the spec's PISO, Eqs. (2.63)-(2.65)); cross-track diffusion is
//! split off and taken by backward Euler before the last projection ([`crate::cross_diffusion`]).
//! The adaptive time step is bounded by advection (Courant number), vertical diffusion, the
//! turbulence time scale k/eps, the beach damping and `time.max_dt`.

use crate::cross_diffusion::{diffuse_across, CrossDiffusionWork};
use crate::forcing::{add_axial_forces, add_background_sources};
use crate::idp::InitialDataPlane;
use crate::momentum::{v_tendency, w_tendency, CornerStress, MomentumInputs};
pub use crate::pressure::{divergence, project, Projector};
use crate::setup::{Setup, PRANDTL, SCHMIDT};
use crate::state::WakeState;
use crate::transport::{advect_diffuse, Diffusivity, Transported};
use crate::turbulence::{add_k_eps_sources, Derived};
use ndarray::Array2;
use rayon::prelude::*;
use wakelab_core::config::WakelabConfig;
use wakelab_core::WakelabError;

/// Smallest time step before the run is declared blown up (s).
const MIN_DT: f64 = 1e-3;

/// The solver of one wake: state, fixed setup and work space.
pub struct WakeSolver {
    pub setup: Setup,
    state: WakeState,
    derived: Derived,
    projector: Projector,
    tendency: WakeState,
    stage: WakeState,
    corner: CornerStress,
    cross_work: CrossDiffusionWork,
    time: f64,
    steps: usize,
    cfl: f64,
    max_dt: f64,
    last_dt: f64,
}

/// What limited the last time step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepLimit {
    Advection,
    Diffusion,
    Turbulence,
    Maximum,
}

impl WakeSolver {
    /// A solver starting from the ship's initial data plane (Eqs. (2.26)-(2.62)).
    pub fn new(config: &WakelabConfig) -> Self {
        let setup = Setup::new(config);
        let env = &config.environment;
        let idp = InitialDataPlane::new(
            &config.ship,
            env.kinematic_viscosity,
            env.reference_density,
            env.gravity,
        );
        let state = WakeState::from_idp(&setup.grid, &idp, env.ambient_tke, env.ambient_dissipation);
        let mut solver = Self::with_state(config, setup, state);
        solver.project_state();
        solver
    }

    /// A solver starting from a given state (for tests and restarts).
    pub fn with_state(config: &WakelabConfig, setup: Setup, state: WakeState) -> Self {
        let (ny, nz) = (setup.ny, setup.nz);
        let projector = Projector::new(&setup);
        let derived = Derived::new(ny * nz, setup.somero);
        Self {
            tendency: state.clone(),
            stage: state.clone(),
            state,
            derived,
            projector,
            corner: CornerStress::new(&setup),
            cross_work: CrossDiffusionWork::default(),
            time: 0.0,
            steps: 0,
            cfl: config.time.cfl,
            max_dt: config.time.max_dt,
            last_dt: 0.0,
            setup,
        }
    }

    pub fn state(&self) -> &WakeState {
        &self.state
    }

    pub fn state_mut(&mut self) -> &mut WakeState {
        &mut self.state
    }

    /// Simulated time since the IDP (s).
    pub fn time(&self) -> f64 {
        self.time
    }

    pub fn steps(&self) -> usize {
        self.steps
    }

    pub fn last_dt(&self) -> f64 {
        self.last_dt
    }

    /// Eddy viscosity and other derived fields of the current state.
    pub fn derived(&mut self) -> &Derived {
        self.derived.update(&self.setup, &self.state);
        &self.derived
    }

    /// Make the current velocity divergence-free (used once on the initial data plane).
    pub fn project_state(&mut self) {
        self.projector.apply(&self.setup, &mut self.state);
    }

    /// Largest |div u| over the cells (1/s).
    pub fn max_divergence(&self) -> f64 {
        let mut d = Array2::zeros((self.setup.ny, self.setup.nz));
        divergence(&self.setup, &self.state, &mut d);
        d.iter().fold(0.0f64, |m, x| m.max(x.abs()))
    }

    /// The stable time step of the current state and what limits it.
    pub fn stable_dt(&mut self) -> (f64, StepLimit) {
        self.derived.update(&self.setup, &self.state);
        stable_dt(&self.setup, &self.state, &self.derived, self.cfl, self.max_dt)
    }

    /// Advance by one step of at most `limit` seconds; returns the step taken.
    pub fn step(&mut self, limit: f64) -> Result<f64, WakelabError> {
        // L(s0), which also brings the derived fields up to date for the time step
        evaluate_tendency(
            &self.setup,
            &mut self.derived,
            &mut self.corner,
            &self.state,
            &mut self.tendency,
        );
        let (dt, why) = stable_dt(&self.setup, &self.state, &self.derived, self.cfl, self.max_dt);
        if dt < MIN_DT && limit > MIN_DT {
            let field = match why {
                StepLimit::Advection => "V/W (Courant number)",
                StepLimit::Diffusion => "nu_t (diffusion limit)",
                StepLimit::Turbulence => "k/eps (turbulence time scale)",
                StepLimit::Maximum => "time step",
            };
            return Err(WakelabError::BlowUp {
                step: self.steps,
                time: self.time,
                detail: format!("time step collapsed to {dt:.2e} s, limited by {field}"),
            });
        }
        let dt = dt.min(limit);
        // Heun: s1 = s0 + dt L(s0); s_new = (s0 + s1 + dt L(s1)) / 2, each pass fused with the
        // positivity floor of k and eps and (last) the check for non-finite values.
        let floors = self.floors();
        for ((stage, base), (tend, floor)) in fields_mut(&mut self.stage)
            .into_iter()
            .zip(fields(&self.state))
            .zip(fields(&self.tendency).into_iter().zip(floors))
        {
            euler_update(slice_mut(stage), slice(base), slice(tend), dt, floor);
        }
        self.projector.apply(&self.setup, &mut self.stage);
        evaluate_tendency(
            &self.setup,
            &mut self.derived,
            &mut self.corner,
            &self.stage,
            &mut self.tendency,
        );
        let mut bad = Vec::new();
        for (((state, stage), tend), (floor, name)) in fields_mut(&mut self.state)
            .into_iter()
            .zip(fields(&self.stage))
            .zip(fields(&self.tendency))
            .zip(floors.into_iter().zip(FIELD_NAMES))
        {
            if !heun_update(slice_mut(state), slice(stage), slice(tend), dt, floor) {
                bad.push(name);
            }
        }
        if bad.is_empty() {
            diffuse_across(
                &self.setup,
                &self.derived,
                &self.corner.viscosity,
                &mut self.state,
                dt,
                &mut self.cross_work,
            );
        }
        self.projector.apply(&self.setup, &mut self.state);
        self.time += dt;
        self.steps += 1;
        self.last_dt = dt;
        if !bad.is_empty() {
            return Err(WakelabError::BlowUp {
                step: self.steps,
                time: self.time,
                detail: format!("not finite: {}", bad.join(", ")),
            });
        }
        Ok(dt)
    }

    /// Advance to time `t_end` exactly.
    pub fn run_until(&mut self, t_end: f64) -> Result<(), WakelabError> {
        while self.time < t_end - 1e-9 {
            self.step(t_end - self.time)?;
        }
        Ok(())
    }

    /// Lower bounds of each field in [`fields`] order: k and eps stay positive, at a thousandth
    /// of their ambient values.
    fn floors(&self) -> [f64; 7] {
        let f = f64::NEG_INFINITY;
        [
            f,
            f,
            f,
            1e-3 * self.setup.ambient_k,
            1e-3 * self.setup.ambient_eps,
            f,
            f,
        ]
    }
}

fn slice(a: &Array2<f64>) -> &[f64] {
    a.as_slice().expect("standard layout")
}

fn slice_mut(a: &mut Array2<f64>) -> &mut [f64] {
    a.as_slice_mut().expect("standard layout")
}

const CHUNK: usize = 1 << 14;

/// out = base + dt * tend, floored.
fn euler_update(out: &mut [f64], base: &[f64], tend: &[f64], dt: f64, floor: f64) {
    out.par_chunks_mut(CHUNK).enumerate().for_each(|(c, o)| {
        let i0 = c * CHUNK;
        for (i, x) in o.iter_mut().enumerate() {
            *x = (base[i0 + i] + dt * tend[i0 + i]).max(floor);
        }
    });
}

/// state = (state + stage + dt * tend) / 2, floored; false if any value is not finite.
fn heun_update(state: &mut [f64], stage: &[f64], tend: &[f64], dt: f64, floor: f64) -> bool {
    state.par_chunks_mut(CHUNK).enumerate().all(|(c, o)| {
        let i0 = c * CHUNK;
        let mut finite = true;
        for (i, x) in o.iter_mut().enumerate() {
            let v = 0.5 * (*x + stage[i0 + i] + dt * tend[i0 + i]);
            finite &= v.is_finite();
            *x = v.max(floor);
        }
        finite
    })
}

fn fields(s: &WakeState) -> [&Array2<f64>; 7] {
    [&s.u, &s.v, &s.w, &s.k, &s.eps, &s.temperature, &s.salinity]
}

fn fields_mut(s: &mut WakeState) -> [&mut Array2<f64>; 7] {
    [
        &mut s.u,
        &mut s.v,
        &mut s.w,
        &mut s.k,
        &mut s.eps,
        &mut s.temperature,
        &mut s.salinity,
    ]
}

const FIELD_NAMES: [&str; 7] = ["U", "V", "W", "k", "eps", "dT", "dS"];

/// The stable time step (see module docs).
fn stable_dt(s: &Setup, state: &WakeState, d: &Derived, cfl: f64, max_dt: f64) -> (f64, StepLimit) {
    let nz = s.nz;
    let v = state.v.as_slice().expect("layout");
    let w = state.w.as_slice().expect("layout");
    let k = state.k.as_slice().expect("layout");
    let eps = state.eps.as_slice().expect("layout");
    let inv_dz2 = 1.0 / (s.dz * s.dz);
    let (adv, diff, turb) = (0..s.ny)
        .into_par_iter()
        .map(|j| {
            let inv_dy = 1.0 / s.dy[j];
            let (mut a, mut df, mut t) = (0.0f64, 0.0f64, 0.0f64);
            for kk in 0..nz {
                let i = j * nz + kk;
                let vc = 0.5 * (v[j * nz + kk].abs() + v[(j + 1) * nz + kk].abs());
                let wc = 0.5 * (w[j * (nz + 1) + kk].abs() + w[j * (nz + 1) + kk + 1].abs());
                a = a.max(vc * inv_dy + wc / s.dz);
                // Vertical only: cross-track diffusion is implicit.
                df = df.max(d.viscosity[i] * 2.0 * inv_dz2);
                t = t.max(eps[i] / k[i]);
            }
            (a, df, t)
        })
        .reduce(|| (0.0, 0.0, 0.0), |x, y| (x.0.max(y.0), x.1.max(y.1), x.2.max(y.2)));
    let damping = s.damping_centre.iter().fold(0.0f64, |m, &x| m.max(x));
    let candidates = [
        (cfl / adv.max(1e-30), StepLimit::Advection),
        (0.4 / diff.max(1e-30), StepLimit::Diffusion),
        (0.15 / turb.max(1e-30), StepLimit::Turbulence),
        (0.9 / damping.max(1e-30), StepLimit::Diffusion),
        (max_dt, StepLimit::Maximum),
    ];
    candidates.into_iter().fold(
        (f64::INFINITY, StepLimit::Maximum),
        |best, c| if c.0 < best.0 { c } else { best },
    )
}

/// Evaluate the right-hand side of every prognostic equation into `out`.
fn evaluate_tendency(s: &Setup, d: &mut Derived, corner: &mut CornerStress, state: &WakeState, out: &mut WakeState) {
    d.update(s, state);
    let c = s.constants;
    let u = state.u.as_slice().expect("layout");
    let v = state.v.as_slice().expect("layout");
    let w = state.w.as_slice().expect("layout");
    let nut = &d.eddy_viscosity;
    let somero_shear = d.somero_shear.as_deref();
    corner.update(s, v, w, &d.viscosity, somero_shear);
    let inputs = MomentumInputs {
        u,
        v,
        w,
        viscosity: &d.viscosity,
        buoyancy: &d.buoyancy,
        corner,
        normal_correction: d.somero_normal.as_ref().map(|(a, b)| (a.as_slice(), b.as_slice())),
    };
    v_tendency(s, &inputs, out.v.as_slice_mut().expect("layout"));
    w_tendency(s, &inputs, out.w.as_slice_mut().expect("layout"));

    let scalar = |molecular: f64, sigma: f64| Diffusivity {
        molecular,
        turbulent_factor: 1.0 / sigma,
        eddy_viscosity: nut,
        vertical_factor: None,
    };
    let momentum = Diffusivity {
        vertical_factor: somero_shear,
        ..scalar(s.viscosity, 1.0)
    };
    let transported = [
        Transported {
            values: u,
            diffusivity: momentum,
            ambient: 0.0,
        },
        Transported {
            values: slice(&state.k),
            diffusivity: scalar(s.viscosity, c.sigma_k),
            ambient: s.ambient_k,
        },
        Transported {
            values: slice(&state.eps),
            diffusivity: scalar(s.viscosity, c.sigma_eps),
            ambient: s.ambient_eps,
        },
        Transported {
            values: slice(&state.temperature),
            diffusivity: scalar(s.viscosity / PRANDTL, c.sigma_t),
            ambient: 0.0,
        },
        Transported {
            values: slice(&state.salinity),
            diffusivity: scalar(s.viscosity / SCHMIDT, c.sigma_t),
            ambient: 0.0,
        },
    ];
    let WakeState {
        u: du,
        k: dk,
        eps: deps,
        temperature: dtemp,
        salinity: dsal,
        ..
    } = out;
    let (du, dk, deps, dtemp, dsal) = (
        du.as_slice_mut().expect("layout"),
        dk.as_slice_mut().expect("layout"),
        deps.as_slice_mut().expect("layout"),
        dtemp.as_slice_mut().expect("layout"),
        dsal.as_slice_mut().expect("layout"),
    );
    advect_diffuse(
        s,
        &transported,
        v,
        w,
        [&mut *du, &mut *dk, &mut *deps, &mut *dtemp, &mut *dsal],
    );
    add_axial_forces(s, u, du);
    add_k_eps_sources(s, state, d, dk, deps);
    let col = &s.column;
    add_background_sources(
        s,
        nut,
        w,
        transported[3].values,
        &col.dtemperature_dz,
        &col.face_dtemperature_dz,
        dtemp,
    );
    add_background_sources(
        s,
        nut,
        w,
        transported[4].values,
        &col.dsalinity_dz,
        &col.face_dsalinity_dz,
        dsal,
    );
}

//! wakelab-hydro: stage 1 of the pipeline (spec 2.1): the ship's turbulent, stratified wake as a
//! 2D+t RANS simulation, turned into a surface map by x = U_ship t.
//!
//! [`simulate_wake`] runs a whole case from a [`WakelabConfig`]; [`simulate_wake_with`] does the
//! same while handing every saved slice to an observer (to stream it to disk and show progress).
//! [`WakeSolver`] steps a case by hand, for tests and studies.

// Stencil loops index several arrays at offsets of the loop index: ranges read clearer there.
#![allow(clippy::needless_range_loop)]

pub mod cross_diffusion;
pub mod eos;
pub mod forcing;
pub mod idp;
pub mod inputs;
pub mod momentum;
pub mod output;
pub mod pressure;
pub mod setup;
pub mod slices;
pub mod solver;
pub mod state;
pub mod stokes;
pub mod transport;
pub mod turbulence;

pub use idp::{IdpScalars, InitialDataPlane};
pub use inputs::HydroInputs;
pub use slices::{CrossSection, SliceField, SurfaceMap, SurfaceSlice, SLICE_FIELDS};
pub use solver::WakeSolver;
pub use state::WakeState;
pub use stokes::stokes_drift;

use wakelab_core::{WakelabConfig, WakelabError};

/// What a running simulation reports to its observer.
#[derive(Debug)]
pub enum WakeEvent<'a> {
    /// After every step.
    Progress { time: f64, dt: f64, steps: usize },
    /// A saved surface slice (every `time.surface_interval`).
    Surface(&'a SurfaceSlice),
    /// A saved full cross-section (every `time.output_interval`).
    Section(&'a CrossSection),
}

/// The result of a wake simulation.
#[derive(Debug, Clone)]
pub struct WakeSlices {
    pub idp: IdpScalars,
    /// Surface slices, every `time.surface_interval`, from t = 0.
    pub surface: Vec<SurfaceSlice>,
    /// Full cross-sections, every `time.output_interval`, from t = 0 (empty from
    /// [`simulate_wake_with`], which streams them to its observer instead).
    pub sections: Vec<CrossSection>,
    pub steps: usize,
}

impl WakeSlices {
    /// The surface map (Eq. (2.24)) at along-track spacing `dx` over the grid's core.
    pub fn surface_map(&self, config: &WakelabConfig, dx: f64) -> SurfaceMap {
        let grid = wakelab_core::CrossGrid::new(&config.grid);
        SurfaceMap::from_slices(
            &self.surface,
            config.ship.speed,
            self.idp.x_idp,
            &grid.y_centres,
            grid.core.clone(),
            dx,
        )
    }
}

/// The IDP model of the configured ship.
pub fn initial_data_plane(config: &WakelabConfig) -> InitialDataPlane {
    let env = &config.environment;
    InitialDataPlane::new(
        &config.ship,
        env.kinematic_viscosity,
        env.reference_density,
        env.gravity,
    )
}

/// Run the configured case and return its surface map at `output.map_dx` (what the surface stage
/// reads).
pub fn simulate_surface_map(config: &WakelabConfig) -> Result<SurfaceMap, WakelabError> {
    config.validate()?;
    HydroInputs::of(config).simulate()
}

/// Run the configured case and keep every slice in memory.
pub fn simulate_wake(config: &WakelabConfig) -> Result<WakeSlices, WakelabError> {
    config.validate()?;
    keep_every_slice(config)
}

/// [`simulate_wake`] on a configuration already validated.
pub(crate) fn keep_every_slice(config: &WakelabConfig) -> Result<WakeSlices, WakelabError> {
    let mut sections = Vec::new();
    let mut run = run_wake(config, &mut |e| {
        if let WakeEvent::Section(s) = e {
            sections.push(s.clone());
        }
        Ok(())
    })?;
    run.sections = sections;
    Ok(run)
}

/// Run the configured case, handing progress and every saved slice to `observer`.
pub fn simulate_wake_with(
    config: &WakelabConfig,
    observer: &mut dyn FnMut(WakeEvent<'_>) -> Result<(), WakelabError>,
) -> Result<WakeSlices, WakelabError> {
    config.validate()?;
    run_wake(config, observer)
}

/// [`simulate_wake_with`] on a configuration already validated.
fn run_wake(
    config: &WakelabConfig,
    observer: &mut dyn FnMut(WakeEvent<'_>) -> Result<(), WakelabError>,
) -> Result<WakeSlices, WakelabError> {
    let mut solver = WakeSolver::new(config);
    let t = &config.time;
    let mut surface = Vec::new();
    let schedule = |interval: f64| {
        let n = (t.duration / interval + 1e-9).floor() as usize;
        let mut times: Vec<f64> = (0..=n).map(|i| i as f64 * interval).collect();
        if t.duration - times[n] > 1e-9 {
            times.push(t.duration);
        }
        times
    };
    let surface_times = schedule(t.surface_interval);
    let section_times = schedule(t.output_interval);
    let (mut next_surface, mut next_section) = (0, 0);
    // Steps land on the section times; surface slices, saved more often than the step allows,
    // are interpolated between the states on either side of their time.
    let mut before = solver.surface_slice();
    loop {
        let now = solver.time();
        let after = solver.surface_slice();
        while next_surface < surface_times.len() && surface_times[next_surface] <= now + 1e-6 {
            let slice = before.interpolate(&after, surface_times[next_surface]);
            observer(WakeEvent::Surface(&slice))?;
            surface.push(slice);
            next_surface += 1;
        }
        before = after;
        if next_section < section_times.len() && (section_times[next_section] - now).abs() < 1e-6 {
            let section = solver.cross_section();
            observer(WakeEvent::Section(&section))?;
            next_section += 1;
        }
        if now >= t.duration - 1e-6 {
            break;
        }
        let target = section_times.get(next_section).copied().unwrap_or(t.duration);
        let dt = solver.step(target - now)?;
        observer(WakeEvent::Progress {
            time: solver.time(),
            dt,
            steps: solver.steps(),
        })?;
    }
    Ok(WakeSlices {
        idp: initial_data_plane(config).scalars,
        surface,
        sections: Vec::new(),
        steps: solver.steps(),
    })
}

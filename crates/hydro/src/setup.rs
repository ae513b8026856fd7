//! Everything the solver needs that does not change during a run: grid metrics, the seawater
//! column, the Stokes drift profile, beach damping rates and model constants.

use crate::eos::SeawaterColumn;
use crate::stokes::StokesProfile;
use wakelab_core::config::{LateralBoundary, WakelabConfig};
use wakelab_core::CrossGrid;

/// Constants of Rodi's buoyant k-epsilon model (spec 2.1.1, Eqs. (2.9)-(2.14)).
#[derive(Debug, Clone, Copy)]
pub struct KEpsilonConstants {
    pub c1: f64,
    pub c2: f64,
    pub c3: f64,
    pub c_mu: f64,
    pub sigma_k: f64,
    pub sigma_eps: f64,
    pub sigma_t: f64,
}

/// The spec's values: C1 = 1.44, C2 = 1.92, C3 = 0.144, sigma_eps = 1.3, sigma_k = sigma_t = 1,
/// C_mu = 0.09.
pub const RODI: KEpsilonConstants = KEpsilonConstants {
    c1: 1.44,
    c2: 1.92,
    c3: 0.144,
    c_mu: 0.09,
    sigma_k: 1.0,
    sigma_eps: 1.3,
    sigma_t: 1.0,
};

/// Molecular Prandtl number of seawater near 15 C (sigma_T of Eq. (2.22)).
pub const PRANDTL: f64 = 7.0;
/// Molecular Schmidt number of salt in seawater (sigma_S of Eq. (2.23)).
pub const SCHMIDT: f64 = 700.0;

/// Fixed inputs of one solver run.
#[derive(Debug, Clone)]
pub struct Setup {
    pub grid: CrossGrid,
    pub ny: usize,
    pub nz: usize,
    pub dy: Vec<f64>,
    /// Distance between neighbouring centres across y face jf (boundary faces: half a cell).
    pub dyc: Vec<f64>,
    pub dz: f64,
    pub column: SeawaterColumn,
    pub gravity: f64,
    pub viscosity: f64,
    /// Stokes drift at cell-centre levels.
    pub stokes_centre: StokesProfile,
    /// Stokes drift at z-face levels.
    pub stokes_face: StokesProfile,
    /// Beach damping rate (1/s) at cell centres and at y faces.
    pub damping_centre: Vec<f64>,
    pub damping_face: Vec<f64>,
    pub ambient_k: f64,
    pub ambient_eps: f64,
    pub lateral: LateralBoundary,
    pub somero: bool,
    pub max_eddy_viscosity: f64,
    pub constants: KEpsilonConstants,
}

impl Setup {
    pub fn new(config: &WakelabConfig) -> Self {
        let grid = CrossGrid::new(&config.grid);
        let (ny, nz) = (grid.ny(), grid.nz());
        let env = &config.environment;
        let column = SeawaterColumn::new(env, &grid.z_centres, grid.dz);
        let z_faces: Vec<f64> = (0..=nz).map(|kf| -(kf as f64) * grid.dz).collect();
        let mut dyc = vec![0.0; ny + 1];
        dyc[0] = 0.5 * grid.dy[0];
        dyc[ny] = 0.5 * grid.dy[ny - 1];
        for (jf, d) in dyc.iter_mut().enumerate().take(ny).skip(1) {
            *d = grid.dy_centres(jf);
        }
        let beach = config.grid.beach_width;
        let rate = |depth: f64| {
            if beach > 0.0 {
                config.solver.beach_damping * (depth / beach).powi(2)
            } else {
                0.0
            }
        };
        let damping_centre = (0..ny).map(|j| rate(grid.beach_depth(j))).collect();
        let lo = grid.y_faces[grid.core.start];
        let hi = grid.y_faces[grid.core.end];
        let damping_face = grid
            .y_faces
            .iter()
            .map(|&y| {
                rate(if y < lo {
                    lo - y
                } else if y > hi {
                    y - hi
                } else {
                    0.0
                })
            })
            .collect();
        Self {
            ny,
            nz,
            dy: grid.dy.clone(),
            dyc,
            dz: grid.dz,
            stokes_centre: StokesProfile::new(&env.swell, env.gravity, &grid.z_centres),
            stokes_face: StokesProfile::new(&env.swell, env.gravity, &z_faces),
            column,
            gravity: env.gravity,
            viscosity: env.kinematic_viscosity,
            damping_centre,
            damping_face,
            ambient_k: env.ambient_tke,
            ambient_eps: env.ambient_dissipation,
            lateral: config.solver.lateral_boundary,
            somero: config.solver.somero_anisotropy,
            max_eddy_viscosity: config.solver.max_eddy_viscosity,
            constants: RODI,
            grid,
        }
    }
}

impl Setup {
    /// Eddy viscosity of the ambient turbulence, C_mu k_amb^2 / eps_amb (Eq. (2.11)).
    pub fn ambient_eddy_viscosity(&self) -> f64 {
        (self.constants.c_mu * self.ambient_k * self.ambient_k / self.ambient_eps).min(self.max_eddy_viscosity)
    }
}

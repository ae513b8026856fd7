//! The prognostic fields of the 2D+t wake on the staggered (MAC) grid.
//!
//! Cell centres (ny x nz): axial velocity U (the x component carried with zero x-derivatives,
//! spec 2.1.2), k, eps, dT, dS. y faces ((ny + 1) x nz): cross-track velocity V. z faces
//! (ny x (nz + 1)): vertical velocity W, with W = 0 on the lid (face 0) and the bottom (face nz).
//! Arrays are row-major with z fastest: `a[[j, k]]`, k = 0 at the top.

use crate::idp::InitialDataPlane;
use ndarray::Array2;
use wakelab_core::CrossGrid;

/// The solved fields.
#[derive(Debug, Clone, PartialEq)]
pub struct WakeState {
    /// Axial (along-track) velocity in the Earth frame, positive along the ship's heading (m/s).
    pub u: Array2<f64>,
    /// Cross-track velocity at y faces (m/s, positive to port).
    pub v: Array2<f64>,
    /// Vertical velocity at z faces (m/s, up).
    pub w: Array2<f64>,
    /// Turbulence kinetic energy (m^2/s^2).
    pub k: Array2<f64>,
    /// Dissipation rate of k (m^2/s^3).
    pub eps: Array2<f64>,
    /// Temperature perturbation dT (K), Eq. (2.22).
    pub temperature: Array2<f64>,
    /// Salinity perturbation dS (PSU), Eq. (2.23).
    pub salinity: Array2<f64>,
}

impl WakeState {
    /// An ocean at rest with ambient turbulence.
    pub fn at_rest(grid: &CrossGrid, ambient_k: f64, ambient_eps: f64) -> Self {
        let (ny, nz) = (grid.ny(), grid.nz());
        Self {
            u: Array2::zeros((ny, nz)),
            v: Array2::zeros((ny + 1, nz)),
            w: Array2::zeros((ny, nz + 1)),
            k: Array2::from_elem((ny, nz), ambient_k),
            eps: Array2::from_elem((ny, nz), ambient_eps),
            temperature: Array2::zeros((ny, nz)),
            salinity: Array2::zeros((ny, nz)),
        }
    }

    /// The initial data plane (Eqs. (2.26)-(2.62)) on the grid, over the ambient state.
    ///
    /// The spec's U_0 is the wake velocity relative to the ship (jet positive); in the Earth frame
    /// a drag wake follows the ship and a jet is thrown back, so the Earth-frame axial velocity
    /// along the heading is u = -U_0.
    pub fn from_idp(grid: &CrossGrid, idp: &InitialDataPlane, ambient_k: f64, ambient_eps: f64) -> Self {
        let mut s = Self::at_rest(grid, ambient_k, ambient_eps);
        let dz = grid.dz;
        for (j, &y) in grid.y_centres.iter().enumerate() {
            for (kk, &z) in grid.z_centres.iter().enumerate() {
                let p = idp.at(y, -z);
                s.u[[j, kk]] = -p.u0;
                s.k[[j, kk]] = ambient_k + p.k;
                s.eps[[j, kk]] = ambient_eps + p.eps;
            }
        }
        for (jf, &y) in grid.y_faces.iter().enumerate() {
            for (kk, &z) in grid.z_centres.iter().enumerate() {
                s.v[[jf, kk]] = idp.at(y, -z).v;
            }
        }
        for (j, &y) in grid.y_centres.iter().enumerate() {
            for kf in 1..grid.nz() {
                s.w[[j, kf]] = idp.at(y, kf as f64 * dz).w;
            }
        }
        s
    }
}

//! Cross-plane momentum (the y and z components of Eq. (2.3)) on the staggered grid:
//! advection in flux form with limited upwind values, the full viscous stress
//! (nu + nu_t)(dU_i/dx_j + dU_j/dx_i), Boussinesq buoyancy (Eq. (2.5)), the Craik-Leibovich vortex
//! force u_S x omega (Eq. (2.6)) and the beach damping. Pressure enters through the projection.
//! The tendencies here leave out the stress's cross-track Laplacian, nu d2V/dy2 and nu d2W/dy2,
//! which [`crate::cross_diffusion`] applies implicitly after the explicit step.
//!
//! With d/dx = 0 (2D+t) and u_S = (u_Sx, u_Sy, 0)(z), omega = (dW/dy - dV/dz, dU/dz, -dU/dy), so
//! u_S x omega = (-u_Sy dU/dy, u_Sx dU/dy, u_Sx dU/dz - u_Sy (dW/dy - dV/dz)): the swell turns the
//! shear of the axial wake into cross-plane circulation, which is what makes wakes persist.

use crate::forcing::{beach_damping, vortex_force_cross, vortex_force_vertical};
use crate::setup::Setup;
use crate::transport::upwind_face;
use rayon::prelude::*;
use wakelab_core::config::LateralBoundary;

/// Per-stage fields the momentum tendencies read.
pub struct MomentumInputs<'a> {
    pub u: &'a [f64],
    pub v: &'a [f64],
    pub w: &'a [f64],
    /// nu + nu_t at cell centres.
    pub viscosity: &'a [f64],
    /// Buoyancy b' = -g (rho - rho_b) / rho_b at cell centres.
    pub buoyancy: &'a [f64],
    /// Shear stress at the corners.
    pub corner: &'a CornerStress,
    /// Somero's extra normal stresses (v'v', w'w' corrections) at centres, if enabled.
    pub normal_correction: Option<(&'a [f64], &'a [f64])>,
}

/// The shear stress at the corners ((ny + 1) x (nz + 1)), zero on the lid, bottom and sides
/// (free slip), and the viscosity there.
#[derive(Debug, Clone)]
pub struct CornerStress {
    /// tau_yz / rho = (nu + nu_t)(dV/dz + dW/dy), what V's equation reads.
    pub shear: Vec<f64>,
    /// (nu + nu_t) dV/dz, the explicit part of tau_yz in W's equation: its (nu + nu_t) dW/dy part
    /// is taken implicitly ([`crate::cross_diffusion`]).
    pub vertical_shear: Vec<f64>,
    /// nu + nu_t at the corners (the turbulent part scaled by Somero's factor where enabled).
    pub viscosity: Vec<f64>,
}

impl CornerStress {
    pub fn new(s: &Setup) -> Self {
        let n = (s.ny + 1) * (s.nz + 1);
        Self {
            shear: vec![0.0; n],
            vertical_shear: vec![0.0; n],
            viscosity: vec![0.0; n],
        }
    }

    /// The stress of velocity (v, w) with centre viscosity nu + nu_t; `factor` scales the
    /// turbulent part (Somero's v'w' damping) if given.
    pub fn update(&mut self, s: &Setup, v: &[f64], w: &[f64], viscosity: &[f64], factor: Option<&[f64]>) {
        let (ny, nz) = (s.ny, s.nz);
        self.shear
            .par_chunks_mut(nz + 1)
            .zip(self.vertical_shear.par_chunks_mut(nz + 1))
            .zip(self.viscosity.par_chunks_mut(nz + 1))
            .enumerate()
            .for_each(|(jf, ((shear, vertical), nu_out))| {
                shear.fill(0.0);
                vertical.fill(0.0);
                nu_out.fill(0.0);
                if jf == 0 || jf == ny {
                    return;
                }
                for kf in 1..nz {
                    let c = |j: usize, k: usize| {
                        let i = j * nz + k;
                        let nu_t = viscosity[i] - s.viscosity;
                        s.viscosity + nu_t * factor.map_or(1.0, |f| f[i])
                    };
                    let nu = 0.25 * (c(jf - 1, kf - 1) + c(jf - 1, kf) + c(jf, kf - 1) + c(jf, kf));
                    let dvdz = (v[jf * nz + kf - 1] - v[jf * nz + kf]) / s.dz;
                    let dwdy = (w[jf * (nz + 1) + kf] - w[(jf - 1) * (nz + 1) + kf]) / s.dyc[jf];
                    shear[kf] = nu * (dvdz + dwdy);
                    vertical[kf] = nu * dvdz;
                    nu_out[kf] = nu;
                }
            });
    }
}

/// Tendency of V at every y face (boundary faces are set by the boundary condition later).
pub fn v_tendency(s: &Setup, f: &MomentumInputs, out: &mut [f64]) {
    let (ny, nz, dz) = (s.ny, s.nz, s.dz);
    let (u, v, w) = (f.u, f.v, f.w);
    out.par_chunks_mut(nz).enumerate().for_each(|(jf, col)| {
        if jf == 0 || jf == ny {
            col.fill(0.0);
            return;
        }
        let vf = |j: usize, k: usize| v[j * nz + k];
        // flux of V through the cell centre c (between faces c and c + 1) at level k
        let centre_flux = |c: usize, k: usize| {
            let vel = 0.5 * (vf(c, k) + vf(c + 1, k));
            let face = if vel >= 0.0 {
                upwind_face(if c >= 1 { Some(vf(c - 1, k)) } else { None }, vf(c, k), vf(c + 1, k))
            } else {
                upwind_face(
                    if c + 2 <= ny { Some(vf(c + 2, k)) } else { None },
                    vf(c + 1, k),
                    vf(c, k),
                )
            };
            // Half of the normal stress 2 nu dV/dy: the other half is implicit (cross_diffusion).
            let mut tau = f.viscosity[c * nz + k] * (vf(c + 1, k) - vf(c, k)) / s.dy[c];
            if let Some((vv, _)) = f.normal_correction {
                tau -= vv[c * nz + k];
            }
            vel * face - tau
        };
        let wf = |j: usize, kf: usize| w[j * (nz + 1) + kf];
        let mut top = 0.0;
        for k in 0..nz {
            let bottom = if k + 1 < nz {
                let kf = k + 1;
                let vel = 0.5 * (wf(jf - 1, kf) + wf(jf, kf));
                let face = if vel >= 0.0 {
                    upwind_face(
                        if kf + 1 < nz { Some(vf(jf, kf + 1)) } else { None },
                        vf(jf, kf),
                        vf(jf, kf - 1),
                    )
                } else {
                    upwind_face(
                        if kf >= 2 { Some(vf(jf, kf - 2)) } else { None },
                        vf(jf, kf - 1),
                        vf(jf, kf),
                    )
                };
                vel * face - f.corner.shear[jf * (nz + 1) + kf]
            } else {
                0.0
            };
            let div = (centre_flux(jf, k) - centre_flux(jf - 1, k)) / s.dyc[jf] - (bottom - top) / dz;
            let dudy = (u[jf * nz + k] - u[(jf - 1) * nz + k]) / s.dyc[jf];
            let vortex = vortex_force_cross(s.stokes_centre.along[k], dudy);
            col[k] = -div + vortex - beach_damping(s.damping_face[jf], vf(jf, k));
            top = bottom;
        }
    });
}

/// Tendency of W at every z face (zero on the lid and the bottom).
pub fn w_tendency(s: &Setup, f: &MomentumInputs, out: &mut [f64]) {
    let (ny, nz, dz) = (s.ny, s.nz, s.dz);
    let (u, v, w) = (f.u, f.v, f.w);
    out.par_chunks_mut(nz + 1).enumerate().for_each(|(j, col)| {
        col[0] = 0.0;
        col[nz] = 0.0;
        let wf = |j: usize, kf: usize| w[j * (nz + 1) + kf];
        let vf = |jf: usize, k: usize| v[jf * nz + k];
        // upward flux of W through the centre of cell c (between faces c and c + 1)
        let centre_flux = |c: usize| {
            let vel = 0.5 * (wf(j, c) + wf(j, c + 1));
            let face = if vel >= 0.0 {
                upwind_face(
                    if c + 2 <= nz { Some(wf(j, c + 2)) } else { None },
                    wf(j, c + 1),
                    wf(j, c),
                )
            } else {
                upwind_face(if c >= 1 { Some(wf(j, c - 1)) } else { None }, wf(j, c), wf(j, c + 1))
            };
            let mut tau = 2.0 * f.viscosity[j * nz + c] * (wf(j, c) - wf(j, c + 1)) / dz;
            if let Some((_, ww)) = f.normal_correction {
                tau -= ww[j * nz + c];
            }
            vel * face - tau
        };
        // cross-track flux of W through the corner (jf, kf)
        let corner_flux = |jf: usize, kf: usize| {
            let vel = 0.5 * (vf(jf, kf - 1) + vf(jf, kf));
            if jf == 0 || jf == ny {
                return match s.lateral {
                    LateralBoundary::Wall => 0.0,
                    LateralBoundary::Outlet => {
                        let inside = wf(if jf == 0 { 0 } else { ny - 1 }, kf);
                        let inflow = (jf == 0 && vel > 0.0) || (jf == ny && vel < 0.0);
                        vel * if inflow { 0.0 } else { inside }
                    }
                };
            }
            let (l, r) = (jf - 1, jf);
            let face = if vel >= 0.0 {
                upwind_face(if l >= 1 { Some(wf(l - 1, kf)) } else { None }, wf(l, kf), wf(r, kf))
            } else {
                upwind_face(
                    if r + 1 < ny { Some(wf(r + 1, kf)) } else { None },
                    wf(r, kf),
                    wf(l, kf),
                )
            };
            vel * face - f.corner.vertical_shear[jf * (nz + 1) + kf]
        };
        let inv_dy = 1.0 / s.dy[j];
        for kf in 1..nz {
            let div =
                (corner_flux(j + 1, kf) - corner_flux(j, kf)) * inv_dy + (centre_flux(kf - 1) - centre_flux(kf)) / dz;
            let buoyancy = 0.5 * (f.buoyancy[j * nz + kf - 1] + f.buoyancy[j * nz + kf]);
            let dudz = (u[j * nz + kf - 1] - u[j * nz + kf]) / dz;
            let (jl, jr) = (j.saturating_sub(1), (j + 1).min(ny - 1));
            let dwdy = if jr > jl {
                (wf(jr, kf) - wf(jl, kf)) / (s.grid.y_centres[jr] - s.grid.y_centres[jl])
            } else {
                0.0
            };
            let dvdz = 0.5 * ((vf(j, kf - 1) - vf(j, kf)) + (vf(j + 1, kf - 1) - vf(j + 1, kf))) / dz;
            let vortex = vortex_force_vertical(s.stokes_face.along[kf], s.stokes_face.across[kf], dudz, dwdy - dvdz);
            col[kf] = -div + buoyancy + vortex - beach_damping(s.damping_centre[j], wf(j, kf));
        }
    });
}

//! Forcing terms the solver adds to the axial velocity and the background scalars after their
//! transport: the vortex force on U (Eq. (2.6)), the beaches' damping, and the right-hand sides
//! of the background temperature and salinity perturbations (Eqs. (2.22)-(2.23)).

use crate::setup::Setup;
use rayon::prelude::*;

/// The axial component of the Craik-Leibovich vortex force u_S x omega, f_x = -u_Sy dU/dy
/// (Eq. (2.6)), for cross-track Stokes drift `stokes_across` and shear `dudy`.
fn vortex_force_axial(stokes_across: f64, dudy: f64) -> f64 {
    -stokes_across * dudy
}

/// The cross-track component of the vortex force, f_y = u_Sx dU/dy (Eq. (2.6)), for along-track
/// Stokes drift `stokes_along`.
pub(crate) fn vortex_force_cross(stokes_along: f64, dudy: f64) -> f64 {
    stokes_along * dudy
}

/// The vertical component of the vortex force, f_z = u_Sx dU/dz - u_Sy omega_x (Eq. (2.6)),
/// omega_x = dW/dy - dV/dz the axial vorticity.
pub(crate) fn vortex_force_vertical(stokes_along: f64, stokes_across: f64, dudz: f64, axial_vorticity: f64) -> f64 {
    stokes_along * dudz - stokes_across * axial_vorticity
}

/// The beaches' relaxation of a perturbation `value` at rate `rate` (1/s): not physics, a sponge
/// that keeps the domain's sides from reflecting (see `Setup::damping_centre`).
pub(crate) fn beach_damping(rate: f64, value: f64) -> f64 {
    rate * value
}

/// Adds to dU/dt the vortex force (Eq. (2.6)) and the beaches' damping.
pub(crate) fn add_axial_forces(s: &Setup, u: &[f64], du: &mut [f64]) {
    let (ny, nz) = (s.ny, s.nz);
    du.par_chunks_mut(nz).enumerate().for_each(|(j, col)| {
        let (jl, jr) = (j.saturating_sub(1), (j + 1).min(ny - 1));
        let dist = s.grid.y_centres[jr] - s.grid.y_centres[jl];
        for (kk, x) in col.iter_mut().enumerate() {
            let dudy = (u[jr * nz + kk] - u[jl * nz + kk]) / dist;
            *x += vortex_force_axial(s.stokes_centre.across[kk], dudy)
                - beach_damping(s.damping_centre[j], u[j * nz + kk]);
        }
    });
}

/// Right-hand sides of Eqs. (2.22)-(2.23): -W d f_b/dz + d/dz(nu_t / sigma_t d f_b/dz), with no
/// turbulent flux through the lid or bottom, and beach damping of the perturbation.
///
/// The background is steady under the ambient turbulence (it solves its own equation, Eq. (2.8)),
/// so only the wake's excess eddy viscosity nu_t - nu_t,amb mixes it.
pub(crate) fn add_background_sources(
    s: &Setup,
    nut: &[f64],
    w: &[f64],
    perturbation: &[f64],
    grad: &[f64],
    face_grad: &[f64],
    out: &mut [f64],
) {
    let nz = s.nz;
    let inv_sigma = 1.0 / s.constants.sigma_t;
    let amb = s.ambient_eddy_viscosity();
    out.par_chunks_mut(nz).enumerate().for_each(|(j, col)| {
        let face_flux = |kf: usize| {
            if kf == 0 || kf == nz {
                0.0
            } else {
                (0.5 * (nut[j * nz + kf - 1] + nut[j * nz + kf]) - amb) * inv_sigma * face_grad[kf]
            }
        };
        for (kk, x) in col.iter_mut().enumerate() {
            let wc = 0.5 * (w[j * (nz + 1) + kk] + w[j * (nz + 1) + kk + 1]);
            // flux K df_b/dz is upward-positive gradient flux; its divergence is (top - bottom)/dz
            let diffusion = (face_flux(kk) - face_flux(kk + 1)) / s.dz;
            *x += -wc * grad[kk] + diffusion - beach_damping(s.damping_centre[j], perturbation[j * nz + kk]);
        }
    });
}

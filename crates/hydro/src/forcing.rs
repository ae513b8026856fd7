//! Forcing terms the solver adds to the axial velocity and the background scalars after their
//! transport: the vortex force on U (Eq. (2.6)) with beach damping, and the right-hand sides of
//! the background temperature and salinity perturbations (Eqs. (2.22)-(2.23)).

use crate::setup::Setup;
use rayon::prelude::*;

/// Vortex force on U, f_x = -u_Sy dU/dy (Eq. (2.6)), and beach damping.
pub(crate) fn add_axial_forces(s: &Setup, u: &[f64], du: &mut [f64]) {
    let (ny, nz) = (s.ny, s.nz);
    du.par_chunks_mut(nz).enumerate().for_each(|(j, col)| {
        let (jl, jr) = (j.saturating_sub(1), (j + 1).min(ny - 1));
        let dist = s.grid.y_centres[jr] - s.grid.y_centres[jl];
        for (kk, x) in col.iter_mut().enumerate() {
            let dudy = (u[jr * nz + kk] - u[jl * nz + kk]) / dist;
            *x += -s.stokes_centre.across[kk] * dudy - s.damping_centre[j] * u[j * nz + kk];
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
            *x += -wc * grad[kk] + diffusion - s.damping_centre[j] * perturbation[j * nz + kk];
        }
    });
}

//! Advection and diffusion of cell-centred fields in conservative flux form (the left-hand sides
//! of Eqs. 2.9, 2.10, 2.22 and 2.23, and of the axial momentum component of Eq. 2.3).
//!
//! Advective face values are MUSCL reconstructions with the minmod limiter (second order where
//! the field is smooth, no new extrema at fronts); diffusive fluxes use the face-averaged
//! diffusivity. Fluxes through the lid and bottom are zero; at an outlet the advective flux
//! carries the boundary cell's value out and the ambient value in, with no diffusive flux.

use crate::setup::Setup;
use rayon::prelude::*;
use wakelab_core::config::LateralBoundary;

/// minmod slope limiter.
#[inline]
pub fn minmod(a: f64, b: f64) -> f64 {
    if a * b <= 0.0 {
        0.0
    } else if a.abs() < b.abs() {
        a
    } else {
        b
    }
}

/// Limited upwind face value for flow from `a` towards `b`; `aa` lies behind `a` if it exists.
#[inline]
pub fn upwind_face(aa: Option<f64>, a: f64, b: f64) -> f64 {
    match aa {
        Some(aa) => a + 0.5 * minmod(a - aa, b - a),
        None => a,
    }
}

/// Diffusivity of a transported field: `molecular + nu_t * turbulent_factor`.
#[derive(Debug, Clone, Copy)]
pub struct Diffusivity<'a> {
    pub molecular: f64,
    pub turbulent_factor: f64,
    pub eddy_viscosity: &'a [f64],
    /// Extra factor on the turbulent part of the vertical flux (Somero's u'w' damping), if any.
    pub vertical_factor: Option<&'a [f64]>,
}

impl Diffusivity<'_> {
    #[inline]
    fn horizontal(&self, i: usize) -> f64 {
        self.molecular + self.turbulent_factor * self.eddy_viscosity[i]
    }

    #[inline]
    fn vertical(&self, i: usize) -> f64 {
        let f = self.vertical_factor.map_or(1.0, |f| f[i]);
        self.molecular + self.turbulent_factor * self.eddy_viscosity[i] * f
    }
}

/// Cross-track flux (per unit area) of `phi` through y face `jf` at level `k`.
#[inline]
fn y_flux(s: &Setup, phi: &[f64], v: &[f64], diff: &Diffusivity, jf: usize, k: usize, ambient: f64) -> f64 {
    let (ny, nz) = (s.ny, s.nz);
    let vel = v[jf * nz + k];
    if jf == 0 || jf == ny {
        return match s.lateral {
            LateralBoundary::Wall => 0.0,
            LateralBoundary::Outlet => {
                let inside = phi[if jf == 0 { k } else { (ny - 1) * nz + k }];
                let inflow = (jf == 0 && vel > 0.0) || (jf == ny && vel < 0.0);
                vel * if inflow { ambient } else { inside }
            }
        };
    }
    let (l, r) = (jf - 1, jf);
    let at = |j: usize| phi[j * nz + k];
    let face = if vel >= 0.0 {
        upwind_face(if l >= 1 { Some(at(l - 1)) } else { None }, at(l), at(r))
    } else {
        upwind_face(if r + 1 < ny { Some(at(r + 1)) } else { None }, at(r), at(l))
    };
    let kd = 0.5 * (diff.horizontal(l * nz + k) + diff.horizontal(r * nz + k));
    vel * face - kd * (at(r) - at(l)) / s.dyc[jf]
}

/// Tendency of a cell-centred field from advection by (V, W) and diffusion, written to `out`.
pub fn advect_diffuse(s: &Setup, phi: &[f64], v: &[f64], w: &[f64], diff: &Diffusivity, ambient: f64, out: &mut [f64]) {
    let nz = s.nz;
    let dz = s.dz;
    out.par_chunks_mut(nz).enumerate().for_each(|(j, col)| {
        let c = &phi[j * nz..(j + 1) * nz];
        let wcol = &w[j * (nz + 1)..(j + 1) * (nz + 1)];
        let inv_dy = 1.0 / s.dy[j];
        // upward flux through the top face of cell k (zero at the lid)
        let mut top = 0.0;
        for k in 0..nz {
            let bottom = if k + 1 < nz {
                let kf = k + 1;
                let vel = wcol[kf];
                // the face lies between cell kf - 1 (above) and kf (below)
                let face = if vel >= 0.0 {
                    upwind_face(if kf + 1 < nz { Some(c[kf + 1]) } else { None }, c[kf], c[kf - 1])
                } else {
                    upwind_face(if kf >= 2 { Some(c[kf - 2]) } else { None }, c[kf - 1], c[kf])
                };
                let kd = 0.5 * (diff.vertical(j * nz + kf - 1) + diff.vertical(j * nz + kf));
                vel * face - kd * (c[kf - 1] - c[kf]) / dz
            } else {
                0.0
            };
            let west = y_flux(s, phi, v, diff, j, k, ambient);
            let east = y_flux(s, phi, v, diff, j + 1, k, ambient);
            col[k] = -(east - west) * inv_dy + (bottom - top) / dz;
            top = bottom;
        }
    });
}

//! Advection and diffusion of cell-centred fields in conservative flux form (the left-hand sides
//! of Eqs. (2.9), (2.10), (2.22) and (2.23), and of the axial momentum component of Eq. (2.3)).
//!
//! Advective face values are MUSCL reconstructions with the minmod limiter (second order where
//! the field is smooth, no new extrema at fronts); vertical diffusive fluxes use the
//! face-averaged diffusivity. Cross-track diffusion is not here: it is taken implicitly after the
//! explicit step ([`crate::cross_diffusion`]), with the same face diffusivity. Fluxes through the
//! lid and bottom are zero; at an outlet the advective flux carries the boundary cell's value out
//! and the ambient value in, with no diffusive flux.

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
    fn vertical(&self, i: usize) -> f64 {
        let f = self.vertical_factor.map_or(1.0, |f| f[i]);
        self.molecular + self.turbulent_factor * self.eddy_viscosity[i] * f
    }
}

/// One transported field: its values, diffusivity, inflow value at outlets and tendency.
pub struct Transported<'a> {
    pub values: &'a [f64],
    pub diffusivity: Diffusivity<'a>,
    /// Value carried in through an outlet.
    pub ambient: f64,
}

/// Columns per parallel task: each task computes every y-face flux of its columns once.
pub const COLUMN_BLOCK: usize = 32;

/// Cross-track advective fluxes (per unit area) of every field through y face `jf` at level `k`,
/// into `out`.
#[inline]
fn y_fluxes<const N: usize>(s: &Setup, f: &[Transported; N], v: &[f64], jf: usize, k: usize, out: &mut [f64; N]) {
    let (ny, nz) = (s.ny, s.nz);
    let vel = v[jf * nz + k];
    if jf == 0 || jf == ny {
        let inside = if jf == 0 { k } else { (ny - 1) * nz + k };
        let inflow = (jf == 0 && vel > 0.0) || (jf == ny && vel < 0.0);
        for (o, t) in out.iter_mut().zip(f) {
            *o = match s.lateral {
                LateralBoundary::Wall => 0.0,
                LateralBoundary::Outlet => vel * if inflow { t.ambient } else { t.values[inside] },
            };
        }
        return;
    }
    let (l, r) = ((jf - 1) * nz + k, jf * nz + k);
    let (a, b, aa) = if vel >= 0.0 {
        (l, r, (jf >= 2).then(|| l - nz))
    } else {
        (r, l, (jf + 1 < ny).then(|| r + nz))
    };
    for (o, t) in out.iter_mut().zip(f) {
        let p = t.values;
        *o = vel * upwind_face(aa.map(|i| p[i]), p[a], p[b]);
    }
}

/// Tendencies of N cell-centred fields from advection by (V, W) and vertical diffusion, in one
/// pass that shares the velocity, upwind direction and eddy viscosity of every face; written to
/// `out`.
pub fn advect_diffuse<const N: usize>(
    s: &Setup,
    fields: &[Transported; N],
    v: &[f64],
    w: &[f64],
    out: [&mut [f64]; N],
) {
    let nz = s.nz;
    let dz = s.dz;
    let size = nz * COLUMN_BLOCK;
    let mut iters = out.map(|o| o.chunks_mut(size));
    let blocks: Vec<[&mut [f64]; N]> = (0..s.ny.div_ceil(COLUMN_BLOCK))
        .map(|_| std::array::from_fn(|f| iters[f].next().expect("block")))
        .collect();
    blocks.into_par_iter().enumerate().for_each(|(b, block)| {
        let j0 = b * COLUMN_BLOCK;
        let columns = block[0].len() / nz;
        let mut west = vec![[0.0; N]; nz];
        let mut east = vec![[0.0; N]; nz];
        for (k, wf) in west.iter_mut().enumerate() {
            y_fluxes(s, fields, v, j0, k, wf);
        }
        for dj in 0..columns {
            let j = j0 + dj;
            for (k, e) in east.iter_mut().enumerate() {
                y_fluxes(s, fields, v, j + 1, k, e);
            }
            let wcol = &w[j * (nz + 1)..(j + 1) * (nz + 1)];
            let inv_dy = 1.0 / s.dy[j];
            let base = j * nz;
            // upward flux through the top face of cell k (zero at the lid)
            let mut top = [0.0; N];
            for k in 0..nz {
                let mut bottom = [0.0; N];
                if k + 1 < nz {
                    let kf = k + 1;
                    let vel = wcol[kf];
                    // the face lies between cell kf - 1 (above) and kf (below)
                    let (a, bb, aa) = if vel >= 0.0 {
                        (kf, kf - 1, (kf + 1 < nz).then_some(kf + 1))
                    } else {
                        (kf - 1, kf, (kf >= 2).then(|| kf - 2))
                    };
                    for (o, t) in bottom.iter_mut().zip(fields) {
                        let c = &t.values[base..base + nz];
                        let face = upwind_face(aa.map(|i| c[i]), c[a], c[bb]);
                        let kd = 0.5 * (t.diffusivity.vertical(base + kf - 1) + t.diffusivity.vertical(base + kf));
                        *o = vel * face - kd * (c[kf - 1] - c[kf]) / dz;
                    }
                }
                for f in 0..N {
                    block[f][dj * nz + k] = -(east[k][f] - west[k][f]) * inv_dy + (bottom[f] - top[f]) / dz;
                }
                top = bottom;
            }
            std::mem::swap(&mut west, &mut east);
        }
    });
}

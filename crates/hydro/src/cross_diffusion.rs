//! Cross-track (y) diffusion taken implicitly: backward Euler, one tridiagonal solve per level.
//!
//! The grid is 0.5 m across and 1.5 m deep (spec 2.1.2), so the explicit limit of the y part of
//! the diffusion terms of Eqs. (2.3), (2.9), (2.10), (2.22) and (2.23), dt < dy^2 / (4 nu), held
//! the paper run at 0.36-3 s per step for its first 40 minutes while advection and the
//! turbulence time scale allowed 3-30 s. The y fluxes of the diffusion are therefore split off
//! the explicit step (Lie splitting) and applied afterwards by backward Euler,
//! (I - dt D_y) phi_new = phi*, which is unconditionally stable, keeps k and eps positive (its
//! matrix is an M-matrix) and conserves the integral of phi where the sides carry no flux. What
//! is left explicit is vertical diffusion, whose limit dt < dz^2 / (4 nu) is nine times larger.
//!
//! For the velocity on the staggered grid the implicit part is the Laplacian part of the viscous
//! stress: nu d2W/dy2 through the corners for W and nu d2V/dy2 through the centres for V. The
//! rest of V's normal stress, d/dy(nu dV/dy), stays explicit beside the cross term d/dz(nu dW/dy):
//! together they are nu d/dy(div u) plus gradient-of-nu terms, which vanish on the projected,
//! divergence-free velocity, so the explicit step keeps no stiff y term.

use crate::setup::{Setup, PRANDTL, SCHMIDT};
use crate::state::WakeState;
use crate::turbulence::Derived;
use std::ops::Range;

/// One field's y lines: unknown rows `rows` of an array laid out `[row * stride + level]`,
/// levels `levels`. Row `j`'s control volume is `width(j)` wide; the face between rows `j - 1`
/// and `j` conducts `conductance(j, level)` = K / distance (m/s). A face with zero conductance
/// carries no flux; where a face at the ends of `rows` conducts, the row beyond it is a fixed
/// (Dirichlet) value read from the array.
pub struct Lines<'a, C, W> {
    pub values: &'a mut [f64],
    pub stride: usize,
    pub rows: Range<usize>,
    pub levels: Range<usize>,
    pub conductance: C,
    pub width: W,
}

impl<C, W> Lines<'_, C, W>
where
    C: Fn(usize, usize) -> f64,
    W: Fn(usize) -> f64,
{
    /// Solve phi - dt / width(j) [g_{j+1} (phi_{j+1} - phi_j) - g_j (phi_j - phi_{j-1})] = phi*
    /// in place (the Thomas algorithm, all levels of a row at once so the inner loop runs over
    /// contiguous memory). `modified_upper` is work space of at least rows x levels.
    pub fn solve_backward_euler(self, dt: f64, modified_upper: &mut Vec<f64>) {
        let Lines {
            values,
            stride,
            rows,
            levels,
            conductance,
            width,
        } = self;
        let nl = levels.len();
        if rows.is_empty() || nl == 0 {
            return;
        }
        modified_upper.resize(rows.len() * nl, 0.0);
        let (first, last) = (rows.start, rows.end - 1);
        for j in rows.clone() {
            let r = dt / width(j);
            let row = j * stride;
            let prev = (j - rows.start).checked_sub(1).map(|p| p * nl);
            let here = (j - rows.start) * nl;
            for (l, k) in levels.clone().enumerate() {
                let lower = r * conductance(j, k);
                let upper = r * conductance(j + 1, k);
                let mut rhs = values[row + k];
                if j == first && lower > 0.0 {
                    rhs += lower * values[row - stride + k];
                }
                if j == last && upper > 0.0 {
                    rhs += upper * values[row + stride + k];
                }
                // Row: -lower phi_{j-1} + (1 + lower + upper) phi_j - upper phi_{j+1} = rhs.
                // Thomas: c'_j = C_j / m_j, d'_j = (D_j - A_j d'_{j-1}) / m_j with
                // m_j = B_j - A_j c'_{j-1}, A_j = -lower, C_j = -upper.
                let (pivot, rhs) = match prev {
                    Some(p) => {
                        let cp = modified_upper[p + l];
                        let d_prev = values[row - stride + k];
                        (1.0 + lower + upper + lower * cp, rhs + lower * d_prev)
                    }
                    None => (1.0 + lower + upper, rhs),
                };
                let upper_here = if j == last { 0.0 } else { upper };
                modified_upper[here + l] = -upper_here / pivot;
                values[row + k] = rhs / pivot;
            }
        }
        for j in (first..last).rev() {
            let here = (j - rows.start) * nl;
            for (l, k) in levels.clone().enumerate() {
                let next = values[(j + 1) * stride + k];
                values[j * stride + k] -= modified_upper[here + l] * next;
            }
        }
    }
}

/// Work space of [`diffuse_across`]: one line buffer per field.
#[derive(Debug, Clone, Default)]
pub struct CrossDiffusionWork {
    buffers: [Vec<f64>; 7],
}

/// Apply one backward-Euler step of the cross-track diffusion of every field of `state`, with
/// the diffusivities of the stage that `derived` and `corner_viscosity` (nu + nu_t at the
/// corners, Somero's factor included) were computed from.
pub fn diffuse_across(
    s: &Setup,
    derived: &Derived,
    corner_viscosity: &[f64],
    state: &mut WakeState,
    dt: f64,
    work: &mut CrossDiffusionWork,
) {
    let (ny, nz) = (s.ny, s.nz);
    let c = s.constants;
    let nut = derived.eddy_viscosity.as_slice();
    let (dy, dyc) = (s.dy.as_slice(), s.dyc.as_slice());
    // Face diffusivity of a cell-centred field, as in the explicit fluxes of `transport`.
    let centred = |molecular: f64, factor: f64| {
        move |jf: usize, k: usize| {
            if jf == 0 || jf == ny {
                0.0
            } else {
                (molecular + factor * 0.5 * (nut[(jf - 1) * nz + k] + nut[jf * nz + k])) / dyc[jf]
            }
        }
    };
    let cell_width = |j: usize| dy[j];
    let viscosity = derived.viscosity.as_slice();
    let WakeState {
        u,
        v,
        w,
        k,
        eps,
        temperature,
        salinity,
    } = state;
    let [bu, bv, bw, bk, beps, bt, bs] = &mut work.buffers;
    rayon::scope(|sc| {
        let centred_fields = [
            (u, bu, s.viscosity, 1.0),
            (k, bk, s.viscosity, 1.0 / c.sigma_k),
            (eps, beps, s.viscosity, 1.0 / c.sigma_eps),
            (temperature, bt, s.viscosity / PRANDTL, 1.0 / c.sigma_t),
            (salinity, bs, s.viscosity / SCHMIDT, 1.0 / c.sigma_t),
        ];
        for (values, buffer, molecular, factor) in centred_fields {
            sc.spawn(move |_| {
                Lines {
                    values: values.as_slice_mut().expect("layout"),
                    stride: nz,
                    rows: 0..ny,
                    levels: 0..nz,
                    conductance: centred(molecular, factor),
                    width: cell_width,
                }
                .solve_backward_euler(dt, buffer)
            });
        }
        // V on the y faces 1..ny - 1 (faces 0 and ny hold the boundary values); its control
        // volume spans the centres on either side, whose viscosity conducts.
        sc.spawn(|_| {
            Lines {
                values: v.as_slice_mut().expect("layout"),
                stride: nz,
                rows: 1..ny,
                levels: 0..nz,
                conductance: |jf: usize, k: usize| viscosity[(jf - 1) * nz + k] / dy[jf - 1],
                width: |jf: usize| dyc[jf],
            }
            .solve_backward_euler(dt, bv)
        });
        // W on the interior z faces; the corners conduct, none through the sides (free slip).
        sc.spawn(|_| {
            Lines {
                values: w.as_slice_mut().expect("layout"),
                stride: nz + 1,
                rows: 0..ny,
                levels: 1..nz,
                conductance: |jf: usize, kf: usize| {
                    if jf == 0 || jf == ny {
                        0.0
                    } else {
                        corner_viscosity[jf * (nz + 1) + kf] / dyc[jf]
                    }
                },
                width: cell_width,
            }
            .solve_backward_euler(dt, bw)
        });
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A Gaussian on a uniform line with no-flux ends spreads as the heat kernel:
    /// variance sigma0^2 + 2 K t, and its integral is conserved.
    #[test]
    fn a_gaussian_spreads_as_the_heat_kernel_and_keeps_its_integral() {
        let (n, h, kappa) = (801, 0.5, 0.1);
        let centre = 0.5 * (n as f64 - 1.0) * h;
        let sigma0: f64 = 4.0;
        let mut phi: Vec<f64> = (0..n)
            .map(|j| (-(j as f64 * h - centre).powi(2) / (2.0 * sigma0 * sigma0)).exp())
            .collect();
        let mass0: f64 = phi.iter().sum::<f64>() * h;
        let (dt, steps) = (2.0, 100);
        let mut work = Vec::new();
        for _ in 0..steps {
            Lines {
                values: &mut phi,
                stride: 1,
                rows: 0..n,
                levels: 0..1,
                conductance: |j: usize, _| if j == 0 || j == n { 0.0 } else { kappa / h },
                width: |_| h,
            }
            .solve_backward_euler(dt, &mut work);
        }
        let mass: f64 = phi.iter().sum::<f64>() * h;
        assert!((mass - mass0).abs() < 1e-10 * mass0, "integral {mass} vs {mass0}");
        let variance = phi
            .iter()
            .enumerate()
            .map(|(j, p)| p * (j as f64 * h - centre).powi(2))
            .sum::<f64>()
            * h
            / mass;
        let expected = sigma0 * sigma0 + 2.0 * kappa * dt * steps as f64;
        // Backward Euler's variance grows by exactly 2 K dt per step on an unbounded uniform
        // line (the discrete Laplacian's second moment), so only the ends could differ.
        assert!(
            (variance - expected).abs() < 1e-6 * expected,
            "variance {variance} vs {expected}"
        );
        assert!(phi.iter().all(|&p| p >= 0.0), "backward Euler keeps values positive");
    }

    /// Fixed values beyond the ends: the steady state between them is the straight line, and
    /// levels are solved independently.
    #[test]
    fn dirichlet_ends_relax_to_the_linear_profile_at_every_level() {
        let (rows, levels) = (50, 3);
        let stride = levels;
        let mut v = vec![0.0; (rows + 2) * stride];
        for k in 0..levels {
            v[k] = 1.0 + k as f64;
            v[(rows + 1) * stride + k] = -2.0;
        }
        let mut work = Vec::new();
        Lines {
            values: &mut v,
            stride,
            rows: 1..rows + 1,
            levels: 0..levels,
            conductance: |_, _| 1.0,
            width: |_| 1.0,
        }
        .solve_backward_euler(1e9, &mut work);
        for k in 0..levels {
            let (a, b) = (1.0 + k as f64, -2.0);
            for j in 0..rows + 2 {
                let exact = a + (b - a) * j as f64 / (rows + 1) as f64;
                assert!((v[j * stride + k] - exact).abs() < 1e-6, "row {j} level {k}");
            }
        }
    }
}

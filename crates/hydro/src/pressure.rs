//! The projection step (Eq. (2.65)): the cell divergence, the direct pressure Poisson solver and
//! the correction of the velocity to divergence-free.
//!
//! On the staggered (MAC) grid the pressure Laplacian is D G, with D the cell divergence and G
//! the face gradient. z is uniform with no-flux lid and bottom, so a DCT-II in z diagonalises the
//! vertical part exactly (eigenvalues -4 sin^2(pi m / 2 nz) / dz^2); each vertical mode then needs
//! one tridiagonal solve across y, where the grid stretches in the beaches. The Thomas
//! factorisation of every mode is computed once, so a solve is two DCTs per column plus two
//! sweeps per mode: O(N log nz), in parallel over columns and modes.

use crate::setup::Setup;
use crate::state::WakeState;
use ndarray::Array2;
use rayon::prelude::*;
use rustdct::{DctPlanner, TransformType2And3};
use std::sync::Arc;
use wakelab_core::config::LateralBoundary;
use wakelab_core::CrossGrid;

/// Factorised Poisson operator for one grid and lateral boundary.
pub struct PressureSolver {
    ny: usize,
    nz: usize,
    dct: Arc<dyn TransformType2And3<f64>>,
    /// Sub-diagonal a_j (coefficient of p[j-1]) of row j.
    lower: Vec<f64>,
    /// Thomas factorisation per mode: modified super-diagonal c'_j and 1 / pivot, [m][j].
    c_prime: Vec<f64>,
    inv_pivot: Vec<f64>,
    /// Whether mode 0 is singular (walls) and pinned at j = 0.
    pinned: bool,
}

impl PressureSolver {
    pub fn new(grid: &CrossGrid, lateral: LateralBoundary) -> Self {
        let (ny, nz) = (grid.ny(), grid.nz());
        let mut lower = vec![0.0; ny];
        let mut upper = vec![0.0; ny];
        let mut diag = vec![0.0; ny];
        for j in 0..ny {
            let a = if j > 0 {
                1.0 / (grid.dy[j] * grid.dy_centres(j))
            } else {
                0.0
            };
            let c = if j + 1 < ny {
                1.0 / (grid.dy[j] * grid.dy_centres(j + 1))
            } else {
                0.0
            };
            lower[j] = a;
            upper[j] = c;
            diag[j] = -(a + c);
            let at_edge = j == 0 || j + 1 == ny;
            if at_edge && lateral == LateralBoundary::Outlet {
                // p = 0 on the outlet face, half a cell away.
                diag[j] -= 1.0 / (grid.dy[j] * 0.5 * grid.dy[j]);
            }
        }
        let pinned = lateral == LateralBoundary::Wall;
        let mut c_prime = vec![0.0; nz * ny];
        let mut inv_pivot = vec![0.0; nz * ny];
        for m in 0..nz {
            let s = (std::f64::consts::PI * m as f64 / (2.0 * nz as f64)).sin();
            let lambda = -4.0 * s * s / (grid.dz * grid.dz);
            let cp = &mut c_prime[m * ny..(m + 1) * ny];
            let ip = &mut inv_pivot[m * ny..(m + 1) * ny];
            for j in 0..ny {
                let (mut a, mut b, mut c) = (lower[j], diag[j] + lambda, upper[j]);
                if pinned && m == 0 && j == 0 {
                    // The wall problem's constant mode: fix p at one cell.
                    (a, b, c) = (0.0, 1.0, 0.0);
                }
                let pivot = if j == 0 { b } else { b - a * cp[j - 1] };
                ip[j] = 1.0 / pivot;
                cp[j] = c / pivot;
            }
        }
        let mut planner = DctPlanner::new();
        Self {
            ny,
            nz,
            dct: planner.plan_dct2(nz),
            lower,
            c_prime,
            inv_pivot,
            pinned,
        }
    }

    /// Solve D G p = rhs; `rhs` (ny x nz) is overwritten with p. `scratch` must be nz x ny.
    pub fn solve(&self, rhs: &mut Array2<f64>, scratch: &mut Array2<f64>) {
        let (ny, nz) = (self.ny, self.nz);
        let rhs_s = rhs.as_slice_mut().expect("standard layout");
        rhs_s.par_chunks_mut(nz).for_each_init(
            || vec![0.0; self.dct.get_scratch_len()],
            |buf, col| self.dct.process_dct2_with_scratch(col, buf),
        );
        let modes = scratch.as_slice_mut().expect("standard layout");
        // Transpose to mode-major so each mode's y line is contiguous.
        modes.par_chunks_mut(ny).enumerate().for_each(|(m, line)| {
            for (j, v) in line.iter_mut().enumerate() {
                *v = rhs_s[j * nz + m];
            }
        });
        modes.par_chunks_mut(ny).enumerate().for_each(|(m, line)| {
            let cp = &self.c_prime[m * ny..(m + 1) * ny];
            let ip = &self.inv_pivot[m * ny..(m + 1) * ny];
            if self.pinned && m == 0 {
                line[0] = 0.0;
            }
            let mut prev = 0.0;
            for j in 0..ny {
                let a = if self.pinned && m == 0 && j == 0 {
                    0.0
                } else {
                    self.lower[j]
                };
                let d = (line[j] - a * prev) * ip[j];
                line[j] = d;
                prev = d;
            }
            for j in (0..ny.saturating_sub(1)).rev() {
                line[j] -= cp[j] * line[j + 1];
            }
        });
        // Back to column-major and inverse DCT (DCT-III scaled by 2 / nz).
        let scale = 2.0 / nz as f64;
        rhs_s.par_chunks_mut(nz).enumerate().for_each_init(
            || vec![0.0; self.dct.get_scratch_len()],
            |buf, (j, col)| {
                for (m, v) in col.iter_mut().enumerate() {
                    *v = modes[m * ny + j] * scale;
                }
                // rustdct's DCT-III halves X_0 itself: DCT-III(DCT-II(x)) = x nz / 2.
                self.dct.process_dct3_with_scratch(col, buf);
            },
        );
    }
}

/// Cell divergence dV/dy + dW/dz.
pub fn divergence(s: &Setup, state: &WakeState, out: &mut Array2<f64>) {
    let nz = s.nz;
    let v = state.v.as_slice().expect("layout");
    let w = state.w.as_slice().expect("layout");
    out.as_slice_mut()
        .expect("layout")
        .par_chunks_mut(nz)
        .enumerate()
        .for_each(|(j, col)| {
            for (kk, x) in col.iter_mut().enumerate() {
                *x = (v[(j + 1) * nz + kk] - v[j * nz + kk]) / s.dy[j]
                    + (w[j * (nz + 1) + kk] - w[j * (nz + 1) + kk + 1]) / s.dz;
            }
        });
}

/// The projection onto divergence-free velocity: the pressure solver and its work arrays.
pub struct Projector {
    solver: PressureSolver,
    rhs: Array2<f64>,
    scratch: Array2<f64>,
}

impl Projector {
    pub fn new(s: &Setup) -> Self {
        Self {
            solver: PressureSolver::new(&s.grid, s.lateral),
            rhs: Array2::zeros((s.ny, s.nz)),
            scratch: Array2::zeros((s.nz, s.ny)),
        }
    }

    /// Project the velocity of `state` (see [`project`]).
    pub fn apply(&mut self, s: &Setup, state: &mut WakeState) {
        project(s, &self.solver, state, &mut self.rhs, &mut self.scratch);
    }
}

/// Project (V, W) onto divergence-free fields (Eq. (2.65)): solve D G p = D u*, then
/// u = u* - G p.
pub fn project(
    s: &Setup,
    solver: &PressureSolver,
    state: &mut WakeState,
    rhs: &mut Array2<f64>,
    scratch: &mut Array2<f64>,
) {
    let (ny, nz) = (s.ny, s.nz);
    {
        let v = state.v.as_slice_mut().expect("layout");
        match s.lateral {
            LateralBoundary::Outlet => {
                for kk in 0..nz {
                    v[kk] = v[nz + kk];
                    v[ny * nz + kk] = v[(ny - 1) * nz + kk];
                }
            }
            LateralBoundary::Wall => {
                v[..nz].fill(0.0);
                v[ny * nz..].fill(0.0);
            }
        }
    }
    divergence(s, state, rhs);
    solver.solve(rhs, scratch);
    let p = rhs.as_slice().expect("layout");
    let outlet = s.lateral == LateralBoundary::Outlet;
    state
        .v
        .as_slice_mut()
        .expect("layout")
        .par_chunks_mut(nz)
        .enumerate()
        .for_each(|(jf, col)| {
            for (kk, x) in col.iter_mut().enumerate() {
                let grad = if jf == 0 {
                    if outlet {
                        p[kk] / (0.5 * s.dy[0])
                    } else {
                        0.0
                    }
                } else if jf == ny {
                    if outlet {
                        -p[(ny - 1) * nz + kk] / (0.5 * s.dy[ny - 1])
                    } else {
                        0.0
                    }
                } else {
                    (p[jf * nz + kk] - p[(jf - 1) * nz + kk]) / s.dyc[jf]
                };
                *x -= grad;
            }
        });
    state
        .w
        .as_slice_mut()
        .expect("layout")
        .par_chunks_mut(nz + 1)
        .enumerate()
        .for_each(|(j, col)| {
            for kf in 1..nz {
                col[kf] -= (p[j * nz + kf - 1] - p[j * nz + kf]) / s.dz;
            }
        });
}

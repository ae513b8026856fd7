//! Surfactant (SAS) redistribution by the wake, spec Eq. (2.66), steady in the ship-fixed frame.
//!
//! A surface film is carried by the surface flow and diffused by nu + nu_t. For a film the
//! surface divergence of the flow concentrates or dilutes it, so the equation is solved in its
//! conservative form, d/dx[(U_ship - u) Gamma] + d/dy(V Gamma) = d/dy[(nu + nu_t) dGamma/dy]
//! (Stone 1990), which reduces to Eq. (2.66) where the surface flow is divergence-free. x is the
//! distance behind the stern: the sea passes the ship at U_ship - u (u the wake's along-heading
//! velocity). Since U_ship is hundreds of times the cross-track speeds, diffusion along x is
//! negligible and the equation is marched in x (the parabolic form), implicitly in the diffusion.
//! Gamma = 1 upstream of the first row; the sides of the map are no-flux, so the flux
//! integral of (U_ship - u) Gamma dy is the same through every row.

use crate::constants::NU;
use rayon::prelude::*;
use wakelab_hydro::{SliceField, SurfaceMap};

/// Gamma on the rows and columns of the surface map (x-major).
#[derive(Debug, Clone)]
pub struct SurfactantField {
    pub gamma: Vec<f64>,
    pub rows: usize,
    pub cols: usize,
}

/// Solve for Gamma over the surface map of a ship moving at `ship_speed`.
pub fn redistribute_surfactant(map: &SurfaceMap, ship_speed: f64) -> SurfactantField {
    let (rows, cols) = (map.x.len(), map.y.len());
    let u = map.field(SliceField::U);
    let v = map.field(SliceField::V);
    let nut = map.field(SliceField::NuT);
    let y = &map.y;
    let width = column_widths(y);
    let mut gamma = vec![1.0; rows * cols];
    let mut lower = vec![0.0; cols];
    let mut diag = vec![0.0; cols];
    let mut upper = vec![0.0; cols];
    let mut rhs = vec![0.0; cols];
    for r in 1..rows {
        let dx = map.x[r] - map.x[r - 1];
        let prev = r - 1;
        let speed = |row: usize, j: usize| ship_speed - u[row * cols + j] as f64;
        // explicit cross-track advection of the previous row (upwind, no flux through the sides)
        let g_prev = &gamma[prev * cols..r * cols];
        let face_flux = |jf: usize| -> f64 {
            if jf == 0 || jf == cols {
                return 0.0;
            }
            let vel = 0.5 * (v[prev * cols + jf - 1] + v[prev * cols + jf]) as f64;
            let up = if vel >= 0.0 { g_prev[jf - 1] } else { g_prev[jf] };
            vel * up
        };
        for j in 0..cols {
            let q = speed(prev, j) * g_prev[j];
            rhs[j] = q - dx * (face_flux(j + 1) - face_flux(j)) / width[j];
        }
        // implicit diffusion: W Gamma - dx d/dy(K dGamma/dy) = rhs
        for j in 0..cols {
            let k_face = |a: usize, b: usize| NU + 0.5 * (nut[r * cols + a] + nut[r * cols + b]) as f64;
            let west = if j > 0 {
                dx * k_face(j - 1, j) / ((y[j] - y[j - 1]) * width[j])
            } else {
                0.0
            };
            let east = if j + 1 < cols {
                dx * k_face(j, j + 1) / ((y[j + 1] - y[j]) * width[j])
            } else {
                0.0
            };
            lower[j] = -west;
            upper[j] = -east;
            diag[j] = speed(r, j) + west + east;
        }
        let out = &mut gamma[r * cols..(r + 1) * cols];
        solve_tridiagonal(&lower, &diag, &upper, &rhs, out);
    }
    SurfactantField { gamma, rows, cols }
}

/// The flux integral of (U_ship - u) Gamma over each row (m^2/s, Gamma relative).
pub fn row_fluxes(map: &SurfaceMap, field: &SurfactantField, ship_speed: f64) -> Vec<f64> {
    let cols = field.cols;
    let u = map.field(SliceField::U);
    let width = column_widths(&map.y);
    (0..field.rows)
        .into_par_iter()
        .map(|r| {
            (0..cols)
                .map(|j| (ship_speed - u[r * cols + j] as f64) * field.gamma[r * cols + j] * width[j])
                .sum()
        })
        .collect()
}

/// Width of each column's cell: edges half-way between neighbouring columns, the map's ends.
fn column_widths(y: &[f64]) -> Vec<f64> {
    let cols = y.len();
    (0..cols)
        .map(|j| {
            let lo = if j == 0 { y[0] } else { 0.5 * (y[j - 1] + y[j]) };
            let hi = if j + 1 == cols {
                y[cols - 1]
            } else {
                0.5 * (y[j] + y[j + 1])
            };
            (hi - lo).max(1e-9)
        })
        .collect()
}

/// Thomas algorithm for a diagonally dominant tridiagonal system.
pub fn solve_tridiagonal(lower: &[f64], diag: &[f64], upper: &[f64], rhs: &[f64], out: &mut [f64]) {
    let n = diag.len();
    let mut c = vec![0.0; n];
    let mut d = vec![0.0; n];
    c[0] = upper[0] / diag[0];
    d[0] = rhs[0] / diag[0];
    for i in 1..n {
        let m = diag[i] - lower[i] * c[i - 1];
        c[i] = upper[i] / m;
        d[i] = (rhs[i] - lower[i] * d[i - 1]) / m;
    }
    out[n - 1] = d[n - 1];
    for i in (0..n - 1).rev() {
        out[i] = d[i] - c[i] * out[i + 1];
    }
}

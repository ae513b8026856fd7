//! Wake modulation of short waves by the wave action balance, spec Eq. (2.67), steady in the
//! ship-fixed frame.
//!
//! Along a ray (dx/dt = U + c_g) the action density of a wave whose wavenumber is refracted by
//! the current, dk_j/dt = -k_i dU_i/dx_j, obeys dN/dt = (beta - gamma) N - alpha N^2. Written
//! for the ratio r = N / N_0(k) to the undisturbed spectrum at the radar's fixed wavenumber k,
//! refraction becomes a source r (d ln N_0 / dk_j) k_i dU_i/dx_j (the relaxation form of Hughes
//! 1978 and Alpers & Hennings 1984, first order in the small wavenumber shift):
//!   dr/dt = r [beta - gamma + (d ln N_0/dk_j) k_i dU_i/dx_j - alpha N_0 r],
//! with alpha N_0 = beta - gamma_0 so the undisturbed sea (gamma = gamma_0, no current) sits at
//! r = 1 (spec 2.3). Where the wind cannot outgrow the ambient damping (beta <= gamma_0) the
//! undisturbed sea is held at r = 1 by the rate 0.01 beta instead.
//!
//! The rays are marched downstream in x (behind the stern) over the rows of the hydro surface map;
//! each step integrates the logistic equation exactly for that step's coefficients (so the
//! march is stable for any relaxation rate), and the cross-track drift V + c_gy moves r between
//! columns by upwind advection in stable sub-steps.

use crate::film::{total_damping, wind_growth, Film};
use crate::spectrum::{angular_frequency, group_speed, SeaSpectrum};
use crate::surfactant::SurfactantField;
use rayon::prelude::*;
use wakelab_hydro::SurfaceMap;

/// A radar's Bragg wave vector in the heading frame (x along the heading, y to port), rad/m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WaveVector {
    pub kx: f64,
    pub ky: f64,
}

impl WaveVector {
    pub fn magnitude(&self) -> f64 {
        self.kx.hypot(self.ky)
    }
}

/// Coefficients of the relaxation equation for one wave vector.
#[derive(Debug, Clone, Copy)]
pub struct Relaxation {
    pub k: WaveVector,
    /// Wind growth beta (1/s), Eq. (2.68).
    pub growth: f64,
    /// Ambient damping gamma_0 (1/s).
    pub ambient_damping: f64,
    /// alpha N_0: the non-linear decay rate at r = 1 (1/s).
    pub decay: f64,
    /// Gradient of ln N_0 in k (m), heading frame.
    pub dln_action_dk: (f64, f64),
    /// Group velocity (m/s), heading frame.
    pub group_velocity: (f64, f64),
}

impl Relaxation {
    pub fn new(k: WaveVector, sea: &SeaSpectrum, film: &Film, ambient_eps: f64) -> Self {
        let km = k.magnitude();
        let (g, tau) = (sea.gravity, sea.tension);
        let omega = angular_frequency(km, g, tau);
        let growth = wind_growth(km, omega, sea.wind_speed);
        let ambient_damping = total_damping(km, film, 1.0, ambient_eps, tau, g);
        let decay = (growth - ambient_damping).max(0.01 * growth);
        let h = 1e-4 * km;
        let ln_n = |kx: f64, ky: f64| sea.action(kx, ky).max(1e-300).ln();
        let dx = (ln_n(k.kx + h, k.ky) - ln_n(k.kx - h, k.ky)) / (2.0 * h);
        let dy = (ln_n(k.kx, k.ky + h) - ln_n(k.kx, k.ky - h)) / (2.0 * h);
        let cg = group_speed(km, g, tau);
        Self {
            k,
            growth,
            ambient_damping,
            decay,
            dln_action_dk: (dx, dy),
            group_velocity: (cg * k.kx / km, cg * k.ky / km),
        }
    }

    /// Net linear rate a = (decay) + (gamma_0 - gamma) + refraction source, for damping `gamma`
    /// and current gradients [[du/dx, du/dy], [dv/dx, dv/dy]] in the heading frame.
    pub fn linear_rate(&self, gamma: f64, grad: [[f64; 2]; 2]) -> f64 {
        let (kx, ky) = (self.k.kx, self.k.ky);
        let (gx, gy) = self.dln_action_dk;
        // (d ln N0 / dk_j) k_i dU_i/dx_j
        let refraction = gx * (kx * grad[0][0] + ky * grad[1][0]) + gy * (kx * grad[0][1] + ky * grad[1][1]);
        self.decay + (self.ambient_damping - gamma) + refraction
    }
}

/// Exact solution of dr/dt = r (a - b r) over dt.
pub fn logistic_step(r: f64, a: f64, b: f64, dt: f64) -> f64 {
    if (a * dt).abs() < 1e-12 {
        return r / (1.0 + b * r * dt);
    }
    let e = (a * dt).exp();
    a * r * e / (a + b * r * (e - 1.0))
}

/// r = N / N_0 on the rows and columns of the surface map for one wave vector.
pub fn modulate_short_waves(
    map: &SurfaceMap,
    gamma: &SurfactantField,
    relaxation: &Relaxation,
    sea: &SeaSpectrum,
    film: &Film,
    ship_speed: f64,
) -> Vec<f64> {
    let (rows, cols) = (map.x.len(), map.y.len());
    let (u, v, eps) = (map.field("U"), map.field("V"), map.field("eps"));
    let km = relaxation.k.magnitude();
    // damping everywhere on the map (the expensive part), in parallel
    let damping: Vec<f64> = (0..rows * cols)
        .into_par_iter()
        .map(|i| total_damping(km, film, gamma.gamma[i], eps[i] as f64, sea.tension, sea.gravity))
        .collect();
    let y = &map.y;
    let dy_min = y.windows(2).map(|w| w[1] - w[0]).fold(f64::INFINITY, f64::min);
    let at = |f: &[f32], r: usize, j: usize| f[r * cols + j] as f64;
    let mut out = vec![1.0; rows * cols];
    let mut row = vec![1.0; cols];
    let mut next = vec![1.0; cols];
    let (cgx, cgy) = relaxation.group_velocity;
    for r in 1..rows {
        let dxb = map.x[r] - map.x[r - 1];
        // gradients at this row: d/dx_heading = -d/dx_behind (Eq. 2.25 gives d/dx from d/dt)
        for j in 0..cols {
            let (jl, jr) = (j.saturating_sub(1), (j + 1).min(cols - 1));
            let ydist = (y[jr] - y[jl]).max(1e-9);
            let (ra, rb) = (r - 1, r);
            let grad = [
                [
                    -(at(u, rb, j) - at(u, ra, j)) / dxb,
                    (at(u, rb, jr) - at(u, rb, jl)) / ydist,
                ],
                [
                    -(at(v, rb, j) - at(v, ra, j)) / dxb,
                    (at(v, rb, jr) - at(v, rb, jl)) / ydist,
                ],
            ];
            let rel_speed = (ship_speed - 0.5 * (at(u, ra, j) + at(u, rb, j)) - cgx).max(0.5);
            let dt = dxb / rel_speed;
            let gamma_here = 0.5 * (damping[ra * cols + j] + damping[rb * cols + j]);
            let a = relaxation.linear_rate(gamma_here, grad);
            next[j] = logistic_step(row[j], a, relaxation.decay, dt);
        }
        // cross-track drift of the rays in sub-steps of Courant number <= 0.8
        let drift_max = (0..cols).map(|j| (at(v, r, j) + cgy).abs()).fold(0.0, f64::max);
        let t_row = dxb / (ship_speed - cgx).max(0.5);
        let substeps = ((drift_max * t_row / dy_min) / 0.8).ceil().max(1.0) as usize;
        let dts = t_row / substeps as f64;
        for _ in 0..substeps {
            row.copy_from_slice(&next);
            for j in 0..cols {
                let vel = at(v, r, j) + cgy;
                let (jl, jr) = (j.saturating_sub(1), (j + 1).min(cols - 1));
                next[j] = if vel > 0.0 && j > 0 {
                    row[j] - vel * dts * (row[j] - row[jl]) / (y[j] - y[jl])
                } else if vel < 0.0 && j + 1 < cols {
                    row[j] - vel * dts * (row[jr] - row[j]) / (y[jr] - y[j])
                } else {
                    row[j]
                };
            }
        }
        row.copy_from_slice(&next);
        out[r * cols..(r + 1) * cols].copy_from_slice(&row);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn logistic_step_is_exact() {
        // r(t) = a / (b + (a/r0 - b) e^{-a t})
        let (a, b, r0) = (0.7, 0.5, 0.2);
        let mut r = r0;
        for _ in 0..10 {
            r = logistic_step(r, a, b, 0.3);
        }
        let exact = a / (b + (a / r0 - b) * (-a * 3.0f64).exp());
        assert!((r - exact).abs() < 1e-12);
        assert!((logistic_step(1.0, 0.4, 0.4, 1e3) - 1.0).abs() < 1e-12);
    }
}

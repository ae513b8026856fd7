//! Wake modulation of short waves by the wave action balance, spec Eq. (2.67), steady in the
//! ship-fixed frame, in the bounded relaxation form (erratum 14).
//!
//! Printed, (2.67) is a logistic equation dN/dt = (beta - gamma) N - alpha N^2: where the wake's
//! damping beats the wind's growth it has no positive steady state and N falls without a floor,
//! which no radar observation shows. wakelab integrates instead the relaxation form of Hughes
//! (1978) and Alpers & Hennings (1984): along a ray (dx/dt = U + c_g), whose wavenumber the
//! current refracts (dk_j/dt = -k_i dU_i/dx_j), the ratio r = N / N_0 to the undisturbed
//! spectrum at the radar's fixed wavenumber obeys
//!   dr/dt = mu (1 - r) - d r + R r,
//! with mu the relaxation rate of the short-wave balance (Kudryavtsev et al. 2005, Eq. 34;
//! [`ShortWaves::relaxation_rate`]: wind growth with its directional factor, the non-linear
//! loss and the breaking-generated source, linearised), d the wake's extra damping by film and
//! excess turbulence over the undisturbed sea's ([`WakeDamping`]) and
//! R = (d ln N_0 / dk_j) k_i dU_i/dx_j the refraction source, first order in the wavenumber
//! shift. Under constant d the steady state is mu / (mu + d - R), positive under any damping,
//! reached with e-folding time 1 / (mu + d - R). Where converging currents would make
//! mu + d - R vanish, it is held at a tenth of mu (r at most 10): the non-linear loss the
//! linear form omits.
//!
//! Where the spectrum is isotropic, so is mu. Linearised about a steady level B, Eq. 34 reads
//! mu = omega [(n + 1) (B / alpha)^n - beta_v(phi)]: with B the same in every direction, as
//! Yurovskaya et al. (2013) measured for decimetre waves ([`crate::bragg_scale`]), its leading
//! term is isotropic. KHCC03's own balance, whose B is not isotropic there, gives S-band Bragg
//! waves travelling across the wind a rate ten times below the along-wind one (0.024 against
//! 0.29 /s at 5 m/s). So mu = (1 - i) mu(phi) + i mu_mean, with i the spectrum's isotropy at k
//! ([`SeaSpectrum::isotropy`]: 1 well below 100 rad/m, 0 above) and mu_mean Eq. 34 averaged over
//! direction (its magnitude stays that of KHCC03's balance; the residual -omega beta_v(phi)
//! anisotropy is left out).
//!
//! The rays are marched downstream in x (behind the stern) over the rows of the hydro surface
//! map; each step integrates the linear equation exactly for that step's coefficients (so the
//! march is stable at any rate), and the cross-track drift V + c_gy moves r between columns by
//! upwind advection in stable sub-steps.

use crate::film::WakeDamping;
use crate::short_waves::ShortWaves;
use crate::spectrum::{group_speed, SeaSpectrum};
use crate::surfactant::SurfactantField;
use rayon::prelude::*;
use wakelab_hydro::{SliceField, SurfaceMap};

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
    /// Relaxation rate mu (1/s), Kudryavtsev et al. (2005) Eq. 34, isotropic where the
    /// spectrum is (module doc).
    pub rate: f64,
    /// Gradient of ln N_0 in k (m), heading frame.
    pub dln_action_dk: (f64, f64),
    /// Group velocity (m/s), heading frame.
    pub group_velocity: (f64, f64),
}

/// The smallest net rate as a fraction of mu (r <= 10 under converging currents).
pub(crate) const SATURATION: f64 = 0.1;

impl Relaxation {
    pub fn new(k: WaveVector, sea: &SeaSpectrum, short_waves: &ShortWaves) -> Self {
        let km = k.magnitude();
        let h = 1e-4 * km;
        let ln_n = |kx: f64, ky: f64| sea.action(kx, ky).max(1e-300).ln();
        let dx = (ln_n(k.kx + h, k.ky) - ln_n(k.kx - h, k.ky)) / (2.0 * h);
        let dy = (ln_n(k.kx, k.ky + h) - ln_n(k.kx, k.ky - h)) / (2.0 * h);
        let cg = group_speed(km, sea.gravity, sea.tension);
        Self {
            k,
            rate: {
                let isotropy = sea.isotropy(km);
                let own = short_waves.relaxation_rate(km, k.ky.atan2(k.kx));
                if isotropy > 0.0 {
                    (1.0 - isotropy) * own + isotropy * short_waves.mean_relaxation_rate(km)
                } else {
                    own
                }
            },
            dln_action_dk: (dx, dy),
            group_velocity: (cg * k.kx / km, cg * k.ky / km),
        }
    }

    /// Refraction source R = (d ln N0 / dk_j) k_i dU_i/dx_j (1/s) for current gradients
    /// [[du/dx, du/dy], [dv/dx, dv/dy]] in the heading frame.
    pub fn refraction(&self, grad: [[f64; 2]; 2]) -> f64 {
        let (kx, ky) = (self.k.kx, self.k.ky);
        let (gx, gy) = self.dln_action_dk;
        gx * (kx * grad[0][0] + ky * grad[1][0]) + gy * (kx * grad[0][1] + ky * grad[1][1])
    }

    /// Net decay rate mu + d - R of r, for extra damping `damping` and current gradients.
    pub fn net_rate(&self, damping: f64, grad: [[f64; 2]; 2]) -> f64 {
        (self.rate + damping - self.refraction(grad)).max(SATURATION * self.rate)
    }
}

/// Exact solution over dt of dr/dt = mu - lambda r: the relaxation equation
/// dr/dt = mu (1 - r) - d r + R r with lambda = mu + d - R.
pub fn relaxation_step(r: f64, mu: f64, lambda: f64, dt: f64) -> f64 {
    let steady = mu / lambda;
    steady + (r - steady) * (-lambda * dt).exp()
}

/// r = N / N_0 on the rows and columns of the surface map for one wave vector.
pub fn modulate_short_waves(
    map: &SurfaceMap,
    gamma: &SurfactantField,
    relaxation: &Relaxation,
    sea: &SeaSpectrum,
    wake: &WakeDamping,
    ship_speed: f64,
) -> Vec<f64> {
    let damping = extra_damping(map, gamma, relaxation.k.magnitude(), sea, wake);
    relax_short_waves(map, &damping, relaxation, ship_speed)
}

/// The wake's extra damping (1/s) of waves of wavenumber `k` on every cell of the surface map
/// (row-major like its fields), in parallel: the same for every wave vector of that length.
pub fn extra_damping(
    map: &SurfaceMap,
    gamma: &SurfactantField,
    k: f64,
    sea: &SeaSpectrum,
    wake: &WakeDamping,
) -> Vec<f64> {
    let eps = map.field(SliceField::Eps);
    let at_k = wake.at(k, sea.tension, sea.gravity);
    gamma
        .gamma
        .par_iter()
        .zip(eps.par_iter())
        .map(|(&g, &e)| at_k.extra(g, e as f64))
        .collect()
}

/// The surface current's gradients [[du/dx, du/dy], [dv/dx, dv/dy]] (1/s, heading frame) on
/// row r >= 1 and column j of the surface map: backward in x from row r - 1 (d/dx_heading =
/// -d/dx_behind; Eq. (2.25) gives d/dx from d/dt), centred across the track (one-sided at the
/// edges).
pub fn current_gradient(map: &SurfaceMap, r: usize, j: usize) -> [[f64; 2]; 2] {
    let cols = map.y.len();
    let (u, v) = (map.field(SliceField::U), map.field(SliceField::V));
    let at = |f: &[f32], r: usize, j: usize| f[r * cols + j] as f64;
    let (jl, jr) = (j.saturating_sub(1), (j + 1).min(cols - 1));
    let ydist = (map.y[jr] - map.y[jl]).max(1e-9);
    let dxb = map.x[r] - map.x[r - 1];
    let gradient = |f: &[f32]| {
        [
            -(at(f, r, j) - at(f, r - 1, j)) / dxb,
            (at(f, r, jr) - at(f, r, jl)) / ydist,
        ]
    };
    [gradient(u), gradient(v)]
}

/// r = N / N_0 on the rows and columns of the surface map for one wave vector, under the wake's
/// extra damping `damping` on each cell (from [`extra_damping`]).
pub fn relax_short_waves(map: &SurfaceMap, damping: &[f64], relaxation: &Relaxation, ship_speed: f64) -> Vec<f64> {
    let (rows, cols) = (map.x.len(), map.y.len());
    let (u, v) = (map.field(SliceField::U), map.field(SliceField::V));
    let y = &map.y;
    let dy_min = y.windows(2).map(|w| w[1] - w[0]).fold(f64::INFINITY, f64::min);
    let at = |f: &[f32], r: usize, j: usize| f[r * cols + j] as f64;
    let mut out = vec![1.0; rows * cols];
    let mut row = vec![1.0; cols];
    let mut next = vec![1.0; cols];
    let (cgx, cgy) = relaxation.group_velocity;
    for r in 1..rows {
        let dxb = map.x[r] - map.x[r - 1];
        for j in 0..cols {
            let (ra, rb) = (r - 1, r);
            let grad = current_gradient(map, r, j);
            let rel_speed = (ship_speed - 0.5 * (at(u, ra, j) + at(u, rb, j)) - cgx).max(0.5);
            let dt = dxb / rel_speed;
            let gamma_here = 0.5 * (damping[ra * cols + j] + damping[rb * cols + j]);
            let lambda = relaxation.net_rate(gamma_here, grad);
            next[j] = relaxation_step(row[j], relaxation.rate, lambda, dt);
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

    /// r(t) = mu / lambda + (r0 - mu / lambda) e^{-lambda t}, stepped in pieces.
    #[test]
    fn relaxation_step_is_exact() {
        let (mu, lambda, r0) = (0.7, 1.2, 0.2);
        let mut r = r0;
        for _ in 0..10 {
            r = relaxation_step(r, mu, lambda, 0.3);
        }
        let exact = mu / lambda + (r0 - mu / lambda) * (-lambda * 3.0f64).exp();
        assert!((r - exact).abs() < 1e-12);
        assert!((relaxation_step(1.0, 0.4, 0.4, 1e3) - 1.0).abs() < 1e-12);
    }

    /// S-band Bragg waves (50 rad/m, decimetre) relax at one rate in every direction, Eq. 34's
    /// mean over the ring; X-band ones (250 rad/m) at Eq. 34's own directional rate; a
    /// Pierson-Moskowitz sea (no decimetre revision) keeps the directional rate everywhere.
    #[test]
    fn decimetre_waves_relax_isotropically() {
        let c = wakelab_core::WakelabConfig::default();
        let sea = SeaSpectrum::wind_sea(&c.sea, 5.0, 0.0, 9.81);
        let short = ShortWaves::new(&sea);
        let along = |k: f64, phi: f64, sea: &SeaSpectrum, short: &ShortWaves| {
            Relaxation::new(
                WaveVector {
                    kx: k * phi.cos(),
                    ky: k * phi.sin(),
                },
                sea,
                short,
            )
            .rate
        };
        let mean = short.mean_relaxation_rate(50.0);
        for phi in [0.0, 1.0, std::f64::consts::FRAC_PI_2, std::f64::consts::PI] {
            let rate = along(50.0, phi, &sea, &short);
            assert!((rate / mean - 1.0).abs() < 5e-3, "{phi}: {rate} vs {mean}");
            let x = along(250.0, phi, &sea, &short);
            let own = short.relaxation_rate(250.0, phi);
            assert!((x / own - 1.0).abs() < 1e-3, "{phi}: {x} vs {own}");
        }
        // Eq. 34 itself is anisotropic there: slow across the wind
        assert!(short.relaxation_rate(50.0, std::f64::consts::FRAC_PI_2) < 0.5 * short.relaxation_rate(50.0, 0.0));
        let mut pm_config = c.sea.clone();
        pm_config.spectrum = wakelab_core::config::SpectrumModel::PiersonMoskowitz;
        let pm = SeaSpectrum::wind_sea(&pm_config, 5.0, 0.0, 9.81);
        let pm_short = ShortWaves::new(&pm);
        let cross = along(50.0, std::f64::consts::FRAC_PI_2, &pm, &pm_short);
        assert_eq!(cross, pm_short.relaxation_rate(50.0, std::f64::consts::FRAC_PI_2));
    }
}

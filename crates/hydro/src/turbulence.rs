//! Rodi's buoyant k-epsilon model (spec Eqs. (2.9)-(2.14)), the eddy viscosity, the buoyancy field
//! and Somero's near-surface anisotropy correction (Eqs. (2.15)-(2.21), with erratum 3).

use crate::setup::Setup;
use crate::state::WakeState;
use rayon::prelude::*;

/// Fields derived from the state at the start of each stage.
#[derive(Debug, Clone)]
pub struct Derived {
    /// Eddy viscosity nu_t = C_mu k^2 / eps (Eq. (2.11)), capped.
    pub eddy_viscosity: Vec<f64>,
    /// nu + nu_t.
    pub viscosity: Vec<f64>,
    /// b' = -g (rho - rho_b) / rho_b (Eq. (2.5)), m/s^2.
    pub buoyancy: Vec<f64>,
    /// Shear production P (Eq. (2.12)).
    pub production: Vec<f64>,
    /// Buoyancy production G = -N^2 nu_t / sigma_t (Eqs. (2.13)-(2.14)).
    pub buoyancy_production: Vec<f64>,
    /// Somero factors: (shear damping of u'w', v'w'; v'v' and w'w' corrections), if enabled.
    pub somero_shear: Option<Vec<f64>>,
    pub somero_normal: Option<(Vec<f64>, Vec<f64>)>,
}

/// Eddy viscosity nu_t = C_mu k^2 / eps (Eq. (2.11)), capped at the setup's maximum.
#[inline]
pub fn eddy_viscosity(s: &Setup, k: f64, eps: f64) -> f64 {
    (s.constants.c_mu * k * k / eps).min(s.max_eddy_viscosity)
}

impl Derived {
    pub fn new(n: usize, somero: bool) -> Self {
        Self {
            eddy_viscosity: vec![0.0; n],
            viscosity: vec![0.0; n],
            buoyancy: vec![0.0; n],
            production: vec![0.0; n],
            buoyancy_production: vec![0.0; n],
            somero_shear: somero.then(|| vec![1.0; n]),
            somero_normal: somero.then(|| (vec![0.0; n], vec![0.0; n])),
        }
    }

    /// Recompute every derived field from `state`.
    pub fn update(&mut self, s: &Setup, state: &WakeState) {
        let nz = s.nz;
        let c = s.constants;
        let k = state.k.as_slice().expect("layout");
        let eps = state.eps.as_slice().expect("layout");
        let dt = state.temperature.as_slice().expect("layout");
        let ds = state.salinity.as_slice().expect("layout");
        let (u, v, w) = (
            state.u.as_slice().expect("layout"),
            state.v.as_slice().expect("layout"),
            state.w.as_slice().expect("layout"),
        );
        let col = &s.column;
        self.eddy_viscosity
            .par_chunks_mut(nz)
            .zip(self.viscosity.par_chunks_mut(nz))
            .zip(self.buoyancy.par_chunks_mut(nz))
            .enumerate()
            .for_each(|(j, ((nut, visc), b))| {
                for kk in 0..nz {
                    let i = j * nz + kk;
                    let t = eddy_viscosity(s, k[i], eps[i]);
                    nut[kk] = t;
                    visc[kk] = s.viscosity + t;
                    b[kk] = -s.gravity * col.density_anomaly(kk, dt[i], ds[i]) / col.density[kk];
                }
            });
        let buoy = &self.buoyancy;
        let nut_all = &self.eddy_viscosity;
        let ny = s.ny;
        self.production
            .par_chunks_mut(nz)
            .zip(self.buoyancy_production.par_chunks_mut(nz))
            .enumerate()
            .for_each(|(j, (p, g))| {
                let (jl, jr) = (j.saturating_sub(1), (j + 1).min(ny - 1));
                let ydist = s.grid.y_centres[jr] - s.grid.y_centres[jl];
                for kk in 0..nz {
                    let i = j * nz + kk;
                    let (ku, kd) = (kk.saturating_sub(1), (kk + 1).min(nz - 1));
                    let zdist = (kd - ku) as f64 * s.dz;
                    let ddz = |f: &[f64], stride: usize, off: usize| {
                        (f[j * stride + ku + off] - f[j * stride + kd + off]) / zdist
                    };
                    let dvdy = (v[(j + 1) * nz + kk] - v[j * nz + kk]) / s.dy[j];
                    let dwdz = (w[j * (nz + 1) + kk] - w[j * (nz + 1) + kk + 1]) / s.dz;
                    let vc = |jj: usize, kq: usize| 0.5 * (v[jj * nz + kq] + v[(jj + 1) * nz + kq]);
                    let wc = |jj: usize, kq: usize| 0.5 * (w[jj * (nz + 1) + kq] + w[jj * (nz + 1) + kq + 1]);
                    let dvdz = (vc(j, ku) - vc(j, kd)) / zdist;
                    let dwdy = (wc(jr, kk) - wc(jl, kk)) / ydist;
                    let dudy = (u[jr * nz + kk] - u[jl * nz + kk]) / ydist;
                    let dudz = ddz(u, nz, 0);
                    // S^2 = 2 S_ij S_ij for the 2D+t velocity gradient (Eq. (2.12))
                    let s2 = 2.0 * (dvdy * dvdy + dwdz * dwdz) + (dvdz + dwdy).powi(2) + dudy * dudy + dudz * dudz;
                    p[kk] = nut_all[i] * s2;
                    // N^2 = N_b^2 + db'/dz (total stratification); G = -N^2 nu_t / sigma_t.
                    let n2 = col.n2[kk] + ddz(buoy, nz, 0);
                    g[kk] = -n2 * nut_all[i] / c.sigma_t;
                }
            });
        if let (Some(shear), Some((vv, ww))) = (self.somero_shear.as_mut(), self.somero_normal.as_mut()) {
            somero_corrections(s, state, &self.eddy_viscosity, shear, vv, ww);
        }
    }
}

/// Somero (2021) wall factor f(z) = (C k^{3/2} / (eps |z|))^a, C = 0.07, a = 2 (Eq. (2.21)).
pub fn somero_wall_factor(k: f64, eps: f64, depth: f64) -> f64 {
    (0.07 * k.powf(1.5) / (eps * depth.max(1e-6))).powi(2)
}

/// Somero's corrections for wall factor `f`, as multiples of the k-epsilon stresses:
/// (kept fraction of u'w' and v'w', added v'v' per w'w', added w'w' per w'w'), Eqs. (2.16)-(2.19).
/// The u'u' gain of (2.15) (erratum 3) has no effect when d/dx = 0.
pub fn somero_factors(f: f64) -> (f64, f64, f64) {
    let shear_kept = 1.0 - 1.0 / (1.0 + 2.0 / (3.0 * f)); // (2.18), (2.19)
    let vv = 1.0 / (3.0 + 1.0 / f); // (2.16)
    let ww = -1.0 / (1.0 + 1.0 / (2.0 * f)); // (2.17)
    (shear_kept, vv, ww)
}

/// Eqs. (2.15)-(2.20): damping of u'w' and v'w' and the redistribution of w'w' near the surface.
fn somero_corrections(s: &Setup, state: &WakeState, nut: &[f64], shear: &mut [f64], vv: &mut [f64], ww: &mut [f64]) {
    let nz = s.nz;
    let k = state.k.as_slice().expect("layout");
    let eps = state.eps.as_slice().expect("layout");
    let w = state.w.as_slice().expect("layout");
    for j in 0..s.ny {
        for kk in 0..nz {
            let i = j * nz + kk;
            let f = somero_wall_factor(k[i], eps[i], -s.grid.z_centres[kk]);
            let (kept, vv_gain, ww_gain) = somero_factors(f);
            shear[i] = kept;
            let dwdz = (w[j * (nz + 1) + kk] - w[j * (nz + 1) + kk + 1]) / s.dz;
            let w2 = (2.0 / 3.0 * k[i] - 2.0 * nut[i] * dwdz).max(0.0);
            vv[i] = vv_gain * w2;
            ww[i] = ww_gain * w2;
        }
    }
}

/// Source terms of k and eps (right-hand sides of Eqs. (2.9) and (2.10)), added to `dk`, `deps`.
///
/// The ambient turbulence (k_amb, eps_amb) is part of the background of Eq. (2.7): a steady
/// solution of its own equations, held by forcing the model does not resolve. Its tendency is
/// therefore subtracted, as the sustaining terms of Spalart & Rumsey (2007):
/// S_k = eps_amb - G_b(z) and S_eps = C2 eps_amb^2 / k_amb - C1 C3 (eps_amb / k_amb) G_b(z), with
/// G_b = -N_b^2 nu_t,amb / sigma_t, so the sea away from the wake neither decays nor grows;
/// beaches relax both towards the ambient state.
pub fn add_k_eps_sources(s: &Setup, state: &WakeState, d: &Derived, dk: &mut [f64], deps: &mut [f64]) {
    let c = s.constants;
    let k = state.k.as_slice().expect("layout");
    let eps = state.eps.as_slice().expect("layout");
    let nz = s.nz;
    let amb_ratio = s.ambient_eps / s.ambient_k;
    let amb_nut = s.ambient_eddy_viscosity();
    dk.par_chunks_mut(nz)
        .zip(deps.par_chunks_mut(nz))
        .enumerate()
        .for_each(|(j, (dkc, dec))| {
            let sigma = s.damping_centre[j];
            for kk in 0..nz {
                let i = j * nz + kk;
                let g_b = -s.column.n2[kk] * amb_nut / c.sigma_t;
                let sustain_k = s.ambient_eps - g_b;
                let sustain_eps = c.c2 * s.ambient_eps * amb_ratio - c.c1 * amb_ratio * c.c3 * g_b;
                let (p, g) = (d.production[i], d.buoyancy_production[i]);
                let ratio = eps[i] / k[i];
                dkc[kk] += p + g - eps[i] + sustain_k - sigma * (k[i] - s.ambient_k);
                dec[kk] += c.c1 * ratio * (p + c.c3 * g) - c.c2 * eps[i] * ratio + sustain_eps
                    - sigma * (eps[i] - s.ambient_eps);
            }
        });
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The limits the spec states for Eqs. (2.15)-(2.21): at the surface (1/f -> 0) all of w'w' is
    /// removed, one third of it goes to v'v' and the shear stresses u'w', v'w' vanish; far from the
    /// surface (f -> 0) every correction vanishes.
    #[test]
    fn somero_corrections_reach_the_limits_of_the_spec() {
        let surface = somero_wall_factor(0.01, 1e-5, 1e-9);
        let (kept, vv, ww) = somero_factors(surface);
        assert!(kept < 1e-9 && (vv - 1.0 / 3.0).abs() < 1e-9 && (ww + 1.0).abs() < 1e-9);
        let deep = somero_wall_factor(1e-4, 1e-6, 100.0);
        let (kept, vv, ww) = somero_factors(deep);
        assert!((kept - 1.0).abs() < 1e-6 && vv.abs() < 1e-6 && ww.abs() < 1e-6);
        // f = (C k^1.5 / (eps z))^a with C = 0.07, a = 2 (Eq. (2.21))
        assert!((somero_wall_factor(1.0, 1.0, 0.07) - 1.0).abs() < 1e-12);
    }
}

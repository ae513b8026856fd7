//! Seawater density from TEOS-10 (spec Eq. (2.4)) through the `gsw` crate.
//!
//! The solver carries the perturbations dT, dS of in-situ temperature and practical salinity
//! about the background T_b(z), S_b(z) (Eqs. (2.7), (2.22)-(2.23)). TEOS-10 needs Absolute Salinity
//! SA and Conservative Temperature CT; `gsw` 0.2 has neither `SA_from_SP` nor `CT_from_t`, so:
//! - SA is taken as the Reference Salinity SR = SP * 35.16504 / 35 (`gsw::conversions::sr_from_sp`),
//!   which differs from SA by the Absolute Salinity Anomaly, under 0.03 g/kg in the open ocean
//!   (McDougall et al. 2012);
//! - potential temperature is taken as in-situ temperature, CT = `ct_from_pt(SA, T)`: over the
//!   300 m of the domain the adiabatic lapse rate makes them differ by under 0.04 K.
//!
//! Per level, the density perturbation at the level's pressure is the second-order Taylor
//! expansion of TEOS-10 density in (dT, dS), its coefficients taken from `gsw::volume::rho` by
//! central differences: rho' = r_T dT + r_S dS + (r_TT dT^2 + 2 r_TS dT dS + r_SS dS^2) / 2.
//! Its error grows as the cube of the perturbation: under 1e-5 kg/m^3 for |dT| <= 0.5 K and
//! |dS| <= 0.2 PSU, under 5e-4 kg/m^3 (0.06 %) for |dT| <= 2 K and |dS| <= 1 PSU (tested against `rho`);
//! it costs a few multiplications per cell where the 75-term polynomial would cost hundreds.

use wakelab_core::config::EnvironmentConfig;

/// Background state and density expansion coefficients at each level of the grid.
#[derive(Debug, Clone)]
pub struct SeawaterColumn {
    /// Background in-situ temperature T_b (deg C) at each level.
    pub temperature: Vec<f64>,
    /// Background practical salinity S_b (PSU).
    pub salinity: Vec<f64>,
    /// Sea pressure (dbar).
    pub pressure: Vec<f64>,
    /// Background in-situ density rho_b (kg/m^3), the rho_ref of Eq. (2.5).
    pub density: Vec<f64>,
    /// Background buoyancy frequency squared N_b^2 (1/s^2).
    pub n2: Vec<f64>,
    /// d T_b / dz (K/m, z up).
    pub dtemperature_dz: Vec<f64>,
    /// d S_b / dz (PSU/m, z up).
    pub dsalinity_dz: Vec<f64>,
    /// Expansion coefficients of rho' in (dT, dS): [r_T, r_S, r_TT, r_TS, r_SS].
    coefficients: Vec<[f64; 5]>,
    /// Turbulent-diffusive flux divergence of the background, per unit diffusivity, at faces:
    /// the background gradients at the z faces (K/m, PSU/m).
    pub face_dtemperature_dz: Vec<f64>,
    pub face_dsalinity_dz: Vec<f64>,
}

/// Reference-salinity approximation to Absolute Salinity (g/kg).
pub fn absolute_salinity(sp: f64) -> f64 {
    gsw::conversions::sr_from_sp(sp)
}

/// Conservative Temperature from in-situ temperature, taking potential = in-situ temperature.
pub fn conservative_temperature(sa: f64, t: f64) -> f64 {
    gsw::conversions::ct_from_pt(sa, t).expect("valid salinity and temperature")
}

/// Sea pressure (dbar) at height z (m, <= 0) at a latitude.
pub fn sea_pressure(z: f64, latitude: f64) -> f64 {
    gsw::conversions::p_from_z(z.min(0.0), latitude, Some(0.0), Some(0.0)).expect("z <= 0")
}

/// In-situ density (kg/m^3) from TEOS-10 of in-situ temperature t, practical salinity sp, z.
pub fn density(t: f64, sp: f64, z: f64, latitude: f64) -> f64 {
    let sa = absolute_salinity(sp);
    gsw::volume::rho(sa, conservative_temperature(sa, t), sea_pressure(z, latitude)).expect("valid state")
}

impl SeawaterColumn {
    /// Evaluate the background at cell centres `z` (top first) with spacing `dz`.
    pub fn new(env: &EnvironmentConfig, z: &[f64], dz: f64) -> Self {
        let n = z.len();
        let t_at = |z: f64| env.temperature.at_depth(-z);
        let s_at = |z: f64| env.salinity.at_depth(-z);
        let mut out = Self {
            temperature: Vec::with_capacity(n),
            salinity: Vec::with_capacity(n),
            pressure: Vec::with_capacity(n),
            density: Vec::with_capacity(n),
            n2: Vec::with_capacity(n),
            dtemperature_dz: Vec::with_capacity(n),
            dsalinity_dz: Vec::with_capacity(n),
            coefficients: Vec::with_capacity(n),
            face_dtemperature_dz: Vec::with_capacity(n + 1),
            face_dsalinity_dz: Vec::with_capacity(n + 1),
        };
        for &zc in z {
            let (t, s) = (t_at(zc), s_at(zc));
            let sa = absolute_salinity(s);
            let ct = conservative_temperature(sa, t);
            let p = sea_pressure(zc, env.latitude);
            let rho = gsw::volume::rho(sa, ct, p).expect("valid state");
            // Derivatives of the composite rho(SA(S + dS), CT(SA, T + dT), p) in (dT, dS) by
            // central differences of gsw's rho: exact to second order, cross-dependence included.
            let rho_of = |dt: f64, ds: f64| {
                let sa = absolute_salinity(s + ds);
                gsw::volume::rho(sa, conservative_temperature(sa, t + dt), p).expect("valid state")
            };
            let (ht, hs) = (0.05, 0.05);
            let r_t = (rho_of(ht, 0.0) - rho_of(-ht, 0.0)) / (2.0 * ht);
            let r_s = (rho_of(0.0, hs) - rho_of(0.0, -hs)) / (2.0 * hs);
            let r_tt = (rho_of(ht, 0.0) - 2.0 * rho + rho_of(-ht, 0.0)) / (ht * ht);
            let r_ss = (rho_of(0.0, hs) - 2.0 * rho + rho_of(0.0, -hs)) / (hs * hs);
            let r_ts = (rho_of(ht, hs) - rho_of(ht, -hs) - rho_of(-ht, hs) + rho_of(-ht, -hs)) / (4.0 * ht * hs);
            let half = 0.5 * dz;
            let dtdz = (t_at(zc + half) - t_at(zc - half)) / dz;
            let dsdz = (s_at(zc + half) - s_at(zc - half)) / dz;
            // TEOS-10 N^2 (IOC et al. 2010, Eq. 3.10.2): -(g / rho) (drho/dT dT_b/dz + drho/dS dS_b/dz)
            // at constant pressure.
            let n2 = -env.gravity / rho * (r_t * dtdz + r_s * dsdz);
            out.temperature.push(t);
            out.salinity.push(s);
            out.pressure.push(p);
            out.density.push(rho);
            out.n2.push(n2);
            out.dtemperature_dz.push(dtdz);
            out.dsalinity_dz.push(dsdz);
            out.coefficients.push([r_t, r_s, r_tt, r_ts, r_ss]);
        }
        for kf in 0..=n {
            let zf = -(kf as f64) * dz;
            out.face_dtemperature_dz
                .push((t_at(zf + 1e-6) - t_at(zf - 1e-6)) / 2e-6);
            out.face_dsalinity_dz.push((s_at(zf + 1e-6) - s_at(zf - 1e-6)) / 2e-6);
        }
        out
    }

    /// Density perturbation rho - rho_b (kg/m^3) at level `k` for perturbations dT, dS.
    #[inline]
    pub fn density_anomaly(&self, k: usize, dt: f64, ds: f64) -> f64 {
        let [rt, rs, rtt, rts, rss] = self.coefficients[k];
        rt * dt + rs * ds + 0.5 * (rtt * dt * dt + 2.0 * rts * dt * ds + rss * ds * ds)
    }

    /// Largest background buoyancy frequency (1/s).
    pub fn max_buoyancy_frequency(&self) -> f64 {
        self.n2.iter().fold(0.0f64, |m, &n2| m.max(n2.max(0.0).sqrt()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use wakelab_core::WakelabConfig;

    #[test]
    fn taylor_expansion_matches_full_teos10() {
        let env = WakelabConfig::default().environment;
        let z: Vec<f64> = (0..30).map(|k| -(k as f64 + 0.5) * 4.0).collect();
        let col = SeawaterColumn::new(&env, &z, 4.0);
        for (k, &zc) in z.iter().enumerate() {
            for (dt, ds, tol) in [
                (0.1, 0.0, 1e-7),
                (-0.5, 0.2, 1e-5),
                (0.0, 0.02, 1e-7),
                (-2.0, 0.5, 5e-4),
                (1.5, -1.0, 5e-4),
            ] {
                let t = col.temperature[k] + dt;
                let s = col.salinity[k] + ds;
                let full = density(t, s, zc, env.latitude) - col.density[k];
                let approx = col.density_anomaly(k, dt, ds);
                assert!((full - approx).abs() < tol, "k={k} dT={dt} dS={ds}: {full} vs {approx}");
            }
        }
    }

    #[test]
    fn n2_matches_finite_difference_of_potential_density() {
        // N^2 = -(g/rho) d(rho_pot)/dz with rho at a common pressure: an independent route.
        let env = WakelabConfig::default().environment;
        let z = [-50.0];
        let col = SeawaterColumn::new(&env, &z, 2.0);
        let p = col.pressure[0];
        let rho_at = |zz: f64| {
            let sa = absolute_salinity(env.salinity.at_depth(-zz));
            gsw::volume::rho(sa, conservative_temperature(sa, env.temperature.at_depth(-zz)), p).unwrap()
        };
        let n2 = -env.gravity / col.density[0] * (rho_at(-49.0) - rho_at(-51.0)) / 2.0;
        assert!(((col.n2[0] - n2) / n2).abs() < 1e-3, "{} vs {n2}", col.n2[0]);
        assert!(col.n2[0] > 0.0);
    }
}

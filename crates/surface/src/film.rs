//! Growth and damping of short waves (spec Eqs. 2.68-2.69) and the surface film model.
//!
//! The spec leaves the film's equation of state to Somero (2021) (erratum 7). wakelab uses the
//! von Szyszkowski-Langmuir equation of state for a soluble surfactant monolayer (Adamson & Gast,
//! "Physical Chemistry of Surfaces", 6th ed., 1997, Sec. III-7):
//!   Pi(Gamma) = Pi_s ln(1 + Gamma / a),
//! and the Gibbs dilational elasticity E = dPi / d ln Gamma = Pi_s (Gamma / a) / (1 + Gamma / a)
//! (Lucassen & Hansen 1967). Gamma is relative to the ambient concentration; with a = 1 the
//! scale Pi_s = 2 E_ref makes the ambient film's elasticity E(1) = `sea.film_elasticity`.
//! The default, 3 mN/m, is a weak open-ocean film: with Eq. (2.69) a 10 mN/m film (a slick, in
//! the 5-30 mN/m of Alpers & Huehnerfuss 1989) already out-damps the 5 m/s wind's growth of
//! C- and X-band Bragg waves.

use crate::spectrum::{angular_frequency, RHO_WATER};
use std::f64::consts::PI;

/// Molecular kinematic viscosity of sea water (m^2/s), Table 2.1.
pub const NU: f64 = 1e-6;

/// The surface film's equation of state.
#[derive(Debug, Clone, Copy)]
pub struct Film {
    /// E at the ambient concentration Gamma = 1 (N/m).
    pub reference_elasticity: f64,
}

impl Film {
    /// Film pressure Pi(Gamma) (N/m).
    pub fn pressure(&self, gamma: f64) -> f64 {
        2.0 * self.reference_elasticity * (1.0 + gamma.max(0.0)).ln()
    }

    /// Dilational elasticity E(Gamma) (N/m).
    pub fn elasticity(&self, gamma: f64) -> f64 {
        let g = gamma.max(0.0);
        2.0 * self.reference_elasticity * g / (1.0 + g)
    }
}

/// Wind growth rate, Eq. (2.68) after Plant (1982): beta = 0.04 (k^2 / omega) U*^2 with
/// U* = 0.03 U_wind (Somero 2021).
pub fn wind_growth(k: f64, omega: f64, wind_speed: f64) -> f64 {
    let ustar = 0.03 * wind_speed;
    0.04 * k * k / omega * ustar * ustar
}

/// Film damping, Eq. (2.69) (Cini et al. 1987; Somero 2021):
/// gamma_s = 4 nu k^2 (X + XY - 2X^2) / (1 - 2X + 2X^2) with
/// X = |E| k^2 / (4 rho sqrt(pi^3 nu f^3)), Y = |E| k / (8 pi rho nu f),
/// f = sqrt(g k + (tau_w - Pi) k^3 / rho) / (2 pi).
pub fn film_damping(k: f64, elasticity: f64, film_pressure: f64, tension: f64, gravity: f64) -> f64 {
    let f = (gravity * k + (tension - film_pressure).max(0.0) * k.powi(3) / RHO_WATER).sqrt() / (2.0 * PI);
    let e = elasticity.abs();
    let x = e * k * k / (4.0 * RHO_WATER * (PI.powi(3) * NU * f.powi(3)).sqrt());
    let y = e * k / (8.0 * PI * RHO_WATER * NU * f);
    4.0 * NU * k * k * (x + x * y - 2.0 * x * x) / (1.0 - 2.0 * x + 2.0 * x * x)
}

/// Viscous damping of clean water, 4 nu k^2 (Lamb 1932, Art. 348): Eq. (2.69) gives the film's
/// part; the clean-surface part is added to it.
pub fn viscous_damping(k: f64) -> f64 {
    4.0 * NU * k * k
}

/// Turbulent damping gamma_t = 4 nu_k k^2 with the eddy viscosity of the turbulence at the wave's
/// own scale, nu_k = C eps^{1/3} k^{-4/3}, C = 0.4 (the Kolmogorov-scaling spectral eddy
/// viscosity; Heisenberg 1948, Kraichnan 1976): only eddies the size of the wave damp it.
pub fn turbulent_damping(k: f64, dissipation: f64) -> f64 {
    4.0 * 0.4 * dissipation.max(0.0).cbrt() * k.powf(2.0 / 3.0)
}

/// All damping of a wave of wavenumber k in a film of concentration Gamma over turbulence eps.
pub fn total_damping(k: f64, film: &Film, gamma: f64, dissipation: f64, tension: f64, gravity: f64) -> f64 {
    viscous_damping(k)
        + film_damping(k, film.elasticity(gamma), film.pressure(gamma), tension, gravity)
        + turbulent_damping(k, dissipation)
}

/// Growth minus ambient damping at Gamma = 1 and ambient turbulence: the undisturbed sea's net
/// rate, which sets the non-linear decay alpha = (beta - gamma_0) / N_0 (spec 2.3).
pub fn net_ambient_rate(k: f64, wind_speed: f64, film: &Film, ambient_eps: f64, tension: f64, gravity: f64) -> f64 {
    let omega = angular_frequency(k, gravity, tension);
    wind_growth(k, omega, wind_speed) - total_damping(k, film, 1.0, ambient_eps, tension, gravity)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A clean surface adds nothing to 4 nu k^2; an inextensible film (E -> infinity) damps wave
    /// energy at k sqrt(nu omega / 2), the classic limit (Lamb 1932, Art. 351; Phillips 1977, 3.4),
    /// about sqrt(omega / nu) / (4 sqrt(2) k) times the clean-water rate.
    #[test]
    fn film_damping_reaches_the_clean_and_inextensible_limits() {
        assert_eq!(film_damping(100.0, 0.0, 0.0, 0.072, 9.81), 0.0);
        for k in [20.0f64, 75.0, 230.0] {
            let omega = 2.0 * PI * (9.81 * k + 0.072 * k.powi(3) / RHO_WATER).sqrt() / (2.0 * PI);
            let inextensible = k * (NU * omega / 2.0).sqrt();
            let got = viscous_damping(k) + film_damping(k, 1e4, 0.0, 0.072, 9.81);
            assert!(
                (got / inextensible - 1.0).abs() < 1e-3,
                "k={k}: {got} vs {inextensible}"
            );
        }
        // below the Marangoni resonance (E of a few mN/m at Bragg scales) a weak natural film damps
        // more where it is concentrated
        let film = Film {
            reference_elasticity: 0.003,
        };
        let k = 230.0;
        assert!(
            total_damping(k, &film, 3.0, 0.0, 0.072, 9.81) > total_damping(k, &film, 1.0, 0.0, 0.072, 9.81),
            "more film, more damping"
        );
    }

    #[test]
    fn szyszkowski_film_elasticity_is_d_pressure_d_ln_gamma() {
        let film = Film {
            reference_elasticity: 0.01,
        };
        assert!((film.elasticity(1.0) - 0.01).abs() < 1e-15);
        for g in [0.3, 1.0, 2.5] {
            let h = 1e-6;
            let e = (film.pressure(g * (1.0 + h)) - film.pressure(g * (1.0 - h))) / (2.0 * h);
            assert!((e - film.elasticity(g)).abs() < 1e-9);
        }
    }
}

//! Damping of short waves (spec Eq. (2.69), film; clean water; turbulence) and the surface film
//! model. Wind growth (Eq. (2.68)) is in [`crate::short_waves`].
//!
//! The spec leaves the film's equation of state to Somero (2021) (erratum 7). wakelab uses the
//! von Szyszkowski-Langmuir equation of state for a soluble surfactant monolayer (Adamson & Gast,
//! "Physical Chemistry of Surfaces", 6th ed., 1997, Sec. III-7):
//!   Pi(Gamma) = Pi_s ln(1 + Gamma / a),
//! and the Gibbs dilational elasticity E = dPi / d ln Gamma = Pi_s (Gamma / a) / (1 + Gamma / a)
//! (Lucassen & Hansen 1967). Gamma is relative to the ambient concentration; with a = 1 the
//! scale Pi_s = 2 E_ref makes the ambient film's elasticity E(1) = `sea.film_elasticity`.
//! The default, 3 mN/m, is a weak open-ocean film; slicks reach 5-30 mN/m (Alpers &
//! Huehnerfuss 1989).

use crate::constants::{KARMAN, NU, RHO_AIR, RHO_WATER};
use std::f64::consts::PI;

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
    turbulent_coefficient(k) * dissipation.max(0.0).cbrt()
}

/// gamma_t / eps^{1/3} at wavenumber k: 4 C k^{2/3} (see [`turbulent_damping`]).
fn turbulent_coefficient(k: f64) -> f64 {
    4.0 * 0.4 * k.powf(2.0 / 3.0)
}

/// Dissipation of the wind-driven surface layer at depth z (m): the law of the wall
/// eps = u*_w^3 / (kappa z), u*_w = u* sqrt(rho_a / rho_w) the water-side friction velocity
/// (e.g. Terray et al. 1996, J. Phys. Oceanogr. 26, 792, below their wave-breaking layer).
/// The physical ambient against which a wake's turbulence counts as extra.
pub fn surface_layer_dissipation(air_friction_velocity: f64, depth: f64) -> f64 {
    let water = air_friction_velocity * (RHO_AIR / RHO_WATER).sqrt();
    water.powi(3) / (KARMAN * depth.max(1e-3))
}

/// The wake's damping of short waves over the undisturbed sea's: what the film's
/// redistribution and the wake's excess turbulence add (or, where the film is thinner than
/// ambient, take away). The undisturbed sea's own damping is part of its spectrum.
#[derive(Debug, Clone, Copy)]
pub struct WakeDamping {
    pub film: Film,
    /// The sea's own near-surface dissipation at the depth of the map's values (m^2/s^3).
    pub ambient_dissipation: f64,
    /// The hydro stage's ambient dissipation, counted as part of the sea's (m^2/s^3).
    pub model_ambient_dissipation: f64,
}

impl WakeDamping {
    /// Extra damping (1/s) of waves of wavenumber k in a film of relative concentration Gamma
    /// over a wake whose dissipation (from the hydro stage) is `dissipation`.
    pub fn extra(&self, k: f64, gamma: f64, dissipation: f64, tension: f64, gravity: f64) -> f64 {
        self.at(k, tension, gravity).extra(gamma, dissipation)
    }

    /// The damping of the undisturbed sea at wavenumber k, for many evaluations at one k.
    pub fn at(&self, k: f64, tension: f64, gravity: f64) -> WakeDampingAt {
        WakeDampingAt {
            wake: *self,
            k,
            tension,
            gravity,
            ambient_film: film_damping(k, self.film.elasticity(1.0), self.film.pressure(1.0), tension, gravity),
            ambient_turbulence: turbulent_damping(k, self.ambient_dissipation),
            turbulence_coefficient: turbulent_coefficient(k),
        }
    }
}

/// [`WakeDamping`] at one wavenumber, with the undisturbed sea's damping worked out once.
#[derive(Debug, Clone, Copy)]
pub struct WakeDampingAt {
    wake: WakeDamping,
    k: f64,
    tension: f64,
    gravity: f64,
    ambient_film: f64,
    ambient_turbulence: f64,
    turbulence_coefficient: f64,
}

impl WakeDampingAt {
    /// Extra damping (1/s) in a film of relative concentration Gamma over a wake of
    /// dissipation `dissipation` (see [`WakeDamping::extra`]).
    pub fn extra(&self, gamma: f64, dissipation: f64) -> f64 {
        let w = &self.wake;
        let film = if gamma == 1.0 {
            self.ambient_film
        } else {
            film_damping(
                self.k,
                w.film.elasticity(gamma),
                w.film.pressure(gamma),
                self.tension,
                self.gravity,
            )
        };
        let excess = (dissipation - w.model_ambient_dissipation).max(0.0);
        let turbulence = if excess > 0.0 {
            self.turbulence_coefficient * (w.ambient_dissipation + excess).cbrt()
        } else {
            self.ambient_turbulence
        };
        film - self.ambient_film + turbulence - self.ambient_turbulence
    }
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
        let wake = WakeDamping {
            film,
            ambient_dissipation: 1e-6,
            model_ambient_dissipation: 1e-10,
        };
        assert!(wake.extra(k, 3.0, 1e-10, 0.072, 9.81) > 0.0, "more film, more damping");
        assert!(wake.extra(k, 0.5, 1e-10, 0.072, 9.81) < 0.0, "less film, less damping");
        assert_eq!(
            wake.extra(k, 1.0, 1e-10, 0.072, 9.81),
            0.0,
            "the ambient sea adds nothing"
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

//! The narrow-V: Bragg scattering from the Kelvin pattern's own short waves.
//!
//! Far behind the ship the Kelvin field of [`crate::kelvin`] is, at each point, the sum of a
//! transverse and a divergent wave (Lighthill 1978, Sec. 3.10): the stationary points of
//!   zeta = (1 / 2 pi) int dq [Z(q) e^{i(K x + q y)} + c.c.]
//! where K'(q) = -y/x. On the ray at angle phi to the track the divergent wave runs at theta to the
//! track with tan phi = tan theta / (1 + 2 tan^2 theta) and has wavenumber k0 sec^2 theta, so
//! the short divergent waves lie close to the track. Where they have the radar's Bragg
//! wavenumber k_B and run along its look, the radar sees them: the narrow-V of Munk,
//! Scully-Power & Zachariasen (1987), whose half-angle is then, for k_B >> k0,
//!   phi_B ~ sqrt(k0 / k_B) / 2 = sqrt(g lambda_B / (8 pi)) / U,
//! and which shows when the look is nearly across the track, i.e. when the ship travels close
//! to the SAR's flight direction (Harger 1989; Tunaley 2004).
//!
//! The divergent wave's amplitude by stationary phase is a = |Z(q)| sqrt(2 / (pi x |K''(q)|))
//! (the first term and its conjugate), with
//!   q = k0 t sqrt(1 + t^2),  |K''| = |1 - 2 t^2| sqrt(1 + t^2) / (k0 (1 + 2 t^2)^3),
//! t = tan theta. Viscosity damps its energy at 4 nu k^2 (Lamb 1932, Sec. 348) for the time
//! x / (U - c_g,x) = x / (U (1 - cos^2 theta / 2)) since the ship made it. Thin-ship theory
//! knows no breaking: the sharp ends of a Wigley hull send out short waves whose steepness grows
//! without bound near the ship. Short gravity waves steeper than about 0.1 shed parasitic
//! capillaries and lose their energy (Longuet-Higgins 1963), so wakelab caps a k at
//! [`BREAKING_STEEPNESS`].
//!
//! What the radar sees of a deterministic wave depends on how coherent it stays over the
//! resolution cell. The longer waves of the sea strain and turn short waves riding on them by
//! the order of their slope (Longuet-Higgins & Stewart 1960), so wakelab spreads the wave's
//! variance a^2/2 over a Gaussian of standard deviation sigma = k_B s around +-k in the
//! two-sided spectrum, s the rms slope of the waves longer than the two-scale cut:
//!   F(k_B) + F(-k_B) += (a^2 / 2) [G(k_B - k) + G(k_B + k)],
//!   G(d) = exp(-|d|^2 / (2 sigma^2)) / (2 pi sigma^2).
//! This is an estimate of the coherence, not a published model; the arms' position does not
//! depend on it, their brightness does. Capillarity, which changes the steady waves' dispersion
//! by (k_B / 370 rad/m)^2, is left out, as in the thin-ship field.

use crate::kelvin::KelvinWaves;
use std::f64::consts::PI;

/// The spread's Gaussians end at 6 standard deviations, where their exponent is 18 (e^-18 of
/// their peak).
pub const SPREAD_END: f64 = 18.0;

/// The steepness a k above which the Kelvin pattern's short waves lose their energy (module doc).
pub const BREAKING_STEEPNESS: f64 = 0.1;

/// Where the Kelvin pattern's divergent wave at a point runs: its ray's geometry, which
/// depends on the direction y/x alone.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DivergentRay {
    /// tan theta, theta the wave's direction from the track.
    pub tan_theta: f64,
    /// Wave vector (behind, port), rad/m; -k describes the same wave.
    pub wave_vector: (f64, f64),
    /// Its wavenumber |k| = k0 sec^2 theta (rad/m).
    pub wavenumber: f64,
}

/// The divergent wave's ray through `x` m behind the stern and `y` m to port; None ahead of the
/// stern, on the track, outside Kelvin's wedge, and near its cusp lines (within 1 deg), where the
/// stationary points merge.
pub fn divergent_ray(waves: &KelvinWaves, x: f64, y: f64) -> Option<DivergentRay> {
    if x <= 0.0 {
        return None;
    }
    let ray = y.abs() / x; // tan phi
    let cusp = (8f64.sqrt().recip().atan() - 1f64.to_radians()).tan();
    if ray <= 0.0 || ray >= cusp {
        return None;
    }
    // the divergent (larger) root of 2 ray t^2 - t + ray = 0
    let t = (1.0 + (1.0 - 8.0 * ray * ray).sqrt()) / (4.0 * ray);
    let k0 = waves.ship.kelvin_wavenumber();
    let q = k0 * t * (1.0 + t * t).sqrt();
    // the first term's stationary point has q of the opposite sign to y
    Some(DivergentRay {
        tan_theta: t,
        wave_vector: (waves.along_track_wavenumber(q), -y.signum() * q),
        wavenumber: k0 * (1.0 + t * t),
    })
}

impl DivergentRay {
    /// The wave's amplitude (m) at `x` m behind the stern: [`Self::linear_amplitude`] capped at
    /// [`BREAKING_STEEPNESS`] / k.
    pub fn amplitude(&self, waves: &KelvinWaves, x: f64, viscosity: f64) -> f64 {
        self.linear_amplitude(waves, x, viscosity)
            .min(BREAKING_STEEPNESS / self.wavenumber)
    }

    /// The wave's amplitude (m) at `x` m behind the stern by stationary phase (module doc),
    /// damped by a kinematic `viscosity` (m^2/s): linear theory's, without breaking.
    pub fn linear_amplitude(&self, waves: &KelvinWaves, x: f64, viscosity: f64) -> f64 {
        let (t2, kappa) = (self.tan_theta * self.tan_theta, self.wavenumber);
        let k0 = waves.ship.kelvin_wavenumber();
        let curvature = (1.0 - 2.0 * t2).abs() * (1.0 + t2).sqrt() / (k0 * (1.0 + 2.0 * t2).powi(3));
        let (_, _, z) = waves.wave(self.wave_vector.1);
        let age = x / (waves.ship.speed * (1.0 - 0.5 / (1.0 + t2)));
        let decay = (-2.0 * viscosity * kappa * kappa * age).exp();
        z.norm() * (2.0 / (PI * x * curvature)).sqrt() * decay
    }

    /// The weight G(k_B - k) + G(k_B + k) (m^2) by which a wave of this ray adds its variance
    /// a^2 / 2 to F(k_B) + F(-k_B) at the Bragg wave vector `bragg` (track frame, rad/m), spread
    /// over Gaussians of standard deviation `spread` (rad/m) around +-k (module doc), which end
    /// where their exponent reaches [`SPREAD_END`].
    pub fn bragg_weight(&self, bragg: (f64, f64), spread: f64) -> f64 {
        let (kx, ky) = self.wave_vector;
        let s2 = spread * spread;
        let gauss = |dx: f64, dy: f64| {
            let exponent = (dx * dx + dy * dy) / (2.0 * s2);
            if exponent > SPREAD_END {
                0.0
            } else {
                (-exponent).exp()
            }
        };
        (gauss(bragg.0 - kx, bragg.1 - ky) + gauss(bragg.0 + kx, bragg.1 + ky)) / (2.0 * PI * s2)
    }
}

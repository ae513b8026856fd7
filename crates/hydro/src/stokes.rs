//! Stokes drift of the swell, spec Eq. (2.1), and its direction relative to the track.

use wakelab_core::config::SwellConfig;

/// Stokes drift speed of a deep-water swell at height `z` (m, <= 0), Eq. (2.1):
/// u_S = (2 pi a_s / lambda)^2 sqrt(g lambda / 2 pi) exp(4 pi z / lambda).
pub fn stokes_drift(amplitude: f64, wavelength: f64, gravity: f64, z: f64) -> f64 {
    let k = 2.0 * std::f64::consts::PI / wavelength;
    (amplitude * k).powi(2) * (gravity / k).sqrt() * (2.0 * k * z).exp()
}

/// The Stokes drift vector (u_Sx along the heading, u_Sy to port) at each level of a grid.
#[derive(Debug, Clone, PartialEq)]
pub struct StokesProfile {
    /// Along-track component at each z.
    pub along: Vec<f64>,
    /// Cross-track component at each z.
    pub across: Vec<f64>,
}

impl StokesProfile {
    /// Evaluate at heights `z` (m); zero everywhere for a calm sea.
    pub fn new(swell: &SwellConfig, gravity: f64, z: &[f64]) -> Self {
        match swell.angle() {
            None => Self {
                along: vec![0.0; z.len()],
                across: vec![0.0; z.len()],
            },
            Some(angle) => {
                let speed: Vec<f64> = z
                    .iter()
                    .map(|&z| stokes_drift(swell.amplitude, swell.wavelength, gravity, z))
                    .collect();
                Self {
                    along: speed.iter().map(|s| s * angle.cos()).collect(),
                    across: speed.iter().map(|s| s * angle.sin()).collect(),
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Eq. (2.1) against the textbook form u_S = a^2 omega k exp(2 k z) with the deep-water
    /// dispersion relation omega^2 = g k (Phillips 1977, Eq. 3.3.21).
    #[test]
    fn equals_a2_omega_k_with_deep_water_dispersion() {
        for (a, lambda, z) in [
            (1.0, 100.0, 0.0),
            (1.0, 100.0, -5.0),
            (0.5, 60.0, -12.0),
            (2.0, 250.0, -30.0),
        ] {
            let k = 2.0 * std::f64::consts::PI / lambda;
            let omega = (9.81 * k).sqrt();
            let want = a * a * omega * k * (2.0 * k * z).exp();
            let got = stokes_drift(a, lambda, 9.81, z);
            assert!(((got - want) / want).abs() < 1e-12, "{got} vs {want}");
        }
        // a = 1 m, lambda = 100 m at the surface: 0.04933 m/s (hand-computed).
        assert!((stokes_drift(1.0, 100.0, 9.81, 0.0) - 0.049330).abs() < 1e-5);
        // e-folding depth lambda / 4 pi
        let ratio =
            stokes_drift(1.0, 100.0, 9.81, -100.0 / (4.0 * std::f64::consts::PI)) / stokes_drift(1.0, 100.0, 9.81, 0.0);
        assert!((ratio - (-1f64).exp()).abs() < 1e-12);
    }
}

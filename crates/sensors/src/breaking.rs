//! Radar scattering from breaking waves (KHCC03 Eqs. 56-60; Kudryavtsev, Hauser, Caudal &
//! Chapron 2003, J. Geophys. Res. 108(C3), 8054): the fraction q of the surface their zones
//! cover, the mean direction of the breakers, and the NRCS of a breaking zone.

use std::f64::consts::PI;
use wakelab_surface::short_waves::{breaking_wavenumber, ShortWaves};
use wakelab_surface::spectrum::SeaSpectrum;

/// Breaking-zone constants of KHCC03 (Eqs. 56-60).
const BREAKING_SLOPE_VARIANCE: f64 = 0.19;
const BREAKING_THICKNESS: f64 = 0.005;
pub(crate) const BREAKING_TILT: f64 = 0.05;
const BREAKING_FRACTION_CONSTANT: f64 = 10.5;
const GRAVITY_SATURATION: f64 = 5.04e-3;

/// sigma_wb0(theta) of KHCC03 Eq. 60: the NRCS of breaking zones.
pub fn breaking_zone_nrcs(theta: f64) -> f64 {
    let t = theta.tan();
    ((-t * t / BREAKING_SLOPE_VARIANCE).exp() / theta.cos().powi(4) + BREAKING_THICKNESS) / BREAKING_SLOPE_VARIANCE
}

/// The breaking waves a radar of wavenumber k0 sees, for look direction `look`: their surface
/// fraction q and the mean cosine A_wb of their direction to the look (KHCC03 Eqs. 56-60).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BreakingZones {
    pub fraction: f64,
    pub asymmetry: f64,
}

/// q and A_wb over the long waves of `spectrum` with the growth of `short_waves`.
pub fn breaking_zones(spectrum: &SeaSpectrum, short_waves: &ShortWaves, k0: f64, look: f64) -> BreakingZones {
    let k_hi = breaking_wavenumber(k0);
    let k_lo = 0.5 * spectrum.peak_wavenumber();
    if k_hi <= k_lo || spectrum.wind_speed <= 0.0 {
        return BreakingZones {
            fraction: 0.0,
            asymmetry: 0.0,
        };
    }
    let (n, angles) = (120, 72);
    let step = (k_hi / k_lo).ln() / n as f64;
    let dphi = 2.0 * PI / angles as f64;
    let (mut total, mut along) = (0.0, 0.0);
    for i in 0..n {
        let k = k_lo * ((i as f64 + 0.5) * step).exp();
        let (ring, net_growth) = (spectrum.ring(k), short_waves.net_growth_at(k));
        for a in 0..angles {
            let phi = (a as f64 + 0.5) * dphi;
            let beta_v = net_growth(phi);
            if beta_v > 0.0 {
                let b = k.powi(4) * ring.at(phi);
                // Lambda dk dphi = beta_v B / (2 alpha) dln k dphi
                let lambda = beta_v * b / (2.0 * GRAVITY_SATURATION) * step * dphi;
                total += lambda;
                along += lambda * (phi - look).cos();
            }
        }
    }
    BreakingZones {
        fraction: (BREAKING_FRACTION_CONSTANT * total).min(1.0),
        asymmetry: if total > 0.0 { along / total } else { 0.0 },
    }
}

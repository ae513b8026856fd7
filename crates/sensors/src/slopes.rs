//! What the two-scale model takes from the observed statistics of sea-surface slopes rather than
//! from the wave spectrum: the up-/cross-wind partition of the slope variance and the peakedness
//! of the slope distribution, both from the sun-glitter photographs of Cox & Munk (1954,
//! J. Opt. Soc. Am. 44, 838-850; "CM54"), the reference every glint and scatterometer model
//! uses.
//!
//! Why not the spectrum's own: the Elfouhaily et al. (1997) spreading makes the slopes of the
//! tilting waves 1.6 times steeper up-wind than cross-wind at 5 m/s, where CM54 observed 1.25,
//! and a Gaussian has no tails: both made the two-scale sigma0 at 20-25 degrees far more
//! anisotropic than CMOD5.N (3-6 dB up/cross where it has 0.8-1.4 dB). The spectrum still sets
//! the total variance of each range of scales.

use std::f64::consts::PI;

/// CM54's Gram-Charlier coefficients of the clean surface (their Table 1): the peakedness
/// c40 (cross-wind), c22 and c04 (up-wind). Their skewness terms (c21, c03) are left out, so the
/// density stays centro-symmetric: the up-/down-wind asymmetry comes from the breakers.
const PEAKEDNESS_CROSS: f64 = 0.40;
const PEAKEDNESS_MIXED: f64 = 0.12;
const PEAKEDNESS_UP: f64 = 0.23;

/// CM54's clean-surface slope variances up-wind and cross-wind, s_u^2 = 3.16e-3 U and
/// s_c^2 = 0.003 + 1.92e-3 U, U in m/s (their wind at 12.5 m; wakelab's 10 m wind is 2 % lower
/// in a neutral log profile, left as it is).
pub fn cox_munk_variances(wind_speed: f64) -> (f64, f64) {
    let u = wind_speed.max(0.0);
    (3.16e-3 * u, 3e-3 + 1.92e-3 * u)
}

/// A total slope variance split up-wind and cross-wind in CM54's ratio.
pub fn wind_frame_variances(total: f64, wind_speed: f64) -> (f64, f64) {
    let (up, cross) = cox_munk_variances(wind_speed);
    let up_share = up / (up + cross);
    (total * up_share, total * (1.0 - up_share))
}

/// The variances (along, across) a look direction `from_wind` radians from the wind's, of
/// slopes whose total variance is `variances.0 + variances.1`, in CM54's up-/cross-wind ratio.
pub fn look_frame_variances(variances: (f64, f64), wind_speed: f64, from_wind: f64) -> (f64, f64) {
    let total = variances.0 + variances.1;
    let (up, cross) = wind_frame_variances(total, wind_speed);
    let (c2, s2) = (from_wind.cos().powi(2), from_wind.sin().powi(2));
    let along = up * c2 + cross * s2;
    (along, total - along)
}

/// The joint density of the slopes (up-wind s_u, cross-wind s_c): a Gaussian of the given
/// variances times CM54's Gram-Charlier peakedness (their Eq. 4 without the skewness terms),
///   p = exp(-(xi^2 + eta^2) / 2) / (2 pi sigma_u sigma_c)
///       [1 + c40 H4(xi) / 24 + c22 H2(xi) H2(eta) / 4 + c04 H4(eta) / 24],
/// xi = s_c / sigma_c, eta = s_u / sigma_u, H2(x) = x^2 - 1, H4(x) = x^4 - 6 x^2 + 3; held at zero
/// where the series turns negative, far in the tails.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlopeDensity {
    pub up_variance: f64,
    pub cross_variance: f64,
}

impl SlopeDensity {
    /// Density at slope (up-wind, cross-wind).
    pub fn at(&self, up: f64, cross: f64) -> f64 {
        let (su, sc) = (self.up_variance.sqrt(), self.cross_variance.sqrt());
        if su <= 0.0 || sc <= 0.0 {
            return 0.0;
        }
        let (eta, xi) = (up / su, cross / sc);
        let gauss = (-0.5 * (xi * xi + eta * eta)).exp() / (2.0 * PI * su * sc);
        gauss * peakedness(xi, eta)
    }
}

/// The Gram-Charlier factor of [`SlopeDensity`] at normalised slopes xi (cross-wind) and eta
/// (up-wind), at least zero.
pub fn peakedness(xi: f64, eta: f64) -> f64 {
    let h2 = |x: f64| x * x - 1.0;
    let h4 = |x: f64| x.powi(4) - 6.0 * x * x + 3.0;
    (1.0 + PEAKEDNESS_CROSS / 24.0 * h4(xi)
        + PEAKEDNESS_MIXED / 4.0 * h2(xi) * h2(eta)
        + PEAKEDNESS_UP / 24.0 * h4(eta))
    .max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Moments of the density over the slope plane, by the midpoint rule over +-12 standard
    /// deviations: (integral, up-wind variance, cross-wind variance, cross-wind fourth moment).
    fn moments(d: &SlopeDensity) -> (f64, f64, f64, f64) {
        let (su, sc) = (d.up_variance.sqrt(), d.cross_variance.sqrt());
        let n = 600;
        let h = 24.0 / n as f64;
        let (mut m0, mut mu, mut mc, mut m4) = (0.0, 0.0, 0.0, 0.0);
        for i in 0..n {
            let eta = -12.0 + (i as f64 + 0.5) * h;
            for j in 0..n {
                let xi = -12.0 + (j as f64 + 0.5) * h;
                let w = d.at(eta * su, xi * sc) * su * sc * h * h;
                m0 += w;
                mu += w * (eta * su).powi(2);
                mc += w * (xi * sc).powi(2);
                m4 += w * xi.powi(4);
            }
        }
        (m0, mu, mc, m4)
    }

    /// The Gram-Charlier terms are orthogonal to 1, x^2 and y^2 under the Gaussian: the density
    /// integrates to one and keeps the variances it was given, while its cross-wind kurtosis is
    /// 3 + c40 (CM54's definition of the peakedness coefficient). The clamp at zero changes
    /// none of this here (the series is positive within 12 standard deviations).
    #[test]
    fn the_density_is_normalised_keeps_its_variances_and_has_cox_and_munks_kurtosis() {
        let d = SlopeDensity {
            up_variance: 0.02,
            cross_variance: 0.013,
        };
        let (m0, mu, mc, m4) = moments(&d);
        assert!((m0 - 1.0).abs() < 1e-6, "integral {m0}");
        assert!((mu / 0.02 - 1.0).abs() < 1e-6, "up {mu}");
        assert!((mc / 0.013 - 1.0).abs() < 1e-6, "cross {mc}");
        assert!((m4 - (3.0 + PEAKEDNESS_CROSS)).abs() < 1e-6, "kurtosis {m4}");
    }

    /// A transcription check of CM54's clean-surface regression lines (their values at
    /// 10 m/s, 0.0316 up-wind and 0.0222 cross-wind), and the partition conserves the total
    /// variance, keeps CM54's ratio and turns with the look (equal shares at 45 degrees).
    #[test]
    fn partition_follows_cox_and_munk() {
        let (up, cross) = cox_munk_variances(10.0);
        assert!((up - 0.0316).abs() < 1e-12 && (cross - 0.0222).abs() < 1e-12);
        let (u, c) = wind_frame_variances(0.01, 10.0);
        assert!((u / c - 0.0316 / 0.0222).abs() < 1e-12 && (u + c - 0.01).abs() < 1e-15);
        let along_wind = look_frame_variances((0.004, 0.006), 10.0, 0.0);
        let across_wind = look_frame_variances((0.004, 0.006), 10.0, PI / 2.0);
        assert!((along_wind.0 - u).abs() < 1e-15 && (across_wind.0 - c).abs() < 1e-15);
        let oblique = look_frame_variances((0.004, 0.006), 10.0, PI / 4.0);
        assert!((oblique.0 - oblique.1).abs() < 1e-15);
    }
}

//! Black-body radiance, spec Eqs. (3.16)-(3.17): Planck's law and its integral over a band.

/// Planck constant (J s), speed of light (m/s), Boltzmann constant (J/K): SI 2019 exact values.
pub const H: f64 = 6.626_070_15e-34;
pub const C: f64 = 299_792_458.0;
pub const K_B: f64 = 1.380_649e-23;

/// Spectral radiance L_lambda (W m^-2 sr^-1 per m of wavelength) at wavelength `m` (metres) and
/// temperature `t` (K), Eq. (3.16) with emissivity 1.
pub fn spectral_radiance(m: f64, t: f64) -> f64 {
    2.0 * H * C * C / m.powi(5) / ((H * C / (m * K_B * t)).exp_m1())
}

/// Radiance in the band [lo, hi] (micrometres) by Gauss-Legendre quadrature on 8 panels of
/// 8 nodes, Eq. (3.17) integrated rather than L_lambda times the width (W m^-2 sr^-1).
pub fn band_radiance(lo_um: f64, hi_um: f64, t: f64) -> f64 {
    // 8-point Gauss-Legendre nodes and weights on [-1, 1]
    const X: [f64; 4] = [
        0.183_434_642_495_649_8,
        0.525_532_409_916_329,
        0.796_666_477_413_626_7,
        0.960_289_856_497_536_3,
    ];
    const W: [f64; 4] = [
        0.362_683_783_378_362,
        0.313_706_645_877_887_3,
        0.222_381_034_453_374_5,
        0.101_228_536_290_376_3,
    ];
    let (a, b) = (lo_um * 1e-6, hi_um * 1e-6);
    let panels = 8;
    let width = (b - a) / panels as f64;
    let mut sum = 0.0;
    for p in 0..panels {
        let mid = a + (p as f64 + 0.5) * width;
        for (x, w) in X.iter().zip(W) {
            for sign in [-1.0, 1.0] {
                sum += w * spectral_radiance(mid + sign * x * 0.5 * width, t);
            }
        }
    }
    sum * 0.5 * width
}

/// Brightness temperature (K) whose band radiance is `radiance` (bisection to 1e-6 K).
pub fn brightness_temperature(lo_um: f64, hi_um: f64, radiance: f64) -> f64 {
    let (mut lo, mut hi) = (1.0, 10_000.0);
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if band_radiance(lo_um, hi_um, mid) < radiance {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The band integral against the independent series of the Planck integral:
    /// int_x^inf x^3 / (e^x - 1) dx = sum_n e^{-n x} (x^3/n + 3 x^2/n^2 + 6 x/n^3 + 6/n^4)
    /// (Widger & Woodall 1976), with x = h c / (lambda k T).
    #[test]
    fn band_radiance_matches_the_planck_series() {
        let tail = |x: f64| -> f64 {
            (1..200)
                .map(|n| {
                    let n = n as f64;
                    (-n * x).exp() * (x.powi(3) / n + 3.0 * x * x / (n * n) + 6.0 * x / n.powi(3) + 6.0 / n.powi(4))
                })
                .sum()
        };
        for (lo, hi, t) in [(10.5, 11.5, 300.0), (3.7, 4.1, 300.0), (8.0, 12.0, 273.15)] {
            let x = |um: f64| H * C / (um * 1e-6 * K_B * t);
            let factor = 2.0 * (K_B * t).powi(4) / (H.powi(3) * C * C);
            let series = factor * (tail(x(hi)) - tail(x(lo)));
            let quad = band_radiance(lo, hi, t);
            assert!(
                (quad / series - 1.0).abs() < 1e-9,
                "{lo}-{hi} um at {t} K: {quad} vs {series}"
            );
        }
        // a 300 K black body gives about 9.3 W m^-2 sr^-1 over 10.5-11.5 um
        let l = band_radiance(10.5, 11.5, 300.0);
        assert!((l - 9.3).abs() < 0.3, "{l}");
    }

    #[test]
    fn wien_peak_and_brightness_temperature_round_trip() {
        for t in [293.0, 1000.0, 5800.0] {
            // golden-section search for the peak of L_lambda
            let (mut a, mut b) = (0.1e-6, 30e-6);
            for _ in 0..200 {
                let (c1, c2) = (b - 0.618 * (b - a), a + 0.618 * (b - a));
                if spectral_radiance(c1, t) > spectral_radiance(c2, t) {
                    b = c2;
                } else {
                    a = c1;
                }
            }
            let peak_um_k = 0.5 * (a + b) * 1e6 * t;
            assert!((peak_um_k - 2897.77).abs() < 0.5, "{t} K: {peak_um_k}");
        }
        let l = band_radiance(3.7, 4.1, 288.0);
        assert!((brightness_temperature(3.7, 4.1, l) - 288.0).abs() < 1e-5);
    }
}

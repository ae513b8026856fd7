//! Complex relative permittivity of sea water at microwave frequencies (erratum 5): the Debye
//! model of Klein & Swift (1977), IEEE Trans. Antennas Propag. AP-25(1), 104-111, valid from
//! 1 to 10 GHz (S, C and X band), with their fits of the static permittivity, relaxation time
//! and ionic conductivity in temperature T (deg C) and salinity S (PSU).
//! Convention e^{+i omega t}: eps = eps' - i eps''.

use num_complex::Complex64;

/// Permittivity of free space (F/m).
pub const EPSILON_0: f64 = 8.854_187_812_8e-12;
/// High-frequency permittivity of Klein & Swift.
pub const EPSILON_INFINITY: f64 = 4.9;

/// Static permittivity eps_s(T, S).
pub fn static_permittivity(t: f64, s: f64) -> f64 {
    let e0 = 87.134 - 1.949e-1 * t - 1.276e-2 * t * t + 2.491e-4 * t.powi(3);
    let a = 1.0 + 1.613e-5 * s * t - 3.656e-3 * s + 3.210e-5 * s * s - 4.232e-7 * s.powi(3);
    e0 * a
}

/// Debye relaxation time tau(T, S) (s).
pub fn relaxation_time(t: f64, s: f64) -> f64 {
    let tau0 = 1.768e-11 - 6.086e-13 * t + 1.104e-14 * t * t - 8.111e-17 * t.powi(3);
    let b = 1.0 + 2.282e-5 * s * t - 7.638e-4 * s - 7.760e-6 * s * s + 1.105e-8 * s.powi(3);
    tau0 * b
}

/// Ionic conductivity sigma(T, S) (S/m).
pub fn conductivity(t: f64, s: f64) -> f64 {
    let s25 = s * (0.182521 - 1.46192e-3 * s + 2.09324e-5 * s * s - 1.28205e-7 * s.powi(3));
    let d = 25.0 - t;
    let alpha = 2.033e-2 + 1.266e-4 * d + 2.464e-6 * d * d - s * (1.849e-5 - 2.551e-7 * d + 2.551e-8 * d * d);
    s25 * (-d * alpha).exp()
}

/// eps(f, T, S) = eps_inf + (eps_s - eps_inf) / (1 + i omega tau) - i sigma / (omega eps_0).
pub fn seawater_permittivity(frequency: f64, t: f64, s: f64) -> Complex64 {
    let omega = 2.0 * std::f64::consts::PI * frequency;
    let debye = (static_permittivity(t, s) - EPSILON_INFINITY) / Complex64::new(1.0, omega * relaxation_time(t, s));
    Complex64::new(EPSILON_INFINITY, 0.0) + debye - Complex64::new(0.0, conductivity(t, s) / (omega * EPSILON_0))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Independent reference values: pure water's static permittivity 80.1 at 20 C (CRC
    /// Handbook), its Debye relaxation time 9.3 ps at 20 C (Kaatze 1989), and the conductivity of
    /// standard sea water (S = 35) 5.3 S/m at 25 C (UNESCO 1983 / PSS-78: C(35, 15 C) = 4.29 S/m).
    #[test]
    fn klein_swift_fits_match_reference_values() {
        assert!((static_permittivity(20.0, 0.0) - 80.1).abs() < 0.15);
        assert!((relaxation_time(20.0, 0.0) - 9.3e-12).abs() < 0.1e-12);
        assert!((conductivity(25.0, 35.0) - 5.3).abs() < 0.05);
        assert!((conductivity(15.0, 35.0) - 4.29).abs() < 0.05);
    }

    #[test]
    fn sea_water_is_lossy_and_less_polar_at_higher_frequency() {
        let s = seawater_permittivity(3.1e9, 15.0, 35.0);
        let x = seawater_permittivity(9.6e9, 15.0, 35.0);
        assert!(s.im < 0.0 && x.im < 0.0);
        assert!(x.re < s.re, "the Debye dispersion lowers eps' with frequency");
        // at C band eps is near 65 - 37i (Klein & Swift 1977, Fig. 5 region)
        let c = seawater_permittivity(5.3e9, 20.0, 35.0);
        assert!(c.re > 55.0 && c.re < 75.0 && -c.im > 30.0 && -c.im < 45.0, "{c}");
    }
}

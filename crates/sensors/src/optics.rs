//! Infrared optics of sea water (spec 3.2.2): complex refractive index (Eqs. (3.7)-(3.8)), Fresnel
//! reflectance (Eqs. (3.9)-(3.13)) and Kirchhoff emissivity (Eq. (3.14)).
//!
//! Data (shipped in `crates/sensors/data` with their provenance headers; erratum 12):
//! - n_pure, kappa_pure: Hale & Querry (1973), Appl. Opt. 12, 555, pure water, interpolated
//!   linearly in wavelength (the spec's choice).
//! - Salinity: for 1.5-9 um the spec's rule Delta n = 6e-3 S / S_ref, Delta kappa = 0,
//!   S_ref = 34.3; for 9-15 um Friedman's table is not available, so the per-PSU coefficients of
//!   Pinkley & Williams (1976) (with Roettgers et al. 2014) shipped in the IOSEE table are used
//!   (the spec notes the two agree).
//! - Temperature: Newman et al. (2005)'s c_n, c_kappa are not available; their substitute is the
//!   temperature slope of the Wang et al. (2026) n(T), kappa(T) at 295-303 K, applied as
//!   c (T - 27 C) over 770-1230 cm^-1 and zero outside, as the spec prescribes.

use num_complex::Complex64;
use std::sync::OnceLock;

/// Refractive index of air (Hecht 2017), spec 3.2.2.
pub const N_AIR: f64 = 1.0003;
/// Reference salinity of the spec's salinity rule (PSU).
pub const S_REF: f64 = 34.3;

const HALE_QUERRY: &str = include_str!("../data/hale_querry_1973_water_nk.csv");
const IOSEE: &str = include_str!("../data/iosee_wang2026_water_nk_vs_T_2p7to20um.csv");

/// Rows of a CSV table after its `#` comment lines and header.
fn rows(text: &str) -> impl Iterator<Item = Vec<f64>> + '_ {
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .skip(1)
        .map(|l| {
            l.split(',')
                .map(|v| v.trim().parse::<f64>().expect("numeric table"))
                .collect()
        })
}

struct Tables {
    /// (wavelength um, n, kappa), increasing wavelength.
    hale_querry: Vec<(f64, f64, f64)>,
    /// (wavelength um, dn/dT, dkappa/dT, n per PSU, kappa per PSU), increasing wavelength.
    iosee: Vec<(f64, f64, f64, f64, f64)>,
}

fn tables() -> &'static Tables {
    static T: OnceLock<Tables> = OnceLock::new();
    T.get_or_init(|| {
        let hale_querry = rows(HALE_QUERRY).map(|r| (r[0], r[1], r[2])).collect();
        // columns: wavenumber, wavelength, n at 271..311 K (11), k at 271..311 K (11), n/PSU, k/PSU
        let mut iosee: Vec<(f64, f64, f64, f64, f64)> = rows(IOSEE)
            .map(|r| {
                // 295 K and 303 K are columns 6 and 8 of each block of eleven temperatures
                let (n295, n303) = (r[2 + 6], r[2 + 8]);
                let (k295, k303) = (r[13 + 6], r[13 + 8]);
                (r[1], (n303 - n295) / 8.0, (k303 - k295) / 8.0, r[24], r[25])
            })
            .collect();
        iosee.sort_by(|a, b| a.0.total_cmp(&b.0));
        Tables { hale_querry, iosee }
    })
}

/// Linear interpolation in a table sorted by its first column.
fn interpolate<const N: usize>(table: &[[f64; N]], x: f64) -> [f64; N] {
    let i = table.partition_point(|r| r[0] < x).clamp(1, table.len() - 1);
    let (a, b) = (&table[i - 1], &table[i]);
    let f = ((x - a[0]) / (b[0] - a[0])).clamp(0.0, 1.0);
    std::array::from_fn(|j| a[j] + f * (b[j] - a[j]))
}

/// Complex refractive index of sea water n - i kappa (Eq. (3.8)) at wavelength `um` (0.2-200 um),
/// practical salinity `s` (PSU) and temperature `t` (deg C).
pub fn seawater_index(um: f64, s: f64, t: f64) -> Complex64 {
    let tb = tables();
    let hq: Vec<[f64; 3]> = tb.hale_querry.iter().map(|&(w, n, k)| [w, n, k]).collect();
    let [_, n_pure, k_pure] = interpolate(&hq, um);
    let iosee_at = |um: f64| -> Option<[f64; 5]> {
        let first = tb.iosee.first()?.0;
        let last = tb.iosee.last()?.0;
        if um < first || um > last {
            return None;
        }
        let t: Vec<[f64; 5]> = tb.iosee.iter().map(|&(w, a, b, c, d)| [w, a, b, c, d]).collect();
        Some(interpolate(&t, um))
    };
    let (dn_s, dk_s) = if (1.5..9.0).contains(&um) {
        (6e-3 * s / S_REF, 0.0)
    } else if (9.0..=15.0).contains(&um) {
        iosee_at(um).map_or((0.0, 0.0), |r| (r[3] * s, r[4] * s))
    } else {
        (0.0, 0.0)
    };
    let wavenumber = 1e4 / um;
    let (dn_t, dk_t) = if (770.0..=1230.0).contains(&wavenumber) {
        iosee_at(um).map_or((0.0, 0.0), |r| (r[1] * (t - 27.0), r[2] * (t - 27.0)))
    } else {
        (0.0, 0.0)
    };
    Complex64::new(n_pure + dn_s + dn_t, -(k_pure + dk_s + dk_t))
}

/// Fresnel power reflectances (rho_s, rho_p) from a medium of real index `n1` onto one of complex
/// index `n2` at incidence `theta` (rad), Eqs. (3.9)-(3.13).
pub fn fresnel_reflectance(n1: f64, n2: Complex64, theta: f64) -> (f64, f64) {
    let (s, c) = theta.sin_cos();
    // n2 cos(theta_t) = sqrt(n2^2 - n1^2 sin^2): the root with positive real part
    let n2_cos_t = (n2 * n2 - n1 * n1 * s * s).sqrt();
    let n2_cos_t = if n2_cos_t.re < 0.0 { -n2_cos_t } else { n2_cos_t };
    let cos_t_times_n1 = n1 * n2_cos_t / n2; // n1 cos(theta_t)
    let rs = (n1 * c - n2_cos_t) / (n1 * c + n2_cos_t);
    let rp = (n2 * c - cos_t_times_n1) / (n2 * c + cos_t_times_n1);
    (rs.norm_sqr(), rp.norm_sqr())
}

/// Unpolarised reflectance (Eq. (3.10)) and Kirchhoff emissivity 1 - rho (Eq. (3.14)c).
pub fn reflectance_and_emissivity(n2: Complex64, theta: f64) -> (f64, f64) {
    let (rs, rp) = fresnel_reflectance(N_AIR, n2, theta);
    let rho = 0.5 * (rs + rp);
    (rho, 1.0 - rho)
}

/// Wilson (1979) empirical emissivity, Eq. (3.15).
pub fn wilson_emissivity(theta: f64) -> f64 {
    0.98 * (1.0 - (1.0 - theta.cos()).powi(5))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn fresnel_for_the_spec_figure_3_9_index() {
        let n = Complex64::new(1.1, -0.5);
        for i in 1..90 {
            let th = (i as f64).to_radians();
            let (rs, rp) = fresnel_reflectance(1.0, n, th);
            assert!(rs > rp, "{i} deg: rho_s {rs} <= rho_p {rp}");
        }
        let (rs, rp) = fresnel_reflectance(1.0, n, FRAC_PI_2 - 1e-6);
        assert!(rs > 0.9999 && rp > 0.999, "grazing: {rs} {rp}");
        let (rs, rp) = fresnel_reflectance(1.0, n, 0.0);
        let normal = ((n - 1.0) / (n + 1.0)).norm_sqr();
        assert!((rs - normal).abs() < 1e-14 && (rp - normal).abs() < 1e-14);
        let (rho, eps) = reflectance_and_emissivity(n, 0.7);
        assert!((rho + eps - 1.0).abs() < 1e-15);
    }

    /// A lossless interface has no p reflection at Brewster's angle atan(n2 / n1).
    #[test]
    fn brewster_angle_of_a_lossless_interface() {
        let (_, rp) = fresnel_reflectance(1.0, Complex64::new(1.33, 0.0), 1.33f64.atan());
        assert!(rp < 1e-20);
    }

    /// The tables: pure water near 10 um has n = 1.218, kappa = 0.0508 (Hale & Querry 1973, Table 1),
    /// and the sea-water index at 11 um is within 1 % of the CRTM's Wieliczka + Friedman table.
    #[test]
    fn refractive_index_matches_the_published_tables() {
        let pure = seawater_index(10.0, 0.0, 27.0);
        assert!(
            (pure.re - 1.218).abs() < 2e-3 && (-pure.im - 0.0508).abs() < 2e-3,
            "{pure}"
        );
        let crtm: Vec<[f64; 3]> = rows(include_str!("../data/crtm_wieliczka1989_friedman1969_seawater_nk.csv"))
            .map(|r| [r[1], r[2], r[3]])
            .collect();
        let mut sorted = crtm.clone();
        sorted.sort_by(|a, b| a[0].total_cmp(&b[0]));
        for um in [3.9, 10.0, 11.0, 12.0] {
            let [_, n, k] = interpolate(&sorted, um);
            let sea = seawater_index(um, 34.3, 20.0);
            assert!((sea.re / n - 1.0).abs() < 0.015, "{um} um: n {} vs CRTM {n}", sea.re);
            assert!(
                (-sea.im / k - 1.0).abs() < 0.15,
                "{um} um: kappa {} vs CRTM {k}",
                -sea.im
            );
        }
    }

    /// Emissivity at 10-12 um lies near Wilson's curve below 60 degrees and falls at grazing
    /// incidence (spec Fig. 3.14).
    #[test]
    fn emissivity_follows_wilson_and_falls_at_grazing() {
        for um in [10.0, 11.0, 12.0] {
            let n = seawater_index(um, 35.0, 20.0);
            for deg in [0.0, 20.0, 40.0, 60.0] {
                let th = f64::to_radians(deg);
                let (_, e) = reflectance_and_emissivity(n, th);
                assert!(
                    (e - wilson_emissivity(th)).abs() < 0.02,
                    "{um} um {deg} deg: {e} vs Wilson {}",
                    wilson_emissivity(th)
                );
            }
            let e80 = reflectance_and_emissivity(n, 80f64.to_radians()).1;
            let e89 = reflectance_and_emissivity(n, 89f64.to_radians()).1;
            assert!(e80 < 0.9 && e89 < e80 && e89 < 0.2);
        }
    }
}

//! Infrared images, spec 3.2: Algorithm 1 with the radiance balance of Eq. (3.4) reduced to
//! Eq. (3.5), R = eps R_sea + rho (R_sun + R_sky), per surface facet.
//!
//! - Facets (3.2.2): the normal of each pixel's facet from the scene's long-wave slopes; r the
//!   unit vector to the sensor (the platform's incidence and look direction); the direction the
//!   reflected light comes from, i = 2 n cos(beta) - r (Eq. (3.6)), cos(beta) = r . n.
//! - eps, rho from the Fresnel equations with the sea-water index at the band centre
//!   (`optics`); R_sea the band radiance of the surface at T_b(0) + dT (Eq. (3.17), integrated).
//! - Sun (Eqs. (3.18)-(3.19)): (r_sun / D_sun)^2 L(T_sun) phi(Delta theta_s), phi Henyey-Greenstein,
//!   Delta theta_s the angle between i and the direction to the sun.
//! - Sky (Eq. (3.20)): a black body at T_sky(gamma), gamma the zenith angle of i (the downwelling
//!   term the spec writes R_ss,down); below the horizon, T_horizon.
//! - Atmospheric transmission and path radiance (the other terms of Eq. (3.4)) are 1 and 0, as in
//!   the spec; [`RadianceTerms`] keeps them apart so they can be added.

use crate::optics::{reflectance_and_emissivity, seawater_index};
use crate::planck::band_radiance;
use serde::Serialize;
use std::f64::consts::PI;
use wakelab_core::WakelabConfig;

/// Radius of the sun and mean Sun-Earth distance (m).
pub const SUN_RADIUS: f64 = 6.957e8;
pub const SUN_DISTANCE: f64 = 1.495_978_707e11;

/// The two infrared bands (erratum 13).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum IrBand {
    /// Mid-wave, 3.7-4.1 um.
    Mwir,
    /// Long-wave, 10.5-11.5 um (the spec's 11 um).
    Lwir,
}

impl IrBand {
    pub const ALL: [IrBand; 2] = [IrBand::Mwir, IrBand::Lwir];

    /// Band edges (um).
    pub fn range(&self) -> (f64, f64) {
        match self {
            IrBand::Mwir => (3.7, 4.1),
            IrBand::Lwir => (10.5, 11.5),
        }
    }

    pub fn centre(&self) -> f64 {
        let (a, b) = self.range();
        0.5 * (a + b)
    }

    pub fn name(&self) -> &'static str {
        match self {
            IrBand::Mwir => "MWIR",
            IrBand::Lwir => "LWIR",
        }
    }
}

/// Henyey-Greenstein phase function (1/sr), Eq. (3.19).
pub fn henyey_greenstein(cos_angle: f64, g: f64) -> f64 {
    let d = 1.0 + g * g - 2.0 * g * cos_angle;
    (1.0 - g * g) / (4.0 * PI * d * d.sqrt())
}

/// Sky brightness temperature at zenith angle `gamma` (rad), Eq. (3.20).
pub fn sky_temperature(gamma: f64, zenith: f64, horizon: f64) -> f64 {
    let g = gamma.clamp(0.0, PI / 2.0);
    zenith + (horizon - zenith) * (2.0 * g / PI).powf(2.5)
}

/// The parts of Eq. (3.4) for one facet (W m^-2 sr^-1).
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct RadianceTerms {
    pub emissivity: f64,
    pub reflectance: f64,
    pub sea: f64,
    pub sun: f64,
    pub sky: f64,
    /// Transmission of the path from the surface to the sensor (1 in the spec's Eq. (3.5)).
    pub transmission: f64,
    /// Upwelling atmospheric and scattered solar path radiance (0 in Eq. (3.5)).
    pub path: f64,
}

impl RadianceTerms {
    /// R = tau (eps R_sea + rho (R_sun + R_sky)) + R_path, Eq. (3.4).
    pub fn total(&self) -> f64 {
        self.transmission * (self.emissivity * self.sea + self.reflectance * (self.sun + self.sky)) + self.path
    }
}

/// Fixed inputs of one band's IR image.
pub struct IrView {
    pub band: IrBand,
    /// Unit vector from the surface to the sensor, heading frame (x, y, z up).
    pub to_sensor: [f64; 3],
    /// Unit vector from the surface to the sun.
    pub to_sun: [f64; 3],
    /// Sun band radiance times (r_sun / D_sun)^2 (Eq. (3.18) without the phase function).
    pub sun_radiance: f64,
    pub asymmetry: f64,
    pub sky: (f64, f64),
    pub index: num_complex::Complex64,
}

impl IrView {
    pub fn new(config: &WakelabConfig, band: IrBand) -> Self {
        let (lo, hi) = band.range();
        let theta = config.platform.incidence.to_radians();
        let look = config.platform.look_direction.to_radians();
        let ir = &config.ir;
        let (el, az) = (ir.sun_elevation.to_radians(), ir.sun_azimuth.to_radians());
        let env = &config.environment;
        Self {
            band,
            // the sensor looks along `look`, so it lies in the opposite direction, theta from zenith
            to_sensor: [-theta.sin() * look.cos(), -theta.sin() * look.sin(), theta.cos()],
            to_sun: [el.cos() * az.cos(), el.cos() * az.sin(), el.sin()],
            sun_radiance: (SUN_RADIUS / SUN_DISTANCE).powi(2) * band_radiance(lo, hi, ir.sun_temperature),
            asymmetry: ir.sun_asymmetry,
            sky: (ir.sky_zenith_temperature, ir.sky_horizon_temperature),
            index: seawater_index(band.centre(), env.salinity.at_depth(0.0), env.temperature.at_depth(0.0)),
        }
    }

    /// Eq. (3.5) for a facet of heading-frame slopes (dz/dx, dz/dy) at temperature `t_kelvin`.
    pub fn facet(&self, slope_x: f64, slope_y: f64, t_kelvin: f64) -> RadianceTerms {
        let (lo, hi) = self.band.range();
        self.facet_with(
            slope_x,
            slope_y,
            band_radiance(lo, hi, t_kelvin),
            |cos_beta| reflectance_and_emissivity(self.index, cos_beta.acos()).0,
            |cos_gamma| band_radiance(lo, hi, sky_temperature(cos_gamma.acos(), self.sky.0, self.sky.1)),
        )
    }

    /// [`Self::facet`] with the sea's radiance given and the reflectance (of the cosine of the
    /// local incidence beta) and sky radiance (of the cosine of the zenith angle gamma it comes
    /// from) supplied by the caller.
    pub fn facet_with(
        &self,
        slope_x: f64,
        slope_y: f64,
        sea: f64,
        reflectance: impl Fn(f64) -> f64,
        sky: impl Fn(f64) -> f64,
    ) -> RadianceTerms {
        self.terms(&self.geometry(slope_x, slope_y), sea, reflectance, sky)
    }

    /// Where a facet of heading-frame slopes (dz/dx, dz/dy) faces: the parts of Eq. (3.5) that
    /// no band changes (the view's sensor and sun directions and the phase function's asymmetry
    /// are the same in every band).
    pub fn geometry(&self, slope_x: f64, slope_y: f64) -> FacetGeometry {
        let norm = (slope_x * slope_x + slope_y * slope_y + 1.0).sqrt();
        let n = [-slope_x / norm, -slope_y / norm, 1.0 / norm];
        let r = self.to_sensor;
        let cos_beta = (n[0] * r[0] + n[1] * r[1] + n[2] * r[2]).clamp(-1.0, 1.0);
        // direction the reflected light comes from, Eq. (3.6)
        let i: [f64; 3] = std::array::from_fn(|k| 2.0 * n[k] * cos_beta - r[k]);
        let s = self.to_sun;
        let cos_sun = (i[0] * s[0] + i[1] * s[1] + i[2] * s[2]).clamp(-1.0, 1.0);
        FacetGeometry {
            cos_incidence: cos_beta,
            cos_sky_zenith: i[2].clamp(-1.0, 1.0),
            sun_phase: if s[2] > 0.0 && i[2] > 0.0 {
                henyey_greenstein(cos_sun, self.asymmetry)
            } else {
                0.0
            },
        }
    }

    /// Eq. (3.5)'s terms for a facet of geometry `g` in this band.
    pub fn terms(
        &self,
        g: &FacetGeometry,
        sea: f64,
        reflectance: impl Fn(f64) -> f64,
        sky: impl Fn(f64) -> f64,
    ) -> RadianceTerms {
        if g.cos_incidence <= 0.0 {
            // a facet turned away from the sensor shows nothing of itself
            return RadianceTerms {
                emissivity: 0.0,
                reflectance: 0.0,
                sea: 0.0,
                sun: 0.0,
                sky: 0.0,
                transmission: 1.0,
                path: 0.0,
            };
        }
        let rho = reflectance(g.cos_incidence);
        RadianceTerms {
            emissivity: 1.0 - rho,
            reflectance: rho,
            sea,
            sun: self.sun_radiance * g.sun_phase,
            sky: sky(g.cos_sky_zenith),
            transmission: 1.0,
            path: 0.0,
        }
    }
}

/// The band-free geometry of a facet (see [`IrView::geometry`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FacetGeometry {
    /// cos of the local incidence beta.
    pub cos_incidence: f64,
    /// cos of the zenith angle the reflected sky light comes from.
    pub cos_sky_zenith: f64,
    /// The sun's Henyey-Greenstein phase towards the sensor (1/sr), 0 when the sun or the
    /// reflected direction is below the horizon.
    pub sun_phase: f64,
}

impl IrView {
    /// The reflectance over the cosine of the local incidence and the sky's band radiance over
    /// the cosine of its zenith angle, tabulated at 4096 points in [0, 1] (values beyond an end
    /// are the end's).
    pub(crate) fn tables(&self) -> (SmoothTable, SmoothTable) {
        let (lo, hi) = self.band.range();
        (
            SmoothTable::new(0.0, 1.0, 4096, |c| reflectance_and_emissivity(self.index, c.acos()).0),
            // light from below the horizon is the horizon's (Eq. (3.20) holds the zenith angle at
            // 90 degrees): the table ends there, at its kink
            SmoothTable::new(0.0, 1.0, 4096, |c| {
                band_radiance(lo, hi, sky_temperature(c.acos(), self.sky.0, self.sky.1))
            }),
        )
    }
}

/// A smooth function on [lo, hi] tabulated at `n` points, linear in between.
pub(crate) struct SmoothTable {
    lo: f64,
    per_step: f64,
    values: Vec<f64>,
}

impl SmoothTable {
    fn new(lo: f64, hi: f64, n: usize, f: impl Fn(f64) -> f64) -> Self {
        Self {
            lo,
            per_step: (n - 1) as f64 / (hi - lo),
            values: (0..n).map(|i| f(lo + (hi - lo) * i as f64 / (n - 1) as f64)).collect(),
        }
    }

    pub(crate) fn at(&self, x: f64) -> f64 {
        let last = (self.values.len() - 1) as f64;
        let x = ((x - self.lo) * self.per_step).clamp(0.0, last);
        let i = (x as usize).min(self.values.len() - 2);
        let f = x - i as f64;
        self.values[i] * (1.0 - f) + self.values[i + 1] * f
    }

    /// The x at which an increasing table takes the value y (linear in between), if y is
    /// inside the table: the brightness temperature of a radiance.
    pub(crate) fn inverse(&self, y: f64) -> Option<f64> {
        let v = &self.values;
        if !(v[0]..=v[v.len() - 1]).contains(&y) {
            return None;
        }
        let i = v.partition_point(|&x| x < y).clamp(1, v.len() - 1);
        let f = (y - v[i - 1]) / (v[i] - v[i - 1]);
        Some(self.lo + (i as f64 - 1.0 + f) / self.per_step)
    }
}

/// Band radiance over temperature in [t0, t1] (K), tabulated in 0.01 K steps, linear in
/// between.
pub(crate) fn radiance_table(band: IrBand, t0: f64, t1: f64) -> SmoothTable {
    let step = 0.01;
    let (lo, hi) = band.range();
    let n = ((t1 - t0) / step).ceil() as usize + 2;
    SmoothTable::new(t0, t0 + (n - 1) as f64 * step, n, |t| band_radiance(lo, hi, t))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::planck::brightness_temperature;

    /// The radiance table read backwards gives the brightness temperature that inverting the
    /// Planck band integral by bisection gives, within 1e-5 K, and nothing outside its span.
    #[test]
    fn the_radiance_table_inverts_to_the_brightness_temperature() {
        for band in IrBand::ALL {
            let (lo, hi) = band.range();
            let table = radiance_table(band, 285.0, 295.0);
            for t in [285.3, 288.0, 290.123, 294.9] {
                let r = band_radiance(lo, hi, t);
                let got = table.inverse(r).expect("inside");
                assert!(
                    (got - brightness_temperature(lo, hi, r)).abs() < 1e-5,
                    "{band:?} {t}: {got}"
                );
            }
            assert_eq!(table.inverse(band_radiance(lo, hi, 280.0)), None);
        }
    }

    /// The tables the image uses give every facet's radiance within 1e-6 of the exact terms,
    /// over slopes up to 1 in every direction and both bands.
    #[test]
    fn tabulated_facets_match_the_exact_ones() {
        let config = WakelabConfig::from_toml_str("[ir]\nsun_elevation = 35.0\n", "test").unwrap();
        for band in IrBand::ALL {
            let view = IrView::new(&config, band);
            let (reflectance, sky) = view.tables();
            let (lo, hi) = band.range();
            let sea = band_radiance(lo, hi, 290.0);
            let mut worst = 0.0f64;
            for i in 0..41 {
                for j in 0..41 {
                    let (sx, sy) = (-1.0 + i as f64 / 20.0, -1.0 + j as f64 / 20.0);
                    let exact = view.facet(sx, sy, 290.0).total();
                    let tabulated = view
                        .facet_with(sx, sy, sea, |c| reflectance.at(c), |c| sky.at(c))
                        .total();
                    if exact > 0.0 {
                        worst = worst.max((tabulated / exact - 1.0).abs());
                    }
                }
            }
            assert!(worst < 1e-6, "{band:?}: {worst:e}");
        }
    }

    #[test]
    fn henyey_greenstein_is_normalised_and_sky_profile_has_its_ends() {
        // integral over the sphere of phi = 1
        let g = 0.8;
        let n = 20_000;
        let sum: f64 = (0..n)
            .map(|i| {
                let th = (i as f64 + 0.5) * PI / n as f64;
                henyey_greenstein(th.cos(), g) * 2.0 * PI * th.sin() * PI / n as f64
            })
            .sum();
        assert!((sum - 1.0).abs() < 1e-6, "{sum}");
        assert_eq!(sky_temperature(0.0, 233.15, 293.15), 233.15);
        assert!((sky_temperature(PI / 2.0, 233.15, 293.15) - 293.15).abs() < 1e-12);
        // half the contrast about 15 degrees above the horizon (Levesque & St-Germain)
        let half = sky_temperature(75f64.to_radians(), 233.15, 293.15);
        assert!((half - 263.15).abs() < 10.0, "{half}");
    }

    /// The spec's check of the sky model (Eq. (3.21), Fig. 3.16): Saunders' (1968) fit of measured
    /// sky radiance over 8.5-12.5 um, N = A - B exp(-C (z - 1)) with A = 3540, B = 2570
    /// uW cm^-2 sr^-1, C = 0.285, z = sqrt(4.9e5 cos^2 + 1401) - 700 cos, against the Planck
    /// radiance of Eq. (3.20) with a 20 C horizon and a -40 C zenith.
    #[test]
    fn sky_model_follows_saunders_measurements() {
        for deg in [0.0f64, 30.0, 50.0, 70.0, 80.0] {
            let cos = deg.to_radians().cos();
            let z = (4.9e5 * cos * cos + 1401.0).sqrt() - 700.0 * cos;
            let saunders = (3540.0 - 2570.0 * (-0.285 * (z - 1.0)).exp()) * 1e-6 * 1e4; // W m^-2 sr^-1
            let model = band_radiance(8.5, 12.5, sky_temperature(deg.to_radians(), 233.15, 293.15));
            eprintln!("sky at {deg} deg: Saunders {saunders:.2}, Planck model {model:.2} W m^-2 sr^-1");
            assert!((model / saunders - 1.0).abs() < 0.1, "{deg} deg: {model} vs {saunders}");
        }
    }
}

//! Normalised radar cross section of the sea, spec Eqs. (3.1)-(3.3), with the non-Bragg
//! scattering of breaking waves the spec leaves out (erratum 16): the semi-empirical model of
//! Kudryavtsev, Hauser, Caudal & Chapron (2003, J. Geophys. Res. 108(C3), 8054; "KHCC03"):
//!   sigma0 = (sigma_B + sigma_S) (1 - q) + q sigma_wb.
//!
//! - Bragg, Eq. (3.1) with erratum 15: first-order small-perturbation theory for a facet tilted
//!   by psi towards the radar in the plane of incidence and delta across it (Valenzuela 1978,
//!   Boundary-Layer Meteorol. 13, 61-85, Eqs. 23-26):
//!   sigma_B = 8 pi k0^4 cos^4(theta_i) |G|^2 [F(k_B) + F(-k_B)], k_B = 2 k0 sin(theta_i),
//!   F normalised so that its integral over the whole wavenumber plane is the elevation
//!   variance: for a centro-symmetric F this is 16 pi k0^4 cos^4 |G|^2 F(k_B).
//!   cos(theta_i) = cos(theta - psi) cos(delta), and for VV
//!   G = (sin(theta - psi) cos(delta) / sin(theta_i))^2 g_VV(theta_i) + (sin(delta) / sin(theta_i))^2 g_HH(theta_i)
//!   (HH with g_VV and g_HH exchanged), g_HH = (eps - 1) / (cos + sqrt(eps - sin^2))^2,
//!   g_VV = (eps - 1)(eps (1 + sin^2) - sin^2) / (eps cos + sqrt(eps - sin^2))^2. F at the
//!   Bragg scale is the background spectrum's (Elfouhaily et al. 1997 by default): KHCC03's own
//!   short-wave balance ([`ShortWaves`]) was tried as the Bragg level, with its breaking source
//!   taken from that spectrum (cross-wind C-band sigma0 3-5 dB below CMOD5.N) and with the
//!   constants and self-consistent source of Kudryavtsev, Chapron & Makin (2014): within
//!   1.5 dB of CMOD5.N at 25-50 degrees and 10-15 m/s, but 3-13 dB too dark cross-wind at
//!   3-7 m/s, where only breaking feeds the cross-wind waves. So it sets only the growth and
//!   relaxation of the Bragg waves. Elfouhaily's spreading at the Bragg scale is strengthened
//!   by a fitted factor (`SHORT_WAVE_SPREADING_GAIN`), so the up-/cross-wind ratio follows
//!   CMOD5.N's at 30-45 degrees (see the tests), and below k ~ 100 rad/m the level is revised
//!   as Yurovskaya et al. (2013) measured it: decimetre waves almost isotropic and weakly wind
//!   dependent ([`wakelab_surface::bragg_scale`], two of its constants calibrated on CMOD5.N).
//! - Two scales: the tilts are averaged over a Gaussian slope distribution (erratum 6) of the
//!   waves between the image's resolved scale and the cut k_d = k_B / 4 (KHCC03's d = 1/4); a
//!   facet tilted so far that its own Bragg wavenumber falls below k_d scatters no Bragg power
//!   (its resonant waves belong to the tilting scales). The spectrum sets the tilts' total
//!   variance, Cox & Munk (1954) their up-/cross-wind ratio ([`crate::slopes`]). The resolved
//!   slopes tilt each pixel through Eq. (3.3).
//! - Specular, Eq. (3.2) with erratum 4: sigma_S = pi sec^4(theta) |R_e|^2 p(tan theta, 0)
//!   (slope along the look, none across), p the density of the slopes of the waves longer than
//!   four radar wavelengths (k < k0 / 4, KAJC05's d = 1/4: Kudryavtsev, Akimov, Johannessen &
//!   Chapron 2005, J. Geophys. Res. 110, C07016, Eq. 5): their variance from the spectrum, the
//!   up-/cross-wind ratio and the peakedness of Cox & Munk's (1954) Gram-Charlier density.
//!   |R_e|^2 = |R(0)|^2 exp(-4 k0^2 h^2), R(0) = (1 - sqrt(eps)) / (1 + sqrt(eps)): the
//!   reflectivity of a facet roughened by the shorter waves of variance h^2 (the effective
//!   reflection coefficient of Valenzuela 1978 and KAJC05 Eq. 5).
//! - Breaking (KHCC03 Eqs. 56-60): a fraction q of the surface is covered by breaking zones
//!   that scatter like very rough facets, the same for VV and HH:
//!   sigma_wb = sigma_wb0(theta) (1 + M_wb theta_wb A_wb),
//!   sigma_wb0 = [sec^4(theta) exp(-tan^2(theta) / s_wb^2) + eps_wb] / s_wb^2, s_wb^2 = 0.19,
//!   eps_wb = 0.005, M_wb = d ln sigma_wb0 / d theta, theta_wb = 0.05 the zones' mean tilt
//!   and A_wb the mean cosine between the breakers' direction and the look: the up-/down-wind
//!   asymmetry. q = c_q int int Lambda(k, phi) dk dphi over the breaking waves k < k_wb = k0 / 10,
//!   with the length of breaking crests Lambda = beta_v B / (2 alpha k) of the equilibrium
//!   range (KHCC03 Eq. 28 with (B / alpha)^n = beta_v), c_q = 10.5, alpha = 5.04e-3.

use crate::breaking::BREAKING_TILT;
pub use crate::breaking::{breaking_zone_nrcs, breaking_zones, BreakingZones};
use crate::slopes::{look_frame_variances, wind_frame_variances, SlopeDensity};
use num_complex::Complex64;
use std::f64::consts::PI;
use wakelab_core::config::Polarisation;
use wakelab_surface::short_waves::ShortWaves;
use wakelab_surface::spectrum::SeaSpectrum;

/// The waves that reflect specularly are longer than 1 / SPECULAR_CUT radar wavelengths
/// (k < k0 / 4: KAJC05's d = 1/4, Kudryavtsev, Akimov, Johannessen & Chapron 2005, Eq. 5).
const SPECULAR_CUT: f64 = 0.25;

/// First-order Bragg coefficients (g_HH, g_VV) at incidence `theta` (rad), Eq. (3.1).
pub fn bragg_coefficients(theta: f64, eps: Complex64) -> (Complex64, Complex64) {
    let (s, c) = theta.sin_cos();
    let root = (eps - s * s).sqrt();
    let hh = (eps - 1.0) / (c + root).powi(2);
    let vv = (eps - 1.0) * (eps * (1.0 + s * s) - s * s) / (eps * c + root).powi(2);
    (hh, vv)
}

/// Squared modulus of the normal-incidence Fresnel coefficient |R(0)|^2 (Eq. (3.2), erratum 4).
pub fn normal_reflectivity(eps: Complex64) -> f64 {
    let r = eps.sqrt();
    ((1.0 - r) / (1.0 + r)).norm_sqr()
}

/// The sea as a radar sees it in one band, look direction and polarisation.
pub struct RadarSea<'a> {
    pub spectrum: &'a SeaSpectrum,
    pub short_waves: &'a ShortWaves,
    /// Radar wavenumber k0 (rad/m).
    pub k0: f64,
    pub permittivity: Complex64,
    pub polarisation: Polarisation,
    /// Horizontal look direction (radians from the heading): the Bragg waves run along it.
    pub look: f64,
    /// The two-scale cut k_d (rad/m): waves below it tilt, waves above it scatter.
    pub cut: f64,
    /// Variances of the unresolved tilting slopes along and across the look direction.
    pub tilt_variance: (f64, f64),
    /// The slopes of the waves longer than four radar wavelengths, which reflect specularly.
    pub specular_slopes: SlopeDensity,
    /// |R(0)|^2 exp(-4 k0^2 h^2): the Fresnel reflectivity of those facets, lowered by the
    /// roughness h of the shorter waves on them.
    pub specular_reflectivity: f64,
    pub breaking: BreakingZones,
}

/// The parts of a sea's NRCS (linear).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sigma0Parts {
    pub bragg: f64,
    pub specular: f64,
    pub breaking: f64,
    /// The breakers' surface fraction q.
    pub fraction: f64,
}

impl Sigma0Parts {
    /// (sigma_B + sigma_S)(1 - q) + q sigma_wb (KHCC03 Eq. 1), with the Bragg waves scaled by
    /// `bragg_ratio` (N/N0) and the breakers by `breaking_ratio`.
    pub fn total_modulated(&self, bragg_ratio: f64, breaking_ratio: f64) -> f64 {
        let q = (self.fraction * breaking_ratio).min(1.0);
        (bragg_ratio * self.bragg + self.specular) * (1.0 - q) + q * self.breaking
    }

    pub fn total(&self) -> f64 {
        self.total_modulated(1.0, 1.0)
    }
}

impl<'a> RadarSea<'a> {
    /// Set up for a band of wavenumber `k0` looking along `look`, imaged at pixel spacing `dx`.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        spectrum: &'a SeaSpectrum,
        short_waves: &'a ShortWaves,
        k0: f64,
        permittivity: Complex64,
        polarisation: Polarisation,
        look: f64,
        incidence: f64,
        dx: f64,
    ) -> Self {
        let cut = 0.5 * k0 * incidence.sin();
        let resolved = PI / dx;
        let (wind, from_wind) = (spectrum.wind_speed, look - spectrum.wind_direction);
        let tilts = spectrum.slope_variances(look, resolved.min(cut), cut);
        let long = spectrum.slope_variances(look, 1e-3, SPECULAR_CUT * k0);
        let (up_variance, cross_variance) = wind_frame_variances(long.0 + long.1, wind);
        let roughness = spectrum.elevation_variance(SPECULAR_CUT * k0, 4000.0);
        Self {
            spectrum,
            short_waves,
            k0,
            permittivity,
            polarisation,
            look,
            cut,
            tilt_variance: look_frame_variances(tilts, wind, from_wind),
            specular_slopes: SlopeDensity {
                up_variance,
                cross_variance,
            },
            specular_reflectivity: normal_reflectivity(permittivity) * (-4.0 * k0 * k0 * roughness).exp(),
            breaking: breaking_zones(spectrum, short_waves, k0, look),
        }
    }

    /// Bragg NRCS of a facet tilted by psi (towards the radar) and delta (across), linear,
    /// Eq. (3.1) for one facet (Valenzuela 1978); zero where the facet's own Bragg wavenumber
    /// falls below the two-scale cut.
    pub fn tilted_bragg(&self, theta: f64, psi: f64, delta: f64) -> f64 {
        let cos_i = ((theta - psi).cos() * delta.cos()).clamp(-1.0, 1.0);
        if cos_i <= 0.0 {
            return 0.0;
        }
        let theta_i = cos_i.acos();
        let sin_i = theta_i.sin().max(1e-9);
        let kb = 2.0 * self.k0 * sin_i;
        if kb < self.cut {
            return 0.0;
        }
        let (ghh, gvv) = bragg_coefficients(theta_i, self.permittivity);
        let a = ((theta - psi).sin() * delta.cos() / sin_i).powi(2);
        let b = (delta.sin() / sin_i).powi(2);
        let g = match self.polarisation {
            Polarisation::Vv => gvv * a + ghh * b,
            Polarisation::Hh => ghh * a + gvv * b,
        };
        // Bragg waves along the look direction, towards (-) and away from (+) the radar
        let (c, s) = (self.look.cos(), self.look.sin());
        let density = self.spectrum.bragg_density(-kb * c, -kb * s) + self.spectrum.bragg_density(kb * c, kb * s);
        8.0 * PI * self.k0.powi(4) * cos_i.powi(4) * g.norm_sqr() * density
    }

    /// Two-scale Bragg NRCS (Eq. (3.1)): the tilted Bragg NRCS averaged over the unresolved slopes.
    pub fn bragg(&self, theta: f64) -> f64 {
        let (vr, va) = self.tilt_variance;
        if vr <= 0.0 && va <= 0.0 {
            return self.tilted_bragg(theta, 0.0, 0.0);
        }
        // midpoint rule over +-4 standard deviations of each slope
        let n = 24;
        let (sr, sa) = (vr.sqrt(), va.sqrt());
        let mut sum = 0.0;
        let mut weight = 0.0;
        for i in 0..n {
            let xr = -4.0 + 8.0 * (i as f64 + 0.5) / n as f64;
            for j in 0..n {
                let xa = -4.0 + 8.0 * (j as f64 + 0.5) / n as f64;
                let w = (-0.5 * (xr * xr + xa * xa)).exp();
                sum += w * self.tilted_bragg(theta, (xr * sr).atan(), (xa * sa).atan());
                weight += w;
            }
        }
        sum / weight
    }

    /// Specular NRCS (Eq. (3.2) with erratum 4): the facets whose normal points at the radar
    /// have slope tan(theta) along the look, which lies `look - wind` from the wind.
    pub fn specular(&self, theta: f64) -> f64 {
        let t = theta.tan();
        let from_wind = self.look - self.spectrum.wind_direction;
        let p = self.specular_slopes.at(t * from_wind.cos(), t * from_wind.sin());
        PI / theta.cos().powi(4) * self.specular_reflectivity * p
    }

    /// NRCS of the breaking zones, sigma_wb0 (1 + M_wb theta_wb A_wb) (KHCC03 Eq. 60).
    pub fn breaking(&self, theta: f64) -> f64 {
        let h = 1e-4;
        let m = ((breaking_zone_nrcs(theta + h) / breaking_zone_nrcs(theta - h)).ln()) / (2.0 * h);
        breaking_zone_nrcs(theta) * (1.0 + m * BREAKING_TILT * self.breaking.asymmetry).max(0.0)
    }

    /// Every part at incidence `theta`.
    pub fn parts(&self, theta: f64) -> Sigma0Parts {
        Sigma0Parts {
            bragg: self.bragg(theta),
            specular: self.specular(theta),
            breaking: self.breaking(theta),
            fraction: self.breaking.fraction,
        }
    }
}

/// Linear NRCS to dB.
pub fn to_db(sigma: f64) -> f64 {
    10.0 * sigma.max(1e-30).log10()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::permittivity::seawater_permittivity;
    use crate::sigma0_report::{sigma0_of_sea, Sigma0Report};
    use wakelab_core::units::RadarBand;
    use wakelab_core::WakelabConfig;

    fn sea(wind: f64) -> SeaSpectrum {
        SeaSpectrum::wind_sea(&WakelabConfig::default().sea, wind, 0.0, 9.81)
    }

    fn db(wind: f64, band: RadarBand, pol: Polarisation, inc: f64, look_deg: f64) -> f64 {
        let eps = seawater_permittivity(band.frequency(), 15.0, 35.0);
        sigma0_of_sea(&sea(wind), band, eps, pol, look_deg.to_radians(), inc, 10.0).sigma0_db
    }

    #[test]
    fn sigma0_falls_with_incidence_vv_exceeds_hh_and_rises_with_wind() {
        for band in RadarBand::ALL {
            let mut last = f64::INFINITY;
            for inc in [25.0, 30.0, 35.0, 40.0, 45.0, 50.0] {
                let vv = db(8.0, band, Polarisation::Vv, inc, 90.0);
                let hh = db(8.0, band, Polarisation::Hh, inc, 90.0);
                assert!(vv < last, "{band:?} {inc}: {vv} dB not below {last}");
                assert!(vv >= hh, "{band:?} {inc}: VV {vv} < HH {hh}");
                last = vv;
            }
            // from 5 m/s: below it the Elfouhaily long-wave tail makes S-band Bragg waves fall
            // with wind (a quirk of that spectrum, not of the scattering)
            let mut last = f64::NEG_INFINITY;
            for wind in [5.0, 8.0, 12.0, 16.0] {
                let v = db(wind, band, Polarisation::Vv, 35.0, 90.0);
                assert!(v > last, "{band:?} wind {wind}: {v} dB not above {last}");
                last = v;
            }
        }
    }

    /// The high-permittivity limits of the Bragg coefficients (Valenzuela 1978): g_HH -> 1 and
    /// g_VV -> (1 + sin^2) / cos^2 as eps -> infinity; and g_HH = g_VV at normal incidence.
    #[test]
    fn bragg_coefficients_reach_their_perfect_conductor_limits() {
        let eps = Complex64::new(1e12, 1e10);
        for inc in [10.0f64, 30.0, 50.0] {
            let t = inc.to_radians();
            let (hh, vv) = bragg_coefficients(t, eps);
            assert!((hh - 1.0).norm() < 1e-5, "{inc}: g_HH {hh}");
            let limit = (1.0 + t.sin().powi(2)) / t.cos().powi(2);
            assert!((vv - limit).norm() < 1e-5 * limit, "{inc}: g_VV {vv} vs {limit}");
        }
        let sea = Complex64::new(60.0, 35.0);
        let (hh, vv) = bragg_coefficients(0.0, sea);
        assert!((hh - vv).norm() < 1e-12 * hh.norm());
    }

    /// A perfectly conducting flat surface (eps -> infinity, no tilt): g_HH -> 1 and
    /// g_VV -> (1 + sin^2) / cos^2, so sigma_HH = 16 pi k0^4 cos^4(theta) F(k_B) for the
    /// centro-symmetric F of a wind sea (Valenzuela 1978; erratum 15).
    #[test]
    fn perfect_conductor_gives_the_closed_form() {
        let spectrum = sea(8.0);
        let short = ShortWaves::new(&spectrum);
        let eps = Complex64::new(1e14, 0.0);
        let k0 = RadarBand::C.wavenumber();
        for inc in [25.0f64, 35.0, 45.0] {
            let theta = inc.to_radians();
            for (pol, g) in [
                (Polarisation::Hh, 1.0),
                (Polarisation::Vv, (1.0 + theta.sin().powi(2)) / theta.cos().powi(2)),
            ] {
                let mut radar = RadarSea::new(&spectrum, &short, k0, eps, pol, 0.3, theta, 10.0);
                radar.tilt_variance = (0.0, 0.0);
                let kb = 2.0 * k0 * theta.sin();
                let f = spectrum.bragg_density(kb * 0.3f64.cos(), kb * 0.3f64.sin());
                let closed = 16.0 * PI * k0.powi(4) * theta.cos().powi(4) * g * g * f;
                let got = radar.bragg(theta);
                assert!((got / closed - 1.0).abs() < 1e-6, "{pol:?} {inc}: {got} vs {closed}");
            }
        }
    }

    /// The specular term at normal incidence is the geometric-optics closed form
    /// |R(0)|^2 exp(-4 k0^2 h^2) (1 + c40 / 8 + c22 / 4 + c04 / 8) / (2 s_u s_c) (Eq. (3.2) with
    /// erratum 4; the Gram-Charlier factor of Cox & Munk 1954 at zero slope), h^2 the variance
    /// of the waves shorter than four radar wavelengths.
    #[test]
    fn specular_at_normal_incidence_is_the_closed_form() {
        let spectrum = sea(8.0);
        let short = ShortWaves::new(&spectrum);
        let eps = crate::permittivity::seawater_permittivity(5.3e9, 15.0, 35.0);
        let k0 = 111.0;
        let radar = RadarSea::new(&spectrum, &short, k0, eps, Polarisation::Vv, 0.0, 0.6, 10.0);
        let slopes = radar.specular_slopes;
        let h2 = spectrum.elevation_variance(k0 / 4.0, 4000.0);
        let factor = 1.0 + 0.40 / 8.0 + 0.12 / 4.0 + 0.23 / 8.0;
        let closed = normal_reflectivity(eps) * (-4.0 * k0 * k0 * h2).exp() * factor
            / (2.0 * (slopes.up_variance * slopes.cross_variance).sqrt());
        assert!((radar.specular(1e-9) / closed - 1.0).abs() < 1e-9);
        // and the slopes are those of the waves longer than four radar wavelengths
        let (along, across) = spectrum.slope_variances(0.0, 1e-3, k0 / 4.0);
        assert!(((slopes.up_variance + slopes.cross_variance) / (along + across) - 1.0).abs() < 1e-12);
    }

    /// C-band VV against CMOD5.N (Hersbach 2010) over 20-50 degrees, 3-15 m/s, up-, cross-
    /// and down-wind, for CMOD5.N's 25 km cell (no wave resolved: every slope tilts): the
    /// issue's 2 dB everywhere. Measured worst (see the printout): 1.9 dB, at 50 degrees and
    /// 15 m/s cross-wind, a cell the decimetre revision does not touch (k_B = 170 rad/m).
    /// Not an independent check: two constants of the decimetre revision (w0, U_ref in
    /// `wakelab_surface::bragg_scale`) were chosen on this table, and the spreading gain on the
    /// ratio below. What is independent is its shape, from Yurovskaya et al. (2013): with the
    /// isotropy alone (w0 = 1) the worst is 2.4 dB, and without the revision 3.2 dB (cross-wind,
    /// 25 degrees, 5-7 m/s). The up-/cross-wind ratio is CMOD5.N's within 1.5 dB at 30-45
    /// degrees and every wind (measured 1.4).
    #[test]
    fn c_band_vv_is_near_cmod5n() {
        // incidence, limit up-/down-wind, limit cross-wind (dB)
        const LIMITS: [(f64, f64, f64); 7] = [
            (20.0, 2.0, 2.0),
            (25.0, 2.0, 2.0),
            (30.0, 2.0, 2.0),
            (35.0, 2.0, 2.0),
            (40.0, 2.0, 2.0),
            (45.0, 2.0, 2.0),
            (50.0, 2.0, 2.0),
        ];
        let eps = seawater_permittivity(RadarBand::C.frequency(), 15.0, 35.0);
        let mut worst_ratio = 0.0f64;
        let mut worst = [(0.0f64, 0.0f64); 7];
        for wind in [3.0, 5.0, 7.0, 10.0, 12.0, 15.0] {
            let spectrum = sea(wind);
            for (i, &(inc, along_limit, cross_limit)) in LIMITS.iter().enumerate() {
                // wind towards heading 0: looking along 180 is looking up-wind
                let at = |look: f64| {
                    sigma0_of_sea(
                        &spectrum,
                        RadarBand::C,
                        eps,
                        Polarisation::Vv,
                        look,
                        inc,
                        crate::gmf::CELL_SIZE,
                    )
                };
                let (up, cross, down) = (at(PI), at(PI / 2.0), at(0.0));
                let d = |r: &Sigma0Report| r.sigma0_db - r.cmod5n_db.expect("C band");
                let along = d(&up).abs().max(d(&down).abs());
                assert!(along < along_limit, "{wind} {inc}: {} {}", d(&up), d(&down));
                assert!(d(&cross).abs() < cross_limit, "{wind} {inc} cross: {}", d(&cross));
                worst[i] = (worst[i].0.max(along), worst[i].1.max(d(&cross).abs()));
                if (30.0..=45.0).contains(&inc) {
                    let ratio = (up.sigma0_db - cross.sigma0_db) - (up.cmod5n_db.unwrap() - cross.cmod5n_db.unwrap());
                    assert!(ratio.abs() < 1.5, "{wind} {inc} ratio {ratio}");
                    worst_ratio = worst_ratio.max(ratio.abs());
                }
            }
        }
        for (&(inc, ..), (along, cross)) in LIMITS.iter().zip(worst) {
            eprintln!("{inc} deg: worst |wakelab - CMOD5.N| up/down {along:.2} dB, cross {cross:.2} dB");
        }
        eprintln!("worst up/cross ratio difference at 30-45 deg: {worst_ratio:.2} dB");
    }

    /// Up-wind above down-wind (the breakers' asymmetry, A_wb) at 30-50 degrees, as every
    /// scatterometer observes.
    #[test]
    fn up_wind_exceeds_down_wind() {
        let eps = seawater_permittivity(RadarBand::C.frequency(), 15.0, 35.0);
        for wind in [7.0, 12.0] {
            let spectrum = sea(wind);
            for inc in [30.0, 40.0, 50.0] {
                let at =
                    |look: f64| sigma0_of_sea(&spectrum, RadarBand::C, eps, Polarisation::Vv, look, inc, 10.0).sigma0;
                assert!(at(PI) > at(0.0), "{wind} {inc}");
            }
        }
    }
}

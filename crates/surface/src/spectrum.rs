//! Background wave spectra (spec 2.3): Pierson-Moskowitz (Eq. (2.71)) with the Lyzenga-Bennett
//! short-wave power law (Eq. (2.70)), or the Elfouhaily et al. (1997) unified spectrum, plus a
//! narrow swell component.
//!
//! Conventions: `omni(k)` is the omnidirectional elevation spectrum Psi(k) (m^3), with
//! m0 = integral Psi dk; `directional(kx, ky)` is the two-sided 2D spectrum F (m^4) over the whole
//! wavenumber plane, F(k, phi) = Psi(k) D(k, phi) / k with the spreading D integrating to 1 over
//! 2 pi, so that m0 = integral F dkx dky. Directions are angles counter-clockwise from the ship's
//! heading, as everywhere in wakelab. Deep water, gravity-capillary dispersion
//! omega^2 = g k + tau k^3 / rho.

use crate::constants::RHO_WATER;
use serde::Serialize;
use std::f64::consts::PI;
use wakelab_core::config::{NamedDirection, SeaConfig, SpectrumModel, SwellConfig, SwellDirection};

/// Pierson-Moskowitz constants of Eq. (2.71).
pub const PM_ALPHA: f64 = 8.1e-3;
pub const PM_BETA: f64 = 0.74;

/// Factor on Elfouhaily's short-wave spreading coefficient a_m = 0.13 u* / c_m (Elfouhaily et
/// al. 1997, in their Eq. 57), fitted there to measured short-wave directionality. With it the C-band up-/cross-wind sigma0 ratio of this
/// two-scale model falls 1.5-3 dB short of CMOD5.N (Hersbach 2010) at 35-45 degrees and
/// 7-15 m/s, a known weakness of that spreading at Bragg scales. 2.5 is the value that brings
/// the ratio within 1.5 dB of CMOD5.N's over 30-45 degrees and 3-15 m/s (a fit of this one
/// number to that published model function, stated as such; 2 and 3 each leave a wind outside
/// it). It changes Delta(k) little below k ~ 20 rad/m, where c >> c_m. The radar's Bragg level
/// further tapers Delta below 100 rad/m ([`crate::bragg_scale`]); with that taper the ratio
/// stays within 1.5 dB (measured 1.4).
pub const SHORT_WAVE_SPREADING_GAIN: f64 = 2.5;

/// Intrinsic frequency omega (rad/s) of a gravity-capillary wave.
pub fn angular_frequency(k: f64, gravity: f64, tension: f64) -> f64 {
    (gravity * k + tension / RHO_WATER * k.powi(3)).sqrt()
}

/// Group velocity d omega / dk (m/s).
pub fn group_speed(k: f64, gravity: f64, tension: f64) -> f64 {
    (gravity + 3.0 * tension / RHO_WATER * k * k) / (2.0 * angular_frequency(k, gravity, tension))
}

/// The midpoints k and widths dk of `n` log-spaced bins over [k_lo, k_hi): the radial rule of
/// every band integral of the spectrum.
fn log_bins(k_lo: f64, k_hi: f64, n: usize) -> impl Iterator<Item = (f64, f64)> {
    let step = (k_hi / k_lo).ln() / n as f64;
    (0..n).map(move |i| {
        let k = k_lo * ((i as f64 + 0.5) * step).exp();
        (k, k * step)
    })
}

/// The background sea: wind waves of one model plus an optional swell.
#[derive(Debug, Clone)]
pub struct SeaSpectrum {
    pub model: SpectrumModel,
    pub wind_speed: f64,
    /// Direction the wind blows towards (radians from the heading).
    pub wind_direction: f64,
    pub gravity: f64,
    pub tension: f64,
    inverse_wave_age: f64,
    short_exponent: f64,
    join_factor: f64,
    swell: Option<Swell>,
}

#[derive(Debug, Clone, Copy)]
struct Swell {
    k: f64,
    direction: f64,
    m0: f64,
    width: f64,
    spread: f64,
}

impl SeaSpectrum {
    pub fn new(sea: &SeaConfig, wind_speed: f64, wind_direction_deg: f64, swell: &SwellConfig, gravity: f64) -> Self {
        let swell = swell.angle().map(|direction| Swell {
            k: 2.0 * PI / swell.wavelength,
            direction,
            // a sinusoid of amplitude a has variance a^2 / 2
            m0: 0.5 * swell.amplitude * swell.amplitude,
            width: sea.swell_width,
            spread: sea.swell_spread.to_radians(),
        });
        Self {
            model: sea.spectrum,
            wind_speed,
            wind_direction: wind_direction_deg.to_radians(),
            gravity,
            tension: sea.surface_tension,
            inverse_wave_age: sea.inverse_wave_age,
            short_exponent: sea.short_wave_exponent,
            join_factor: sea.short_wave_join,
            swell,
        }
    }

    /// The wind sea alone, without a swell: what scatterometers' model functions (CMOD5.N) and
    /// slope statistics (Cox & Munk) describe.
    pub fn wind_sea(sea: &SeaConfig, wind_speed: f64, wind_direction_deg: f64, gravity: f64) -> Self {
        let calm = SwellConfig {
            amplitude: 0.0,
            wavelength: 1.0,
            direction: SwellDirection::Named(NamedDirection::Calm),
        };
        Self::new(sea, wind_speed, wind_direction_deg, &calm, gravity)
    }

    /// Peak wavenumber of the wind sea (rad/m).
    pub fn peak_wavenumber(&self) -> f64 {
        let g = self.gravity;
        let u = self.wind_speed.max(1e-3);
        match self.model {
            // omega_p = (4 beta / 5)^(1/4) g / U for Eq. (2.71); k_p = omega_p^2 / g
            SpectrumModel::PiersonMoskowitz => (0.8 * PM_BETA).sqrt() * g / (u * u),
            SpectrumModel::Elfouhaily => self.inverse_wave_age.powi(2) * g / (u * u),
        }
    }

    /// Friction velocity u* = sqrt(C_D) U10 with C_D = (0.8 + 0.065 U10) 1e-3 (Wu 1982), as
    /// Elfouhaily et al. (1997) use.
    pub fn friction_velocity(&self) -> f64 {
        let u = self.wind_speed;
        ((0.8 + 0.065 * u) * 1e-3).sqrt() * u
    }

    /// Omnidirectional wind-sea elevation spectrum Psi(k) (m^3).
    pub fn wind_omni(&self, k: f64) -> f64 {
        if self.wind_speed <= 0.0 || k <= 0.0 {
            return 0.0;
        }
        match self.model {
            SpectrumModel::PiersonMoskowitz => self.pm_omni(k),
            SpectrumModel::Elfouhaily => self.elfouhaily_omni(k),
        }
    }

    /// Eq. (2.71) in wavenumber, S(omega) d omega / dk with omega^2 = g k:
    /// Psi(k) = alpha / (2 k^3) exp(-beta g^2 / (U^4 k^2)); above k_j = join k_p the 2D spectrum
    /// follows the power law B k^-c of Eq. (2.70), B from continuity at k_j.
    fn pm_omni(&self, k: f64) -> f64 {
        let g = self.gravity;
        let u = self.wind_speed;
        let pm = |k: f64| PM_ALPHA / (2.0 * k.powi(3)) * (-PM_BETA * g * g / (u.powi(4) * k * k)).exp();
        let kj = self.join_factor * self.peak_wavenumber();
        if k <= kj {
            pm(k)
        } else {
            // 2D F = Psi / (2 pi k) on average over direction: F ~ k^-c  =>  Psi ~ k^(1 - c)
            pm(kj) * (k / kj).powf(1.0 - self.short_exponent)
        }
    }

    /// Elfouhaily et al. (1997), Eqs. (30)-(40) of that paper: S(k) = k^-3 (B_l + B_h).
    fn elfouhaily_omni(&self, k: f64) -> f64 {
        let g = self.gravity;
        let u10 = self.wind_speed;
        let omega_c = self.inverse_wave_age;
        let km = 370.0;
        let cm = 0.23;
        let k0 = g / (u10 * u10);
        let kp = k0 * omega_c * omega_c;
        let cp = (g / kp).sqrt();
        let c = ((g / k) * (1.0 + (k / km).powi(2))).sqrt();
        let ustar = self.friction_velocity();
        let gamma = if omega_c < 1.0 {
            1.7
        } else {
            1.7 + 6.0 * omega_c.log10()
        };
        let sigma = 0.08 * (1.0 + 4.0 * omega_c.powf(-3.0));
        let big_gamma = (-((k / kp).sqrt() - 1.0).powi(2) / (2.0 * sigma * sigma)).exp();
        let jp = gamma.powf(big_gamma);
        let lpm = (-1.25 * (kp / k).powi(2)).exp();
        let alpha_p = 6e-3 * omega_c.sqrt();
        let fp = lpm * jp * (-omega_c / 10f64.sqrt() * ((k / kp).sqrt() - 1.0)).exp();
        let bl = 0.5 * alpha_p * (cp / c) * fp;
        let alpha_m = if ustar < cm {
            1e-2 * (1.0 + (ustar / cm).ln())
        } else {
            1e-2 * (1.0 + 3.0 * (ustar / cm).ln())
        };
        let fm = lpm * jp * (-0.25 * (k / km - 1.0).powi(2)).exp();
        let bh = 0.5 * alpha_m * (cm / c) * fm;
        (bl + bh) / k.powi(3)
    }

    /// Elfouhaily spreading D(k, phi) = (1 + Delta(k) cos 2 (phi - phi_w)) / (2 pi), used by both
    /// models (a centro-symmetric spread; Elfouhaily et al. 1997, Eqs. 49, 57), with the
    /// short-wave coefficient a_m raised by [`SHORT_WAVE_SPREADING_GAIN`].
    pub fn spreading(&self, k: f64, phi: f64) -> f64 {
        (1.0 + self.spreading_contrast(k) * (2.0 * (phi - self.wind_direction)).cos()) / (2.0 * PI)
    }

    /// Delta(k) of the spreading (Elfouhaily et al. 1997, Eq. 57).
    pub(crate) fn spreading_contrast(&self, k: f64) -> f64 {
        let g = self.gravity;
        let cm = 0.23;
        let km = 370.0;
        let kp = self.peak_wavenumber();
        let c = ((g / k) * (1.0 + (k / km).powi(2))).sqrt();
        let cp = (g / kp).sqrt();
        let a0 = 2f64.ln() / 4.0;
        let ap = 4.0;
        let am = SHORT_WAVE_SPREADING_GAIN * 0.13 * self.friction_velocity() / cm;
        (a0 + ap * (c / cp).powf(2.5) + am * (cm / c).powf(2.5)).tanh()
    }

    /// The swell's share of F at (k, phi) (m^4): Gaussian in k and in direction about the
    /// swell's own (one-sided) direction; zero without a swell.
    pub(crate) fn swell_density(&self, k: f64, phi: f64) -> f64 {
        let Some(s) = self.swell else {
            return 0.0;
        };
        let sk = s.width * s.k;
        let dphi = (phi - s.direction + PI).rem_euclid(2.0 * PI) - PI;
        let radial = (-(k - s.k).powi(2) / (2.0 * sk * sk)).exp() / ((2.0 * PI).sqrt() * sk);
        let angular = (-dphi * dphi / (2.0 * s.spread * s.spread)).exp() / ((2.0 * PI).sqrt() * s.spread);
        s.m0 * radial * angular / k
    }

    /// Two-sided 2D elevation spectrum F(kx, ky) (m^4): wind sea plus swell.
    pub fn directional(&self, kx: f64, ky: f64) -> f64 {
        let k = kx.hypot(ky);
        if k <= 0.0 {
            return 0.0;
        }
        self.ring(k).at(ky.atan2(kx))
    }

    /// The spectrum on the circle of wavenumber k: its parts that depend on k alone worked out
    /// once, for the quadratures that sweep the directions of each k.
    pub fn ring(&self, k: f64) -> Ring<'_> {
        let positive = k > 0.0;
        Ring {
            sea: self,
            k,
            omni_per_k: if positive { self.wind_omni(k) / k } else { 0.0 },
            contrast: if positive { self.spreading_contrast(k) } else { 0.0 },
        }
    }

    /// Slope variances along and across direction `look` of the waves with k_lo <= k < k_hi.
    pub fn slope_variances(&self, look: f64, k_lo: f64, k_hi: f64) -> (f64, f64) {
        if k_hi <= k_lo {
            return (0.0, 0.0);
        }
        let angles = 72;
        // the directions, their angle from the wind's for the spreading, and from the look
        let directions: Vec<(f64, f64, f64, f64)> = (0..angles)
            .map(|a| {
                let phi = (a as f64 + 0.5) * 2.0 * PI / angles as f64;
                let (s, c) = (phi - look).sin_cos();
                (phi, (2.0 * (phi - self.wind_direction)).cos(), c * c, s * s)
            })
            .collect();
        let (mut along, mut across) = (0.0, 0.0);
        for (k, dk) in log_bins(k_lo, k_hi, 400) {
            let ring = self.ring(k);
            for &(phi, twice_from_wind, cos2, sin2) in &directions {
                let f = ring.at_with(phi, twice_from_wind) * k * dk * 2.0 * PI / angles as f64;
                along += f * k * k * cos2;
                across += f * k * k * sin2;
            }
        }
        (along, across)
    }

    /// Elevation variance (m^2) of the wind waves with k_lo <= k < k_hi: the integral of
    /// Psi(k) (log-spaced midpoint rule).
    pub fn elevation_variance(&self, k_lo: f64, k_hi: f64) -> f64 {
        if k_hi <= k_lo || k_lo <= 0.0 {
            return 0.0;
        }
        log_bins(k_lo, k_hi, 400).map(|(k, dk)| self.wind_omni(k) * dk).sum()
    }

    /// Wave action spectral density N = rho omega F / k, up to the constant rho (Eq. (2.67)).
    pub fn action(&self, kx: f64, ky: f64) -> f64 {
        let k = kx.hypot(ky);
        angular_frequency(k, self.gravity, self.tension) * self.directional(kx, ky) / k
    }

    /// Integrated properties of the spectrum up to `k_max` (rad/m).
    pub fn summary(&self, k_max: f64) -> SpectrumSummary {
        // log-spaced radial integration; exact angular integrals of the spreading where possible
        let (mut m0, mut up, mut cross) = (0.0, 0.0, 0.0);
        let (mut peak_k, mut peak_v) = (0.0, 0.0);
        let angles = 72;
        for (k, dk) in log_bins(1e-4, k_max, 4000) {
            let mut ring = 0.0;
            let (mut ring_up, mut ring_cross) = (0.0, 0.0);
            let spectrum = self.ring(k);
            for a in 0..angles {
                let phi = (a as f64 + 0.5) * 2.0 * PI / angles as f64;
                let f = spectrum.at(phi) * k * 2.0 * PI / angles as f64;
                ring += f;
                let rel = phi - self.wind_direction;
                ring_up += f * k * k * rel.cos().powi(2);
                ring_cross += f * k * k * rel.sin().powi(2);
            }
            m0 += ring * dk;
            up += ring_up * dk;
            cross += ring_cross * dk;
            let omni = ring;
            let in_omega = omni / group_speed(k, self.gravity, self.tension);
            if in_omega > peak_v {
                peak_v = in_omega;
                peak_k = k;
            }
        }
        SpectrumSummary {
            significant_wave_height: 4.0 * m0.sqrt(),
            peak_angular_frequency: angular_frequency(peak_k, self.gravity, self.tension),
            peak_frequency_hz: angular_frequency(peak_k, self.gravity, self.tension) / (2.0 * PI),
            mss_upwind: up,
            mss_crosswind: cross,
            slope_cutoff_wavenumber: k_max,
        }
    }
}

/// What `wakelab spectrum` prints about the sea.
#[derive(Debug, Clone, Serialize)]
pub struct SpectrumSummary {
    /// Hs = 4 sqrt(m0) (m).
    pub significant_wave_height: f64,
    /// Peak of S(omega) (rad/s).
    pub peak_angular_frequency: f64,
    pub peak_frequency_hz: f64,
    /// Mean-square slope along the wind.
    pub mss_upwind: f64,
    /// Mean-square slope across the wind.
    pub mss_crosswind: f64,
    /// Largest wavenumber in the slope integrals (rad/m).
    pub slope_cutoff_wavenumber: f64,
}

/// [`SeaSpectrum::directional`] on one circle |k| = k (see [`SeaSpectrum::ring`]).
pub struct Ring<'a> {
    sea: &'a SeaSpectrum,
    k: f64,
    omni_per_k: f64,
    contrast: f64,
}

impl Ring<'_> {
    /// F(k cos phi, k sin phi) (m^4): the wind sea Psi(k) D(k, phi) / k, plus the swell.
    pub fn at(&self, phi: f64) -> f64 {
        self.at_with(phi, (2.0 * (phi - self.sea.wind_direction)).cos())
    }

    /// [`Self::at`] with cos 2 (phi - phi_w) given, for sweeps over the same directions at
    /// every k.
    pub fn at_with(&self, phi: f64, cos_twice_from_wind: f64) -> f64 {
        if self.k <= 0.0 {
            return 0.0;
        }
        let sea = self.sea;
        let spreading = (1.0 + self.contrast * cos_twice_from_wind) / (2.0 * PI);
        self.omni_per_k * spreading + sea.swell_density(self.k, phi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use wakelab_core::WakelabConfig;

    fn pm(u: f64) -> SeaSpectrum {
        let mut c = WakelabConfig::default();
        c.sea.spectrum = SpectrumModel::PiersonMoskowitz;
        // the power law joins far out, so Hs is Pierson-Moskowitz's own
        c.sea.short_wave_join = 1000.0;
        c.environment.swell.amplitude = 0.0;
        SeaSpectrum::new(&c.sea, u, 0.0, &c.environment.swell, 9.81)
    }

    /// Hs = 2 sqrt(alpha / beta) U^2 / g = 0.2092 U^2 / g and omega_p = 0.8772 g / U (closed forms
    /// of Eq. (2.71); Pierson & Moskowitz 1964).
    #[test]
    fn pierson_moskowitz_hs_and_peak_match_closed_forms() {
        for (u, hs) in [(5.0, 0.533), (10.0, 2.133), (15.0, 4.799)] {
            let s = pm(u).summary(50.0);
            assert!(
                (s.significant_wave_height - hs).abs() / hs < 0.003,
                "U={u}: Hs {}",
                s.significant_wave_height
            );
            let wp = 0.8772 * 9.81 / u;
            assert!(
                (s.peak_angular_frequency - wp).abs() / wp < 0.01,
                "U={u}: wp {}",
                s.peak_angular_frequency
            );
        }
    }

    /// The variance of a band of Pierson-Moskowitz waves has a closed form: Psi(k) =
    /// alpha / (2 k^3) exp(-beta g^2 / (k^2 U^4)) integrates to alpha / (4 b) (exp(-b / k_hi^2)
    /// - exp(-b / k_lo^2)) with b = beta g^2 / U^4 (Eq. (2.71)).
    #[test]
    fn band_variance_matches_the_pierson_moskowitz_closed_form() {
        let (u, g) = (8.0f64, 9.81);
        let b = PM_BETA * g * g / u.powi(4);
        for (lo, hi) in [(0.05, 0.2), (0.1, 5.0)] {
            let closed = PM_ALPHA / (4.0 * b) * ((-b / (hi * hi)).exp() - (-b / (lo * lo)).exp());
            let got = pm(u).elevation_variance(lo, hi);
            assert!((got / closed - 1.0).abs() < 1e-4, "{lo}-{hi}: {got} vs {closed}");
        }
    }

    /// Cox & Munk (1954) clean-surface total mss = 0.003 + 5.12e-3 U (+- 0.004): Elfouhaily et al.
    /// tuned their short waves to it.
    #[test]
    fn elfouhaily_mss_is_near_cox_munk() {
        let c = WakelabConfig::default();
        for u in [5.0, 10.0] {
            let s = SeaSpectrum::wind_sea(&c.sea, u, 0.0, 9.81).summary(2000.0);
            let total = s.mss_upwind + s.mss_crosswind;
            let cm = 0.003 + 5.12e-3 * u;
            assert!((total - cm).abs() < 0.25 * cm, "U={u}: mss {total} vs Cox-Munk {cm}");
            assert!(s.mss_upwind > s.mss_crosswind);
        }
    }

    #[test]
    fn swell_adds_its_variance() {
        let mut c = WakelabConfig::default();
        c.sea.spectrum = SpectrumModel::PiersonMoskowitz;
        c.sea.short_wave_join = 1000.0;
        let with = SeaSpectrum::new(&c.sea, 5.0, 0.0, &c.environment.swell, 9.81).summary(50.0);
        let without = pm(5.0).summary(50.0);
        let m0 = |hs: f64| (hs / 4.0).powi(2);
        let added = m0(with.significant_wave_height) - m0(without.significant_wave_height);
        assert!(
            (added - 0.5).abs() < 0.01,
            "swell of a = 1 m adds a^2/2 = 0.5 m^2, got {added}"
        );
    }
}

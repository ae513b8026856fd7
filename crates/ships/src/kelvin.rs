//! A ship's speed from its transverse Kelvin waves. Behind a ship in deep water the transverse
//! waves run with it, crests across the track, at the phase speed of the ship: wavelength
//! lambda = 2 pi U^2 / g (Lamb 1932, section 226). Along the track the image's profile therefore repeats every lambda; its periodogram
//! peaks there, and U = sqrt(g lambda / (2 pi)). The wavelength is resolvable only when it spans
//! at least two resolution cells, and its uncertainty is half a frequency bin of the profile.
//! The sea's own profile is red (correlated speckle, wind and slicks varying over hundreds of
//! metres), so it is whitened before its peak is sought, lest its slope pass for waves.

use rustfft::{num_complex::Complex, FftPlanner};
use serde::Serialize;

/// A speed and its standard uncertainty (m/s), with how it was read.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Speed {
    pub value: f64,
    pub sigma: f64,
}

/// Why no Kelvin speed was read, or the speed with its wavelength (m) and the peak's power over
/// the sides' power at its wavelength, or the profile's median power where that is larger.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct KelvinReading {
    pub speed: Speed,
    pub wavelength_m: f64,
    pub peak_ratio: f64,
}

/// The least peak-over-median power that counts as waves (a periodogram's ordinates of noise
/// are exponential: one exceeds 12 times the median with probability exp(-12 ln 2) = 2.4e-4).
pub const MIN_PEAK_RATIO: f64 = 12.0;

/// The periodogram of `values` (detrended by a line, Hann-tapered, zero-padded to `padded`).
fn periodogram(values: &[f64], padded: usize) -> Vec<f64> {
    let n = values.len();
    let mean = values.iter().sum::<f64>() / n as f64;
    let x_mean = 0.5 * (n - 1) as f64;
    let slope = values
        .iter()
        .enumerate()
        .map(|(i, v)| (i as f64 - x_mean) * (v - mean))
        .sum::<f64>()
        / (0..n).map(|i| (i as f64 - x_mean).powi(2)).sum::<f64>().max(1e-300);
    let mut buffer: Vec<Complex<f64>> = (0..padded)
        .map(|i| {
            if i < n {
                let hann = 0.5 - 0.5 * (2.0 * std::f64::consts::PI * i as f64 / (n - 1) as f64).cos();
                Complex::new((values[i] - mean - slope * (i as f64 - x_mean)) * hann, 0.0)
            } else {
                Complex::new(0.0, 0.0)
            }
        })
        .collect();
    FftPlanner::new().plan_fft_forward(padded).process(&mut buffer);
    buffer.iter().take(padded / 2).map(|c| c.norm_sqr()).collect()
}

/// The lag-1 autocorrelation of `values` about their mean, held to 0-0.95.
fn lag_one_correlation(values: &[f64]) -> f64 {
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    let variance: f64 = values.iter().map(|v| (v - mean).powi(2)).sum();
    let lagged: f64 = values.windows(2).map(|w| (w[0] - mean) * (w[1] - mean)).sum();
    (lagged / variance.max(1e-300)).clamp(0.0, 0.95)
}

/// `values` whitened by the AR(1) filter x_i - rho x_(i-1) (prewhitening: Percival and Walden
/// 1993, section 9.10). A sea's profile is red, not white: the speckle is correlated over
/// pixels, and wind and slicks vary over hundreds of metres, so its power falls with frequency
/// and, against the band's median, its long wavelengths stand out as peaks (a fifth of AR(1)
/// noise profiles of lag-1 correlation 0.5-0.8 read a speed so, against the sides, and nearly
/// all without them; `red_noise_reads_no_speed`). The filter is smooth, so a ship's waves stay
/// a narrow peak.
fn whitened(values: &[f64], rho: f64) -> Vec<f64> {
    values.windows(2).map(|w| w[1] - rho * w[0]).collect()
}

/// The finite values of a profile (no data left out).
fn finite(profile: &[f32]) -> Vec<f64> {
    profile.iter().filter(|v| v.is_finite()).map(|&v| v as f64).collect()
}

/// The median of `values` (0 when empty).
fn median_of(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values.get(values.len() / 2).copied().unwrap_or(0.0)
}

/// The least peak power over the profile's own mean power around it ([`local_level`]) that
/// counts as waves. A periodogram's ordinates over their local mean are exponential, but the
/// band holds a few hundred of them at the 4-fold padding: measured on 300 white, red (AR(1)
/// 0.5, 0.8) and white-beside-red profiles of 150 samples (numpy, 2026-11-29), 10 lets 1-3 %
/// of them read a speed with the sides' test, 8 lets 9 % of the white-beside-red ones.
pub const MIN_LOCAL_RATIO: f64 = 10.0;

/// The profile's own mean power around frequency bin `k`: over bins k/2 either way (at least 8
/// beyond the lobe), leaving out the peak's main lobe (a Hann window's is two bins of the
/// unpadded profile either way: `2 * oversampling` padded bins). The window is symmetric,
/// mirrored at zero and at the Nyquist frequency as a real profile's spectrum is, so that on a
/// sloping spectrum its mean is the level at `k`. A peak must stand over its own spectrum's
/// level there, not only over the sides': a profile along a trough at the noise floor is whiter
/// than the sea beside it, and against the sides alone its short wavelengths stood out as waves
/// (1,204 of 2,000 white profiles beside red sides; `a_white_trough_beside_a_red_sea_reads_no_speed`).
fn local_level(power: &[f64], k: usize, oversampling: usize) -> f64 {
    let n = power.len() as isize;
    let lobe = 2 * oversampling as isize;
    let k = k as isize;
    let w = (k / 2).max(lobe + 8);
    let mirrored = |j: isize| {
        let j = j.abs();
        (if j >= n { 2 * n - j } else { j }).clamp(0, n - 1) as usize
    };
    let around: Vec<f64> = (k - w..=k + w)
        .filter(|j| (j - k).abs() > lobe)
        .map(|j| power[mirrored(j)])
        .collect();
    (around.iter().sum::<f64>() / around.len() as f64).max(1e-300)
}

/// The Kelvin speed of `profile`, samples `step` metres apart along the track from the ship,
/// for wavelengths from `min_wavelength` (two resolution cells) to those of `max_speed`; an
/// error says why none (too short, unresolved, no peak). `sides`: profiles parallel to it
/// outside the Kelvin wedge, whose power is the reference a peak must stand over (the swell and
/// the wind waves are there too; the ship's transverse waves are not); without them the
/// reference is the profile's own median power. Profile and sides are first whitened by the
/// sea's lag-1 correlation (prewhitening), measured on the sides where there are some.
pub fn kelvin_speed(
    profile: &[f32],
    sides: &[Vec<f32>],
    step: f64,
    min_wavelength: f64,
    max_speed: f64,
) -> Result<KelvinReading, String> {
    let raw = finite(profile);
    if raw.len() < 17 {
        return Err("the wake's profile is too short".into());
    }
    let raw_sides: Vec<Vec<f64>> = sides.iter().map(|p| finite(p)).filter(|v| v.len() >= 17).collect();
    // the sea's correlation, from the sides where there are some (the ship's waves are not
    // there to pass for it), else from the profile itself
    let rho = if raw_sides.is_empty() {
        lag_one_correlation(&raw)
    } else {
        raw_sides.iter().map(|v| lag_one_correlation(v)).sum::<f64>() / raw_sides.len() as f64
    };
    let values = whitened(&raw, rho);
    let n = values.len();
    let longest = 2.0 * std::f64::consts::PI * max_speed * max_speed / crate::GRAVITY;
    let length = n as f64 * step;
    let max_wavelength = longest.min(length / 3.0);
    if max_wavelength <= min_wavelength {
        return Err(format!(
            "waves shorter than {max_wavelength:.0} m (three in the profile) are not resolved at this pixel spacing"
        ));
    }
    let padded = (4 * n).next_power_of_two();
    let power = periodogram(&values, padded);
    // the sides' mean power, smoothed over +-2 bins (a side's own peak is as wide as the taper's)
    let side_powers: Vec<Vec<f64>> = raw_sides
        .iter()
        .map(|v| periodogram(&whitened(v, rho), padded))
        .collect();
    let reference = |k: usize| -> Option<f64> {
        (!side_powers.is_empty()).then(|| {
            let (lo, hi) = (k.saturating_sub(2), (k + 2).min(padded / 2 - 1));
            let sum: f64 = side_powers.iter().flat_map(|p| p[lo..=hi].iter()).sum();
            sum / (side_powers.len() * (hi - lo + 1)) as f64
        })
    };
    let wavelength = |k: usize| padded as f64 * step / k as f64;
    let band: Vec<usize> = (1..padded / 2)
        .filter(|&k| (min_wavelength..=max_wavelength).contains(&wavelength(k)))
        .collect();
    if band.len() < 4 {
        return Err("too few wavelengths between the resolvable and the longest".into());
    }
    let median = median_of(band.iter().map(|&k| power[k]).collect()).max(1e-300);
    let over = |k: usize| power[k] / reference(k).map_or(median, |r| r.max(median));
    let over_local = |k: usize| power[k] / local_level(&power, k, padded / n);
    // a peak must pass both tests: the one it passes by the least is its score
    let score = |k: usize| (over(k) / MIN_PEAK_RATIO).min(over_local(k) / MIN_LOCAL_RATIO);
    let &peak = band
        .iter()
        .max_by(|&&a, &&b| score(a).total_cmp(&score(b)))
        .expect("a band");
    let ratio = over(peak);
    if score(peak) < 1.0 {
        return Err(format!(
            "no wave peak along the track (peak {ratio:.1} x the median power, {:.1} x its own level around it)",
            over_local(peak)
        ));
    }
    let lambda = wavelength(peak);
    let speed = (crate::GRAVITY * lambda / (2.0 * std::f64::consts::PI)).sqrt();
    // half a bin of the unpadded profile: d(1/lambda) = 1 / (2 n step)
    let sigma_lambda = lambda * lambda / (2.0 * length);
    Ok(KelvinReading {
        speed: Speed {
            value: speed,
            sigma: 0.5 * speed * sigma_lambda / lambda,
        },
        wavelength_m: lambda,
        peak_ratio: ratio,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Waves of 2 pi U^2 / g for U = 8 m/s (41.0 m) sampled every 5 m over 1 km, with noise:
    /// the speed comes back within its uncertainty and 3 %.
    #[test]
    fn the_transverse_wavelength_gives_the_speed() {
        let u = 8.0;
        let lambda = 2.0 * std::f64::consts::PI * u * u / crate::GRAVITY;
        let mut state = 12345u64;
        let mut noise = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 33) as f64 / (1u64 << 31) as f64 - 0.5) as f32
        };
        let profile: Vec<f32> = (0..200)
            .map(|i| (2.0 * std::f64::consts::PI * 5.0 * i as f64 / lambda).sin() as f32 + noise())
            .collect();
        let reading = kelvin_speed(&profile, &[], 5.0, 10.0, 20.0).unwrap();
        assert!((reading.speed.value - u).abs() < 0.03 * u, "{reading:?}");
        assert!(
            (reading.speed.value - u).abs() < 2.0 * reading.speed.sigma + 0.05,
            "{reading:?}"
        );
        // at 150 m cells even a 20 m/s ship's waves (256 m) span less than two: not resolved
        assert!(kelvin_speed(&profile, &[], 150.0, 300.0, 20.0).is_err());
        // noise alone gives no peak
        let flat: Vec<f32> = (0..200).map(|_| noise()).collect();
        assert!(kelvin_speed(&flat, &[], 5.0, 10.0, 20.0).is_err());
        // a swell of 100 m, four times as high as the ship's waves, on the track and beside it
        // is not the ship's: against the sides the peak is the Kelvin waves', not the swell's
        let swell = |i: usize| 4.0 * (2.0 * std::f64::consts::PI * 5.0 * i as f64 / 100.0).sin() as f32;
        let with_swell: Vec<f32> = profile.iter().enumerate().map(|(i, v)| v + swell(i)).collect();
        let sides: Vec<Vec<f32>> = (0..2).map(|_| (0..200).map(|i| swell(i) + noise()).collect()).collect();
        let reading = kelvin_speed(&with_swell, &sides, 5.0, 10.0, 20.0).unwrap();
        assert!((reading.speed.value - u).abs() < 0.03 * u, "{reading:?}");
        let fooled = kelvin_speed(&with_swell, &[], 5.0, 10.0, 20.0).unwrap();
        assert!(
            (fooled.speed.value - 12.5).abs() < 0.5,
            "without sides the swell reads as 12.5 m/s: {fooled:?}"
        );
    }

    /// `n` samples of AR(1) noise of lag-1 correlation `rho` and unit variance: a sea's profile.
    fn ar1<R: rand::Rng + ?Sized>(rng: &mut R, n: usize, rho: f64) -> Vec<f32> {
        use rand_distr::{Distribution, StandardNormal};
        let mut x = 0.0f64;
        (0..n)
            .map(|_| {
                let e: f64 = StandardNormal.sample(rng);
                x = rho * x + (1.0 - rho * rho).sqrt() * e;
                x as f32
            })
            .collect()
    }

    /// A profile along a trough at the noise floor is white where the sea beside it is red
    /// (lag-1 correlation 0.8): against those sides its short wavelengths have more power, yet
    /// they are no waves. 2,000 draws of 150 samples of 2.5 m: a speed is read from at most 3 %
    /// (measured 50, 2.5 %; 1,204 when a peak was held against the sides and the median only).
    #[test]
    fn a_white_trough_beside_a_red_sea_reads_no_speed() {
        use rand::SeedableRng;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let draws = 2000;
        let read = (0..draws)
            .filter(|_| {
                let profile = ar1(&mut rng, 150, 0.0);
                let sides = [ar1(&mut rng, 150, 0.8), ar1(&mut rng, 150, 0.8)];
                kelvin_speed(&profile, &sides, 2.5, 5.0, 22.5).is_ok()
            })
            .count();
        assert!(read <= draws * 3 / 100, "{read} of {draws} read a speed");
    }

    /// Profiles of noise alone, red as a sea's (AR(1), lag-1 correlation 0, 0.5 and 0.8 over
    /// 150 samples of 10 m), 2,000 of each: against two sides alike, a speed is read from at
    /// most 3 % of them, and alone, whitened by their own correlation, from at most 5 %.
    /// Measured: 1.8-2.4 % and 3.1-4.1 % against the median alone; 0.9-1.1 % and 1.7-2.1 % since
    /// a peak must also stand over its own level around it. Against the band's median without
    /// whitening, 18-26 % read one against the sides and 69-99 % alone (400 draws, 2026-11-29).
    #[test]
    fn red_noise_reads_no_speed() {
        use rand::SeedableRng;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        for rho in [0.0, 0.5, 0.8] {
            let mut red = |n: usize| ar1(&mut rng, n, rho);
            let draws = 2000;
            let (mut with_sides, mut alone) = (0, 0);
            for _ in 0..draws {
                let profile = red(150);
                let sides = [red(150), red(150)];
                with_sides += kelvin_speed(&profile, &sides, 10.0, 20.0, 22.5).is_ok() as usize;
                alone += kelvin_speed(&profile, &[], 10.0, 20.0, 22.5).is_ok() as usize;
            }
            assert!(
                with_sides <= draws * 3 / 100,
                "rho {rho}: {with_sides} of {draws} read a speed against the sides"
            );
            assert!(alone <= draws / 20, "rho {rho}: {alone} of {draws} read a speed alone");
        }
    }
}

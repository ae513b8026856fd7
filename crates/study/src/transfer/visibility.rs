//! How plainly a wake shows in an image at a detector's spacing (issue 38, item 4: the study's
//! wakes against those of real images, by one measure). An observer looks along the wake: the
//! window's profile across the wake's line, in strips of [`STRIP`] pixels parallel to it, each
//! averaged along the line across the window (the Radon transform's view, restricted to the
//! one direction). The wake's strips are those within [`WAKE_WITHIN_M`] of the line, the sea's
//! those beyond [`SEA_BEYOND_M`]; the visibility is the largest departure of a wake strip from
//! the sea strips' median, over the sea profile's strip-to-strip deviation (the standard
//! deviation of its differences over the square root of two, so that a trend across the
//! window is not counted as noise). That deviation holds what hides a wake from a detector at
//! this spacing: the speckle left after averaging (its looks and its correlation), the sea's
//! texture and its slicks. Dark and bright wakes count alike.

use ndarray::Array2;
use wakelab_learn::data::RadarScale;

/// Width of a strip (pixels of the window).
pub const STRIP: f64 = 2.0;
/// Strips whose centre lies this close to the wake's line (m) hold the wake.
pub const WAKE_WITHIN_M: f64 = 150.0;
/// Strips whose centre lies farther than this from the line (m) are the sea.
pub const SEA_BEYOND_M: f64 = 250.0;

/// A line through the image: two points (row, column) in its pixels.
pub type Line = ((f64, f64), (f64, f64));

/// The profile of `image` (linear) across `line` in the window at `(r, c)` of side `n`: per
/// strip of [`STRIP`] pixels parallel to the line that crosses the window (at least `n` of its
/// pixels with a value: no-data is left out), the signed distance of its centre from the line
/// (pixels) and its mean dB.
pub(crate) fn profile(image: &Array2<f32>, (r, c): (usize, usize), n: usize, line: Line) -> Vec<(f64, f32)> {
    let ((r0, c0), (r1, c1)) = line;
    let length = (r1 - r0).hypot(c1 - c0).max(1e-9);
    let normal = (-(c1 - c0) / length, (r1 - r0) / length);
    let offset = |i: usize, j: usize| {
        let (y, x) = ((r + i) as f64 + 0.5 - r0, (c + j) as f64 + 0.5 - c0);
        y * normal.0 + x * normal.1
    };
    let corners = [offset(0, 0), offset(n, 0), offset(0, n), offset(n, n)];
    let lowest = corners.iter().copied().fold(f64::INFINITY, f64::min);
    let highest = corners.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let strips = ((highest - lowest) / STRIP).ceil() as usize + 1;
    let mut sums = vec![(0f64, 0usize); strips];
    for i in 0..n {
        for j in 0..n {
            let value = image[[r + i, c + j]];
            if value.is_finite() {
                let k = (((offset(i, j) - lowest) / STRIP) as usize).min(strips - 1);
                sums[k].0 += f64::from(RadarScale::Linear.decibels(value));
                sums[k].1 += 1;
            }
        }
    }
    sums.into_iter()
        .enumerate()
        .filter(|&(_, (_, count))| count >= n)
        .map(|(k, (sum, count))| (lowest + (k as f64 + 0.5) * STRIP, (sum / count as f64) as f32))
        .collect()
}

/// The strip-to-strip deviation of a profile's values: the standard deviation of their
/// differences over the square root of two (a trend adds a constant difference, not noise).
pub(crate) fn strip_deviation(values: &[f32]) -> Option<f32> {
    if values.len() < 3 {
        return None;
    }
    let steps: Vec<f32> = values.windows(2).map(|w| w[1] - w[0]).collect();
    let mean = steps.iter().sum::<f32>() / steps.len() as f32;
    let variance = steps.iter().map(|d| (d - mean).powi(2)).sum::<f32>() / steps.len() as f32;
    Some((0.5 * variance).sqrt())
}

/// The wake's visibility in the window at `corner` (side `n`) of `image` (linear, pixels of
/// `spacing` m) along `line` (see the module's doc): `None` where the window holds too few
/// strips of wake or sea (at least one and three).
pub fn visibility(image: &Array2<f32>, corner: (usize, usize), n: usize, line: Line, spacing: f64) -> Option<f64> {
    let strips = profile(image, corner, n, line);
    let (near, far) = (WAKE_WITHIN_M / spacing, SEA_BEYOND_M / spacing);
    let sea: Vec<f32> = strips.iter().filter(|s| s.0.abs() > far).map(|s| s.1).collect();
    let deviation = f64::from(strip_deviation(&sea)?).max(1e-6);
    let median = wakelab_core::io::geotiff::quantile(&sea, 0.5);
    strips
        .iter()
        .filter(|s| s.0.abs() <= near)
        .map(|s| (f64::from(s.1) - median).abs() / deviation)
        .reduce(f64::max)
}

/// The median visibility of a wake along `line` (pixels of `image`, spacing `spacing` m) in
/// windows of side `n` centred a quarter, half and three quarters along it (moved inside the
/// image): `None` where the image is smaller than a window or no window tells.
pub fn along(image: &Array2<f32>, n: usize, line: Line, spacing: f64) -> Option<f64> {
    let (rows, cols) = image.dim();
    if rows < n || cols < n {
        return None;
    }
    let ((r0, c0), (r1, c1)) = line;
    let corner = |x: f64, side: usize| (x - 0.5 * n as f64).round().clamp(0.0, (side - n) as f64) as usize;
    let mut values: Vec<f64> = [0.25, 0.5, 0.75]
        .iter()
        .filter_map(|t| {
            let (r, c) = (r0 + t * (r1 - r0), c0 + t * (c1 - c0));
            visibility(image, (corner(r, rows), corner(c, cols)), n, line, spacing)
        })
        .collect();
    values.sort_by(f64::total_cmp);
    values.get(values.len() / 2).copied()
}

/// Quartiles of visibilities and the share above 3 (a wake strip 3 deviations off the sea).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Spread {
    pub count: usize,
    pub quartiles: [f64; 3],
    pub above_3: f64,
}

impl Spread {
    /// The spread of `values`; `None` when there are none.
    pub fn of(values: &[f64]) -> Option<Spread> {
        if values.is_empty() {
            return None;
        }
        let mut sorted = values.to_vec();
        sorted.sort_by(f64::total_cmp);
        let at = |q: f64| sorted[((sorted.len() - 1) as f64 * q).round() as usize];
        Some(Spread {
            count: sorted.len(),
            quartiles: [at(0.25), at(0.5), at(0.75)],
            above_3: sorted.iter().filter(|&&v| v > 3.0).count() as f64 / sorted.len() as f64,
        })
    }

    /// The quartiles as "q1 / median / q3" (no commas: a CSV cell).
    pub fn describe(&self) -> String {
        let [low, median, high] = self.quartiles;
        format!("{low:.1} / {median:.1} / {high:.1}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    /// A sea of `looks`-look speckle (side 64, 20 m pixels) with a band of 6 rows (120 m)
    /// along row 32 changed by `db`.
    fn sea_with_band(looks: usize, db: f32, seed: u64) -> Array2<f32> {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        Array2::from_shape_fn((64, 64), |(i, _)| {
            let speckle = (0..looks).map(|_| -rng.random_range(1e-9f32..1.0).ln()).sum::<f32>() / looks as f32;
            let wake = if (29..35).contains(&i) {
                10f32.powf(db / 10.0)
            } else {
                1.0
            };
            speckle * wake
        })
    }

    /// Against single-look speckle a strip of 2 x 64 pixels has the deviation of a single look's
    /// 5.57 dB over the square root of 128 (0.49 dB): a 3 dB band stands about 6 deviations off
    /// the sea, a 0.3 dB band not 1.5, and a brightening counts as a darkening does.
    #[test]
    fn a_band_stands_off_the_sea_by_its_contrast_over_the_speckle() {
        let line = ((32.0, -10.0), (32.0, 80.0));
        let mean = |db: f32| {
            let v: Vec<f64> = (0..20)
                .filter_map(|s| visibility(&sea_with_band(1, db, s), (0, 0), 64, line, 20.0))
                .collect();
            v.iter().sum::<f64>() / v.len() as f64
        };
        let (dark, faint, bright) = (mean(-3.0), mean(-0.3), mean(3.0));
        assert!((4.5..9.0).contains(&dark), "{dark}");
        assert!(faint < 3.0, "{faint}");
        assert!((4.5..9.0).contains(&bright), "{bright}");
        // the strips' own deviation, on a sea without the band
        let sea = sea_with_band(1, 0.0, 1);
        let values: Vec<f32> = profile(&sea, (0, 0), 64, line).iter().map(|s| s.1).collect();
        let deviation = strip_deviation(&values).unwrap();
        assert!((0.37..0.62).contains(&deviation), "{deviation}");
    }

    /// A trend across the window adds nothing to the deviation; the spread's quartiles and
    /// share are read off sorted values.
    #[test]
    fn a_trend_is_not_noise_and_the_spread_reads_its_values() {
        let trend: Vec<f32> = (0..20).map(|k| 0.5 * k as f32).collect();
        assert!(strip_deviation(&trend).unwrap() < 1e-6);
        let spread = Spread::of(&[1.0, 2.0, 3.5, 4.0, 10.0]).unwrap();
        assert_eq!(spread.quartiles, [2.0, 3.5, 4.0]);
        assert!((spread.above_3 - 0.6).abs() < 1e-12);
        assert_eq!(Spread::of(&[]), None);
    }
}

//! Where in a window its wake lies: the window's strongest line ([`crate::line_sums`]) and the
//! stretch of it that carries the contrast.
//!
//! Why: a scan places what it finds by windows (1.28 km at the transfer detectors' spacing), so
//! its peak can lie 600-900 m from a wake that crosses its strongest window off the middle; on
//! the field's ship-centred chips, a few windows across, that is most of the image. The window's
//! line sums already hold the answer a classic detector reads off the Radon plane (Rey et al.
//! 1990; Karakus et al. 2020): the line of largest |sum| is the window's straightest, strongest
//! contrast, and along it the contiguous run of pixels of the sum's sign with the largest total
//! (the maximum-subarray run, Bentley 1984, each pixel less half the line's mean) is where that
//! contrast lies, a wake's arm or trough from the ship's end to where it fades, not the chord
//! across the window. Its middle is the point; the line's direction is the wake's.

use ndarray::{Array2, ArrayView2};

use crate::line_sums::{line_sums, plan, CLIP};

/// The strongest line of a window and where along it the contrast lies, in the window's pixels
/// (row down, column right; pixel (i, j) spans [i, i + 1) x [j, j + 1)).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct WindowLine {
    /// The middle of the run of the line's pixels that carries its contrast.
    pub row: f64,
    pub col: f64,
    /// The line's direction: degrees in [0, 180), anticlockwise from the image's column axis
    /// (0 = along a row, 90 = up the image), as a detection's `orientation`.
    pub angle: f64,
    /// The run's extent along the line (pixels, first to last pixel centre plus one).
    pub length: f64,
    /// The line's sum in the window's robust deviations over the root of its pixels (unit
    /// variance on uncorrelated noise); negative for a dark line.
    pub z: f64,
}

impl WindowLine {
    /// The line moved by `(rows, cols)` pixels: a window's line in the image's pixels.
    pub fn shifted(self, (rows, cols): (f64, f64)) -> Self {
        Self {
            row: self.row + rows,
            col: self.col + cols,
            ..self
        }
    }
}

/// Lines shorter than this share of the window's side are not considered: a line across a
/// window's corner is a few pixels, and one of them has as much chance of being the noise's
/// largest sum as a line across the window.
const SHORTEST: usize = 4;

/// The strongest line of a square normalised window (see the module): of the lines of at least
/// n / [`SHORTEST`] pixels, the one of largest |line sum|, and along it the run of largest total
/// of its pixels (clipped as the line sums clip them, signed as the sum) less half the line's
/// mean. None where every sum is 0 (a flat window).
pub fn strongest_line(window: ArrayView2<f32>) -> Option<WindowLine> {
    strongest_line_of(window, &line_sums(&window.to_owned()))
}

/// [`strongest_line`] given the window's line sums, where they were made for the network.
pub fn strongest_line_of(window: ArrayView2<f32>, sums: &Array2<f32>) -> Option<WindowLine> {
    let n = window.nrows();
    assert_eq!(n, window.ncols(), "a square window");
    assert_eq!(sums.dim(), (n, n), "the window's line sums");
    let plan = plan(n);
    let long_enough = ((n / SHORTEST).max(1) as f32).sqrt();
    let ((a, b), z) = sums
        .indexed_iter()
        .filter(|&((a, b), _)| plan.roots[a * n + b] >= long_enough)
        .map(|(at, &v)| (at, v))
        .reduce(|best, next| if next.1.abs() > best.1.abs() { next } else { best })?;
    if z == 0.0 {
        return None;
    }
    let theta = std::f64::consts::PI * a as f64 / n as f64;
    let (sin, cos) = theta.sin_cos();
    let centre = 0.5 * n as f64;
    // the line's pixels ordered along it: the normal is (cos, sin) in (column, row), the line
    // runs along (-sin, cos)
    let bins = &plan.bins[a * n * n..(a + 1) * n * n];
    let mut pixels: Vec<(f64, usize, usize, f32)> = bins
        .iter()
        .enumerate()
        .filter(|&(_, &bin)| bin as usize == b)
        .map(|(k, _)| {
            let (r, c) = (k / n, k % n);
            let along = -(c as f64 + 0.5 - centre) * sin + (r as f64 + 0.5 - centre) * cos;
            let v = window[[r, c]];
            let v = if v.is_finite() { v.clamp(-CLIP, CLIP) } else { 0.0 };
            (along, r, c, v * z.signum())
        })
        .collect();
    pixels.sort_by(|p, q| p.0.total_cmp(&q.0));
    // each pixel less half the line's mean contrast: on the raw values a run would wander on
    // into the noise past the wake's end (a random walk's maximum lies anywhere along it), and
    // with the pixels' mean taken off a line the wake covers whole would end at random; half
    // the mean keeps a whole-line wake whole and makes the noise beyond a wake's end drift down
    let half_mean = 0.5 * z.abs() / (pixels.len() as f32).sqrt();
    let (first, last) = strongest_run(&pixels.iter().map(|p| p.3 - half_mean).collect::<Vec<_>>());
    let run = &pixels[first..=last];
    let count = run.len() as f64;
    let length = run[run.len() - 1].0 - run[0].0 + 1.0;
    let row = run.iter().map(|p| p.1 as f64 + 0.5).sum::<f64>() / count;
    let col = run.iter().map(|p| p.2 as f64 + 0.5).sum::<f64>() / count;
    // along (-sin, cos) in (column, row) is (-sin, -cos) with y up the image
    let angle = (-cos).atan2(-sin).to_degrees().rem_euclid(180.0);
    Some(WindowLine {
        row,
        col,
        // 180 (rounding) and -0 are the rows' direction, 0
        angle: if angle >= 180.0 || angle == 0.0 { 0.0 } else { angle },
        length,
        z: z as f64,
    })
}

/// The first and last index of the contiguous run of `values` with the largest sum (Kadane's
/// maximum subarray; the first such run, a single largest value where all are negative).
fn strongest_run(values: &[f32]) -> (usize, usize) {
    let (mut best, mut best_run) = (f32::NEG_INFINITY, (0, 0));
    let (mut running, mut start) = (0.0f32, 0);
    for (i, &v) in values.iter().enumerate() {
        if running <= 0.0 {
            running = v;
            start = i;
        } else {
            running += v;
        }
        if running > best {
            best = running;
            best_run = (start, i);
        }
    }
    best_run
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::Array2;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;
    use rand_distr::{Distribution, StandardNormal};

    fn noise(n: usize, seed: u64) -> Array2<f32> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        Array2::from_shape_simple_fn((n, n), || {
            let v: f64 = StandardNormal.sample(&mut rng);
            v as f32
        })
    }

    #[test]
    fn the_strongest_run_is_the_largest_contiguous_sum() {
        assert_eq!(strongest_run(&[-1.0, 2.0, 3.0, -10.0, 4.0]), (1, 2));
        assert_eq!(strongest_run(&[1.0, -0.5, 1.0]), (0, 2));
        assert_eq!(strongest_run(&[-3.0, -1.0, -2.0]), (1, 1));
    }

    /// A dark arm 1.5 deviations deep from the window's left edge to its middle along row 20, in
    /// unit noise: the line is along the rows (0 degrees), dark, and the run's middle lies near
    /// the arm's middle (row 20.5, column 16), not the window's (32). Its sum is
    /// -1.5 x 32 / sqrt(64) = -6 plus the noise of 64 pixels over 8 (unit variance).
    #[test]
    fn a_half_crossing_arm_is_placed_on_its_half() {
        let n = 64;
        let mut window = noise(n, 11);
        for c in 0..32 {
            window[[20, c]] -= 1.5;
        }
        let line = strongest_line(window.view()).expect("a line");
        assert!(line.angle < 3.0 || line.angle > 177.0, "{line:?}");
        assert!(line.z < 0.0 && (-9.5..-2.5).contains(&line.z), "{line:?}");
        assert!((line.row - 20.5).abs() < 1.0, "{line:?}");
        assert!((line.col - 16.0).abs() < 6.0, "{line:?}");
        assert!((line.length - 32.0).abs() < 12.0, "{line:?}");
    }

    /// A bright line rising at 45 degrees (up and to the right) through the window's centre:
    /// angle 45, point near the centre.
    #[test]
    fn a_diagonal_line_gives_its_direction() {
        let n = 64;
        let mut window = noise(n, 12);
        for k in 0..n {
            window[[n - 1 - k, k]] += 2.0;
        }
        let line = strongest_line(window.view()).expect("a line");
        assert!((line.angle - 45.0).abs() < 4.0, "{line:?}");
        assert!(line.z > 0.0);
        assert!(
            (line.row - 32.0).abs() < 6.0 && (line.col - 32.0).abs() < 6.0,
            "{line:?}"
        );
    }

    /// A dark line across the whole window: the run keeps it whole (half the line's mean taken
    /// off each pixel leaves every pixel of it above zero on average).
    #[test]
    fn a_whole_crossing_line_is_kept_whole() {
        let n = 64;
        let mut window = noise(n, 13);
        for c in 0..n {
            window[[40, c]] -= 1.5;
        }
        let line = strongest_line(window.view()).expect("a line");
        assert!(line.z < 0.0 && line.length > 48.0, "{line:?}");
        assert!(
            (line.row - 40.5).abs() < 1.0 && (line.col - 32.0).abs() < 8.0,
            "{line:?}"
        );
    }

    #[test]
    fn a_flat_window_has_no_line() {
        assert_eq!(strongest_line(Array2::<f32>::zeros((16, 16)).view()), None);
        let line = strongest_line(noise(32, 3).view()).unwrap().shifted((10.0, 20.0));
        assert!(line.row >= 10.0 && line.col >= 20.0);
    }
}

//! A window's line sums: its Radon transform (Radon 1917; Deans 1983), the input a classifier
//! reads when its [`InputForm`] is `line_sums`.
//!
//! Why: a wake is a line, its trough and arms straight for kilometres, while a slick, a rain
//! cell or a front is not, and a ship is a point. On the window's pixels the Table 4.1
//! classifier must learn to integrate along a line of any direction and offset from 3 x 3
//! kernels and a position-bound linear layer, against 2-3 dB of speckle per pixel; it learnt
//! none of the study's faint wakes (docs/results.md). The line sums do that integration: a line
//! of contrast c over L pixels becomes one value c sqrt(L) in units of the pixels' deviation,
//! while a point spreads over a sinusoid of small values. The field's classic wake detectors
//! search the same transform for their peaks (Rey et al. 1990; Karakus et al. 2020).
//!
//! The window is first clipped at +-[`CLIP`] robust deviations (as the classic searches clip
//! their normalised image), so that a ship's return, 50 dB above the sea, cannot outweigh a
//! kilometre of wake. Row `a` of the result is the direction theta = 180 a / n degrees of the
//! lines' normal (0: lines along the columns, 90: along the rows), column `b` the lines
//! x cos theta + y sin theta in [b - n/2, b + 1 - n/2) pixels from the window's centre; each
//! value is the sum of the clipped pixels on its line over the square root of their count, so
//! that on uncorrelated noise of unit variance every value has unit variance, whatever the
//! line's length.
//!
//! With [`InputForm::LineSumsShipsMasked`] the ships' returns are first taken out: every pixel
//! more than [`SHIP`] robust deviations above the window's median, and its eight neighbours
//! (the return's skirt), is set to the median (0). Why: clipped at +3, a large ship 15 pixels
//! long is still a short bright line, 5-6 deviations in its line sum, as strong as a wake's arm;
//! on real sea the line-sum detectors' strongest alarms were open-sea windows with one large ship
//! and no wake (docs/results.md). A wake's arms and trough are a few dB from the sea (the
//! spec's Figs. 3.1-3.2; the transfer study's simulated wakes), a ship's return 20-50 dB over it
//! (a radar cross-section of 10^3-10^5 m^2 spread over a pixel of 100-400 m^2 is 4-30 dB of
//! sigma0, against a sea near -20 dB), so a threshold between the two, in the window's robust
//! deviations, keeps the wake and drops the ship wherever the window's speckle spread is 0.5-3
//! dB. A display-stretched image read as dB spreads its sea wider (7-18 grey levels on SSDD's
//! chips averaged to 20 m), so there a large ship's core is masked and part of its skirt stays.
//! The mask did not find more real wakes (docs/results.md, "The ships' returns masked out of
//! the line sums"); the embedded study reads `line_sums`.

use ndarray::Array2;
use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};
use wakelab_schema::architecture::InputForm;

/// Pixels beyond +-CLIP (robust deviations of the normalised window) are clipped before they
/// are summed.
pub const CLIP: f32 = 3.0;

/// Pixels more than SHIP robust deviations above the window's median are a ship's return (with
/// [`InputForm::LineSumsShipsMasked`]): 8 deviations is 4-24 dB at the 0.5-3 dB spreads of
/// multi-looked sea, above a wake's few dB and below a ship's 20-50 dB.
pub const SHIP: f32 = 8.0;

/// What the network reads of a normalised window ([`crate::data::detector_input`]) in `form`.
pub fn network_input(form: InputForm, window: Array2<f32>) -> Array2<f32> {
    match form {
        InputForm::Pixels => window,
        InputForm::LineSums => line_sums(&window),
        InputForm::LineSumsShipsMasked => line_sums(&ships_masked(window)),
    }
}

/// The window with its ships' returns set to its median (0): every pixel above [`SHIP`] and its
/// eight neighbours (see the module). The 3 x 3 ring is written here: the land mask's dilation
/// (`wakelab_ships::land`) lives in a crate learn does not depend on.
pub fn ships_masked(mut window: Array2<f32>) -> Array2<f32> {
    let (h, w) = window.dim();
    let bright: Vec<(usize, usize)> = window
        .indexed_iter()
        .filter(|&(_, &v)| v > SHIP)
        .map(|(at, _)| at)
        .collect();
    for (r, c) in bright {
        for rr in r.saturating_sub(1)..(r + 2).min(h) {
            for cc in c.saturating_sub(1)..(c + 2).min(w) {
                window[[rr, cc]] = 0.0;
            }
        }
    }
    window
}

/// The line sums of a square window of side n: n directions by n offsets (see the module).
/// Non-finite pixels count as 0 (the window's median).
pub fn line_sums(window: &Array2<f32>) -> Array2<f32> {
    let n = window.nrows();
    assert_eq!(n, window.ncols(), "a square window");
    let plan = plan(n);
    let values: Vec<f32> = window
        .iter()
        .map(|&v| if v.is_finite() { v.clamp(-CLIP, CLIP) } else { 0.0 })
        .collect();
    let mut out = Array2::<f32>::zeros((n, n));
    // one more bin per direction takes the pixels whose line leaves the window's offsets
    let mut sums = vec![0.0f32; n + 1];
    for (a, mut row) in out.outer_iter_mut().enumerate() {
        sums.fill(0.0);
        for (&bin, &v) in plan.bins[a * n * n..(a + 1) * n * n].iter().zip(&values) {
            sums[bin as usize] += v;
        }
        let roots = &plan.roots[a * n..(a + 1) * n];
        for ((o, s), &root) in row.iter_mut().zip(&sums).zip(roots) {
            *o = if root > 0.0 { s / root } else { 0.0 };
        }
    }
    out
}

/// The lines of a window of side n, the same for every window: for each direction and pixel
/// (row-major) the offset bin its centre falls in (n where it falls outside), and for each
/// direction and bin the square root of its pixels.
pub(crate) struct Plan {
    pub(crate) bins: Vec<u16>,
    pub(crate) roots: Vec<f32>,
}

/// The plan of side `n`, made once per side and kept.
pub(crate) fn plan(n: usize) -> Arc<Plan> {
    static PLANS: OnceLock<Mutex<HashMap<usize, Arc<Plan>>>> = OnceLock::new();
    let plans = PLANS.get_or_init(|| Mutex::new(HashMap::new()));
    let mut plans = plans.lock().unwrap_or_else(|e| e.into_inner());
    plans.entry(n).or_insert_with(|| Arc::new(make_plan(n))).clone()
}

fn make_plan(n: usize) -> Plan {
    assert!(n < u16::MAX as usize, "a window side below 65,535");
    let centre = 0.5 * n as f32;
    let mut bins = Vec::with_capacity(n * n * n);
    let mut counts = vec![0.0f32; n * n];
    for a in 0..n {
        let theta = std::f32::consts::PI * a as f32 / n as f32;
        let (cos, sin) = (theta.cos(), theta.sin());
        for r in 0..n {
            // pixel centres at half-integers from the window's centre, shifted by n/2 so that
            // bin b holds offsets [b, b + 1)
            let start = (0.5 - centre) * cos + (r as f32 + 0.5 - centre) * sin + centre;
            for c in 0..n {
                let bin = (start + c as f32 * cos).floor();
                if bin >= 0.0 && bin < n as f32 {
                    bins.push(bin as u16);
                    counts[a * n + bin as usize] += 1.0;
                } else {
                    bins.push(n as u16);
                }
            }
        }
    }
    let roots = counts.iter().map(|k| k.sqrt()).collect();
    Plan { bins, roots }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;
    use rand_distr::{Distribution, StandardNormal};

    /// The sums taken directly, pixel by pixel and direction by direction.
    fn direct(window: &Array2<f32>) -> Array2<f32> {
        let n = window.nrows();
        let centre = 0.5 * n as f32;
        let (mut sum, mut count) = (Array2::<f32>::zeros((n, n)), Array2::<f32>::zeros((n, n)));
        for a in 0..n {
            let theta = std::f32::consts::PI * a as f32 / n as f32;
            let (cos, sin) = (theta.cos(), theta.sin());
            for ((r, c), &v) in window.indexed_iter() {
                let start = (0.5 - centre) * cos + (r as f32 + 0.5 - centre) * sin + centre;
                let bin = (start + c as f32 * cos).floor();
                if bin >= 0.0 && bin < n as f32 {
                    sum[[a, bin as usize]] += if v.is_finite() { v.clamp(-CLIP, CLIP) } else { 0.0 };
                    count[[a, bin as usize]] += 1.0;
                }
            }
        }
        sum.zip_mut_with(&count, |s, &k| *s = if k > 0.0 { *s / k.sqrt() } else { 0.0 });
        sum
    }

    /// The kept plan gives the direct sums bit for bit, at every side, NaN and outliers included.
    #[test]
    fn the_plan_gives_the_direct_sums() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for n in [22, 32, 63, 64] {
            let mut window = Array2::from_shape_simple_fn((n, n), || {
                let v: f64 = StandardNormal.sample(&mut rng);
                (2.0 * v) as f32
            });
            window[[1, 2]] = f32::NAN;
            window[[n / 2, n / 3]] = 500.0;
            assert_eq!(line_sums(&window), direct(&window), "side {n}");
        }
    }

    /// On uncorrelated unit-variance noise every line sum has unit variance (Var of a sum of
    /// L independent values over sqrt(L)); clipping at 3 takes 1.4 % of a Gaussian's variance.
    #[test]
    fn noise_gives_unit_variance_at_every_length() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let n = 64;
        let (mut sum, mut squares, mut values) = (0.0f64, 0.0f64, 0usize);
        for _ in 0..20 {
            let window = Array2::from_shape_simple_fn((n, n), || {
                let v: f64 = StandardNormal.sample(&mut rng);
                v as f32
            });
            for &v in line_sums(&window).iter().filter(|v| **v != 0.0) {
                sum += v as f64;
                squares += (v as f64).powi(2);
                values += 1;
            }
        }
        let mean = sum / values as f64;
        let variance = squares / values as f64 - mean * mean;
        // every pixel lies on n lines of about n pixels, so an image's mean line sum is about
        // (n / sqrt(n)) / n^2 times the sum of its n^2 pixels: standard error sqrt(n) / n over
        // each image, 0.125 / sqrt(20) = 0.028 over the 20
        assert!(mean.abs() < 0.1, "mean {mean}");
        assert!((0.93..1.03).contains(&variance), "variance {variance}");
    }

    /// A dark line along row 20 of contrast -1 over 64 pixels gives -1 x sqrt(64) = -8 at the
    /// direction of its normal (90 degrees, row 32 of the result) and offset bin 20; it is the
    /// transform's minimum, so the line's direction and place come back. In noise of unit
    /// deviation a line of -0.5 still stands 4 deviations off at that point.
    #[test]
    fn a_line_becomes_a_point_of_its_contrast_times_root_length() {
        let n = 64;
        let mut window = Array2::<f32>::zeros((n, n));
        window.row_mut(20).fill(-1.0);
        let sums = line_sums(&window);
        assert!((sums[[32, 20]] + 8.0).abs() < 1e-4, "{}", sums[[32, 20]]);
        let (at, _) = sums.indexed_iter().min_by(|a, b| a.1.total_cmp(b.1)).expect("values");
        assert_eq!(at, (32, 20));
        // along the columns: direction 0
        let mut window = Array2::<f32>::zeros((n, n));
        window.column_mut(40).fill(2.0);
        assert!((line_sums(&window)[[0, 40]] - 16.0).abs() < 1e-4);
        // in noise
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let mut window = Array2::from_shape_simple_fn((n, n), || {
            let v: f64 = StandardNormal.sample(&mut rng);
            v as f32
        });
        window.row_mut(20).mapv_inplace(|v| v - 0.5);
        let v = line_sums(&window)[[32, 20]];
        assert!((-6.5..-1.5).contains(&v), "{v}");
    }

    /// A ship's return of 1,000 deviations is clipped to 3 before it is summed: no line of at
    /// least n / 2 pixels through it reaches 3 / sqrt(n / 2).
    #[test]
    fn a_bright_point_is_clipped_and_spread() {
        let n = 64;
        let mut window = Array2::<f32>::zeros((n, n));
        window[[31, 33]] = 1000.0;
        let sums = line_sums(&window);
        let largest = sums.iter().fold(0.0f32, |m, &v| m.max(v));
        assert!(largest > 0.0 && largest <= 3.0 / (n as f32 / 2.0).sqrt(), "{largest}");
        // every direction sees it once: one value per row
        for row in sums.outer_iter() {
            assert_eq!(row.iter().filter(|&&v| v > 0.0).count(), 1);
        }
        assert_eq!(network_input(InputForm::Pixels, window.clone()), window);
    }

    /// A ship 15 pixels long, 30 deviations bright, beside an arm 3 deviations bright along a
    /// whole row in unit-variance noise. Clipped line sums see the ship as a line of
    /// 3 x 15 / sqrt(64) = 5.6 deviations (noise aside); masked, its line is noise (|v| < 4,
    /// a 4-sigma bound), while the arm keeps its 3 sqrt(64) = 24 (within the noise's +-4).
    #[test]
    fn a_ships_return_is_masked_and_a_wakes_arm_kept() {
        let n = 64;
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let mut window = Array2::from_shape_simple_fn((n, n), || {
            let v: f64 = StandardNormal.sample(&mut rng);
            v as f32
        });
        for c in 20..35 {
            window[[40, c]] += 30.0;
        }
        window.row_mut(10).mapv_inplace(|v| v + 3.0);
        let clipped = network_input(InputForm::LineSums, window.clone());
        let masked = network_input(InputForm::LineSumsShipsMasked, window.clone());
        // direction 32 (lines along the rows), offset bin 40: the ship's row
        assert!(clipped[[32, 40]] > 5.6 - 4.0, "{}", clipped[[32, 40]]);
        assert!(masked[[32, 40]].abs() < 4.0, "{}", masked[[32, 40]]);
        for sums in [&clipped, &masked] {
            assert!((sums[[32, 10]] - 24.0).abs() < 4.0, "{}", sums[[32, 10]]);
        }
        // the mask is the ship and its eight neighbours, nothing else
        let changed = ships_masked(window.clone())
            .iter()
            .zip(window.iter())
            .filter(|(a, b)| a != b)
            .count();
        assert_eq!(changed, 3 * 17);
    }
}

//! Training windows of a footprint cut from a rendered scene pair (issue 38, items 2-3): where
//! the wake's track crosses the scene, windows that hold it (label 1); the same windows of the
//! sea without the ship (label 0: the twin, so that only the wake tells them apart); and the
//! window of that sea with the most dark structure (label 0: its slicks and low-wind patches,
//! the look-alikes). Each is made an input exactly as `wakelab detect` makes one: the image
//! averaged by whole pixels to the detector's spacing, then [`detector_input`].

use crate::steps::context::at_factor;
use crate::steps::open_sea::{distance_to_segment, SeaPair};
use ndarray::{s, Array2, Axis};
use rand::RngExt;
use wakelab_learn::data::{detector_input, RadarScale};
use wakelab_learn::train::Example;
use wakelab_schema::band::Band;

/// Windows along the track per scene.
pub const ON_TRACK: usize = 2;

/// Top-left corners (averaged pixels) of windows of side `n` on an image of `side` whose centre
/// lies within a quarter window of the track (given in averaged pixels), spread along it.
fn on_track_corners(
    side: usize,
    n: usize,
    track: ((f64, f64), (f64, f64)),
    rng: &mut impl rand::Rng,
) -> Vec<(usize, usize)> {
    let ((r0, c0), (r1, c1)) = track;
    let max = (side - n) as f64;
    let mut corners = Vec::new();
    for _ in 0..40 {
        if corners.len() == ON_TRACK {
            break;
        }
        let t: f64 = rng.random_range(0.0..1.0);
        let (r, c) = (r0 + t * (r1 - r0), c0 + t * (c1 - c0));
        let jitter = 0.25 * n as f64;
        let (r, c) = (
            r + rng.random_range(-jitter..jitter),
            c + rng.random_range(-jitter..jitter),
        );
        let corner = (r - 0.5 * n as f64, c - 0.5 * n as f64);
        if !(0.0..=max).contains(&corner.0) || !(0.0..=max).contains(&corner.1) {
            continue;
        }
        let corner = (corner.0.round() as usize, corner.1.round() as usize);
        let centre = (corner.0 as f64 + 0.5 * n as f64, corner.1 as f64 + 0.5 * n as f64);
        if distance_to_segment(centre, track) <= 0.25 * n as f64 {
            corners.push(corner);
        }
    }
    corners
}

/// The window (corner) of `image` (averaged, linear) with the largest share of pixels 3 dB or
/// more below the image's median: its darkest structure.
fn darkest_corner(image: &Array2<f32>, n: usize) -> (usize, usize) {
    let db = image.mapv(|v| RadarScale::Linear.decibels(v));
    let centre = wakelab_learn::data::median(&db);
    let dark = db.mapv(|v| u32::from(v < centre - 3.0));
    let step = (n / 4).max(1);
    let side = image.nrows().min(image.ncols());
    let mut best = ((0, 0), 0);
    for r in (0..=side - n).step_by(step) {
        for c in (0..=side - n).step_by(step) {
            let count: u32 = dark.slice(s![r..r + n, c..c + n]).sum();
            if count > best.1 {
                best = ((r, c), count);
            }
        }
    }
    best.0
}

fn example(image: &Array2<f32>, (r, c): (usize, usize), n: usize, label: u8) -> Example {
    let window = image.slice(s![r..r + n, c..c + n]).to_owned();
    Example {
        image: detector_input(window, Band::C, RadarScale::Linear).insert_axis(Axis(0)),
        label,
        mask: None,
    }
}

/// The windows of side `n` at `factor` scene pixels per pixel cut from `pair` (whose images
/// are already as delivered): those on the track and their twins, and the darkest window of
/// the sea without the ship.
pub(crate) fn training_windows(pair: &SeaPair, factor: usize, n: usize, rng: &mut impl rand::Rng) -> Vec<Example> {
    let (with, without) = (at_factor(&pair.with, factor), at_factor(&pair.without, factor));
    let side = with.nrows().min(with.ncols());
    if side < n {
        return Vec::new();
    }
    let f = factor as f64;
    let ((r0, c0), (r1, c1)) = pair.track;
    let track = ((r0 / f, c0 / f), (r1 / f, c1 / f));
    let mut examples = Vec::new();
    for corner in on_track_corners(side, n, track, rng) {
        examples.push(example(&with, corner, n, 1));
        examples.push(example(&without, corner, n, 0));
    }
    examples.push(example(&without, darkest_corner(&without, n), n, 0));
    examples
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    /// A sea of random brightness with a dark band along the track: the windows on the track
    /// hold the band (a row of their input far below the rest) and their twins do not; the
    /// darkest window of a sea with one dark patch is the patch's.
    #[test]
    fn windows_on_the_track_hold_it_and_the_darkest_window_holds_the_patch() {
        let side = 256;
        let track = ((200.0, -50.0), (200.0, 400.0));
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let sea = Array2::from_shape_fn((side, side), |_| 0.1f32 * rng.random_range(0.7..1.3));
        let mut with = sea.clone();
        with.slice_mut(s![198..202, ..]).mapv_inplace(|v| 0.1 * v);
        let mut without = sea;
        without.slice_mut(s![10..40, 180..250]).mapv_inplace(|v| 0.1 * v);
        let pair = SeaPair {
            with,
            without,
            track,
            spacing: 10.0,
            km2: 6.5536,
        };
        let examples = training_windows(&pair, 2, 64, &mut rng);
        assert_eq!(examples.len(), 2 * ON_TRACK + 1);
        let labels: Vec<u8> = examples.iter().map(|e| e.label).collect();
        assert_eq!(labels, vec![1, 0, 1, 0, 0]);
        let darkest_row = |e: &Example| {
            let rows = e.image.index_axis(Axis(0), 0).mean_axis(Axis(1)).unwrap();
            rows.iter().copied().fold(f32::INFINITY, f32::min)
        };
        for twins in examples[..2 * ON_TRACK].chunks(2) {
            assert!(darkest_row(&twins[0]) < -2.0, "{}", darkest_row(&twins[0]));
            assert!(darkest_row(&twins[1]) > -1.0, "{}", darkest_row(&twins[1]));
        }
        let corner = darkest_corner(&at_factor(&pair.without, 2), 64);
        assert!(corner.0 <= 5 && (61..=90).contains(&corner.1), "{corner:?}");
    }
}

//! Training windows of a footprint cut from a rendered scene pair (issue 38, items 2-3): where
//! the wake's track crosses the scene, windows that hold it (label 1); the same windows of the
//! sea without the ship (label 0: the twin, so that only the wake tells them apart); and the
//! window of that sea with the most dark structure (label 0: its slicks and low-wind patches),
//! and windows of that sea on its other look-alikes (label 0: ships without a wake, internal
//! waves, rain cells, fronts; [`super::look_alikes`]). Each is made an input exactly as `wakelab detect` makes one: the image
//! averaged by whole pixels to the detector's spacing, then [`detector_input`].

use super::real_sea::{self, SeaImage};
use super::visibility::{self, Line};
use crate::steps::context::at_factor;
use crate::steps::open_sea::{distance_to_segment, SeaPair};
use ndarray::{s, Array2, Axis};
use rand::RngExt;
use wakelab_learn::data::{detector_input, RadarScale};
use wakelab_learn::train::Example;
use wakelab_schema::band::Band;

/// Windows along the track per scene.
pub const ON_TRACK: usize = 2;
/// Windows on look-alikes per scene, at most.
pub const ON_LOOK_ALIKES: usize = 3;

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

/// How many of the sea profile's strip-to-strip deviations a strip's change must exceed.
pub const SHOWS_AT: f32 = 3.0;

/// Whether the wake shows in the window at `corner` (side `n`) of `with` against the sea of
/// `without`, as an observer who looks along the wake's `track` sees it: a strip parallel to
/// the track ([`visibility::profile`]) whose mean change exceeds [`SHOWS_AT`] times the sea
/// profile's strip-to-strip deviation ([`visibility::strip_deviation`]). The images are
/// calibrated, averaged alike and speckled alike, so that their ratio is the wake's own
/// change, the ship's return included. The sea's deviation holds what hides a wake from a
/// detector at this spacing: the speckle left after averaging (its looks, its correlation),
/// the sea's own texture and its slicks. A count of pixels changed by 1 dB, a change of
/// sigma0 alone, labelled windows of windy, few-look seas as wakes that no observer sees.
pub(crate) fn wake_shows(
    with: &Array2<f32>,
    without: &Array2<f32>,
    corner: (usize, usize),
    n: usize,
    track: Line,
) -> bool {
    let sea: Vec<f32> = visibility::profile(without, corner, n, track)
        .iter()
        .map(|s| s.1)
        .collect();
    let Some(deviation) = visibility::strip_deviation(&sea) else {
        return false;
    };
    visibility::profile(with, corner, n, track)
        .iter()
        .zip(&sea)
        .any(|(w, o)| (w.1 - o).abs() > SHOWS_AT * deviation)
}

/// `examples` with each wake window repeated so that the wakes are about as many as the
/// windows without one (the classifier's loss weighs the two classes alike).
pub(crate) fn balanced(examples: Vec<Example>) -> Vec<Example> {
    let wakes = examples.iter().filter(|e| e.label == 1).count();
    let repeat = ((examples.len() - wakes) as f64 / wakes.max(1) as f64).round().max(1.0) as usize;
    let mut out = Vec::with_capacity(examples.len() + wakes * (repeat - 1));
    for e in examples {
        let copies = if e.label == 1 { repeat } else { 1 };
        out.extend(std::iter::repeat_n(e, copies));
    }
    out
}

fn example(image: &Array2<f32>, (r, c): (usize, usize), n: usize, label: u8) -> Example {
    let window = image.slice(s![r..r + n, c..c + n]).to_owned();
    Example {
        image: detector_input(window, Band::C, RadarScale::Linear).insert_axis(Axis(0)),
        label,
        mask: None,
    }
}

/// The corner of the window of side `n` on an image of `side` whose centre lies near `point`
/// (within a quarter window), moved inside the image.
fn corner_near(point: (f64, f64), side: usize, n: usize, rng: &mut impl rand::Rng) -> (usize, usize) {
    let jitter = 0.25 * n as f64;
    let max = (side - n) as f64;
    let at = |x: f64, rng: &mut dyn rand::Rng| {
        (x - 0.5 * n as f64 + rng.random_range(-jitter..jitter))
            .clamp(0.0, max)
            .round() as usize
    };
    (at(point.0, rng), at(point.1, rng))
}

/// Training windows of one footprint (of a scene, or of all), how many windows on wakes'
/// tracks were cut and how many of them show the wake ([`wake_shows`]), and the wake's
/// visibility in each as delivered ([`visibility::visibility`]) and that of the same window of
/// the sea without the ship (the measure's floor: the largest of a dozen strips of speckle).
#[derive(Debug, Default)]
pub(crate) struct TrackedWindows {
    pub examples: Vec<Example>,
    pub on_track: usize,
    pub shown: usize,
    pub visibility: Vec<f64>,
    pub sea_visibility: Vec<f64>,
}

/// The windows of side `n` at `factor` scene pixels per pixel cut from `pair` (whose images
/// are as delivered): those on the track and their twins (where `shown_only`, only those where
/// the wake shows in `calibrated`, the same pair before delivery: [`wake_shows`]), the darkest
/// window of the sea without the ship, and windows of that sea on up to [`ON_LOOK_ALIKES`] of
/// the look-alikes' `anchors` (scene pixels), drawn at random; and each wake that shows drawn
/// onto [`real_sea::PER_WAKE`] windows of the real images `sea` (at this spacing), beside them
/// as they are ([`real_sea::wake_on_real_sea`]).
#[allow(clippy::too_many_arguments)]
pub(crate) fn training_windows(
    pair: &SeaPair,
    calibrated: &SeaPair,
    shown_only: bool,
    factor: usize,
    n: usize,
    anchors: &[(f64, f64)],
    sea: &[SeaImage],
    rng: &mut impl rand::Rng,
) -> TrackedWindows {
    let (with, without) = (at_factor(&pair.with, factor), at_factor(&pair.without, factor));
    let side = with.nrows().min(with.ncols());
    if side < n {
        return TrackedWindows::default();
    }
    let truth = (
        at_factor(&calibrated.with, factor),
        at_factor(&calibrated.without, factor),
    );
    let f = factor as f64;
    let ((r0, c0), (r1, c1)) = pair.track;
    let track = ((r0 / f, c0 / f), (r1 / f, c1 / f));
    let mut out = TrackedWindows::default();
    let examples = &mut out.examples;
    for corner in on_track_corners(side, n, track, rng) {
        let shows = wake_shows(&truth.0, &truth.1, corner, n, track);
        out.on_track += 1;
        out.shown += usize::from(shows);
        let spacing = pair.spacing * f;
        out.visibility
            .extend(visibility::visibility(&with, corner, n, track, spacing));
        out.sea_visibility
            .extend(visibility::visibility(&without, corner, n, track, spacing));
        if shows || !shown_only {
            examples.push(example(&with, corner, n, 1));
            examples.push(example(&without, corner, n, 0));
        }
        if shows {
            let (r, c) = corner;
            let (with, without) = (
                truth.0.slice(s![r..r + n, c..c + n]),
                truth.1.slice(s![r..r + n, c..c + n]),
            );
            for _ in 0..if sea.is_empty() { 0 } else { real_sea::PER_WAKE } {
                if let Some((window, ceiling)) = real_sea::sea_window(sea, n, rng) {
                    examples.extend(real_sea::wake_on_real_sea(with, without, window, ceiling));
                }
            }
        }
    }
    examples.push(example(&without, darkest_corner(&without, n), n, 0));
    let mut anchors = anchors.to_vec();
    for k in 0..anchors.len().min(ON_LOOK_ALIKES) {
        let pick = rng.random_range(k..anchors.len());
        anchors.swap(k, pick);
        let (r, c) = anchors[k];
        examples.push(example(&without, corner_near((r / f, c / f), side, n, rng), n, 0));
    }
    out
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
        let windows = training_windows(&pair, &pair, true, 2, 64, &[(25.0, 215.0)], &[], &mut rng);
        assert_eq!((windows.on_track, windows.shown), (ON_TRACK, ON_TRACK));
        let examples = windows.examples;
        assert_eq!(examples.len(), 2 * ON_TRACK + 2);
        let labels: Vec<u8> = examples.iter().map(|e| e.label).collect();
        assert_eq!(labels, vec![1, 0, 1, 0, 0, 0]);
        let darkest_row = |e: &Example| {
            let rows = e.image.index_axis(Axis(0), 0).mean_axis(Axis(1)).unwrap();
            rows.iter().copied().fold(f32::INFINITY, f32::min)
        };
        for twins in examples[..2 * ON_TRACK].chunks(2) {
            assert!(darkest_row(&twins[0]) < -2.0, "{}", darkest_row(&twins[0]));
            assert!(darkest_row(&twins[1]) > -1.0, "{}", darkest_row(&twins[1]));
        }
        // the look-alike's window holds the dark patch it was anchored in (scene pixels
        // 10-40 by 180-250), anchored at its centre
        assert!(darkest_row(&examples[5]) < -2.0, "{}", darkest_row(&examples[5]));
        let corner = darkest_corner(&at_factor(&pair.without, 2), 64);
        assert!(corner.0 <= 5 && (61..=90).contains(&corner.1), "{corner:?}");
        // with the twins equal no window on the track shows a wake: none is taken
        let same = SeaPair {
            with: pair.without.clone(),
            ..pair.clone()
        };
        let shown = training_windows(&pair, &same, true, 2, 64, &[], &[], &mut rng);
        assert_eq!((shown.on_track, shown.shown), (ON_TRACK, 0));
        assert_eq!(shown.examples.iter().map(|e| e.label).collect::<Vec<_>>(), vec![0]);
    }

    /// A wake that darkens a band of 8 rows by 1 dB shows in a sea speckled with 100 looks
    /// (its block means deviate by about 0.1 dB) and not in a single-look sea (about 1.4 dB:
    /// a single look's 5.6 dB over 16 pixels).
    #[test]
    fn a_wake_shows_against_the_speckle_of_many_looks_and_not_of_one() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let n = 64;
        for (looks, shows) in [(100, true), (1, false)] {
            let sea = Array2::from_shape_fn((n, n), |_| {
                (0..looks).map(|_| -rng.random_range(1e-9f32..1.0).ln()).sum::<f32>() / looks as f32
            });
            let mut wake = sea.clone();
            wake.slice_mut(s![28..36, ..]).mapv_inplace(|v| v * 10f32.powf(-0.1));
            assert_eq!(
                wake_shows(&wake, &sea, (0, 0), n, ((32.0, -10.0), (32.0, 80.0))),
                shows,
                "{looks} looks"
            );
        }
    }

    /// Two wake windows among eight are repeated three times: six of twelve.
    #[test]
    fn balancing_repeats_the_wake_windows() {
        let window = |label| Example {
            image: ndarray::Array3::zeros((1, 4, 4)),
            label,
            mask: None,
        };
        let examples: Vec<Example> = [1, 0, 0, 0, 1, 0, 0, 0].into_iter().map(window).collect();
        let out = balanced(examples);
        assert_eq!(out.len(), 12);
        assert_eq!(out.iter().filter(|e| e.label == 1).count(), 6);
    }
}

//! Real wakes as training windows (issue 38, items 1 and 7). Simulated wakes, even drawn onto
//! real sea ([`super::real_sea`]), leave the detectors short of real wakes: on real images the
//! map's peak lies on a wake in about a third of them (docs/results.md). The field's detectors
//! of real wakes learn from real images (OpenSARWake, IEEE GRSL 2024: 3,973 labelled images);
//! Wake2Wake (IEEE TGRS 2024) mixes simulated wakes into them. Here a folder of real images with
//! their wakes drawn, as `--real` reads it, adds windows centred along each drawn wake (label
//! 1: the wake with its ship and the real clutter around it) and windows of the same images
//! clear of every drawn wake (label 0: the real ships without a wake, land, slicks and fronts
//! that a detector trained on the simulator takes for wakes).
//!
//! A window is cut and made an input exactly as a scan cuts one: the image averaged to the
//! detector's spacing, the part of the window past the image's edge taken as no-data and a
//! window more than half no-data left out ([`wakelab_learn::detect::window_at`],
//! [`wakelab_learn::detect::window_example`]), so that a chip smaller than the window trains
//! as it is scanned.

use super::real::{annotations, Annotation};
use super::real_sea::averaged_images;
use crate::steps::open_sea::distance_to_segment;
use crate::Result;
use anyhow::{anyhow, Context};
use ndarray::Array2;
use rand::RngExt;
use std::path::Path;
use wakelab_learn::data::RadarScale;
use wakelab_learn::detect::{window_at, window_example};
use wakelab_learn::train::Example;
use wakelab_schema::band::Band;

/// Windows centred along each drawn wake; as many clear of every wake are cut from its image.
pub const PER_WAKE: usize = 8;
/// A window clear of the wakes has its centre at least this many windows from each drawn
/// wake: most of the wake lies outside it.
pub const CLEAR_OF_WAKES: f64 = 0.75;

/// One real image in dB (NaN for no data), averaged to a detector's spacing, and its drawn
/// wakes as polylines of (row, column) averaged pixels.
#[derive(Debug)]
pub struct WakeImage {
    pub db: Array2<f32>,
    pub wakes: Vec<Vec<(f64, f64)>>,
}

/// The images of `dir`, each with its `NAME.geojson` as `--real` reads them. Refused by name: a
/// folder without a GeoJSON or without any wake drawn, and wakes drawn in longitude and
/// latitude (training places them on the image's pixels). Reads no pixels: a run checks its
/// folder before it writes anything.
pub fn listed(dir: &Path) -> Result<Vec<Annotation>> {
    let listed = annotations(dir).with_context(|| format!("transfer.wake_images {}", dir.display()))?;
    if !listed.iter().any(|a| !a.wakes.is_empty()) {
        return Err(anyhow!(
            "transfer.wake_images {}: no image with a wake drawn in its NAME.geojson (real images without \
             wakes go to --sea-images)",
            dir.display()
        ));
    }
    if let Some(a) = listed.iter().find(|a| a.lonlat && !a.wakes.is_empty()) {
        return Err(anyhow!(
            "transfer.wake_images: {} draws its wakes in longitude and latitude; draw them in the image's pixels \
             (\"wakelab\": {{\"coordinates\": \"pixel\"}})",
            a.image.display()
        ));
    }
    Ok(listed)
}

/// Every image of `dir` ([`listed`]) averaged to each of `spacings` (m) as
/// [`super::real_sea::load`] averages the real sea, its wakes placed on the averaged pixels. A
/// spacing left without any image is refused, naming it.
pub fn load(dir: &Path, spacings: &[f64]) -> Result<Vec<Vec<WakeImage>>> {
    averaged_images(
        listed(dir)?,
        dir,
        spacings,
        "wake_images",
        |annotation, (db, (rows, columns))| {
            let wakes = (annotation.wakes.iter())
                .map(|wake| wake.iter().map(|&(x, y)| (y / rows, x / columns)).collect())
                .collect();
            WakeImage { db, wakes }
        },
    )
}

/// The distance (averaged pixels) from `point` to the nearest of `wakes`.
fn to_wakes(point: (f64, f64), wakes: &[Vec<(f64, f64)>]) -> f64 {
    (wakes.iter())
        .flat_map(|w| w.windows(2).map(|s| distance_to_segment(point, (s[0], s[1]))))
        .chain(
            wakes
                .iter()
                .filter(|w| w.len() == 1)
                .map(|w| distance_to_segment(point, (w[0], w[0]))),
        )
        .fold(f64::INFINITY, f64::min)
}

/// A point drawn uniformly along the polyline `wake`.
fn along(wake: &[(f64, f64)], rng: &mut impl rand::Rng) -> (f64, f64) {
    let length = |s: &[(f64, f64)]| (s[1].0 - s[0].0).hypot(s[1].1 - s[0].1);
    let total: f64 = wake.windows(2).map(length).sum();
    let mut at = rng.random_range(0.0..=total);
    for s in wake.windows(2) {
        let l = length(s);
        if at <= l && l > 0.0 {
            let t = at / l;
            return (s[0].0 + t * (s[1].0 - s[0].0), s[0].1 + t * (s[1].1 - s[0].1));
        }
        at -= l;
    }
    wake[wake.len() - 1]
}

/// The window of side `n` of `image` centred on `centre` as a detector input labelled `label`,
/// None where more than half of it is no-data (a scan scores no such window).
fn window(image: &WakeImage, centre: (f64, f64), n: usize, label: u8) -> Option<Example> {
    let origin = (
        (centre.0 - 0.5 * n as f64).round() as isize,
        (centre.1 - 0.5 * n as f64).round() as isize,
    );
    let cut = window_at(image.db.view(), origin, n);
    if 2 * cut.iter().filter(|v| v.is_nan()).count() > n * n {
        return None;
    }
    Some(Example {
        label,
        ..window_example(cut, Band::C, RadarScale::Db)
    })
}

/// The training windows of side `n` of `images`: [`PER_WAKE`] centred along each drawn wake
/// (at a point drawn along it, moved by up to a quarter window: label 1), and as many centred
/// on the image at least [`CLEAR_OF_WAKES`] windows from every drawn wake ([`PER_WAKE`] on an
/// image without a wake: label 0). A window is drawn again where it falls more than half off the
/// image, up to 40 times, then left out.
pub fn windows(images: &[WakeImage], n: usize, rng: &mut impl rand::Rng) -> Vec<Example> {
    let mut out = Vec::new();
    let jitter = 0.25 * n as f64;
    for image in images {
        for wake in image.wakes.iter().filter(|w| !w.is_empty()) {
            let mut cut = 0;
            for _ in 0..40 * PER_WAKE {
                if cut == PER_WAKE {
                    break;
                }
                let (r, c) = along(wake, rng);
                let centre = (
                    r + rng.random_range(-jitter..=jitter),
                    c + rng.random_range(-jitter..=jitter),
                );
                if let Some(example) = window(image, centre, n, 1) {
                    out.push(example);
                    cut += 1;
                }
            }
        }
        let (rows, columns) = image.db.dim();
        let (mut cut, wanted) = (0, PER_WAKE * image.wakes.len().max(1));
        for _ in 0..40 * wanted {
            if cut == wanted {
                break;
            }
            let centre = (
                rng.random_range(0.0..rows as f64),
                rng.random_range(0.0..columns as f64),
            );
            if to_wakes(centre, &image.wakes) < CLEAR_OF_WAKES * n as f64 {
                continue;
            }
            if let Some(example) = window(image, centre, n, 0) {
                out.push(example);
                cut += 1;
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::{s, Axis};
    use rand::SeedableRng;

    /// A 20 m sea with a line 3 dB dark along row 100 (columns 20-180) and one bright target
    /// far from it: every wake window holds the line (a row of its input far below the rest),
    /// every window without a wake lies clear of it, and the counts are as stated.
    #[test]
    fn windows_along_a_drawn_wake_hold_it_and_the_others_lie_clear_of_it() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let n = 32;
        let mut db = Array2::from_shape_fn((200, 200), |_| -20.0 + rng.random_range(-1.0f32..1.0));
        db.slice_mut(s![99..101, 20..180]).mapv_inplace(|v| v - 3.0);
        let image = WakeImage {
            db,
            wakes: vec![vec![(100.0, 20.0), (100.0, 180.0)]],
        };
        let examples = windows(std::slice::from_ref(&image), n, &mut rng);
        assert_eq!(examples.len(), 2 * PER_WAKE);
        let darkest_row = |e: &Example| {
            let rows = e.image.index_axis(Axis(0), 0).mean_axis(Axis(1)).unwrap();
            rows.iter().copied().fold(f32::INFINITY, f32::min)
        };
        for e in &examples {
            let dark = darkest_row(e) < -2.0;
            assert_eq!(dark, e.label == 1, "label {} darkest row {}", e.label, darkest_row(e));
        }
        assert_eq!(examples.iter().filter(|e| e.label == 1).count(), PER_WAKE);
    }

    /// A chip smaller than the window (24 x 40 under a 32 x 32 window) trains as a scan reads
    /// it: windows more than half off the chip are left out, the rest padded with its median
    /// (the normalised input's zero). An image without a wake gives [`PER_WAKE`] windows.
    #[test]
    fn a_chip_smaller_than_the_window_is_padded_as_a_scan_pads_it() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let image = WakeImage {
            db: Array2::from_shape_fn((24, 40), |(r, c)| (r * 40 + c) as f32),
            wakes: Vec::new(),
        };
        let examples = windows(std::slice::from_ref(&image), 32, &mut rng);
        assert_eq!(examples.len(), PER_WAKE);
        for e in &examples {
            let zeros = e.image.iter().filter(|&&v| v == 0.0).count();
            // at least the rows past the chip's 24 are padding: 8 x 32 of 1,024
            assert!((8 * 32..=512 + 1).contains(&zeros), "{zeros} zeros");
            assert_eq!(e.label, 0);
        }
    }

    #[test]
    fn a_point_along_a_polyline_lies_on_it() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
        let wake = vec![(0.0, 0.0), (0.0, 10.0), (10.0, 10.0)];
        for _ in 0..50 {
            let p = along(&wake, &mut rng);
            assert!(to_wakes(p, std::slice::from_ref(&wake)) < 1e-9, "{p:?}");
        }
        assert!((to_wakes((5.0, 0.0), &[wake]) - 5.0).abs() < 1e-9);
    }
}

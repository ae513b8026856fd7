//! Reading a wakelab dataset for learning (spec 4.2, Algorithm 2): each image made a detector's
//! input ([`detector_input`]), and Monte Carlo balanced train/test samples.
//!
//! The spec normalises each image to zero mean and unit variance (4.2). On linear sigma0 that
//! scale is set by the brightest pixels (a ship returns 50 dB above the sea, and speckle is
//! exponential), so wakelab normalises robustly instead: each image less its median, divided by
//! 1.4826 times its median absolute deviation (the standard deviation for Gaussian data;
//! Rousseeuw & Croux 1993), radar images in dB and infrared ones as brightness temperature, i.e.
//! the brightness-temperature anomaly in units of its spread. (Unscaled, in kelvin, the
//! infrared wakes' tenths of a kelvin left the default study's LWIR detectors at MCC 0.)
//! Training, evaluation and `detect` all read their inputs through it.

use ndarray::Array2;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::{Path, PathBuf};
use wakelab_core::{ConfigError, WakelabError};
use wakelab_schema::band::{Band, Input};
use wakelab_schema::dataset::SceneRecord;
use wakelab_schema::split::Split;

/// The paper's split: 135 training and 14 test images per band (4.2), i.e. this share of the
/// images used is held out for testing.
pub const PAPER_TEST_FRACTION: f64 = 14.0 / 149.0;

/// A dataset directory and its manifest.
pub struct Dataset {
    pub dir: PathBuf,
    pub records: Vec<SceneRecord>,
}

impl Dataset {
    /// Open `dir/manifest.json`. Every scene must have one image side (the networks train on
    /// batches of equal images); a dataset without scenes is refused.
    pub fn open(dir: &Path) -> Result<Self, WakelabError> {
        let path = dir.join("manifest.json");
        let text = std::fs::read_to_string(&path).map_err(|e| WakelabError::io(&path, e))?;
        let records: Vec<SceneRecord> = serde_json::from_str(&text).map_err(|e| WakelabError::Parse {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        let dataset_error = |message: String| WakelabError::Dataset {
            path: dir.display().to_string(),
            message,
        };
        let first = records
            .first()
            .ok_or_else(|| dataset_error("its manifest lists no scenes: render them first (wakelab dataset)".into()))?;
        let size = first.parameters.image_size;
        if let Some(other) = records.iter().find(|r| r.parameters.image_size != size) {
            return Err(dataset_error(format!(
                "scenes {} and {} differ in image_size ({size} and {} pixels); the networks train on images of one size",
                first.id, other.id, other.parameters.image_size
            )));
        }
        Ok(Self {
            dir: dir.to_path_buf(),
            records,
        })
    }

    /// The side of every image of the dataset (pixels; 0 for a dataset built without scenes,
    /// which every architecture then refuses by name).
    pub fn image_size(&self) -> usize {
        self.records.first().map_or(0, |r| r.parameters.image_size)
    }

    /// The median pixel spacing (m) and looks of the dataset's scenes: what its detectors
    /// learned (None for a dataset without scenes).
    pub fn imagery(&self) -> (Option<f64>, Option<f64>) {
        let median = |mut v: Vec<f64>| {
            v.sort_by(f64::total_cmp);
            v.get(v.len() / 2).copied()
        };
        (
            median(self.records.iter().map(|r| r.parameters.pixel_spacing).collect()),
            median(self.records.iter().map(|r| r.parameters.looks as f64).collect()),
        )
    }

    /// The image of scene `i` in `band` as a detector's input ([`detector_input`]).
    pub fn image(&self, i: usize, band: Band) -> Result<Array2<f32>, WakelabError> {
        let r = &self.records[i];
        let rel = r.images.get(&band).ok_or_else(|| WakelabError::Parse {
            path: self.dir.join("manifest.json").display().to_string(),
            message: format!(
                "scene {} has no band {band} (bands: {:?})",
                r.id,
                r.images.keys().collect::<Vec<_>>()
            ),
        })?;
        let path = self.dir.join(rel);
        let image: Array2<f32> = ndarray_npy::read_npy(&path).map_err(|e| WakelabError::Image {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        let size = self.image_size();
        if image.dim() != (size, size) {
            let (rows, cols) = image.dim();
            return Err(WakelabError::Image {
                path: path.display().to_string(),
                message: format!(
                    "{rows} x {cols} pixels; the manifest's image_size is {size}, and every image of a dataset must be {size} x {size}"
                ),
            });
        }
        check_finite(&image, &path)?;
        Ok(detector_input(image, band, RadarScale::Linear))
    }

    /// The wake mask of scene `i` in `band` (1 on the wake, 0 elsewhere; all 0 without a ship).
    pub fn mask(&self, i: usize, band: Band) -> Result<Array2<f32>, WakelabError> {
        let r = &self.records[i];
        let missing = || WakelabError::Parse {
            path: self.dir.join("manifest.json").display().to_string(),
            message: format!("scene {} has no mask for band {band}", r.id),
        };
        let path = self.dir.join(r.masks.get(&band).ok_or_else(missing)?);
        let mask: Array2<u8> = ndarray_npy::read_npy(&path).map_err(|e| WakelabError::Image {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        Ok(mask.mapv(|v| (v > 0) as u8 as f32))
    }

    /// The label of scene `i` for a set of bands: the band's own label (the study's visibility
    /// policy) for one band, whether a ship is in the scene for several.
    pub fn label(&self, i: usize, input: &Input) -> u8 {
        let r = &self.records[i];
        match input.as_single() {
            Some(band) => r.label_by_band.get(&band).copied().unwrap_or(r.label),
            None => r.label,
        }
    }

    /// The share of scenes the study put in its test split (the paper study's 0.1 is the
    /// spec's 14 of 149), or the spec's 14/149 when the manifest has no test split.
    pub fn test_fraction(&self) -> f64 {
        let test = self.records.iter().filter(|r| r.split == Some(Split::Test)).count();
        if test > 0 {
            test as f64 / self.records.len() as f64
        } else {
            PAPER_TEST_FRACTION
        }
    }

    /// The inputs a comma-separated list names, each one band or bands joined by `+` as
    /// channels ("C,S+X"); `None`: every band of the dataset, one at a time. The list is the
    /// `--bands` flag's, and errors name it.
    pub fn inputs(&self, list: Option<&str>) -> Result<Vec<Input>, WakelabError> {
        match list {
            None => Ok(self.bands().into_iter().map(Input::single).collect()),
            Some(t) => t
                .split(',')
                .filter(|s| !s.trim().is_empty())
                .map(|s| {
                    s.trim()
                        .parse::<Input>()
                        .map_err(|e| ConfigError::new("--bands", s.trim(), format!("{e}; several joined by +")).into())
                })
                .collect(),
        }
    }

    /// Bands every scene has an image in.
    pub fn bands(&self) -> Vec<Band> {
        Band::ALL
            .into_iter()
            .filter(|b| !self.records.is_empty() && self.records.iter().all(|r| r.images.contains_key(b)))
            .collect()
    }
}

/// Refuse an image with NaN or infinite pixels: one of them turns every weight a detector learns
/// into NaN, and every probability it gives.
pub fn check_finite(image: &Array2<f32>, path: &Path) -> Result<(), WakelabError> {
    let bad = image.iter().filter(|v| !v.is_finite()).count();
    if bad == 0 {
        return Ok(());
    }
    let (row, col) = image
        .indexed_iter()
        .find(|(_, v)| !v.is_finite())
        .map(|(i, _)| i)
        .expect("counted");
    Err(WakelabError::Image {
        path: path.display().to_string(),
        message: format!(
            "{bad} pixel(s) are NaN or infinite (the first at row {row}, column {col}); images must be finite"
        ),
    })
}

/// How a radar image's pixels are scaled: sigma0 (wakelab's images), sigma0 in dB, or amplitude
/// (sqrt sigma0).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RadarScale {
    #[default]
    Linear,
    Db,
    Amplitude,
}

impl RadarScale {
    pub const ALL: [RadarScale; 3] = [RadarScale::Linear, RadarScale::Db, RadarScale::Amplitude];

    pub fn name(self) -> &'static str {
        match self {
            RadarScale::Linear => "linear",
            RadarScale::Db => "db",
            RadarScale::Amplitude => "amplitude",
        }
    }

    /// A pixel in dB; zero and negative sigma0 or amplitude floor at -300 dB.
    pub fn decibels(self, v: f32) -> f32 {
        let positive = (v as f64).max(1e-30);
        match self {
            RadarScale::Linear => (10.0 * positive.log10()) as f32,
            RadarScale::Db => v,
            RadarScale::Amplitude => (20.0 * positive.max(1e-15).log10()) as f32,
        }
    }
}

impl std::fmt::Display for RadarScale {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for RadarScale {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        wakelab_schema::recipe::parse_named(s, &Self::ALL, Self::name, "a radar scale")
    }
}

/// The detector's input from an image of `band` (module doc), [`robust_normalise`]d: radar
/// pixels (in `scale`) in dB, infrared brightness temperatures (K) as they are, so that the input
/// is the brightness-temperature anomaly about the median in units of its robust spread.
pub fn detector_input(mut image: Array2<f32>, band: Band, scale: RadarScale) -> Array2<f32> {
    if band.is_radar() {
        image.mapv_inplace(|v| scale.decibels(v));
    }
    robust_normalise(image)
}

/// (v - median) / (1.4826 MAD), by [`robust_centre_and_spread`]; a constant image becomes all
/// zeros.
pub fn robust_normalise(mut image: Array2<f32>) -> Array2<f32> {
    let (centre, scale) = robust_centre_and_spread(&image);
    let inverse = if scale > 0.0 { 1.0 / scale } else { 0.0 };
    image.mapv_inplace(|v| ((v - centre) as f64 * inverse) as f32);
    image
}

/// The median of `image` and its robust spread, 1.4826 MAD, which [`robust_normalise`] divides
/// by; where more than half the pixels share one value (MAD 0) the mean absolute deviation about
/// the median stands in (0 for a constant image).
pub fn robust_centre_and_spread(image: &Array2<f32>) -> (f32, f64) {
    let centre = median(image);
    let deviations = image.mapv(|v| (v - centre).abs());
    let mad = median(&deviations) as f64 * 1.4826;
    let spread = if mad > 0.0 {
        mad
    } else {
        deviations.iter().map(|&d| d as f64).sum::<f64>() / deviations.len().max(1) as f64
    };
    (centre, spread)
}

/// The median of an image's finite values (the upper one of an even count).
pub fn median(image: &Array2<f32>) -> f32 {
    let values: Vec<f32> = image.iter().copied().collect();
    wakelab_core::io::geotiff::quantile(&values, 0.5) as f32
}

/// Rotate a square image by `quarter_turns` x 90 degrees counter-clockwise.
pub fn rotate_quarter(image: &Array2<f32>, quarter_turns: u8) -> Array2<f32> {
    let n = image.nrows();
    let mut out = image.clone();
    for _ in 0..quarter_turns % 4 {
        let prev = out.clone();
        out = Array2::from_shape_fn((n, n), |(r, c)| prev[[c, n - 1 - r]]);
    }
    out
}

/// Algorithm 2's Monte Carlo split: `test_per_class` wake and as many no-wake scenes drawn at
/// random (seeded) for testing, `train_per_class` of each of the rest for training; indices into
/// `labels`. Scenes of one group (`groups[i]`, a wake/no-wake pair: the same sea, slicks and
/// speckle with and without the ship) go to one side together: a pair split across train and
/// test would let a detector that memorises the sea score its twin with the opposite label.
/// Errors if the groups cannot fill a side with a class's count.
pub fn balanced_split(
    labels: &[u8],
    groups: &[usize],
    train_per_class: usize,
    test_per_class: usize,
    seed: u64,
) -> Result<(Vec<usize>, Vec<usize>), WakelabError> {
    let mut members: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
    for (i, &g) in groups.iter().enumerate() {
        members.entry(g).or_default().push(i);
    }
    let mut order: Vec<Vec<usize>> = members.into_values().collect();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    // Fisher-Yates shuffle of the groups
    for i in (1..order.len()).rev() {
        let j = rng.random_range(0..=i);
        order.swap(i, j);
    }
    let mut used = vec![false; order.len()];
    let mut take = |want: usize| -> Result<Vec<usize>, WakelabError> {
        let mut have = [0usize; 2];
        let mut out = Vec::new();
        for (group, used) in order.iter().zip(used.iter_mut()) {
            if *used || have == [want, want] {
                continue;
            }
            let wake = group.iter().filter(|&&i| labels[i] == 1).count();
            let count = [group.len() - wake, wake];
            if have[0] + count[0] <= want && have[1] + count[1] <= want {
                have = [have[0] + count[0], have[1] + count[1]];
                out.extend_from_slice(group);
                *used = true;
            }
        }
        if have != [want, want] {
            return Err(WakelabError::Config(wakelab_core::ConfigError::new(
                "train/test sizes",
                format!("{train_per_class} + {test_per_class} per class"),
                format!(
                    "at most what the dataset's pairs can fill: {} wake and {} no-wake scenes left",
                    have[1], have[0]
                ),
            )));
        }
        out.sort();
        Ok(out)
    };
    let test = take(test_per_class)?;
    let train = take(train_per_class)?;
    Ok((train, test))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A band list that does not parse is refused naming the flag it came from.
    #[test]
    fn a_bad_band_list_names_the_flag() {
        let dataset = Dataset {
            dir: PathBuf::from("unused"),
            records: Vec::new(),
        };
        let error = dataset.inputs(Some("C,Q")).unwrap_err().to_string();
        assert!(error.contains("`--bands` = Q"), "{error}");
        assert_eq!(dataset.inputs(Some("C, S+X")).unwrap().len(), 2);
    }

    /// Gaussian pixels of standard deviation 3 about 7 by Box-Muller from a seeded stream.
    fn gaussian_image(n: usize) -> Array2<f32> {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        Array2::from_shape_fn((n, n), |_| {
            let (u, v): (f64, f64) = (rng.random_range(1e-12..1.0), rng.random_range(0.0..1.0));
            (7.0 + 3.0 * (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()) as f32
        })
    }

    /// On Gaussian data 1.4826 MAD is the standard deviation (Rousseeuw & Croux 1993): the
    /// normalised image has median 0 and standard deviation 1 within 2 %.
    #[test]
    fn robust_normalisation_gives_unit_scale_on_gaussian_data() {
        let n = robust_normalise(gaussian_image(256));
        let len = n.len() as f64;
        let mean = n.iter().map(|&v| v as f64).sum::<f64>() / len;
        let sd = (n.iter().map(|&v| (v as f64 - mean).powi(2)).sum::<f64>() / len).sqrt();
        assert!(median(&n).abs() < 0.02, "median {}", median(&n));
        assert!((sd - 1.0).abs() < 0.02, "standard deviation {sd}");
    }

    /// A ship's pixel 50 dB above the sea barely moves the others' inputs (it moved them by
    /// their whole range under the spec's mean and variance); constant images become zeros.
    #[test]
    fn a_bright_ship_does_not_set_the_scale() {
        let sea = gaussian_image(64).mapv(|v| 10f32.powf((v - 20.0) / 10.0));
        let mut ship = sea.clone();
        ship[[10, 10]] = 10f32.powf(3.0);
        let (a, b) = (
            detector_input(sea, Band::C, RadarScale::Linear),
            detector_input(ship, Band::C, RadarScale::Linear),
        );
        let worst = a
            .indexed_iter()
            .filter(|(p, _)| *p != (10, 10))
            .map(|(p, &v)| (v - b[p]).abs())
            .fold(0.0f32, f32::max);
        assert!(worst < 0.05, "{worst}");
        assert!(robust_normalise(Array2::from_elem((4, 4), 3.0))
            .iter()
            .all(|&v| v == 0.0));
        // more than half the pixels equal: the mean absolute deviation scales
        let mut mostly = Array2::from_elem((4, 4), 1.0f32);
        mostly[[0, 0]] = 5.0;
        let m = robust_normalise(mostly);
        assert_eq!((m[[1, 1]], m[[0, 0]]), (0.0, 4.0 / 0.25));
    }

    /// The three radar scales give the same dB, and infrared is the anomaly about the median in
    /// units of its robust spread.
    #[test]
    fn radar_scales_agree_and_infrared_is_an_anomaly() {
        for sigma0 in [1e-3f32, 0.05, 2.0] {
            let db = RadarScale::Linear.decibels(sigma0);
            assert!((RadarScale::Amplitude.decibels(sigma0.sqrt()) - db).abs() < 1e-4);
            assert_eq!(RadarScale::Db.decibels(db), db);
        }
        assert_eq!("DB".parse::<RadarScale>(), Ok(RadarScale::Db));
        assert!("log"
            .parse::<RadarScale>()
            .unwrap_err()
            .contains("linear, db, amplitude"));
        let bt = Array2::from_shape_fn((3, 3), |(r, c)| 290.0 + (r * 3 + c) as f32 * 0.1);
        let anomaly = detector_input(bt, Band::Lwir, RadarScale::Linear);
        // median 290.4 K, MAD 0.2 K: (290.8 - 290.4) / (1.4826 x 0.2)
        assert!(anomaly[[1, 1]].abs() < 1e-4, "{}", anomaly[[1, 1]]);
        assert!(
            (anomaly[[2, 2]] - 0.4 / (1.4826 * 0.2)).abs() < 1e-3,
            "{}",
            anomaly[[2, 2]]
        );
    }

    #[test]
    fn four_quarter_turns_are_the_identity() {
        let img = Array2::from_shape_fn((5, 5), |(r, c)| (r * 5 + c) as f32);
        let once = rotate_quarter(&img, 1);
        // counter-clockwise: the top row becomes the left column, read bottom to top
        assert_eq!(once[[4, 0]], img[[0, 0]]);
        assert_eq!(once[[0, 0]], img[[0, 4]]);
        assert_eq!(rotate_quarter(&img, 4), img);
        assert_eq!(rotate_quarter(&rotate_quarter(&img, 3), 1), img);
    }

    /// 20 pairs (a wake and a no-wake scene each): balanced, disjoint, seeded, and no pair on
    /// both sides, in any of many draws.
    #[test]
    fn monte_carlo_split_is_balanced_disjoint_seeded_and_keeps_pairs() {
        let labels: Vec<u8> = (0..40).map(|i| (i % 2) as u8).collect();
        let pairs: Vec<usize> = (0..40).map(|i| i / 2).collect();
        let (train, test) = balanced_split(&labels, &pairs, 15, 4, 9).unwrap();
        assert_eq!((train.len(), test.len()), (30, 8));
        assert_eq!(test.iter().filter(|&&i| labels[i] == 1).count(), 4);
        assert!(train.iter().all(|i| !test.contains(i)));
        assert_eq!(balanced_split(&labels, &pairs, 15, 4, 9).unwrap(), (train, test));
        assert!(balanced_split(&labels, &pairs, 18, 4, 9).is_err());
        for seed in 0..50 {
            let (train, test) = balanced_split(&labels, &pairs, 16, 4, seed).unwrap();
            let test_pairs: Vec<usize> = test.iter().map(|&i| pairs[i]).collect();
            assert!(train.iter().all(|&i| !test_pairs.contains(&pairs[i])), "seed {seed}");
        }
    }
}

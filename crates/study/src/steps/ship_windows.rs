//! The ships step's second wake detector and the fusion of the two: the study's C-band "base"
//! CNN on windows centred on each detected ship, beside the classic Radon search anchored on the
//! same ship, both scored on the same scenes and on their twins without the ship (where a wake
//! "found" is a false alarm), and fused at decision level by the Bayes classifier (spec Eqs.
//! (5.1)-(5.5)) and by Dempster's rule on discounted masses (spec 5.1). Each source's rates come
//! from the other scenes (leave one scene out): the fused trial is never part of the data that
//! weighs its sources (erratum 11).

use super::context::{at_factor, whole_factor};
use super::whole_scene::model_path;
use crate::Result;
use ndarray::Array2;
use serde::{Deserialize, Serialize};
use std::path::Path;
use wakelab_fusion::bayes::{bayes_fuse, SourceWeights};
use wakelab_fusion::dempster::{classifier_mass, combine, pignistic};
use wakelab_learn::data::RadarScale;
use wakelab_learn::detect::{detect_image, ScanOptions};
use wakelab_learn::device::{parse_device, Device};
use wakelab_learn::store::{load_detector, Detector, ModelInfo};
use wakelab_schema::band::Band;
use wakelab_schema::metrics::{roc_auc, Confusion};

/// The CNN's windows are those centred within this distance (m) of the detected ship: the
/// wake's first kilometre in any direction, as the classic search's rays reach any course.
pub const RADIUS_M: f64 = 1000.0;

/// The study's C-band "base" detector, scanning windows around a ship.
pub struct ShipWindows {
    detector: Detector,
    info: ModelInfo,
    device: Device,
    /// Scene pixels per detector pixel (whole).
    factor: usize,
    /// The detector file's hash, for the step's key.
    pub hash: u64,
}

impl ShipWindows {
    /// The run's saved C-band "base" detector, None when the run has none or it was trained at
    /// a spacing that is not a whole multiple of the scenes' `spacing` (m).
    pub fn load(run_dir: &Path, spacing: f64) -> Result<Option<Self>> {
        let path = model_path(run_dir, Band::C);
        if !path.exists() {
            return Ok(None);
        }
        let bytes = std::fs::read(&path).map_err(|e| wakelab_core::WakelabError::io(&path, e))?;
        let device = parse_device("cpu")?;
        let (detector, info) = load_detector(&path, None, &device)?;
        let Some(factor) = whole_factor(&info, spacing) else {
            return Ok(None);
        };
        Ok(Some(Self {
            detector,
            info,
            device,
            factor,
            hash: wakelab_dataset::fnv(bytes),
        }))
    }

    /// The detector's decision threshold on a window's wake probability.
    pub fn threshold(&self) -> f64 {
        self.info.threshold
    }

    /// The detector's ground footprint (m): its window's side.
    pub fn footprint_m(&self, spacing: f64) -> f64 {
        (self.info.input_size * self.factor) as f64 * spacing
    }

    /// The largest wake probability of the detector's windows (a quarter window apart) centred
    /// within [`RADIUS_M`] of `centre` (the scene's pixels of `spacing` m). `image` is linear
    /// sigma0.
    pub fn score(&self, image: &Array2<f32>, centre: (f64, f64), spacing: f64) -> Result<f64> {
        let f = self.factor as f64;
        let image = at_factor(image, self.factor);
        let (n, dx) = (self.info.input_size, spacing * f);
        let (cr, cc) = (centre.0 / f, centre.1 / f);
        let reach = RADIUS_M / dx + 0.5 * n as f64;
        let span = |c: f64, len: usize| {
            let lo = (c - reach).floor().max(0.0) as usize;
            let hi = ((c + reach).ceil() as usize + 1).min(len);
            // at least a window, inside the image
            let lo = lo.min(len.saturating_sub(n));
            (lo, hi.max(lo + n).min(len))
        };
        let ((r0, r1), (c0, c1)) = (span(cr, image.nrows()), span(cc, image.ncols()));
        let crop = image.slice(ndarray::s![r0..r1, c0..c1]).to_owned();
        let options = ScanOptions {
            stride: Some((n / 4).max(1)),
            scale: RadarScale::Linear,
            ..ScanOptions::default()
        };
        let found = detect_image(&self.detector, &self.info, &crop, options, &self.device, &mut |_, _| {})?;
        let half = 0.5 * n as f64;
        let distance = |t: &wakelab_learn::detect::Tile| {
            ((r0 + t.row) as f64 + half - cr).hypot((c0 + t.col) as f64 + half - cc) * dx
        };
        let near = found
            .tiles
            .iter()
            .filter(|t| distance(t) <= RADIUS_M)
            .map(|t| t.probability)
            .fold(f64::NAN, f64::max);
        // a ship in a corner whose every window centre lies farther: its nearest window
        let best = if near.is_nan() {
            found
                .tiles
                .iter()
                .min_by(|a, b| distance(a).total_cmp(&distance(b)))
                .map_or(0.0, |t| t.probability)
        } else {
            near
        };
        Ok(best)
    }
}

/// One trial: a detected ship's surroundings in its scene (label 1: its wake is there) or in the
/// scene's twin without the ship (label 0), with each source's output: the classic search's
/// (1 when it finds the ship's wake, else 0) and the CNN's largest window probability.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct Trial {
    pub scene: usize,
    pub label: u8,
    pub classic: f64,
    pub cnn: f64,
}

/// A wake detector's record on the trials.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct DetectorScore {
    pub detector: String,
    pub wakes_found: u64,
    pub wakes: u64,
    pub false_alarms: u64,
    pub controls: u64,
    pub mcc: f64,
    /// Area under the ROC curve of the detector's outputs (a yes/no detector's is the mean of
    /// its two rates).
    pub auc: Option<f64>,
}

impl DetectorScore {
    fn new(detector: &str, outputs: &[f64], labels: &[u8], threshold: f64) -> Self {
        let c = Confusion::from_outputs(outputs, labels, threshold);
        Self {
            detector: detector.into(),
            wakes_found: c.tp,
            wakes: c.tp + c.fn_,
            false_alarms: c.fp,
            controls: c.fp + c.tn,
            mcc: c.mcc(),
            auc: roc_auc(outputs, labels),
        }
    }
}

/// The classic search; the CNN at the detector's `threshold` and at a threshold set on the
/// other scenes; and the fusions of the classic search with the CNN at that threshold. Each
/// trial's CNN threshold and both sources' rates come from the other scenes' trials only.
pub fn score_detectors(trials: &[Trial], threshold: f64) -> Vec<DetectorScore> {
    let labels: Vec<u8> = trials.iter().map(|t| t.label).collect();
    let confusion = |subset: &[&Trial], output: fn(&Trial) -> f64, at: f64| {
        let outputs: Vec<f64> = subset.iter().map(|t| output(t)).collect();
        let labels: Vec<u8> = subset.iter().map(|t| t.label).collect();
        Confusion::from_outputs(&outputs, &labels, at)
    };
    let (mut cnn_fitted, mut bayes, mut dempster) = (Vec::new(), Vec::new(), Vec::new());
    for trial in trials {
        let others: Vec<&Trial> = trials.iter().filter(|t| t.scene != trial.scene).collect();
        let fitted = fitted_threshold(&others);
        let (c1, c2) = (
            confusion(&others, |t| t.classic, 0.5),
            confusion(&others, |t| t.cnn, fitted),
        );
        let weights = [SourceWeights::from_confusion(&c1), SourceWeights::from_confusion(&c2)];
        // the CNN's output mapped so that its threshold (not 0.5) separates "wake" from "no
        // wake" in both rules
        let cnn_output = calibrated(trial.cnn, fitted);
        cnn_fitted.push(cnn_output);
        let fused = bayes_fuse(&[trial.classic, cnn_output], &weights);
        bayes.push(if fused.wake { 1.0 } else { 0.0 });
        let masses = (
            classifier_mass(trial.classic, c1.accuracy()),
            classifier_mass(cnn_output, c2.accuracy()),
        );
        let wake = combine(&masses.0, &masses.1).map_or(0.5, |(m, _)| pignistic(&m, 0));
        dempster.push(wake);
    }
    let classic: Vec<f64> = trials.iter().map(|t| t.classic).collect();
    let cnn: Vec<f64> = trials.iter().map(|t| t.cnn).collect();
    vec![
        DetectorScore::new("classic (Radon search from the ship)", &classic, &labels, 0.5),
        DetectorScore::new("CNN (\"base\", windows around the ship)", &cnn, &labels, threshold),
        DetectorScore::new("CNN, threshold set on the other scenes", &cnn_fitted, &labels, 0.5),
        DetectorScore::new("Bayes fusion: classic + CNN (fitted)", &bayes, &labels, 0.5),
        DetectorScore::new(
            "Dempster-Shafer fusion: classic + CNN (fitted)",
            &dempster,
            &labels,
            0.5,
        ),
    ]
}

/// The CNN threshold that classifies `trials` best (most right; of equals, the one in the
/// middle of the widest gap between outputs): a midpoint between two sorted outputs.
fn fitted_threshold(trials: &[&Trial]) -> f64 {
    let mut outputs: Vec<f64> = trials.iter().map(|t| t.cnn).collect();
    outputs.sort_by(f64::total_cmp);
    outputs.dedup();
    let mut best = (0, f64::NEG_INFINITY, 0.5);
    for pair in outputs.windows(2) {
        let at = 0.5 * (pair[0] + pair[1]);
        let right = trials.iter().filter(|t| (t.cnn >= at) == (t.label == 1)).count();
        let gap = pair[1] - pair[0];
        if (right, gap) > (best.0, best.1) {
            best = (right, gap, at);
        }
    }
    best.2
}

/// A probability `p` mapped so that `threshold` lands on 1/2, piecewise linearly.
fn calibrated(p: f64, threshold: f64) -> f64 {
    let t = threshold.clamp(1e-9, 1.0 - 1e-9);
    if p < t {
        0.5 * p / t
    } else {
        0.5 + 0.5 * (p - t) / (1.0 - t)
    }
    .clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn trial(scene: usize, label: u8, classic: f64, cnn: f64) -> Trial {
        Trial {
            scene,
            label,
            classic,
            cnn,
        }
    }

    /// A perfect classic search beside a CNN that says "wake" everywhere: the CNN's record is
    /// all false alarms, and both fusions follow the classic search (the CNN's precision is
    /// 1/2 and its false-omission rate undefined: no information).
    #[test]
    fn fusion_follows_the_informative_source() {
        let trials: Vec<Trial> = (0..6)
            .flat_map(|s| [trial(s, 1, 1.0, 0.9), trial(s, 0, 0.0, 0.9)])
            .collect();
        let scores = score_detectors(&trials, 0.5);
        assert_eq!((scores[0].wakes_found, scores[0].false_alarms), (6, 0));
        assert_eq!((scores[1].wakes_found, scores[1].false_alarms), (6, 6));
        assert_eq!(scores[1].mcc, 0.0);
        for fused in &scores[3..] {
            assert_eq!((fused.wakes_found, fused.false_alarms), (6, 0), "{fused:?}");
            assert!((fused.mcc - 1.0).abs() < 1e-12);
        }
    }

    /// The fitted threshold separates the classes where they separate: halfway across the gap.
    #[test]
    fn the_fitted_threshold_splits_the_classes() {
        let trials: Vec<Trial> = [(1, 0.9), (1, 0.8), (0, 0.6), (0, 0.5), (0, 0.55)]
            .iter()
            .enumerate()
            .map(|(k, &(label, cnn))| trial(k, label, 0.0, cnn))
            .collect();
        let refs: Vec<&Trial> = trials.iter().collect();
        assert!((fitted_threshold(&refs) - 0.7).abs() < 1e-12);
        let scores = score_detectors(&trials, 0.5);
        // held out one at a time, each trial still falls on its side: the fitted CNN is right
        assert_eq!(
            (scores[2].wakes_found, scores[2].false_alarms),
            (2, 0),
            "{:?}",
            scores[2]
        );
        assert_eq!((scores[1].wakes_found, scores[1].false_alarms), (2, 3));
    }

    /// The threshold maps to one half, 0 and 1 stay put.
    #[test]
    fn the_threshold_lands_on_one_half() {
        for t in [0.2, 0.5, 0.9] {
            assert!((calibrated(t, t) - 0.5).abs() < 1e-12);
            assert_eq!(calibrated(0.0, t), 0.0);
            assert!((calibrated(1.0, t) - 1.0).abs() < 1e-12);
        }
    }
}

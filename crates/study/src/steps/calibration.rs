//! The calibration step of `wakelab run`: probabilities that mean what they say, and a scan's
//! threshold set for a stated false-alarm rate (issue 38, item 5).
//!
//! - Every saved detector (the last repetition's of each input and architecture) gets the
//!   temperature of its logit that fits its own test chips best ([`fit_temperature`]; chips it
//!   never trained on). The reliability of all repetitions' test chips is shown before and after,
//!   each chip scaled by a temperature fitted on the other half of its repetition's chips
//!   ([`cross_fitted`]), so that no chip is calibrated with its own label.
//! - The C-band detectors then scan [`SCENES`] simulated C-band scenes of 5.12 km of open sea
//!   with the field's commonest look-alikes the simulator makes (natural slicks drawn long and
//!   thin, up to 30 % of the sea, and wind varying by up to 30 % over the scene), about 1,000
//!   km^2, at the study's sea, winds of 4-10 m/s and any look. Their separate alarms set the
//!   least threshold that holds [`ALARMS_PER_1000_KM2`] on that sea; the same seas with a ship
//!   and its wake say how many wakes survive it (a wake is found when an alarm lies within
//!   [`FOUND_WITHIN_M`] of its track, the rule of issue 38 for real images).
//! - The C-band detectors so calibrated, their threshold stored, are written to `detectors/`:
//!   what `wakelab detect --model` reads for a Sentinel-1 product.
//!
//! It writes `calibration/calibration.json`, which the report renders.

use super::context::{fnv_hex, step_time, whole_factor, write_results};
use super::open_sea::{as_rendered, open_sea_config, scan_scenes, Scanner};
use super::ships::SPACING;
use super::study_run::StudyRun;
use crate::{Result, StepTime};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::time::Instant;
use wakelab_core::{WakelabConfig, WakelabError};
use wakelab_dataset::study::Study;
use wakelab_learn::calibration::{
    brier, cross_fitted, expected_calibration_error, fit_temperature, reliability, threshold_for_alarm_rate,
    ReliabilityBin,
};
use wakelab_learn::device::parse_device;
use wakelab_learn::models::Architecture;
use wakelab_learn::store::{load_detector, save_detector, Calibration};
use wakelab_schema::band::{Band, Input};
use wakelab_schema::metrics::{roc_auc, spearman};
use wakelab_schema::split::Split;

/// The false-alarm rate a calibrated scan's threshold holds on simulated open sea (issue 38:
/// at most 1 per 1,000 km^2, about 40 per Sentinel-1 IW scene before ships anchor them).
pub const ALARMS_PER_1000_KM2: f64 = 1.0;
/// Open-sea scenes (5.12 km each): 40 make 1,049 km^2, enough to see one alarm per 1,000 km^2.
pub const SCENES: usize = 40;
/// A wake is found when an alarm's centre lies this close to its track (m).
pub const FOUND_WITHIN_M: f64 = 500.0;
/// Bins of the reliability diagrams.
pub const BINS: usize = 10;
/// The layout of `calibration.json` and what the step computes.
const RESULTS_FORMAT: &str = "calibration-2";
/// Scene index offset: the ships step's scenes use 0..27.
const FIRST_SCENE: usize = 1000;

/// One saved detector's calibration on its test chips, and (C band) its scan of open sea.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct DetectorCalibration {
    pub input: Input,
    pub architecture: Architecture,
    /// The temperature stored with the detector (fitted on the last repetition's test chips).
    pub temperature: f64,
    /// Test chips of all repetitions, their ECE and Brier score raw and cross-fitted.
    pub test_chips: usize,
    pub ece_raw: f64,
    pub ece_calibrated: f64,
    pub brier_raw: f64,
    pub brier_calibrated: f64,
    pub bins_raw: Vec<ReliabilityBin>,
    pub bins_calibrated: Vec<ReliabilityBin>,
    pub open_sea: Option<OpenSea>,
}

/// A C-band detector's scans of open sea with look-alikes and of the same seas with a wake.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct OpenSea {
    pub scenes: usize,
    pub km2: f64,
    /// The study's threshold (0.5; the same in raw and calibrated probability) and its alarms
    /// per 1,000 km^2 of open sea.
    pub study_threshold: f64,
    pub alarms_at_study_threshold: f64,
    /// The least threshold that holds [`ALARMS_PER_1000_KM2`] (calibrated probability), and the
    /// rate it gives.
    pub threshold: f64,
    pub alarms_at_threshold: f64,
    /// The wakes found among the scenes', at either threshold, and the alarms off the wake in
    /// those scenes (per 1,000 km^2) at either.
    pub wakes_found_at_study_threshold: usize,
    pub wakes_found: usize,
    pub off_wake_alarms_at_study_threshold: f64,
    pub off_wake_alarms: f64,
    /// The largest probability of a window on open sea.
    pub largest_open_sea: f64,
    /// What the windows' own normalisation does on this sea.
    pub normalisation: WindowNormalisation,
    /// The calibrated detector's file.
    pub file: PathBuf,
}

/// `calibration/calibration.json`.
#[derive(Serialize, Deserialize)]
pub struct CalibrationResults {
    key: String,
    seconds: f64,
    pub alarms_target: f64,
    pub detectors: Vec<DetectorCalibration>,
}

fn results_file(run_dir: &Path) -> PathBuf {
    run_dir.join("calibration").join("calibration.json")
}

/// Where the calibrated detectors are written.
pub fn detectors_dir(run_dir: &Path) -> PathBuf {
    run_dir.join("detectors")
}

/// What the calibration step wrote into `run_dir`.
pub fn load_calibration(run_dir: &Path) -> Result<CalibrationResults> {
    let file = results_file(run_dir);
    let text = std::fs::read_to_string(&file).map_err(|e| WakelabError::io(&file, e))?;
    serde_json::from_str(&text).map_err(|e| anyhow::anyhow!("{}: {e}", file.display()))
}

/// The test outputs of `input` and `architecture`: (repetition, score, label).
fn test_outputs(run: &StudyRun, input: &Input, architecture: Architecture) -> Vec<(usize, f64, u8)> {
    run.outputs
        .iter()
        .filter(|o| &o.bands == input && o.architecture == architecture && o.split == Split::Test)
        .map(|o| (o.repetition, o.output, o.label))
        .collect()
}

/// The calibration on test chips of one detector (no open sea yet).
fn chip_calibration(run: &StudyRun, input: &Input, architecture: Architecture) -> Option<DetectorCalibration> {
    let outputs = test_outputs(run, input, architecture);
    let last = outputs.iter().map(|o| o.0).max()?;
    let (scores, labels): (Vec<f64>, Vec<u8>) = outputs.iter().filter(|o| o.0 == last).map(|o| (o.1, o.2)).unzip();
    let temperature = fit_temperature(&scores, &labels);
    let (mut raw, mut calibrated, mut all_labels) = (Vec::new(), Vec::new(), Vec::new());
    for r in 0..=last {
        let (s, l): (Vec<f64>, Vec<u8>) = outputs.iter().filter(|o| o.0 == r).map(|o| (o.1, o.2)).unzip();
        calibrated.extend(cross_fitted(&s, &l));
        raw.extend(s);
        all_labels.extend(l);
    }
    let (bins_raw, bins_calibrated) = (
        reliability(&raw, &all_labels, BINS),
        reliability(&calibrated, &all_labels, BINS),
    );
    Some(DetectorCalibration {
        input: input.clone(),
        architecture,
        temperature,
        test_chips: raw.len(),
        ece_raw: expected_calibration_error(&bins_raw),
        ece_calibrated: expected_calibration_error(&bins_calibrated),
        brier_raw: brier(&raw, &all_labels),
        brier_calibrated: brier(&calibrated, &all_labels),
        bins_raw,
        bins_calibrated,
        open_sea: None,
    })
}

/// What a window's own normalisation (its dB less their median, over their robust spread) does
/// on open sea (issue 38, item 1): whether plain sea scores high where the normalisation
/// stretches it most (the windows of least spread), and whether spread or probability tells
/// the windows on a wake from those of the open sea.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct WindowNormalisation {
    /// Open-sea windows and windows on a wake (centre within half a window of the track).
    pub open_sea_windows: usize,
    pub wake_windows: usize,
    /// Spearman's rho of an open-sea window's robust spread (dB) and its probability.
    pub rho_spread_probability: Option<f64>,
    /// Median robust spread (dB) of the open-sea and the wake windows.
    pub spread_open_sea: f64,
    pub spread_on_wake: f64,
    /// Mean probability of the open-sea windows in the fifth of least spread and in the fifth of
    /// most.
    pub probability_least_spread: f64,
    pub probability_most_spread: f64,
    /// Median probability of the open-sea and the wake windows.
    pub probability_open_sea: f64,
    pub probability_on_wake: f64,
    /// ROC AUC of wake windows against open-sea windows by the detector's probability, and by
    /// the spread alone (larger spread: wake).
    pub auc_probability: Option<f64>,
    pub auc_spread: Option<f64>,
}

/// The median (the mean of the middle two of an even count; NaN when empty).
fn median_of(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    match sorted.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => sorted[n / 2],
        n => 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]),
    }
}

/// [`WindowNormalisation`] of open-sea windows `sea` and wake windows `wake`, each (spread,
/// probability).
fn window_normalisation(sea: &[(f64, f64)], wake: &[(f64, f64)]) -> WindowNormalisation {
    let (sea_spread, sea_p): (Vec<f64>, Vec<f64>) = sea.iter().copied().unzip();
    let (wake_spread, wake_p): (Vec<f64>, Vec<f64>) = wake.iter().copied().unzip();
    let mut by_spread = sea.to_vec();
    by_spread.sort_by(|a, b| a.0.total_cmp(&b.0));
    let fifth = (by_spread.len() / 5).max(1).min(by_spread.len());
    let mean_p = |part: &[(f64, f64)]| part.iter().map(|w| w.1).sum::<f64>() / part.len().max(1) as f64;
    let labels: Vec<u8> = sea.iter().map(|_| 0).chain(wake.iter().map(|_| 1)).collect();
    let scores = |a: &[f64], b: &[f64]| -> Vec<f64> { a.iter().chain(b).copied().collect() };
    WindowNormalisation {
        open_sea_windows: sea.len(),
        wake_windows: wake.len(),
        rho_spread_probability: spearman(&sea_spread, &sea_p),
        spread_open_sea: median_of(&sea_spread),
        spread_on_wake: median_of(&wake_spread),
        probability_least_spread: mean_p(&by_spread[..fifth]),
        probability_most_spread: mean_p(&by_spread[by_spread.len() - fifth..]),
        probability_open_sea: median_of(&sea_p),
        probability_on_wake: median_of(&wake_p),
        auc_probability: roc_auc(&scores(&sea_p, &wake_p), &labels),
        auc_spread: roc_auc(&scores(&sea_spread, &wake_spread), &labels),
    }
}

/// Alarms per 1,000 km^2 of `count` alarms on `km2`.
fn per_1000(count: usize, km2: f64) -> f64 {
    count as f64 * 1000.0 / km2
}

/// The C-band detectors' scans of the first `scenes` open-sea scenes: each detector's
/// [`OpenSea`] (its file written to `detectors/`).
fn open_sea(
    run_dir: &Path,
    base: &WakelabConfig,
    study_threshold: f64,
    detectors: &mut [DetectorCalibration],
    scenes: usize,
) -> Result<()> {
    let device = parse_device("cpu")?;
    let mut scanners = Vec::new();
    for (i, d) in detectors.iter().enumerate() {
        if d.input != Input::single(Band::C) {
            continue;
        }
        let path = crate::output::detector_path(&run_dir.join("learn").join(d.input.name()), &d.input, d.architecture);
        if !path.exists() {
            continue;
        }
        let (detector, mut info) = load_detector(&path, None, &device)?;
        let Some(factor) = whole_factor(&info, SPACING) else {
            continue;
        };
        info.calibration = Some(Calibration {
            temperature: d.temperature,
            false_alarms_per_1000_km2: None,
            open_sea_km2: None,
        });
        scanners.push((i, Scanner { detector, info, factor }));
    }
    if scanners.is_empty() {
        return Ok(());
    }
    let configs: Vec<WakelabConfig> = (0..scenes)
        .filter_map(|j| open_sea_config(base, FIRST_SCENE, j))
        .collect();
    let (indices, scanners): (Vec<usize>, Vec<Scanner>) = scanners.into_iter().unzip();
    let (tallies, km2) = scan_scenes(run_dir, &configs, &as_rendered, &scanners, &device, &mut |_| {})?;
    std::fs::create_dir_all(detectors_dir(run_dir)).map_err(|e| WakelabError::io(detectors_dir(run_dir), e))?;
    for ((i, scanner), tally) in indices.into_iter().zip(scanners).zip(tallies) {
        let threshold = threshold_for_alarm_rate(&tally.sea, km2, ALARMS_PER_1000_KM2);
        let above = |t: f64| tally.sea_alarms(t);
        let found = |t: f64| tally.wakes_found(t, FOUND_WITHIN_M);
        let off = |t: f64| tally.off_wake_alarms(t, FOUND_WITHIN_M);
        let Scanner { detector, mut info, .. } = scanner;
        info.threshold = threshold;
        info.calibration = Some(Calibration {
            temperature: detectors[i].temperature,
            false_alarms_per_1000_km2: Some(ALARMS_PER_1000_KM2),
            open_sea_km2: Some(km2),
        });
        let d = &detectors[i];
        let file = detectors_dir(run_dir).join(format!("{}_{}.safetensors", d.input.name(), d.architecture));
        save_detector(&detector, &info, &file)?;
        detectors[i].open_sea = Some(OpenSea {
            scenes: configs.len(),
            km2,
            study_threshold,
            alarms_at_study_threshold: per_1000(above(study_threshold), km2),
            threshold,
            alarms_at_threshold: per_1000(above(threshold), km2),
            wakes_found_at_study_threshold: found(study_threshold),
            wakes_found: found(threshold),
            off_wake_alarms_at_study_threshold: per_1000(off(study_threshold), km2),
            off_wake_alarms: per_1000(off(threshold), km2),
            largest_open_sea: tally.largest_open_sea(),
            normalisation: window_normalisation(&tally.sea_windows, &tally.wake_windows),
            file,
        });
    }
    Ok(())
}

/// The calibration step (reused when the base configuration, the detectors and wakelab's
/// version are unchanged).
pub fn calibration_step(run_dir: &Path, study: &Study, run: &StudyRun) -> Result<StepTime> {
    let start = Instant::now();
    let base = study.base_config()?;
    let mut pairs = Vec::new();
    for input in &run.inputs {
        for architecture in Architecture::ALL {
            pairs.push((input.clone(), architecture));
        }
    }
    let mut hashes = Vec::new();
    for (input, architecture) in &pairs {
        let path = crate::output::detector_path(&run_dir.join("learn").join(input.name()), input, *architecture);
        if let Ok(bytes) = std::fs::read(&path) {
            hashes.push(wakelab_dataset::fnv(bytes));
        }
    }
    let outputs: Vec<u64> = pairs
        .iter()
        .flat_map(|(i, a)| test_outputs(run, i, *a))
        .map(|o| o.1.to_bits() ^ o.0 as u64)
        .collect();
    let key = fnv_hex(&format!(
        "{base:?} {} {hashes:?} {outputs:?} {} {RESULTS_FORMAT}",
        env!("CARGO_PKG_VERSION"),
        run.plan.threshold
    ));
    if let Ok(found) = load_calibration(run_dir) {
        if found.key == key
            && found
                .detectors
                .iter()
                .all(|d| d.open_sea.as_ref().is_none_or(|o| o.file.exists()))
        {
            return Ok(step_time("calibration", start, Some(found.seconds)));
        }
    }
    let mut detectors: Vec<DetectorCalibration> = pairs
        .iter()
        .filter_map(|(input, architecture)| chip_calibration(run, input, *architecture))
        .collect();
    open_sea(run_dir, &base, run.plan.threshold, &mut detectors, SCENES)?;
    let results = CalibrationResults {
        key,
        seconds: start.elapsed().as_secs_f64(),
        alarms_target: ALARMS_PER_1000_KM2,
        detectors,
    };
    write_results(&results_file(run_dir), &results)?;
    Ok(step_time("calibration", start, None))
}

#[cfg(test)]
mod tests {
    use super::*;
    use wakelab_learn::store::{Detector, ModelInfo};

    /// An untrained C-band detector's scans of two open-sea scenes: the threshold it is given
    /// leaves no alarm on their 52 km^2 (fewer than one allowed), at most as many as 0.5 does,
    /// and the wakes found at the two thresholds are in their order;
    /// the file written holds that threshold, the temperature and the area, and reads back.
    #[test]
    fn the_open_sea_sets_the_threshold_stored_with_the_detector() {
        let study = Study::from_toml_str(wakelab_dataset::study::DEFAULT_STUDY, "default").unwrap();
        let base = study.base_config().unwrap();
        let run_dir = tempfile::tempdir().unwrap();
        let device = parse_device("cpu").unwrap();
        let input = Input::single(Band::C);
        // seeded: an unseeded draw made the threshold fall either side of 0.5 from run to run
        let detector = Detector {
            classifier: wakelab_learn::models::init_seeded(3, &device, |d| {
                wakelab_learn::models::WakeClassifier::new(Architecture::Base.classifier_channels(1), 32, d)
            }),
            segmenter: None,
        };
        let info = ModelInfo {
            architecture: Architecture::Base,
            bands: input.clone(),
            input_size: 32,
            threshold: 0.5,
            unet_width: 16,
            pixel_spacing: Some(SPACING),
            looks: Some(4.0),
            input_scale: Some("linear".into()),
            calibration: None,
            input_form: Default::default(),
            head: Default::default(),
        };
        let path = crate::output::detector_path(&run_dir.path().join("learn").join("C"), &input, Architecture::Base);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        save_detector(&detector, &info, &path).unwrap();
        let bins = reliability(&[], &[], BINS);
        let mut detectors = vec![DetectorCalibration {
            input,
            architecture: Architecture::Base,
            temperature: 1.7,
            test_chips: 0,
            ece_raw: 0.0,
            ece_calibrated: 0.0,
            brier_raw: 0.0,
            brier_calibrated: 0.0,
            bins_raw: bins.clone(),
            bins_calibrated: bins,
            open_sea: None,
        }];
        open_sea(run_dir.path(), &base, 0.5, &mut detectors, 2).unwrap();
        let o = detectors[0]
            .open_sea
            .as_ref()
            .expect("a C-band detector scans the open sea");
        assert_eq!(o.scenes, 2);
        assert!((o.km2 - 2.0 * 5.12 * 5.12).abs() < 1e-9, "{}", o.km2);
        assert_eq!(o.alarms_at_threshold, 0.0);
        assert!(o.alarms_at_study_threshold >= o.alarms_at_threshold);
        // a lower threshold finds at least as many wakes as a higher one
        let (higher, lower) = if o.threshold >= 0.5 {
            (o.wakes_found, o.wakes_found_at_study_threshold)
        } else {
            (o.wakes_found_at_study_threshold, o.wakes_found)
        };
        assert!(higher <= lower && lower <= 2, "{o:?}");
        assert!(o.threshold >= o.largest_open_sea - 1e-12 && o.largest_open_sea > 0.0);
        let (_, stored) = load_detector(&o.file, None, &device).unwrap();
        assert_eq!(stored.threshold, o.threshold);
        let calibration = stored.calibration.expect("calibrated");
        assert_eq!(calibration.temperature, 1.7);
        assert_eq!(calibration.open_sea_km2, Some(o.km2));
        assert_eq!(calibration.false_alarms_per_1000_km2, Some(ALARMS_PER_1000_KM2));
    }

    /// Open-sea windows whose probability falls as their spread grows, and two wake windows of
    /// larger spread and probability: every statistic as counted by hand.
    #[test]
    fn the_window_normalisation_statistics_read_the_windows() {
        let sea: Vec<(f64, f64)> = (0..10).map(|i| (1.0 + 0.1 * i as f64, 0.9 - 0.05 * i as f64)).collect();
        let wake = [(3.0, 0.95), (3.5, 0.99)];
        let w = window_normalisation(&sea, &wake);
        assert_eq!((w.open_sea_windows, w.wake_windows), (10, 2));
        assert!((w.rho_spread_probability.unwrap() + 1.0).abs() < 1e-12);
        // the fifths: spreads 1.0 and 1.1 (p 0.9, 0.85), 1.8 and 1.9 (p 0.5, 0.45)
        assert!((w.probability_least_spread - 0.875).abs() < 1e-12);
        assert!((w.probability_most_spread - 0.475).abs() < 1e-12);
        assert_eq!((w.spread_on_wake, w.spread_open_sea), (3.25, 1.45));
        assert_eq!((w.auc_probability, w.auc_spread), (Some(1.0), Some(1.0)));
    }

    /// Every open-sea scene is a valid 5.12 km scene with its look-alikes.
    #[test]
    fn the_open_sea_scenes_are_valid() {
        let study = Study::from_toml_str(wakelab_dataset::study::DEFAULT_STUDY, "default").unwrap();
        let base = study.base_config().unwrap();
        let configs: Vec<_> = (0..SCENES)
            .filter_map(|j| open_sea_config(&base, FIRST_SCENE, j))
            .collect();
        assert_eq!(configs.len(), SCENES);
        for c in &configs {
            c.validate().unwrap();
            assert_eq!(c.scene.size as f64 * c.scene.pixel_spacing, 5120.0);
            assert!((0.05..0.3).contains(&c.slicks.coverage));
        }
    }
}

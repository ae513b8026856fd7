//! `wakelab run --study transfer` (issue 38): detectors for real C-band images.
//!
//! 1. **Scenes**: [`scenes::training_scene`] draws each training scene's acquisition and sea
//!    from the plan's ranges (domain randomisation) and how its image reaches a user; every
//!    scene is rendered with its ship and wake and without them.
//! 2. **Windows** of each footprint ([`windows::training_windows`]): the wake, its twin without
//!    it, and the darkest window of the sea without it (the look-alikes as negatives); with
//!    `look_alike_training`, also windows on the other look-alikes drawn on the scene
//!    ([`look_alikes`]: ships without a wake, strong targets' sidelobe crosses where the plan
//!    asks, internal waves, rain cells, fronts), only the wake windows where the wake shows,
//!    and the classes balanced.
//! 3. **Training**: one classifier per footprint, the plan's recipe, rotations by any angle.
//! 4. **Threshold**: each detector scans the calibration step's 40 open-sea scenes with slicks
//!    (the same seas the chip detectors' thresholds were set on, so the two compare) and takes
//!    the least threshold that holds the plan's alarm rate there; it then scans as many open-sea
//!    scenes it never saw ([`scenes::FIRST_UNSEEN_SCENE`]), where that rate is counted again,
//!    and the same seas with their wakes (recall: an alarm within 500 m of the track); then the
//!    look-alike test set: the same unseen seas with [`look_alikes`] drawn on them, its alarms
//!    reported apart, and those on ships without a wake apart again.
//! 5. The detectors, their threshold stored, go to `RUN/detectors/C_transfer_<footprint>m`;
//!    `transfer/transfer.json` and the report's `report/transfer.md` and tables say what they do.

pub mod look_alikes;
pub mod real;
mod real_report;
pub mod real_sea;
pub mod real_search;
pub mod real_ships;
pub mod real_wakes;
pub mod report;
pub mod results;
pub mod scenes;
pub mod visibility;
mod windows;

pub use results::{LookAlikeScore, TransferDetector, TransferResults};

use crate::steps::calibration::{detectors_dir, FOUND_WITHIN_M};
use crate::steps::context::{fnv_hex, write_results};
use crate::steps::open_sea::{as_rendered, open_sea_config, render, scan_scenes, Scanner, SeaPair, Tally};
use crate::steps::ships::SPACING;
use crate::{Display, Result};
use rand::SeedableRng;
use std::path::{Path, PathBuf};
use std::time::Instant;
use wakelab_core::WakelabError;
use wakelab_dataset::study::Study;
use wakelab_dataset::transfer::TransferPlan;
use wakelab_learn::calibration::{expected_calibration_error, reliability, threshold_for_alarm_rate};
use wakelab_learn::device::Device;
use wakelab_learn::models::WakeClassifier;
use wakelab_learn::store::{save_detector, Calibration, Detector, ModelInfo};
use wakelab_learn::train::{train_classifier, Recipe};
use wakelab_schema::band::{Band, Input};
use wakelab_schema::metrics::roc_auc;
use wakelab_schema::recipe::{Augmentation, Optimiser};

/// The layout of `transfer.json` and what the study computes.
const RESULTS_FORMAT: &str = "transfer-7";
/// The calibration step's open-sea scenes start here (its `FIRST_SCENE`).
const THRESHOLD_SCENES: usize = 1000;
/// Steps the transfer study's progress display counts.
const STEPS: usize = 5;

fn results_file(run_dir: &Path) -> PathBuf {
    run_dir.join("transfer").join("transfer.json")
}

/// What the transfer study wrote into `run_dir`.
pub fn load_transfer(run_dir: &Path) -> Result<TransferResults> {
    let file = results_file(run_dir);
    let text = std::fs::read_to_string(&file).map_err(|e| WakelabError::io(&file, e))?;
    serde_json::from_str(&text).map_err(|e| anyhow::anyhow!("{}: {e}", file.display()))
}

/// Where the detector of `footprint` (m) is written.
pub fn detector_file(run_dir: &Path, footprint: f64) -> PathBuf {
    detectors_dir(run_dir).join(format!("C_transfer_{footprint:.0}m.safetensors"))
}

/// The training windows of every footprint, with the windows cut on wakes' tracks and those of
/// them in which the wake shows ([`windows::wake_shows`]), and the scenes rendered and those
/// delivered as 8-bit.
fn training_windows(
    run_dir: &Path,
    study: &Study,
    plan: &TransferPlan,
    display: &Display,
    sea: &[Vec<real_sea::SeaImage>],
) -> Result<(Vec<windows::TrackedWindows>, usize, usize)> {
    let base = study.base_config()?;
    let mut per_footprint: Vec<windows::TrackedWindows> = plan.footprints.iter().map(|_| Default::default()).collect();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(plan.seed ^ 0x3E1D_0005);
    let spacings: Vec<f64> = plan.footprints.iter().map(|&f| plan.spacing(f)).collect();
    let wakes = match &plan.wake_images {
        Some(dir) => real_wakes::load(dir, &spacings)?,
        None => spacings.iter().map(|_| Vec::new()).collect(),
    };
    let (mut rendered, mut shown) = (0, 0);
    display.step(1, "training scenes", plan.scenes as u64, "scenes");
    for j in 0..plan.scenes {
        if let Some((c, delivery)) = scenes::training_scene(&base, plan, j) {
            let mut pair = render(&c, run_dir)?;
            let side = pair.with.nrows().min(pair.with.ncols());
            let anchors = if plan.look_alike_training {
                scenes::add_look_alikes(&mut pair, &c, plan).anchors(side, pair.spacing)
            } else {
                Vec::new()
            };
            let calibrated = pair.clone();
            pair.with = delivery.apply(&pair.with, pair.spacing);
            pair.without = delivery.apply(&pair.without, pair.spacing);
            shown += usize::from(delivery.display.is_some());
            rendered += 1;
            for ((windows, &footprint), sea) in per_footprint.iter_mut().zip(&plan.footprints).zip(sea) {
                let factor = (plan.spacing(footprint) / SPACING).round() as usize;
                let scene = windows::training_windows(
                    &pair,
                    &calibrated,
                    plan.look_alike_training,
                    factor,
                    plan.window,
                    &anchors,
                    sea,
                    &mut rng,
                );
                windows.examples.extend(scene.examples);
                windows.on_track += scene.on_track;
                windows.shown += scene.shown;
                windows.visibility.extend(scene.visibility);
                windows.sea_visibility.extend(scene.sea_visibility);
            }
        }
        display.advance(1, format!("{rendered} rendered"));
    }
    for (windows, images) in per_footprint.iter_mut().zip(&wakes) {
        windows
            .examples
            .extend(real_wakes::windows(images, plan.window, &mut rng));
    }
    if plan.look_alike_training {
        for windows in &mut per_footprint {
            windows.examples = windows::balanced(std::mem::take(&mut windows.examples));
        }
    }
    Ok((per_footprint, rendered, shown))
}

/// The plan's recipe: Adam, rotations by any angle, mirror flips and shifts.
fn recipe(plan: &TransferPlan) -> Recipe {
    Recipe {
        epochs: plan.epochs,
        batch_size: plan.batch_size,
        learning_rate: plan.learning_rate,
        optimiser: Optimiser::Adam,
        weight_decay: plan.weight_decay,
        augmentation: Augmentation::Geometric,
        width: 16,
        input: plan.input,
        head: plan.head,
    }
}

/// Per 1,000 km^2.
fn per_1000(count: usize, km2: f64) -> f64 {
    count as f64 * 1000.0 / km2
}

/// `wakelab run --study transfer`: every step of the study in `dir` (reused when the study and
/// wakelab are unchanged), the images of `real` scored where given ([`real`]), then its report.
/// Returns what it did, a line each.
pub fn run_transfer(
    study: &Study,
    dir: &Path,
    device: &Device,
    real: Option<&Path>,
    quiet: bool,
) -> Result<Vec<String>> {
    let plan = study
        .transfer
        .clone()
        .ok_or_else(|| anyhow::anyhow!("the study has no [transfer] table"))?;
    if let Some(sea) = &plan.sea_images {
        real_sea::listed(sea)?;
    }
    if let Some(wakes) = &plan.wake_images {
        real_wakes::listed(wakes)?;
        if let Some(real) = real {
            refuse_images_trained_on(wakes, real)?;
        }
    }
    std::fs::create_dir_all(dir).map_err(|e| WakelabError::io(dir, e))?;
    wakelab_core::io::write_atomically(dir.join("study.toml"), toml::to_string(study)?.as_bytes())?;
    let start = Instant::now();
    // the real images' files by name and size: a folder whose images change trains afresh
    let listing = |dir: &Option<PathBuf>| dir.as_deref().map(real_sea::listing).unwrap_or_default();
    let sea = format!("{} {}", listing(&plan.sea_images), listing(&plan.wake_images));
    let key = fnv_hex(&format!(
        "{:?} {plan:?} {sea} {} {RESULTS_FORMAT}",
        study.base_config()?,
        env!("CARGO_PKG_VERSION")
    ));
    let reused = load_transfer(dir)
        .ok()
        .filter(|r| r.key == key && r.detectors.iter().all(|d| d.file.exists()));
    let results = match reused {
        Some(r) => r,
        None => {
            let display = Display::new(quiet, STEPS, dir);
            let computed = compute(study, &plan, dir, device, &display, key);
            display.finish();
            let mut results = computed?;
            results.seconds = start.elapsed().as_secs_f64();
            write_results(&results_file(dir), &results)?;
            results
        }
    };
    let mut lines: Vec<String> = results.detectors.iter().map(report::describe).collect();
    let real = real_scores(dir, &results, real, quiet)?;
    lines.extend(real.iter().flat_map(|r| r.summaries.iter().map(real_report::describe)));
    lines.extend(
        real.iter()
            .flat_map(|r| r.search_summary.as_ref().map(real_report::describe_search)),
    );
    for file in report::write_report(dir, &results, real.as_ref())? {
        lines.push(format!("wrote {}", file.display()));
    }
    lines.push(format!(
        "study \"{}\" finished in {:.1} s (computed in {:.1} s)",
        study.study.name,
        start.elapsed().as_secs_f64(),
        results.seconds
    ));
    Ok(lines)
}

/// Refuses to score the images of `real` where one of them (by name and size) is among the
/// images `wakes` trains on: a detector scored on its own training images measures nothing.
fn refuse_images_trained_on(wakes: &Path, real: &Path) -> Result<()> {
    // every file but the drawings, by name and size
    let files = |dir: &Path| -> Vec<(std::ffi::OsString, u64)> {
        (real_sea::files(dir).into_iter())
            .filter(|(name, _)| Path::new(name).extension().is_none_or(|x| x != "geojson"))
            .collect()
    };
    let trained = files(wakes);
    let shared: Vec<_> = files(real).into_iter().filter(|f| trained.contains(f)).collect();
    match shared.first() {
        Some((first, _)) => Err(anyhow::anyhow!(
            "--real {} holds {} image(s) that transfer.wake_images {} trains on ({}, by name and size): score the detectors on images they were not trained on",
            real.display(),
            shared.len(),
            wakes.display(),
            first.to_string_lossy()
        )),
        None => Ok(()),
    }
}

/// The images of `real_dir` scored by the study's detectors (written to `transfer/real.json`),
/// or, without it, the scores an earlier run kept for these detectors.
fn real_scores(
    dir: &Path,
    results: &TransferResults,
    real_dir: Option<&Path>,
    quiet: bool,
) -> Result<Option<real::RealResults>> {
    let file = real::real_file(dir);
    let Some(real_dir) = real_dir else {
        let kept = std::fs::read_to_string(&file).ok();
        let kept = kept.and_then(|t| serde_json::from_str::<real::RealResults>(&t).ok());
        return Ok(kept.filter(|r| r.key == results.key));
    };
    let detectors: Vec<(f64, PathBuf)> = results
        .detectors
        .iter()
        .map(|d| (d.footprint, d.file.clone()))
        .collect();
    let template = "{spinner} real images: [{bar:30}] {pos}/{len} | {elapsed_precise}, {eta} left";
    let bar = crate::progress_bar(quiet, 0, template);
    let scored = real::score_real(real_dir, dir, &results.key, &detectors, &mut |done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    });
    bar.finish_and_clear();
    let scored = scored?;
    write_results(&file, &scored)?;
    Ok(Some(scored))
}

fn compute(
    study: &Study,
    plan: &TransferPlan,
    dir: &Path,
    device: &Device,
    display: &Display,
    key: String,
) -> Result<TransferResults> {
    let render_start = Instant::now();
    let spacings: Vec<f64> = plan.footprints.iter().map(|&f| plan.spacing(f)).collect();
    let sea = match &plan.sea_images {
        Some(dir) => real_sea::load(dir, &spacings)?,
        None => spacings.iter().map(|_| Vec::new()).collect(),
    };
    let (examples, training_scenes, display_scenes) = training_windows(dir, study, plan, display, &sea)?;
    let render_seconds = render_start.elapsed().as_secs_f64();
    display.step(2, "training", (plan.footprints.len() * plan.epochs) as u64, "epochs");
    let mut trained = Vec::new();
    for (footprint_windows, &footprint) in examples.iter().zip(&plan.footprints) {
        let windows = &footprint_windows.examples;
        let start = Instant::now();
        let mut last = (f64::NAN, f64::NAN);
        let classifier: WakeClassifier = train_classifier(windows, &recipe(plan), plan.seed, device, &mut |e| {
            last = (e.loss, e.accuracy);
            display.advance(1, format!("{footprint:.0} m: {}", e.describe()));
        })?;
        let spacing = plan.spacing(footprint);
        let info = ModelInfo {
            architecture: plan.architecture,
            bands: Input::single(Band::C),
            input_size: plan.window,
            threshold: 0.5,
            unet_width: 16,
            pixel_spacing: Some(spacing),
            looks: None,
            input_scale: Some("linear".into()),
            calibration: None,
            input_form: plan.input,
            head: plan.head,
        };
        let factor = (spacing / SPACING).round() as usize;
        let detector = Detector {
            classifier,
            segmenter: None,
        };
        let wake_windows = windows.iter().filter(|e| e.label == 1).count();
        let seconds = start.elapsed().as_secs_f64();
        trained.push((
            Scanner { detector, info, factor },
            (
                windows.len(),
                wake_windows,
                seconds,
                last,
                (
                    footprint_windows.on_track,
                    footprint_windows.shown,
                    visibility::Spread::of(&footprint_windows.visibility),
                    visibility::Spread::of(&footprint_windows.sea_visibility),
                ),
            ),
        ));
    }
    let base = study.base_config()?;
    let configs = |first: usize| -> Vec<_> {
        (0..plan.open_sea_scenes)
            .filter_map(|j| open_sea_config(&base, first, j))
            .collect()
    };
    let (scanners, trained): (Vec<Scanner>, Vec<_>) = trained.into_iter().unzip();
    let (threshold_configs, unseen_configs) = (configs(THRESHOLD_SCENES), configs(scenes::FIRST_UNSEEN_SCENE));
    let look_alikes = |c: &wakelab_core::WakelabConfig, pair: &mut SeaPair| {
        let drawn = scenes::add_look_alikes(pair, c, plan);
        drawn.ships.iter().map(|s| s.centre).collect()
    };
    display.step(3, "open sea (threshold)", threshold_configs.len() as u64, "scenes");
    let (tallies, km2) = scan_scenes(dir, &threshold_configs, &as_rendered, &scanners, device, &mut |_| {
        display.advance(1, String::new())
    })?;
    display.step(4, "open sea (unseen)", unseen_configs.len() as u64, "scenes");
    let (unseen, unseen_km2) = scan_scenes(dir, &unseen_configs, &as_rendered, &scanners, device, &mut |_| {
        display.advance(1, String::new())
    })?;
    display.step(5, "look-alike test set", unseen_configs.len() as u64, "scenes");
    let (alike, alike_km2) = scan_scenes(dir, &unseen_configs, &look_alikes, &scanners, device, &mut |_| {
        display.advance(1, String::new())
    })?;
    std::fs::create_dir_all(detectors_dir(dir)).map_err(|e| WakelabError::io(detectors_dir(dir), e))?;
    let mut detectors = Vec::new();
    let per_detector = (scanners.into_iter().zip(trained).zip(tallies))
        .zip(unseen)
        .zip(alike)
        .zip(&plan.footprints)
        .zip(&sea);
    for ((((((scanner, trained), tally), unseen), alike), &footprint), sea) in per_detector {
        let (windows, wake_windows, seconds, last, visibility) = trained;
        let (on_track, on_track_shown, track_visibility, sea_visibility) = visibility;
        let simulated = threshold_for_alarm_rate(&tally.sea, km2, plan.alarms_per_1000_km2);
        let real_sea = real_sea::threshold(&scanner, sea, plan.alarms_per_1000_km2, device)?;
        let threshold = real_sea.as_ref().map_or(simulated, |r| simulated.max(r.threshold));
        let real_sea = real_sea.map(|r| r.at(threshold));
        let (scores, labels) = window_scores(&unseen);
        let reliability_bins = reliability(&scores, &labels, RELIABILITY_BINS);
        let Scanner { detector, mut info, .. } = scanner;
        info.threshold = threshold;
        info.calibration = Some(Calibration {
            temperature: 1.0,
            false_alarms_per_1000_km2: Some(plan.alarms_per_1000_km2),
            open_sea_km2: Some(km2),
        });
        let file = detector_file(dir, footprint);
        save_detector(&detector, &info, &file)?;
        detectors.push(TransferDetector {
            footprint,
            window: plan.window,
            spacing: plan.spacing(footprint),
            training_windows: windows,
            wake_windows,
            track_windows: on_track,
            track_windows_shown: on_track_shown,
            track_visibility,
            sea_visibility,
            training_seconds: seconds,
            final_loss: last.0,
            final_accuracy: last.1,
            scenes: threshold_configs.len(),
            km2,
            alarms_at_half: per_1000(tally.sea_alarms(0.5), km2),
            threshold,
            alarms_at_threshold: per_1000(tally.sea_alarms(threshold), km2),
            wakes_found_at_half: tally.wakes_found(0.5, FOUND_WITHIN_M),
            wakes_found: tally.wakes_found(threshold, FOUND_WITHIN_M),
            off_wake_alarms: per_1000(tally.off_wake_alarms(threshold, FOUND_WITHIN_M), km2),
            window_auc: window_auc(&tally),
            unseen_scenes: unseen_configs.len(),
            unseen_km2,
            unseen_alarms: per_1000(unseen.sea_alarms(threshold), unseen_km2),
            unseen_wakes_found: unseen.wakes_found(threshold, FOUND_WITHIN_M),
            unseen_off_wake_alarms: per_1000(unseen.off_wake_alarms(threshold, FOUND_WITHIN_M), unseen_km2),
            reliability: reliability_bins.clone(),
            calibration_error: expected_calibration_error(&reliability_bins),
            look_alikes: LookAlikeScore {
                km2: alike_km2,
                alarms: per_1000(alike.sea_alarms(threshold), alike_km2),
                ships: alike.ships,
                ship_alarms: alike.ship_alarms(threshold, FOUND_WITHIN_M),
                wakes_found: alike.wakes_found(threshold, FOUND_WITHIN_M),
                off_wake_alarms: per_1000(alike.off_wake_alarms(threshold, FOUND_WITHIN_M), alike_km2),
            },
            real_sea,
            file,
        });
    }
    Ok(TransferResults {
        key,
        seconds: 0.0,
        plan: plan.clone(),
        training_scenes,
        display_scenes,
        render_seconds,
        alarms_target: plan.alarms_per_1000_km2,
        detectors,
    })
}

/// The probabilities of the open sea's windows (label 0) and of the windows on a wake (1).
fn window_scores(tally: &Tally) -> (Vec<f64>, Vec<u8>) {
    let scores = tally
        .sea_windows
        .iter()
        .chain(&tally.wake_windows)
        .map(|w| w.1)
        .collect();
    let labels = tally
        .sea_windows
        .iter()
        .map(|_| 0)
        .chain(tally.wake_windows.iter().map(|_| 1))
        .collect();
    (scores, labels)
}

/// ROC AUC of the windows on a wake against the open sea's, by probability.
fn window_auc(tally: &Tally) -> Option<f64> {
    let (scores, labels) = window_scores(tally);
    roc_auc(&scores, &labels)
}

/// Bins of a reliability diagram.
const RELIABILITY_BINS: usize = 10;

#[cfg(test)]
mod tests {
    use super::*;
    use wakelab_learn::device::parse_device;
    use wakelab_learn::store::load_detector;

    /// A transfer study of two training scenes, one epoch and one open-sea scene each way: the
    /// detector written holds the threshold set on the open sea (no alarm left there: fewer than
    /// one allowed on 26 km^2), its spacing and the area; the report's table has its row; a
    /// second run reuses the results.
    #[test]
    fn a_small_transfer_study_writes_a_thresholded_detector_and_its_report() {
        let mut study = Study::from_toml_str(wakelab_dataset::study::TRANSFER_STUDY, "transfer").unwrap();
        let plan = study.transfer.as_mut().unwrap();
        plan.scenes = 2;
        plan.footprints = vec![1280.0];
        plan.epochs = 1;
        plan.open_sea_scenes = 1;
        plan.swell_fraction = 0.0;
        // every wake window kept, so that the counts below hold (the embedded study trains on
        // the look-alikes and keeps a wake window only where the wake shows)
        plan.look_alike_training = false;
        let dir = tempfile::tempdir().unwrap();
        let device = parse_device("cpu").unwrap();
        let lines = run_transfer(&study, dir.path(), &device, None, true).unwrap();
        assert!(
            lines.iter().any(|l| l.contains("1.28 km window (20 m pixels)")),
            "{lines:?}"
        );
        let results = load_transfer(dir.path()).unwrap();
        let d = &results.detectors[0];
        assert_eq!((d.scenes, d.unseen_scenes), (1, 1));
        assert!(d.training_windows >= 3 && d.wake_windows >= 1, "{d:?}");
        // every wake window is on the track (none dropped: look_alike_training is off), and
        // the wake shows in at most those
        assert_eq!(d.track_windows, d.wake_windows, "{d:?}");
        assert!(d.track_windows_shown <= d.track_windows, "{d:?}");
        // the wake and its twin per window on the track, and the darkest window of each scene
        assert_eq!(
            d.training_windows,
            2 * d.track_windows + results.training_scenes,
            "{d:?}"
        );
        // every window on the track is measured, with and without its wake
        let measured = |v: Option<visibility::Spread>| v.map_or(0, |v| v.count);
        assert_eq!(measured(d.track_visibility), d.track_windows, "{d:?}");
        assert_eq!(measured(d.sea_visibility), d.track_windows, "{d:?}");
        assert_eq!(d.alarms_at_threshold, 0.0);
        assert!((d.km2 - 5.12 * 5.12).abs() < 1e-9);
        let (_, info) = load_detector(&d.file, None, &device).unwrap();
        assert_eq!(
            (info.threshold, info.pixel_spacing, info.input_size),
            (d.threshold, Some(20.0), 64)
        );
        assert_eq!(info.calibration.unwrap().open_sea_km2, Some(d.km2));
        // the look-alike test set is the unseen sea again, with the ships its scene draws
        assert!((d.look_alikes.km2 - d.unseen_km2).abs() < 1e-9);
        let unseen = open_sea_config(&study.base_config().unwrap(), scenes::FIRST_UNSEEN_SCENE, 0).unwrap();
        let blank = ndarray::Array2::from_elem((512, 512), 0.01f32);
        let mut pair = SeaPair {
            with: blank.clone(),
            without: blank,
            track: ((0.0, 0.0), (0.0, 1.0)),
            spacing: 10.0,
            km2: 26.2144,
        };
        let drawn = scenes::add_look_alikes(&mut pair, &unseen, study.transfer.as_ref().unwrap());
        assert_eq!(d.look_alikes.ships, drawn.ships.len(), "{:?}", d.look_alikes);
        // every window of the unseen scene's open sea (7 x 7 of 64 pixels at a stride of 32 on
        // 256) and those on its wake fall in the reliability bins
        let binned: usize = d.reliability.iter().map(|b| b.count).sum();
        assert!((50..=98).contains(&binned) && d.reliability.len() == 10, "{binned}");
        assert!(d.calibration_error.is_finite());
        assert!(dir.path().join("report/transfer_reliability.svg").exists());
        let table = std::fs::read_to_string(dir.path().join("report/tables/transfer.csv")).unwrap();
        assert_eq!(table.lines().count(), 2);
        assert!(table.lines().nth(1).unwrap().starts_with("1280,20,"), "{table}");
        let again = run_transfer(&study, dir.path(), &device, None, true).unwrap();
        assert!(again
            .last()
            .unwrap()
            .contains(&format!("(computed in {:.1} s)", results.seconds)));

        // --real: two images of 10 m speckle, one with a dark line drawn as its wake
        let real = dir.path().join("real");
        std::fs::create_dir_all(&real).unwrap();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let sea = |rng: &mut rand_chacha::ChaCha8Rng| {
            ndarray::Array2::from_shape_fn((256, 256), |_| 0.01 * -(1.0 - rand::RngExt::random::<f32>(rng)).ln())
        };
        let mut wake = sea(&mut rng);
        wake.slice_mut(ndarray::s![40..220, 126..130]).mapv_inplace(|v| v * 0.3);
        ndarray_npy::write_npy(real.join("wake.npy"), &wake).unwrap();
        // the sea holds a ship: 60 m square, 30 dB above the sea
        let mut with_ship = sea(&mut rng);
        with_ship.slice_mut(ndarray::s![60..66, 60..66]).fill(10.0);
        ndarray_npy::write_npy(real.join("sea.npy"), &with_ship).unwrap();
        let hints = r#""wakelab": {"coordinates": "pixel", "pixel_spacing_m": 10, "scale": "linear"}"#;
        let line = r#"{"type": "Feature", "properties": {}, "geometry": {"type": "LineString", "coordinates": [[128, 40], [128, 220]]}}"#;
        std::fs::write(
            real.join("wake.geojson"),
            format!(r#"{{"type": "FeatureCollection", {hints}, "features": [{line}]}}"#),
        )
        .unwrap();
        // its ship drawn as a box, and a second ship drawn where the sea holds none
        let ships = r#"{"type": "Feature", "properties": {"kind": "ship"}, "geometry": {"type": "Polygon", "coordinates": [[[60, 60], [65, 60], [65, 65], [60, 65], [60, 60]]]}},
                       {"type": "Feature", "properties": {"kind": "ship"}, "geometry": {"type": "Point", "coordinates": [200, 200]}}"#;
        std::fs::write(
            real.join("sea.geojson"),
            format!(r#"{{"type": "FeatureCollection", {hints}, "features": [{ships}]}}"#),
        )
        .unwrap();
        let lines = run_transfer(&study, dir.path(), &device, Some(&real), true).unwrap();
        assert!(
            lines.iter().any(|l| l.contains("real images, 1.28 km window")),
            "{lines:?}"
        );
        let scored: real::RealResults =
            serde_json::from_str(&std::fs::read_to_string(real::real_file(dir.path())).unwrap()).unwrap();
        assert_eq!(scored.scores.len(), 2);
        let s = &scored.summaries[0];
        assert_eq!((s.wake_images, s.no_wake_images), (1, 1));
        // 2.56 x 2.56 km (6.55 km^2) each, less any border no full window covers
        assert!(scored.scores.iter().all(|s| s.km2 > 4.0 && s.km2 < 6.56), "{scored:?}");
        assert!(dir.path().join("real/1280m/wake/detections.json").exists());
        // the line darkens 2 of the 20 m pixels by 5.2 dB; a strip of 128 four-look pixels
        // deviates by 2.3 dB over the square root of 128, 0.2 dB: some 13-26 deviations
        let wake_score = scored.scores.iter().find(|s| s.image == "wake.npy").unwrap();
        let visibility = wake_score.wake_visibility[0].unwrap();
        assert!((10.0..40.0).contains(&visibility), "{visibility}");
        // a detector of lines alone finds that line: the strongest line of the scan is on it
        assert_eq!(wake_score.peak_by_line, Some(true), "{wake_score:?}");
        let csv = std::fs::read_to_string(dir.path().join("report/tables/transfer_real.csv")).unwrap();
        assert_eq!(csv.lines().count(), 3, "{csv}");
        // the classic search ran once per image: the line (1.8 km, 5.2 dB dark) is a free wake
        // along the drawn one, and the sea has none
        let search: Vec<_> = scored
            .search
            .iter()
            .map(|s| (s.image.as_str(), s.found, s.false_wakes))
            .collect();
        assert_eq!(search, [("sea.npy", 0, 0), ("wake.npy", 1, 0)], "{:?}", scored.search);
        assert!(scored.search[1].axis_errors_deg[0] < 2.0, "{:?}", scored.search);
        // the drawn ship is found, the one drawn on empty sea is not; the wake image's ships
        // are not drawn, so not scored
        let ships = scored.search[0].drawn_ships.unwrap();
        assert_eq!((ships.drawn, ships.found), (2, 1), "{:?}", scored.search);
        assert_eq!(ships.false_ships, scored.search[0].ships - 1, "{:?}", scored.search);
        assert_eq!(scored.search[1].drawn_ships, None);
        let summary = scored.search_summary.as_ref().unwrap();
        assert_eq!(
            (summary.ship_images, summary.drawn_ships, summary.ships_found),
            (1, 2, 1)
        );
        let csv = std::fs::read_to_string(dir.path().join("report/tables/transfer_real_search.csv")).unwrap();
        assert_eq!(csv.lines().count(), 3, "{csv}");
        // a later run without --real keeps the section while the detectors are the same
        run_transfer(&study, dir.path(), &device, None, true).unwrap();
        let md = std::fs::read_to_string(dir.path().join("report/transfer.md")).unwrap();
        assert!(
            md.contains("## Real images") && md.contains("| wake.npy | 1280 | 1 |"),
            "{md}"
        );

        // --sea-images: the image without a wake as real sea; each wake that shows is drawn
        // onto PER_WAKE of its windows, each beside the window as it is
        let sea_dir = dir.path().join("sea_images");
        std::fs::create_dir_all(&sea_dir).unwrap();
        for file in ["sea.npy", "sea.geojson"] {
            std::fs::copy(real.join(file), sea_dir.join(file)).unwrap();
        }
        let mut on_real_sea = study.clone();
        on_real_sea.transfer.as_mut().unwrap().sea_images = Some(sea_dir.clone());
        let run = dir.path().join("on_real_sea");
        run_transfer(&on_real_sea, &run, &device, None, true).unwrap();
        let results = load_transfer(&run).unwrap();
        let d = &results.detectors[0];
        let drawn = 2 * real_sea::PER_WAKE * d.track_windows_shown;
        assert!(d.track_windows_shown >= 1, "{d:?}");
        assert_eq!(
            d.training_windows,
            2 * d.track_windows + results.training_scenes + drawn,
            "{d:?}"
        );
        assert_eq!(d.wake_windows, d.track_windows + drawn / 2, "{d:?}");
        let md = std::fs::read_to_string(run.join("report/transfer.md")).unwrap();
        assert!(md.contains(&format!("real images of `{}`", sea_dir.display())), "{md}");
        // the threshold also holds the rate on the real sea: its 6.55 km^2 allow no alarm at
        // 1 per 1,000 km^2, so none of its alarms lies above the threshold
        let r = d.real_sea.as_ref().expect("the real sea's threshold");
        assert_eq!(r.images, 1, "{r:?}");
        assert!((r.km2 - 6.5536).abs() < 1e-6, "{r:?}");
        assert!(d.threshold >= r.threshold && r.alarms_at_threshold == 0.0, "{d:?}");
        assert!(
            md.contains("also holds that rate on the real sea of `--sea-images` (7 km^2 in 1 image(s) scanned)"),
            "{md}"
        );
        // its strongest alarms are reported on the image's own 256 x 256 pixels of 10 m,
        // strongest first, at most STRONGEST
        assert!(
            !r.strongest.is_empty() && r.strongest.len() <= real_sea::STRONGEST,
            "{r:?}"
        );
        // no alarm allowed on 6.55 km^2: the threshold is the strongest alarm's probability, taken
        // from the separate list of every alarm, so the table's first row must be that alarm
        assert_eq!(r.threshold, r.strongest[0].probability, "{r:?}");
        for (a, next) in r.strongest.iter().zip(r.strongest.iter().skip(1)) {
            assert!(a.probability >= next.probability, "{r:?}");
        }
        for a in &r.strongest {
            assert_eq!(a.image, "sea.npy");
            assert!((0.0..256.0).contains(&a.row) && (0.0..256.0).contains(&a.col), "{a:?}");
            assert!((0.0..=1.0).contains(&a.probability), "{a:?}");
        }
        assert!(
            md.contains(&format!(
                "| sea.npy | {:.0} | {:.0} |",
                r.strongest[0].row, r.strongest[0].col
            )),
            "{md}"
        );
        // an image with a wake drawn is refused, by name
        std::fs::copy(real.join("wake.geojson"), sea_dir.join("sea.geojson")).unwrap();
        let refused = dir.path().join("refused");
        let e = format!(
            "{:#}",
            run_transfer(&on_real_sea, &refused, &device, None, true).unwrap_err()
        );
        assert!(e.contains("sea.npy has 1 wake(s) drawn"), "{e}");
        assert!(!refused.exists());

        // --wake-images: the folder of both images, its one drawn wake giving PER_WAKE windows
        // along it, and the two images as many clear of it each (the sea's none to be clear of)
        let mut on_real_wakes = study.clone();
        on_real_wakes.transfer.as_mut().unwrap().wake_images = Some(real.clone());
        let run = dir.path().join("on_real_wakes");
        run_transfer(&on_real_wakes, &run, &device, None, true).unwrap();
        let results = load_transfer(&run).unwrap();
        let d = &results.detectors[0];
        let per_wake = real_wakes::PER_WAKE;
        assert_eq!(
            d.training_windows,
            2 * d.track_windows + results.training_scenes + 3 * per_wake,
            "{d:?}"
        );
        assert_eq!(d.wake_windows, d.track_windows + per_wake, "{d:?}");
        let md = std::fs::read_to_string(run.join("report/transfer.md")).unwrap();
        assert!(
            md.contains(&format!("real images of `{}` (`--wake-images`)", real.display())),
            "{md}"
        );
        // scoring the images it trained on is refused before anything is written, as is a
        // folder without a wake drawn
        let refused = dir.path().join("refused_wakes");
        let e = format!(
            "{:#}",
            run_transfer(&on_real_wakes, &refused, &device, Some(&real), true).unwrap_err()
        );
        assert!(e.contains("holds 2 image(s) that transfer.wake_images"), "{e}");
        on_real_wakes.transfer.as_mut().unwrap().wake_images = Some(sea_dir.join("none"));
        std::fs::create_dir_all(sea_dir.join("none")).unwrap();
        std::fs::copy(real.join("sea.npy"), sea_dir.join("none/sea.npy")).unwrap();
        std::fs::copy(real.join("sea.geojson"), sea_dir.join("none/sea.geojson")).unwrap();
        let e = format!(
            "{:#}",
            run_transfer(&on_real_wakes, &refused, &device, None, true).unwrap_err()
        );
        assert!(e.contains("no image with a wake drawn"), "{e}");
        assert!(!refused.exists());
    }
}

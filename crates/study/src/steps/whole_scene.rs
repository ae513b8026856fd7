//! The scan step of `wakelab run`: `wakelab detect`'s scan of one scene eight chips wide, in
//! every band, by the study's own "base" detectors. It writes `whole_scene/` (each band's
//! numbers in `whole_scene.json`, its image, probability map and wake mask as npy), which the
//! report renders.
//!
//! The scene is the study's first pair made large: its sea, wind and sensors, 8 x the chip's
//! side (fewer where the study's wake is too short or the scene would pass [`MAX_SIDE`] pixels),
//! natural slicks over a fifth of the sea and three wakes of the study's ship
//! (`scene.other_wakes`): its own 4 km behind the stern crossing the centre at 30 degrees, one
//! 6 km behind at 300 degrees and one 2.4 km behind at 160 degrees, each passing 0.4 of the
//! half-side off the centre. Each single band's saved "base" detector (`learn/<band>/models/`,
//! the last repetition's) scans it with windows of its input size at half that stride
//! ([`wakelab_learn::detect::detect_image`]). Against the physics mask of that band the report
//! gives whether the map's peak lies on the wake, the map's mean on and off the wake, and the
//! share of off-wake cells above the threshold (false alarms, slicks among them); and, at the
//! threshold that flags 5 % of the detector's own no-wake test chips ([`chip_threshold`]), the
//! shares of off-wake and wake cells above it: whether the chips' false-alarm rate carries over
//! to a whole scene.

use super::context::{fnv_hex, step_time};
use super::study_run::StudyRun;
use crate::{Result, StepTime};
use ndarray::{s, Array2};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::time::Instant;
use wakelab_core::config::WakePlacement;
use wakelab_core::io::write_atomically;
use wakelab_core::WakelabError;
use wakelab_dataset::render::render_pair;
use wakelab_dataset::study::{ScenePair, Study};
use wakelab_learn::data::RadarScale;
use wakelab_learn::detect::{detect_image, ScanOptions};
use wakelab_learn::models::Architecture;
use wakelab_learn::store::load_detector;
use wakelab_schema::band::{Band, Input};
use wakelab_schema::split::Split;

/// The scene's side in chips.
const CHIPS: usize = 8;
/// Largest side of the scene (pixels): the paper study's 1024-pixel chips get a scene of two,
/// whose surface and images take a few hundred MB, not the tens of GB of eight.
const MAX_SIDE: usize = 2048;
/// Distance of the scene centre behind the stern (m) and the ship's heading in it (degrees).
const ALONG_TRACK: f64 = 4000.0;
const HEADING: f64 = 30.0;
/// Expected fraction of the sea under natural slicks.
pub const SLICKS: f64 = 0.2;

/// One band's scan of the scene: its numbers, as `whole_scene.json` holds them.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct WholeSceneBand {
    pub band: Band,
    /// The scene's side (pixels), pixel spacing (m), side in chips and wakes.
    pub side: usize,
    pub pixel_spacing: f64,
    pub chips: usize,
    pub wakes: Vec<WakePlacement>,
    /// The detector's threshold and the largest window probability in the scene.
    pub threshold: f64,
    pub probability: f64,
    pub peak_on_wake: bool,
    /// Mean probability of the cells on and off the wake (None: no such cell).
    pub mean_on_wake: Option<f64>,
    pub mean_off_wake: Option<f64>,
    /// Share of the off-wake cells at or above the threshold.
    pub false_alarm_cells: f64,
    /// The threshold that flags [`CHIP_FALSE_ALARMS`] of the detector's no-wake test chips, and
    /// the shares of the off-wake and the wake cells above it (None without test outputs).
    pub chip_threshold: Option<ChipThreshold>,
}

/// One band's scan with its pictures: the image as rendered (radar sigma0, IR in K), the mean
/// window probability per stride cell (NaN: unscored) and the band's physics mask of the wakes.
pub struct WholeScene {
    pub numbers: WholeSceneBand,
    pub image: Array2<f32>,
    pub map: Array2<f32>,
    pub mask: Array2<u8>,
}

/// The share of no-wake test chips a [`chip_threshold`] flags.
pub const CHIP_FALSE_ALARMS: f64 = 0.05;

/// A whole scene's cells at the threshold calibrated on the detector's test chips.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ChipThreshold {
    pub threshold: f64,
    /// Off-wake cells above it (false alarms) and wake cells above it (detections).
    pub false_alarm_cells: f64,
    pub wake_cells: f64,
    /// The off-wake cells above it among those holding a natural slick's pixel (None: no such
    /// cell) and among the rest, the open sea.
    pub slick_cells: Option<f64>,
    pub open_sea_cells: f64,
}

/// The smallest threshold that at most [`CHIP_FALSE_ALARMS`] of `no_wake` chip outputs exceed:
/// their order statistic of rank ceil((1 - share) n) (the nearest-rank percentile); None when
/// there are none.
pub fn chip_threshold(mut no_wake: Vec<f64>) -> Option<f64> {
    if no_wake.is_empty() {
        return None;
    }
    no_wake.sort_by(f64::total_cmp);
    let rank = ((1.0 - CHIP_FALSE_ALARMS) * no_wake.len() as f64).ceil() as usize;
    Some(no_wake[rank.clamp(1, no_wake.len()) - 1])
}

/// The "base" detector's outputs on the no-wake test chips of `band`, from the repetition whose
/// detector is saved (the last).
fn no_wake_test_outputs(run: &StudyRun, band: Band) -> Vec<f64> {
    let input = Input::single(band);
    let ours = |o: &&wakelab_schema::results::Output| {
        o.bands == input && o.architecture == Architecture::Base && o.split == Split::Test
    };
    let Some(last) = run.outputs.iter().filter(ours).map(|o| o.repetition).max() else {
        return Vec::new();
    };
    run.outputs
        .iter()
        .filter(ours)
        .filter(|o| o.repetition == last && o.label == 0)
        .map(|o| o.output)
        .collect()
}

/// The other wakes' courses in the image (degrees) and their ages as multiples of the first
/// wake's distance behind the stern.
const OTHER_WAKES: [(f64, f64); 2] = [(300.0, 1.5), (160.0, 0.6)];

/// The scene's configuration: the first pair's, made large, with slicks, its own wake at
/// [`HEADING`] through the centre and two more ([`OTHER_WAKES`]) passing 0.4 of the half-side to
/// either side of it; `(pair, chips)`. A study whose simulated wake is too short for a scene
/// [`CHIPS`] chips wide at [`ALONG_TRACK`] (or [`MAX_SIDE`] pixels) gets the widest of 8, 4 or 2 chips that fits, centred
/// at 4 km or halfway along the wake, with its own wake alone if the others do not fit; None if
/// nothing fits.
fn scene_pair(study: &Study) -> Result<Option<(ScenePair, usize)>> {
    let Some(first) = study.pairs()?.into_iter().next() else {
        return Ok(None);
    };
    let halfway = 0.5 * first.config.wake_end();
    let chip = first.config.scene.size;
    for chips in [CHIPS, CHIPS / 2, CHIPS / 4]
        .into_iter()
        .filter(|k| k * chip <= MAX_SIDE)
    {
        for along_track in [ALONG_TRACK, halfway] {
            for others in [true, false] {
                let mut pair = first.clone();
                let c = &mut pair.config;
                c.scene.size *= chips;
                c.scene.along_track = along_track;
                c.scene.cross_track = 0.0;
                c.scene.heading = HEADING;
                let half = 0.5 * c.scene.size as f64 * c.scene.pixel_spacing;
                c.scene.other_wakes = if others {
                    OTHER_WAKES
                        .iter()
                        .zip([0.4, -0.4])
                        .map(|(&(heading, age), side)| WakePlacement {
                            along_track: age * along_track,
                            cross_track: side * half,
                            heading,
                        })
                        .collect()
                } else {
                    Vec::new()
                };
                c.slicks.coverage = SLICKS;
                if c.validate().is_ok() {
                    return Ok(Some((pair, chips)));
                }
            }
        }
    }
    Ok(None)
}

/// Whether the detection map's cell (r, c), `stride` pixels on a side, holds any pixel of `mask`.
fn touches(mask: &Array2<u8>, stride: usize, r: usize, c: usize) -> bool {
    let (h, w) = mask.dim();
    let (r0, c0) = ((r * stride).min(h), (c * stride).min(w));
    let block = mask.slice(s![r0..((r + 1) * stride).min(h), c0..((c + 1) * stride).min(w)]);
    block.iter().any(|&v| v > 0)
}

/// A detection map's probabilities sorted by where their cells lie.
#[derive(Debug, Default, PartialEq)]
struct CellSplit {
    /// Cells holding a pixel of the wake's mask.
    on_wake: Vec<f64>,
    /// Every other cell.
    off_wake: Vec<f64>,
    /// The off-wake cells holding a pixel of a natural slick.
    on_slick: Vec<f64>,
    /// The off-wake cells holding none.
    open_sea: Vec<f64>,
}

/// Sort the map's cells into wake and off-wake, and the off-wake ones into slick and open sea.
fn split_cells(map: &Array2<f32>, stride: usize, wake: &Array2<u8>, slicks: Option<&Array2<u8>>) -> CellSplit {
    let mut split = CellSplit::default();
    for ((r, c), &p) in map.indexed_iter() {
        let p = p as f64;
        if touches(wake, stride, r, c) {
            split.on_wake.push(p);
            continue;
        }
        split.off_wake.push(p);
        match slicks {
            Some(m) if touches(m, stride, r, c) => split.on_slick.push(p),
            _ => split.open_sea.push(p),
        }
    }
    split
}

/// The scan's folder in the run directory.
pub fn scan_dir(run_dir: &Path) -> PathBuf {
    run_dir.join("whole_scene")
}

/// `whole_scene.json`: the scan's key, the seconds it took and every band's numbers.
#[derive(Serialize, Deserialize)]
struct CachedScan {
    key: String,
    seconds: f64,
    bands: Vec<WholeSceneBand>,
}

/// The picture files of `band` in the scan's folder: image, probability map, wake mask.
fn picture_paths(dir: &Path, band: Band) -> [PathBuf; 3] {
    ["image", "probability", "mask"].map(|what| dir.join(format!("{}_{what}.npy", band.name())))
}

/// What the scan depends on: the dataset (its manifest), the scene's configuration, the saved
/// detectors' bytes and wakelab's version.
fn scan_key(run_dir: &Path, manifest_hash: &str, pair: &ScenePair, bands: &[Band]) -> Result<String> {
    let mut text = format!("{manifest_hash} {:?} {}", pair.config, env!("CARGO_PKG_VERSION"));
    for &band in bands {
        let path = model_path(run_dir, band);
        let bytes = std::fs::read(&path).map_err(|e| WakelabError::io(&path, e))?;
        text.push_str(&format!(" {band} {:016x}", wakelab_dataset::fnv(bytes)));
    }
    Ok(fnv_hex(&text))
}

/// The saved "base" detector of `band` in the run directory.
pub(super) fn model_path(run_dir: &Path, band: Band) -> PathBuf {
    let input = Input::single(band);
    crate::output::detector_path(&run_dir.join("learn").join(input.name()), &input, Architecture::Base)
}

/// The scan step: scan the scene (or reuse the scan in `whole_scene/` when its key matches) and
/// write its files.
pub fn scan_step(run_dir: &Path, study: &Study, run: &StudyRun, manifest_hash: &str) -> Result<StepTime> {
    let start = Instant::now();
    let dir = scan_dir(run_dir);
    std::fs::create_dir_all(&dir).map_err(|e| WakelabError::io(&dir, e))?;
    let bands: Vec<Band> = run.inputs.iter().filter_map(|i| i.as_single()).collect();
    let bands: Vec<Band> = bands.into_iter().filter(|&b| model_path(run_dir, b).exists()).collect();
    let pair = if bands.is_empty() { None } else { scene_pair(study)? };
    let key = match &pair {
        Some((pair, _)) => scan_key(run_dir, manifest_hash, pair, &bands)?,
        None => fnv_hex("no scene"),
    };
    let json = dir.join("whole_scene.json");
    let cached: Option<CachedScan> = std::fs::read_to_string(&json)
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok())
        .filter(|c: &CachedScan| c.key == key);
    let complete = |c: &CachedScan| {
        c.bands
            .iter()
            .all(|b| picture_paths(&dir, b.band).iter().all(|p| p.exists()))
    };
    if let Some(c) = cached.filter(complete) {
        return Ok(step_time("scan", start, Some(c.seconds)));
    }
    let scans = match pair {
        Some((pair, chips)) => scan_whole_scene(run_dir, &pair, chips, &bands, run)?,
        None => Vec::new(),
    };
    for scan in &scans {
        let [image, probability, mask] = picture_paths(&dir, scan.numbers.band);
        wakelab_dataset::write_npy_atomically(&image, &scan.image)?;
        wakelab_dataset::write_npy_atomically(&probability, &scan.map)?;
        wakelab_dataset::write_npy_atomically(&mask, &scan.mask)?;
    }
    let cached = CachedScan {
        key,
        seconds: start.elapsed().as_secs_f64(),
        bands: scans.into_iter().map(|s| s.numbers).collect(),
    };
    write_atomically(&json, serde_json::to_string_pretty(&cached)?.as_bytes())?;
    Ok(step_time("scan", start, None))
}

/// The scan the scan step wrote into `run_dir` (empty: no scene fitted or no detector was
/// saved).
pub fn load_whole_scene(run_dir: &Path) -> Result<Vec<WholeScene>> {
    let dir = scan_dir(run_dir);
    let json = dir.join("whole_scene.json");
    let text = std::fs::read_to_string(&json).map_err(|e| WakelabError::io(&json, e))?;
    let cached: CachedScan = serde_json::from_str(&text).map_err(|e| anyhow::anyhow!("{}: {e}", json.display()))?;
    let read = |path: &Path| -> Result<Array2<f32>> {
        ndarray_npy::read_npy(path).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
    };
    cached
        .bands
        .into_iter()
        .map(|numbers| {
            let [image, probability, mask] = picture_paths(&dir, numbers.band);
            let mask: Array2<u8> =
                ndarray_npy::read_npy(&mask).map_err(|e| anyhow::anyhow!("{}: {e}", mask.display()))?;
            Ok(WholeScene {
                image: read(&image)?,
                map: read(&probability)?,
                mask,
                numbers,
            })
        })
        .collect()
}

/// Scan the scene `pair` (`chips` chips wide) with the saved "base" detector of every band of
/// `bands`.
fn scan_whole_scene(
    run_dir: &Path,
    pair: &ScenePair,
    chips: usize,
    bands: &[Band],
    run: &StudyRun,
) -> Result<Vec<WholeScene>> {
    let map = wakelab_dataset::hydro_map(&run.dataset.dir, &pair.config)?;
    let (rendered, _, _) = render_pair(pair, &map, bands);
    let slicks = rendered.slick_mask;
    let device = wakelab_learn::device::parse_device("cpu")?;
    let mut out = Vec::new();
    for band_pair in rendered.bands {
        let band = band_pair.band;
        let chip = pair.config.scene.size / chips;
        let (detector, info) = load_detector(&model_path(run_dir, band), Some((Architecture::Base, chip)), &device)?;
        let options = ScanOptions {
            scale: RadarScale::Linear,
            ..ScanOptions::default()
        };
        let found = detect_image(&detector, &info, &band_pair.wake, options, &device, &mut |_, _| {})?;
        let mask = band_pair.mask;
        let (stride, map) = (found.stride, found.map);
        let cells = split_cells(&map, stride, &mask, slicks.as_ref());
        let alarms = cells.off_wake.iter().filter(|&&p| p >= found.threshold).count();
        let (on, off, on_slick, open_sea) = (cells.on_wake, cells.off_wake, cells.on_slick, cells.open_sea);
        let mean = |v: &[f64]| (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64);
        let peak = (
            (found.peak.row / stride as f64).floor() as usize,
            (found.peak.col / stride as f64).floor() as usize,
        );
        let share_above = |v: &[f64], t: f64| v.iter().filter(|&&p| p > t).count() as f64 / v.len().max(1) as f64;
        let chip_threshold = chip_threshold(no_wake_test_outputs(run, band)).map(|t| ChipThreshold {
            threshold: t,
            false_alarm_cells: share_above(&off, t),
            wake_cells: share_above(&on, t),
            slick_cells: (!on_slick.is_empty()).then(|| share_above(&on_slick, t)),
            open_sea_cells: share_above(&open_sea, t),
        });
        let numbers = WholeSceneBand {
            band,
            side: band_pair.wake.nrows(),
            pixel_spacing: pair.config.scene.pixel_spacing,
            chips,
            wakes: pair.config.scene.wake_placements(),
            peak_on_wake: touches(&mask, stride, peak.0, peak.1),
            mean_on_wake: mean(&on),
            mean_off_wake: mean(&off),
            false_alarm_cells: alarms as f64 / off.len().max(1) as f64,
            probability: found.probability,
            threshold: found.threshold,
            chip_threshold,
        };
        out.push(WholeScene {
            numbers,
            image: band_pair.wake,
            map,
            mask,
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use wakelab_dataset::study::{DEFAULT_STUDY, PAPER_STUDY};

    /// The nearest-rank percentile: of 20 outputs 0.01..0.20 the threshold flags one (5 %).
    /// A map of 3 x 3 cells of 2 px over 6 x 6 px masks: the wake fills the top row of cells, a
    /// slick touches the centre cell with one pixel and also lies under the wake (a wake cell stays
    /// a wake cell); a fourth column of cells past the masks' edge holds no pixel of either.
    #[test]
    fn cells_split_into_wake_slick_and_open_sea() {
        let map = Array2::from_shape_fn((3, 4), |(r, c)| (10 * r + c) as f32);
        let mut wake = Array2::<u8>::zeros((6, 6));
        wake.slice_mut(s![0..2, ..]).fill(1);
        let mut slicks = Array2::<u8>::zeros((6, 6));
        slicks[[3, 2]] = 1;
        slicks[[1, 1]] = 1;
        let split = split_cells(&map, 2, &wake, Some(&slicks));
        assert_eq!(split.on_wake, vec![0.0, 1.0, 2.0]);
        assert_eq!(
            split.off_wake,
            vec![3.0, 10.0, 11.0, 12.0, 13.0, 20.0, 21.0, 22.0, 23.0]
        );
        assert_eq!(split.on_slick, vec![11.0]);
        assert_eq!(split.open_sea, vec![3.0, 10.0, 12.0, 13.0, 20.0, 21.0, 22.0, 23.0]);
        // without slicks every off-wake cell is open sea
        let plain = split_cells(&map, 2, &wake, None);
        assert!(plain.on_slick.is_empty() && plain.open_sea == plain.off_wake);
    }

    #[test]
    fn the_chip_threshold_flags_five_percent_of_the_no_wake_chips() {
        let outputs: Vec<f64> = (1..=20).rev().map(|i| i as f64 / 100.0).collect();
        let t = chip_threshold(outputs.clone()).unwrap();
        assert_eq!(t, 0.19);
        assert_eq!(outputs.iter().filter(|&&p| p > t).count(), 1);
        assert_eq!(chip_threshold(vec![0.3]), Some(0.3));
        assert_eq!(chip_threshold(Vec::new()), None);
    }

    /// The default study's scene is eight 32-pixel chips with its three wakes; the paper study's
    /// 1024-pixel chips are capped at two (2048 pixels), and both configurations are valid.
    #[test]
    fn the_scene_fits_the_study_and_stays_bounded() {
        for (text, name, side, wakes) in [(DEFAULT_STUDY, "default", 256, 3), (PAPER_STUDY, "paper", 2048, 3)] {
            let study = Study::from_toml_str(text, name).unwrap();
            let (pair, _) = scene_pair(&study).unwrap().expect("a scene fits");
            assert_eq!(pair.config.scene.size, side, "{name}");
            assert_eq!(pair.config.scene.wake_placements().len(), wakes, "{name}");
            pair.config.validate().unwrap();
        }
    }
}

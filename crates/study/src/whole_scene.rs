//! The report's whole-scene detection (issue 14): `wakelab detect`'s scan of one scene eight
//! chips wide, in every band, by the study's own "base" detectors.
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

use crate::report::Table;
use crate::stages::StudyRun;
use crate::Result;
use ndarray::{s, Array2};
use std::fmt::Write as _;
use std::path::Path;
use wakelab_core::config::WakePlacement;
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
const SLICKS: f64 = 0.2;

/// One band's scan of the scene.
pub struct WholeScene {
    pub band: Band,
    /// The image as shown (radar in dB, IR in K), its side, and the band's wake mask.
    display: Vec<f32>,
    side: usize,
    pixel_spacing: f64,
    chips: usize,
    wakes: Vec<WakePlacement>,
    mask: Array2<u8>,
    /// Mean window probability per stride cell.
    map: Array2<f32>,
    pub threshold: f64,
    /// Largest window probability in the scene.
    pub probability: f64,
    pub peak_on_wake: bool,
    pub mean_on_wake: f64,
    pub mean_off_wake: f64,
    /// Share of the off-wake cells at or above the threshold.
    pub false_alarm_cells: f64,
    /// The threshold that flags [`CHIP_FALSE_ALARMS`] of the detector's no-wake test chips, and
    /// the shares of the off-wake and the wake cells above it (None without test outputs).
    pub chip_threshold: Option<ChipThreshold>,
}

/// The share of no-wake test chips a [`chip_threshold`] flags.
pub const CHIP_FALSE_ALARMS: f64 = 0.05;

/// A whole scene's cells at the threshold calibrated on the detector's test chips.
#[derive(Debug, Clone, Copy, PartialEq)]
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

/// Scan the scene with every single band's "base" detector of the run in `dir`; bands without
/// a saved detector are left out.
pub fn scan_whole_scene(dir: &Path, study: &Study, run: &StudyRun) -> Result<Vec<WholeScene>> {
    let bands: Vec<Band> = run.inputs.iter().filter_map(|i| i.as_single()).collect();
    let model = |band: Band| {
        let input = Input::single(band);
        crate::output::detector_path(&dir.join("learn").join(input.name()), &input, Architecture::Base)
    };
    let bands: Vec<Band> = bands.into_iter().filter(|&b| model(b).exists()).collect();
    if bands.is_empty() {
        return Ok(Vec::new());
    }
    let Some((pair, chips)) = scene_pair(study)? else {
        return Ok(Vec::new());
    };
    let map = wakelab_dataset::hydro_map(&run.dataset.dir, &pair.config)?;
    let (rendered, _, _) = render_pair(&pair, &map, &bands);
    let slicks = rendered.slick_mask;
    let device = wakelab_learn::device::parse_device("cpu")?;
    let mut out = Vec::new();
    for band_pair in rendered.bands {
        let band = band_pair.band;
        let chip = pair.config.scene.size / chips;
        let (detector, info) = load_detector(&model(band), Some((Architecture::Base, chip)), &device)?;
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
        let mean = |v: &[f64]| {
            if v.is_empty() {
                f64::NAN
            } else {
                v.iter().sum::<f64>() / v.len() as f64
            }
        };
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
        let display = crate::pictures::display_values(&band_pair.wake, band.is_radar());
        out.push(WholeScene {
            band,
            display,
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
            mask,
            map,
        });
    }
    Ok(out)
}

/// A share as a whole percentage, "-" when there is none.
fn percent(share: Option<f64>) -> String {
    share.map_or("-".into(), |v| format!("{:.0}%", 100.0 * v))
}

/// The scans as a table, one row per band.
pub fn whole_scene_table(scans: &[WholeScene]) -> Table {
    let rows = scans
        .iter()
        .map(|w| {
            vec![
                w.band.to_string(),
                format!("{:.2}", w.probability),
                if w.peak_on_wake { "yes" } else { "no" }.into(),
                format!("{:.2}", w.mean_on_wake),
                format!("{:.2}", w.mean_off_wake),
                format!("{:.0}%", 100.0 * w.false_alarm_cells),
                w.chip_threshold.map_or("-".into(), |c| format!("{:.2}", c.threshold)),
                percent(w.chip_threshold.map(|c| c.false_alarm_cells)),
                percent(w.chip_threshold.map(|c| c.wake_cells)),
                percent(w.chip_threshold.and_then(|c| c.slick_cells)),
                percent(w.chip_threshold.map(|c| c.open_sea_cells)),
            ]
        })
        .collect();
    let Some(first) = scans.first() else {
        return Table {
            id: "whole_scene".into(),
            title: "Detection on a whole scene".into(),
            caption: "Not run: the study's simulated wake is too short for a scene of two chips or more.".into(),
            header: vec!["band".into()],
            rows: Vec::new(),
        };
    };
    Table {
        id: "whole_scene".into(),
        title: "Detection on a whole scene".into(),
        caption: format!(
            "The study's first pair's sea made {chips} chips wide ({side} x {side} px of {dx} m), natural slicks \
             over {slicks:.0}% of it and {count} wake(s) of the study's ship ({wakes}), scanned by each band's \
             \"base\" detector (its last repetition) with windows of its input at half that stride. Cells on the \
             wake hold a pixel of the band's physics mask (all wakes); a false-alarm cell is an off-wake cell at \
             or above the threshold ({threshold}). The chips' threshold is the one that flags {chips_fa:.0}% of the \
             detector's no-wake test chips (the same repetition's): the share of off-wake cells above it says \
             whether that false-alarm rate holds on a whole scene, the share of wake cells above it what is found; \
             the off-wake cells are split into those holding a natural slick's pixel and the open sea.",
            chips = first.chips,
            side = first.side,
            dx = first.pixel_spacing,
            slicks = 100.0 * SLICKS,
            count = first.wakes.len(),
            wakes = first
                .wakes
                .iter()
                .map(|w| format!(
                    "{:.1} km behind the stern, course {:.0} degrees, {:.0} m off the centre",
                    w.along_track / 1000.0,
                    w.heading,
                    w.cross_track.abs()
                ))
                .collect::<Vec<_>>()
                .join("; "),
            threshold = first.threshold,
            chips_fa = 100.0 * CHIP_FALSE_ALARMS,
        ),
        header: [
            "band",
            "scene probability",
            "peak on the wake",
            "mean on the wake",
            "mean off the wake",
            "false-alarm cells",
            "chips' 5% threshold",
            "false-alarm cells there",
            "wake cells there",
            "slick cells flagged there",
            "open-sea cells flagged there",
        ]
        .map(String::from)
        .to_vec(),
        rows,
    }
}

/// The scans as HTML: per band, the image, the probability map and the wake mask.
pub fn whole_scene_html(scans: &[WholeScene]) -> Result<String> {
    let mut s = String::new();
    for w in scans {
        let caption = format!("{0} x {0} px", w.side);
        let units = if w.band.is_radar() { "dB" } else { "K" };
        let map: Vec<f32> = w.map.iter().copied().collect();
        let mask: Vec<f32> = w.mask.iter().map(|&m| f32::from(m)).collect();
        let square = (w.side, w.side);
        let _ = write!(s, "<h4>{}</h4><div class=\"grid\">", w.band);
        for (values, shape, title, units, range) in [
            (&w.display, square, "scene", units, crate::pictures::stretch(&w.display)),
            (&map, w.map.dim(), "wake probability", "probability", (0.0, 1.0)),
            (&mask, square, "wake mask", "1 = wake", (0.0, 1.0)),
        ] {
            let title = format!("{} {title}", w.band);
            let png = crate::pictures::field_png(values, shape, title.clone(), units, (256, &caption), range)?;
            let _ = write!(s, "<figure><img alt=\"{title}\" src=\"{png}\"></figure>");
        }
        s.push_str("</div>");
    }
    Ok(s)
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

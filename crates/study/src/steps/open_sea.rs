//! Simulated open sea with look-alikes, and detectors' scans of it: what the calibration step
//! sets its thresholds on, and what the transfer study sets and checks its detectors' on (issue
//! 38). A scene is rendered in C-band VV twice, with its ship and wake and without them, and
//! every detector scans both: its separate alarms on the open sea, its alarms near and far from
//! the wake's track, and every window's spread and probability.

use super::context::at_factor;
use super::ships::{scene_config, SPACING, SPEEDS};
use crate::Result;
use ndarray::Array2;
use rand::{RngExt, SeedableRng};
use std::path::Path;
use wakelab_core::units::RadarBand;
use wakelab_core::WakelabConfig;
use wakelab_learn::data::{median, RadarScale};
use wakelab_learn::detect::{detect_image, ScanOptions};
use wakelab_learn::device::Device;
use wakelab_learn::store::{Detector, ModelInfo};

/// Open-sea scene `j` of the set that starts at scene index `first` (the calibration step's at
/// 1000; the ships step's scenes are 0..27): the ships step's scene draws (its sea, any course
/// and look, a ship of the study's speeds in view) with look-alikes: slicks over 5-30 % of the
/// sea in filaments 4-16 times as long as wide, and the wind varying by up to 30 %.
pub(crate) fn open_sea_config(base: &WakelabConfig, first: usize, j: usize) -> Option<WakelabConfig> {
    let k = first + j;
    let mut c = scene_config(base, k, SPEEDS[j % SPEEDS.len()], true, SPACING)?;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(base.seed ^ (0xCA1B_0000 + k as u64));
    c.slicks.coverage = rng.random_range(0.05..0.3);
    c.slicks.elongation = rng.random_range(4.0..16.0);
    c.environment.wind.variability = rng.random_range(0.0..0.3);
    Some(c)
}

/// One scene rendered in C-band VV with its ship and wake and without them, and the wake's
/// track as a segment (pixels): from the stern to well beyond the scene.
#[derive(Clone)]
pub(crate) struct SeaPair {
    pub with: Array2<f32>,
    pub without: Array2<f32>,
    pub track: ((f64, f64), (f64, f64)),
    pub spacing: f64,
    pub km2: f64,
}

/// Scene `c` rendered with and without its ship (the hydrodynamic wake cached in the run's
/// dataset folder).
pub(crate) fn render(c: &WakelabConfig, run_dir: &Path) -> Result<SeaPair> {
    c.validate()?;
    let map = wakelab_dataset::hydro_map(&run_dir.join("dataset"), c)?;
    let with = wakelab_surface::simulate_surface(c, Some(&map));
    let without = wakelab_surface::simulate_surface(c, None);
    let image = |scene| -> Array2<f32> {
        wakelab_sensors::render_sar(c, scene, RadarBand::C)
            .sigma0
            .mapv(|v| v as f32)
    };
    let side = c.scene.size as f64 * c.scene.pixel_spacing;
    let track = (
        with.grid.pixel_of(0.0, 0.0),
        with.grid.pixel_of(c.scene.along_track + 2.0 * side, 0.0),
    );
    Ok(SeaPair {
        with: image(&with),
        without: image(&without),
        track,
        spacing: c.scene.pixel_spacing,
        km2: (side / 1000.0).powi(2),
    })
}

/// Distance (pixels) of point `p` from the segment `ab`.
pub(crate) fn distance_to_segment(p: (f64, f64), (a, b): ((f64, f64), (f64, f64))) -> f64 {
    let (dr, dc) = (b.0 - a.0, b.1 - a.1);
    let len2 = dr * dr + dc * dc;
    let t = if len2 > 0.0 {
        (((p.0 - a.0) * dr + (p.1 - a.1) * dc) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p.0 - a.0 - t * dr).hypot(p.1 - a.1 - t * dc)
}

/// A C-band detector at a whole multiple of the scenes' spacing.
pub(crate) struct Scanner {
    pub detector: Detector,
    pub info: ModelInfo,
    /// Scene pixels per detector pixel.
    pub factor: usize,
}

/// A scan's findings: its separate alarms and every window, in scene pixels.
pub(crate) struct Scanned {
    /// Window centres (row, column) and probability of the windows that overlap no stronger
    /// one (the alarms at any threshold below their probability).
    pub alarms: Vec<(f64, f64, f64)>,
    /// Every window: centre (row, column), robust spread of its dB (1.4826 MAD, what its
    /// normalisation divides by) and probability.
    pub windows: Vec<(f64, f64, f64, f64)>,
}

impl Scanner {
    /// A scan of `image` (linear sigma0) at half the window's stride.
    pub fn scan(&self, image: &Array2<f32>, device: &Device) -> Result<Scanned> {
        let f = self.factor as f64;
        let image = at_factor(image, self.factor);
        let n = self.info.input_size;
        let options = ScanOptions {
            stride: Some((n / 2).max(1)),
            scale: RadarScale::Linear,
            threshold: Some(0.0),
            ..ScanOptions::default()
        };
        let found = detect_image(&self.detector, &self.info, &image, options, device, &mut |_, _| {})?;
        let half = 0.5 * n as f64;
        let windows = found
            .tiles
            .iter()
            .map(|t| {
                let window = image
                    .slice(ndarray::s![t.row..t.row + n, t.col..t.col + n])
                    .mapv(|v| RadarScale::Linear.decibels(v));
                let centre = median(&window);
                let spread = 1.4826 * median(&window.mapv(|v| (v - centre).abs())) as f64;
                (
                    (t.row as f64 + half) * f,
                    (t.col as f64 + half) * f,
                    spread,
                    t.probability,
                )
            })
            .collect();
        Ok(Scanned {
            alarms: found
                .detections
                .iter()
                .map(|d| (d.row * f, d.col * f, d.score))
                .collect(),
            windows,
        })
    }

    /// The window's side on the ground (m) in scenes of `spacing`.
    pub fn footprint(&self, spacing: f64) -> f64 {
        (self.info.input_size * self.factor) as f64 * spacing
    }
}

/// What one detector's scans of a set of scenes gathered.
#[derive(Default, Clone)]
pub(crate) struct Tally {
    /// The probabilities of the separate alarms on the open sea, and each one's distance (m)
    /// from the nearest ship without a wake drawn there (infinite with none).
    pub sea: Vec<f64>,
    pub sea_from_ship: Vec<f64>,
    /// Ships without a wake drawn on the open sea.
    pub ships: usize,
    /// Per wake scene, its alarms: distance of the centre from the track (m) and probability.
    pub wake_scenes: Vec<Vec<(f64, f64)>>,
    /// Every open-sea window's and every wake window's (centre within half a window of the
    /// track) (robust spread, probability).
    pub sea_windows: Vec<(f64, f64)>,
    pub wake_windows: Vec<(f64, f64)>,
}

impl Tally {
    /// Open-sea alarms above `threshold`.
    pub fn sea_alarms(&self, threshold: f64) -> usize {
        self.sea.iter().filter(|&&p| p > threshold).count()
    }

    /// Open-sea alarms above `threshold` within `within` m of a ship without a wake.
    pub fn ship_alarms(&self, threshold: f64, within: f64) -> usize {
        self.sea
            .iter()
            .zip(&self.sea_from_ship)
            .filter(|&(&p, &d)| p > threshold && d <= within)
            .count()
    }

    /// Wake scenes with an alarm above `threshold` within `within` m of the track.
    pub fn wakes_found(&self, threshold: f64, within: f64) -> usize {
        self.wake_scenes
            .iter()
            .filter(|alarms| alarms.iter().any(|&(d, p)| d <= within && p > threshold))
            .count()
    }

    /// Alarms above `threshold` farther than `within` m from the track in the wake scenes.
    pub fn off_wake_alarms(&self, threshold: f64, within: f64) -> usize {
        self.wake_scenes
            .iter()
            .flatten()
            .filter(|&&(d, p)| d > within && p > threshold)
            .count()
    }

    /// The largest probability of an open-sea alarm (0 with none).
    pub fn largest_open_sea(&self) -> f64 {
        self.sea.iter().copied().fold(0.0, f64::max)
    }
}

/// What is drawn onto each rendered scene before it is scanned (the transfer study's
/// look-alikes): it returns the ships without a wake it drew (pixels).
pub(crate) type Prepare<'a> = &'a dyn Fn(&WakelabConfig, &mut SeaPair) -> Vec<(f64, f64)>;

/// Scenes scanned as rendered.
pub(crate) fn as_rendered(_: &WakelabConfig, _: &mut SeaPair) -> Vec<(f64, f64)> {
    Vec::new()
}

/// Every scanner's [`Tally`] of the scenes `configs`, each rendered and then `prepare`d, and
/// their area (km^2). `on_scene` sees each scene done.
pub(crate) fn scan_scenes(
    run_dir: &Path,
    configs: &[WakelabConfig],
    prepare: Prepare,
    scanners: &[Scanner],
    device: &Device,
    on_scene: &mut dyn FnMut(usize),
) -> Result<(Vec<Tally>, f64)> {
    let mut tallies = vec![Tally::default(); scanners.len()];
    let mut km2 = 0.0;
    for (j, c) in configs.iter().enumerate() {
        let mut pair = render(c, run_dir)?;
        let ships = prepare(c, &mut pair);
        km2 += pair.km2;
        for (tally, scanner) in tallies.iter_mut().zip(scanners) {
            let open = scanner.scan(&pair.without, device)?;
            tally.sea.extend(open.alarms.iter().map(|a| a.2));
            tally.ships += ships.len();
            tally.sea_from_ship.extend(open.alarms.iter().map(|&(r, c, _)| {
                let d = ships
                    .iter()
                    .map(|s| (s.0 - r).hypot(s.1 - c))
                    .fold(f64::INFINITY, f64::min);
                d * pair.spacing
            }));
            tally.sea_windows.extend(open.windows.iter().map(|w| (w.2, w.3)));
            let with = scanner.scan(&pair.with, device)?;
            let metres = |r: f64, c: f64| distance_to_segment((r, c), pair.track) * pair.spacing;
            tally
                .wake_scenes
                .push(with.alarms.iter().map(|&(r, c, p)| (metres(r, c), p)).collect());
            let half_window = 0.5 * scanner.footprint(pair.spacing);
            tally.wake_windows.extend(
                with.windows
                    .iter()
                    .filter(|w| metres(w.0, w.1) <= half_window)
                    .map(|w| (w.2, w.3)),
            );
        }
        on_scene(j);
    }
    Ok((tallies, km2))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_distance_to_a_segment_is_to_its_nearest_point() {
        let seg = ((0.0, 0.0), (0.0, 10.0));
        assert_eq!(distance_to_segment((3.0, 5.0), seg), 3.0);
        assert_eq!(distance_to_segment((0.0, -4.0), seg), 4.0);
        assert_eq!(distance_to_segment((3.0, 14.0), seg), 5.0);
    }

    #[test]
    fn a_tally_counts_alarms_above_the_threshold_and_wakes_within_reach() {
        let t = Tally {
            sea: vec![0.2, 0.7, 0.9],
            sea_from_ship: vec![100.0, 400.0, f64::INFINITY],
            ships: 2,
            wake_scenes: vec![vec![(100.0, 0.8), (900.0, 0.95)], vec![(600.0, 0.99)], vec![]],
            ..Tally::default()
        };
        assert_eq!(t.sea_alarms(0.5), 2);
        assert_eq!(t.sea_alarms(0.9), 0);
        assert_eq!(t.wakes_found(0.5, 500.0), 1);
        assert_eq!(t.wakes_found(0.85, 500.0), 0);
        assert_eq!(t.off_wake_alarms(0.5, 500.0), 2);
        assert_eq!(t.ship_alarms(0.5, 500.0), 1);
        assert_eq!(t.ship_alarms(0.1, 200.0), 1);
        assert_eq!(t.largest_open_sea(), 0.9);
    }
}

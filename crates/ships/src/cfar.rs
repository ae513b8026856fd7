//! Ships as bright targets: a two-parameter CFAR (constant false-alarm rate) detector on the
//! image in dB, the adaptive threshold of SNAP's ship detection and of the field's baselines
//! (Crisp 2004, "The state-of-the-art in ship detection in SAR imagery", DSTO-RR-0272, section
//! 4.3): a pixel is a target when it exceeds the mean of its background ring by t standard
//! deviations, t = Phi^-1(1 - P_fa) for the stated false-alarm probability. The ring lies
//! between a guard window (which holds the ship) and a background window, both given in metres.
//! In dB the sea's speckled intensity is near Gaussian (the log-normal clutter model); a
//! one-look exponential intensity has a lighter upper tail in dB than a Gaussian, so the stated
//! P_fa is an upper bound there. Where a pixel's threshold lies at or above the brightest value
//! of the searched image (a display stretch clipping its ships at its ceiling), SNAP's target
//! window tests the mean of the pixels around it instead ([`CfarOptions::target_m`]).
//!
//! Detected pixels are clustered into targets (8-connected, then joined within `merge_m`);
//! weaker targets on the range or azimuth line of a far brighter one nearby are its sidelobes,
//! and weaker targets on its azimuth line kilometres away its azimuth ambiguities: both are
//! rejected and counted. Pixels that are NaN (no data, land) are neither tested nor counted in
//! a background.

use crate::land::LandOptions;
use crate::Geometry;
use ndarray::{s, Array2, ArrayView2};
use rayon::prelude::*;
use serde::Serialize;

/// The detector's settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CfarOptions {
    /// Side of the guard window (m): larger than the largest ship.
    pub guard_m: f64,
    /// Side of the background window (m).
    pub background_m: f64,
    /// Probability that a pixel of open sea is declared a target.
    pub pfa: f64,
    /// Side (m) of SNAP's target window: a pixel is also a target where the mean (dB) of the
    /// window around it passes the same test against the ring of the image averaged alike, so
    /// a ship of several pixels is found where single pixels cannot stand out (a display
    /// stretch that clips its ships at the grey scale's ceiling, a few deviations above its
    /// sea); 0: single pixels only.
    pub target_m: f64,
    /// A target's peak must also stand this far above its background mean (dB).
    pub min_contrast_db: f64,
    /// Detected pixels this close (m) belong to one target.
    pub merge_m: f64,
    /// Targets longer than this (m) are not ships (coast, platforms' smears).
    pub max_length_m: f64,
    /// Targets of fewer detected pixels are speckle's (or a display's saturated) spikes, not
    /// ships: a ship spans several resolution cells.
    pub min_pixels: usize,
    /// A target this much weaker (dB) than a brighter one on its range or azimuth line within
    /// `sidelobe_m` is a sidelobe of it; on its azimuth line farther away, an azimuth ambiguity.
    pub ghost_db: f64,
    pub sidelobe_m: f64,
    /// Land found in the image itself ([`crate::land`]): targets on it are not ships, and the
    /// wake searches leave it out as no data; None: only the product's mask and the user's
    /// `--exclude` are left out.
    pub land: Option<LandOptions>,
}

impl Default for CfarOptions {
    /// SNAP's defaults for a 10 m product (guard 500 m, background 800 m), a false-alarm
    /// probability of 1e-6, 6 dB of contrast.
    fn default() -> Self {
        Self {
            guard_m: 500.0,
            background_m: 800.0,
            pfa: 1e-6,
            target_m: 0.0,
            min_contrast_db: 6.0,
            merge_m: 40.0,
            max_length_m: 600.0,
            min_pixels: 3,
            ghost_db: 15.0,
            sidelobe_m: 400.0,
            land: Some(LandOptions::default()),
        }
    }
}

impl CfarOptions {
    /// The defaults with the false-alarm probability `pfa` (`wakelab detect --ship-pfa`).
    pub fn with_pfa(pfa: f64) -> Self {
        Self { pfa, ..Self::default() }
    }
}

/// A ship found in the image.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Ship {
    /// The intensity-weighted centre of its return (fractional pixels).
    pub row: f64,
    pub col: f64,
    /// Its brightest pixel and that pixel's sigma0 (linear and dB).
    pub peak_row: usize,
    pub peak_col: usize,
    pub peak_sigma0: f64,
    pub peak_db: f64,
    /// The background ring's mean (dB) and the peak's contrast over it (dB).
    pub background_db: f64,
    pub contrast_db: f64,
    /// Detected pixels, and the return's length, width (m; a uniform segment of length L has
    /// variance L^2 / 12 along it) and orientation (degrees clockwise from up, in [0, 180)).
    pub pixels: usize,
    pub length_m: f64,
    pub width_m: f64,
    pub orientation_deg: f64,
}

/// What the search found: the ships, and the targets rejected as azimuth ambiguities or
/// sidelobes of brighter ones.
#[derive(Debug, Clone, Serialize)]
pub struct ShipSearch {
    pub ships: Vec<Ship>,
    pub ambiguities: Vec<Ship>,
    /// The centres (row, column) of the targets rejected as sidelobes, of those rejected for
    /// their length, and of those on land ([`crate::land`]; filled by the scene's search).
    pub sidelobes: Vec<(f64, f64)>,
    pub too_long: Vec<(f64, f64)>,
    pub on_land: Vec<(f64, f64)>,
    /// The threshold in background standard deviations, Phi^-1(1 - P_fa).
    pub threshold_sigmas: f64,
    pub options: CfarOptions,
}

/// Phi^-1(1 - p): the standard normal quantile a false-alarm probability `p` asks for (by
/// bisection on the complementary error function).
pub fn sigmas_for(p: f64) -> f64 {
    let tail = |x: f64| 0.5 * libm::erfc(x / std::f64::consts::SQRT_2);
    let (mut lo, mut hi) = (-10.0, 40.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if tail(mid) > p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Rows of output computed from one slab of the summed-area tables.
const BAND_ROWS: usize = 256;

/// A band of rows from its first: its targets, background means and thresholds.
type BandMaps = (usize, Array2<bool>, Array2<f32>, Array2<f32>);

/// Whether each pixel is a target, its background's mean (dB) and its threshold, the mean plus
/// `t` standard deviations (both NaN where less than half the ring holds data).
fn cfar_map(
    db: &Array2<f32>,
    half_guard: (usize, usize),
    half_back: (usize, usize),
    t: f64,
    min_contrast: f64,
) -> (Array2<bool>, Array2<f32>, Array2<f32>) {
    let (h, w) = db.dim();
    let mut hit = Array2::from_elem((h, w), false);
    let mut mean = Array2::from_elem((h, w), f32::NAN);
    let mut threshold = Array2::from_elem((h, w), f32::NAN);
    let ring_cells =
        ((2 * half_back.0 + 1) * (2 * half_back.1 + 1) - (2 * half_guard.0 + 1) * (2 * half_guard.1 + 1)) as f64;
    let bands: Vec<usize> = (0..h).step_by(BAND_ROWS).collect();
    let results: Vec<BandMaps> = bands
        .into_par_iter()
        .map(|r0| {
            let r1 = (r0 + BAND_ROWS).min(h);
            let s0 = r0.saturating_sub(half_back.0);
            let s1 = (r1 + half_back.0).min(h);
            // summed-area tables of count, sum and sum of squares over the slab's valid pixels
            let (sh, sw) = (s1 - s0 + 1, w + 1);
            let mut table = vec![[0f64; 3]; sh * sw];
            for r in 0..s1 - s0 {
                let mut row = [0f64; 3];
                for c in 0..w {
                    let v = db[[s0 + r, c]];
                    if v.is_finite() {
                        let v = v as f64;
                        row[0] += 1.0;
                        row[1] += v;
                        row[2] += v * v;
                    }
                    let above = table[r * sw + c + 1];
                    table[(r + 1) * sw + c + 1] = [above[0] + row[0], above[1] + row[1], above[2] + row[2]];
                }
            }
            let sum = |ra: usize, rb: usize, ca: usize, cb: usize| -> [f64; 3] {
                // rows [ra, rb) and columns [ca, cb) of the slab
                let at = |r: usize, c: usize| table[r * sw + c];
                let (a, b, c, d) = (at(rb, cb), at(ra, cb), at(rb, ca), at(ra, ca));
                [
                    a[0] - b[0] - c[0] + d[0],
                    a[1] - b[1] - c[1] + d[1],
                    a[2] - b[2] - c[2] + d[2],
                ]
            };
            let mut hits = Array2::from_elem((r1 - r0, w), false);
            let mut means = Array2::from_elem((r1 - r0, w), f32::NAN);
            let mut thresholds = Array2::from_elem((r1 - r0, w), f32::NAN);
            for r in r0..r1 {
                let rr = r - s0;
                let window = |half: usize| (rr.saturating_sub(half), (rr + half + 1).min(s1 - s0));
                let (ba, bb) = window(half_back.0);
                let (ga, gb) = window(half_guard.0);
                for c in 0..w {
                    let x = db[[r, c]];
                    if !x.is_finite() {
                        continue;
                    }
                    let (ca, cb) = (c.saturating_sub(half_back.1), (c + half_back.1 + 1).min(w));
                    let (gca, gcb) = (c.saturating_sub(half_guard.1), (c + half_guard.1 + 1).min(w));
                    let outer = sum(ba, bb, ca, cb);
                    let inner = sum(ga, gb, gca, gcb);
                    let n = outer[0] - inner[0];
                    if n < 0.5 * ring_cells || n < 8.0 {
                        continue;
                    }
                    let m = (outer[1] - inner[1]) / n;
                    let var = ((outer[2] - inner[2]) / n - m * m).max(0.0);
                    means[[r - r0, c]] = m as f32;
                    thresholds[[r - r0, c]] = (m + t * var.sqrt()) as f32;
                    let x = x as f64;
                    hits[[r - r0, c]] = x > m + t * var.sqrt() && x - m >= min_contrast;
                }
            }
            (r0, hits, means, thresholds)
        })
        .collect();
    for (r0, hits, means, thresholds) in results {
        let rows = hits.nrows();
        hit.slice_mut(s![r0..r0 + rows, ..]).assign(&hits);
        mean.slice_mut(s![r0..r0 + rows, ..]).assign(&means);
        threshold.slice_mut(s![r0..r0 + rows, ..]).assign(&thresholds);
    }
    (hit, mean, threshold)
}

/// The mean of the finite pixels in the (2 half.0 + 1) x (2 half.1 + 1) window around each
/// pixel, NaN where the pixel is or where fewer than half the full window's pixels are finite
/// (so no-data borders and the image's corners are not tested by a few pixels' mean).
fn window_mean(db: &Array2<f32>, half: (usize, usize)) -> Array2<f32> {
    let (h, w) = db.dim();
    let finite = db.mapv(|v| if v.is_finite() { 1.0 } else { 0.0 });
    let share = crate::radon::box_mean(&finite, half);
    let mut mean = crate::radon::box_mean(db, half);
    let full = ((2 * half.0 + 1) * (2 * half.1 + 1)) as f32;
    ndarray::Zip::indexed(&mut mean)
        .and(&share)
        .and(db)
        .for_each(|(r, c), m, &f, &v| {
            // the window's pixels inside the image, of which `share` are finite
            let rows = (r + half.0 + 1).min(h) - r.saturating_sub(half.0);
            let cols = (c + half.1 + 1).min(w) - c.saturating_sub(half.1);
            if !v.is_finite() || f * (rows * cols) as f32 + 1e-3 < 0.5 * full {
                *m = f32::NAN;
            }
        });
    mean
}

/// Union-find over the detected pixels.
fn find(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// How far the brightest value of `image` (linear, NaN for no data) stands above the image's
/// mean, in its standard deviations, all in dB: the most any pixel can stand over an average
/// stretch of its sea in the CFAR's own units ([`sigmas_for`]). A display stretch clips its
/// brightest returns at its ceiling; where its sea lies high in the grey scale, the ceiling can
/// stand under the CFAR's threshold, and a clipped return then passes only by its target
/// window's mean, if at all (docs/results.md: the real held-out images with no ship found).
/// None where fewer than two pixels hold data or they do not spread.
pub fn ceiling_standing(image: ArrayView2<f32>) -> Option<f64> {
    let (mut n, mut sum, mut squares, mut max) = (0.0, 0.0, 0.0, f64::NEG_INFINITY);
    for &v in image.iter().filter(|v| v.is_finite() && **v > 0.0) {
        let db = 10.0 * (v as f64).log10();
        n += 1.0;
        sum += db;
        squares += db * db;
        max = max.max(db);
    }
    let mean = sum / n;
    let spread = (squares / n - mean * mean).max(0.0).sqrt();
    (n >= 2.0 && spread > 0.0).then(|| (max - mean) / spread)
}

/// The ships in `image` (linear sigma0, NaN for no data) placed by `geometry`.
pub fn find_ships(image: ArrayView2<f32>, geometry: &Geometry, options: &CfarOptions) -> ShipSearch {
    let db = image.mapv(|v| {
        if v > 0.0 && v.is_finite() {
            10.0 * v.log10()
        } else {
            f32::NAN
        }
    });
    let half = |m: f64| {
        (
            (0.5 * m / geometry.spacing.0).round().max(1.0) as usize,
            (0.5 * m / geometry.spacing.1).round().max(1.0) as usize,
        )
    };
    let (half_guard, half_back) = (
        half(options.guard_m),
        half(options.background_m.max(options.guard_m * 1.2)),
    );
    let t = sigmas_for(options.pfa);
    let (mut hit, mean, threshold) = cfar_map(&db, half_guard, half_back, t, options.min_contrast_db);
    if options.target_m > 0.0 {
        // SNAP's target window where a single pixel cannot pass: where the threshold lies at or
        // above the brightest value the image holds (a display stretch clips its ships at the
        // grey scale's ceiling, a few of its sea's deviations up). There the window's mean is
        // tested against the ring of the image averaged alike, whose spread then holds the
        // speckle's own correlation; a pixel it passes must itself stand min_contrast_db over
        // its ring, so the return keeps its own footprint.
        let ceiling = db
            .iter()
            .copied()
            .filter(|v| v.is_finite())
            .fold(f32::NEG_INFINITY, f32::max);
        let side = |spacing: f64| ((options.target_m / spacing - 1.0) / 2.0).round().max(1.0) as usize;
        let averaged = window_mean(&db, (side(geometry.spacing.0), side(geometry.spacing.1)));
        let (window_hit, _, _) = cfar_map(&averaged, half_guard, half_back, t, options.min_contrast_db);
        ndarray::Zip::from(&mut hit)
            .and(&window_hit)
            .and(&db)
            .and(&mean)
            .and(&threshold)
            .for_each(|h, &w, &x, &m, &limit| {
                *h |= w && limit >= ceiling && x - m >= options.min_contrast_db as f32;
            });
    }
    // the detected pixels, joined within merge_m
    let pixels: Vec<(usize, usize)> = hit.indexed_iter().filter(|(_, &h)| h).map(|(p, _)| p).collect();
    let mut parent: Vec<usize> = (0..pixels.len()).collect();
    let reach = (
        (options.merge_m / geometry.spacing.0).ceil().max(1.0) as usize,
        (options.merge_m / geometry.spacing.1).ceil().max(1.0) as usize,
    );
    // pixels are in row-major order: each joins the earlier ones within reach
    let index: std::collections::HashMap<(usize, usize), usize> =
        pixels.iter().enumerate().map(|(i, &p)| (p, i)).collect();
    for (i, &(r, c)) in pixels.iter().enumerate() {
        for dr in 0..=reach.0 {
            let Some(rr) = r.checked_sub(dr) else { break };
            for cc in c.saturating_sub(reach.1)..=(c + reach.1) {
                if dr == 0 && cc >= c {
                    break;
                }
                if let Some(&j) = index.get(&(rr, cc)) {
                    let (a, b) = (find(&mut parent, i), find(&mut parent, j));
                    if a != b {
                        parent[a.max(b)] = a.min(b);
                    }
                }
            }
        }
    }
    let mut groups: std::collections::BTreeMap<usize, Vec<(usize, usize)>> = Default::default();
    for (i, &p) in pixels.iter().enumerate() {
        let root = find(&mut parent, i);
        groups.entry(root).or_default().push(p);
    }
    let mut targets: Vec<Ship> = groups
        .into_values()
        .map(|g| describe(&g, image, &mean, geometry))
        .collect();
    targets.sort_by(|a, b| b.peak_sigma0.total_cmp(&a.peak_sigma0));
    let too_long = targets
        .iter()
        .filter(|s| s.length_m > options.max_length_m)
        .map(|s| (s.row, s.col))
        .collect();
    targets.retain(|s| s.length_m <= options.max_length_m && s.pixels >= options.min_pixels);
    // ghosts: weaker targets on the range or azimuth lines of brighter ones
    let (mut ships, mut ambiguities, mut sidelobes) = (Vec::new(), Vec::new(), Vec::new());
    let azimuth = geometry.step(geometry.azimuth_deg);
    for target in targets {
        let verdict = ships
            .iter()
            .find_map(|bright: &Ship| ghost_of(bright, &target, azimuth, geometry, options));
        match verdict {
            Some(Ghost::Sidelobe) => sidelobes.push((target.row, target.col)),
            Some(Ghost::Ambiguity) => ambiguities.push(target),
            None => ships.push(target),
        }
    }
    ShipSearch {
        ships,
        ambiguities,
        sidelobes,
        too_long,
        on_land: Vec::new(),
        threshold_sigmas: t,
        options: *options,
    }
}

enum Ghost {
    Sidelobe,
    Ambiguity,
}

/// Whether `weak` is a sidelobe or an azimuth ambiguity of `bright`.
fn ghost_of(
    bright: &Ship,
    weak: &Ship,
    azimuth: (f64, f64),
    geometry: &Geometry,
    options: &CfarOptions,
) -> Option<Ghost> {
    if bright.peak_db - weak.peak_db < options.ghost_db {
        return None;
    }
    // the separation in metres along azimuth and across it (range)
    let (dr, dc) = (weak.row - bright.row, weak.col - bright.col);
    let (ar, ac) = (azimuth.0 * geometry.spacing.0, azimuth.1 * geometry.spacing.1);
    let (er, ec) = (dr * geometry.spacing.0, dc * geometry.spacing.1);
    let along = er * ar + ec * ac;
    let across = (er * ac - ec * ar).abs();
    let line = (bright.width_m.max(bright.length_m) * 0.5).max(2.0 * geometry.spacing.0.max(geometry.spacing.1));
    let distance = along.hypot(across);
    if distance <= options.sidelobe_m && (across <= line || along.abs() <= line) {
        Some(Ghost::Sidelobe)
    } else if across <= line && (1000.0..=12_000.0).contains(&along.abs()) {
        Some(Ghost::Ambiguity)
    } else {
        None
    }
}

/// A cluster of detected pixels as a [`Ship`].
fn describe(group: &[(usize, usize)], image: ArrayView2<f32>, mean: &Array2<f32>, geometry: &Geometry) -> Ship {
    let (mut sw, mut sr, mut sc) = (0.0, 0.0, 0.0);
    let mut peak = (group[0], f64::NEG_INFINITY);
    for &(r, c) in group {
        let v = image[[r, c]] as f64;
        sw += v;
        sr += v * r as f64;
        sc += v * c as f64;
        if v > peak.1 {
            peak = ((r, c), v);
        }
    }
    let (row, col) = (sr / sw, sc / sw);
    // second moments in metres (unweighted: the shape of the return, not its glints)
    let n = group.len() as f64;
    let (mut yy, mut xx, mut xy) = (0.0, 0.0, 0.0);
    let (mr, mc) = (
        group.iter().map(|p| p.0 as f64).sum::<f64>() / n,
        group.iter().map(|p| p.1 as f64).sum::<f64>() / n,
    );
    for &(r, c) in group {
        let (y, x) = (
            -(r as f64 - mr) * geometry.spacing.0,
            (c as f64 - mc) * geometry.spacing.1,
        );
        yy += y * y / n;
        xx += x * x / n;
        xy += x * y / n;
    }
    let mid = 0.5 * (xx + yy);
    let spread = (0.25 * (xx - yy).powi(2) + xy * xy).sqrt();
    let (major, minor) = (mid + spread, (mid - spread).max(0.0));
    // the major axis's direction (x east, y north), clockwise from up
    let angle = 0.5 * (2.0 * xy).atan2(yy - xx);
    let pixel = geometry.spacing.0.max(geometry.spacing.1);
    let ((pr, pc), peak_sigma0) = peak;
    let peak_db = 10.0 * peak_sigma0.max(1e-30).log10();
    let background_db = mean[[pr, pc]] as f64;
    Ship {
        row,
        col,
        peak_row: pr,
        peak_col: pc,
        peak_sigma0,
        peak_db,
        background_db,
        contrast_db: peak_db - background_db,
        pixels: group.len(),
        length_m: (12.0 * major).sqrt().max(pixel),
        width_m: (12.0 * minor).sqrt().max(pixel),
        orientation_deg: angle.to_degrees().rem_euclid(180.0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn geometry() -> Geometry {
        Geometry::along_rows(10.0, 35.0, None)
    }

    /// Four-look speckle on a sea of sigma0 0.01.
    fn sea(n: usize, seed: u64) -> Array2<f32> {
        crate::speckle(n, n, 4, 0.01, seed)
    }

    /// Half the pixels at 100 dB and half at 120 (mean 110, deviation 10) and one at 140: the
    /// brightest stands 3 deviations up (to within the one pixel's own pull on both).
    #[test]
    fn the_ceiling_stands_its_deviations_over_the_mean() {
        let mut db = Array2::from_shape_fn((100, 100), |(r, _)| if r % 2 == 0 { 100.0 } else { 120.0 });
        db[[0, 0]] = 140.0;
        db[[1, 1]] = f32::NAN;
        let linear = db.mapv(|v: f32| if v.is_nan() { v } else { 10f32.powf(v / 10.0) });
        let standing = ceiling_standing(linear.view()).unwrap();
        assert!((standing - 3.0).abs() < 0.01, "{standing}");
        assert_eq!(ceiling_standing(Array2::from_elem((4, 4), 0.5f32).view()), None);
    }

    #[test]
    fn the_threshold_is_the_normal_quantile() {
        // Phi^-1(1 - 0.001) = 3.0902, Phi^-1(1 - 1e-6) = 4.7534 (standard tables)
        assert!((sigmas_for(1e-3) - 3.0902).abs() < 1e-3);
        assert!((sigmas_for(1e-6) - 4.7534).abs() < 1e-3);
    }

    /// On speckled open sea the false-alarm rate stays at or below the stated P_fa (upper
    /// bound: 4-look speckle in dB has a lighter upper tail than a Gaussian).
    #[test]
    fn open_sea_gives_at_most_the_stated_false_alarms() {
        let image = sea(400, 1);
        let options = CfarOptions {
            pfa: 1e-3,
            min_contrast_db: 0.0,
            ..CfarOptions::default()
        };
        let db = image.mapv(|v| 10.0 * v.log10());
        let (hit, _, _) = cfar_map(&db, (25, 25), (40, 40), sigmas_for(options.pfa), 0.0);
        let rate = hit.iter().filter(|&&h| h).count() as f64 / hit.len() as f64;
        assert!(rate <= 1e-3 && rate > 1e-5, "false-alarm rate {rate}");
        assert!(find_ships(image.view(), &geometry(), &CfarOptions::default())
            .ships
            .is_empty());
    }

    /// A ship of 150 x 20 m, 40 dB over the sea, heading 60 degrees, is found where it is with
    /// its size and orientation; its azimuth ambiguity 5 km up the azimuth line, 25 dB weaker,
    /// and a sidelobe along range are rejected; the edge of a no-data patch raises no alarm.
    #[test]
    fn a_ship_is_found_with_its_size_and_its_ghosts_rejected() {
        let mut image = sea(800, 2);
        let g = geometry();
        let (centre_r, centre_c) = (600.0, 400.0);
        let (ur, uc) = g.step(60.0);
        let (vr, vc) = g.step(150.0);
        let mut paint = |r0: f64, c0: f64, length: f64, width: f64, value: f32| {
            for i in -(length as i64) / 2..=(length as i64) / 2 {
                for j in -(width as i64) / 2..=(width as i64) / 2 {
                    let r = r0 + ur * i as f64 + vr * j as f64;
                    let c = c0 + uc * i as f64 + vc * j as f64;
                    image[[r.round() as usize, c.round() as usize]] = value;
                }
            }
        };
        paint(centre_r, centre_c, 150.0, 20.0, 100.0);
        // the ambiguity: 500 rows up (azimuth along the rows), 25 dB weaker
        paint(centre_r - 500.0, centre_c, 150.0, 20.0, 0.3);
        // a sidelobe: 15 columns to the side (range), a bright line 25 dB weaker
        for r in 595..606 {
            image[[r, 415]] = 0.3;
        }
        // no data (NaN) over a corner
        image.slice_mut(s![0..200, 0..200]).fill(f32::NAN);
        let found = find_ships(image.view(), &g, &CfarOptions::default());
        assert_eq!(found.ships.len(), 1, "{found:#?}");
        let ship = &found.ships[0];
        assert!(
            (ship.row - centre_r).abs() < 2.0 && (ship.col - centre_c).abs() < 2.0,
            "{ship:?}"
        );
        assert!((ship.length_m - 150.0).abs() < 25.0, "length {}", ship.length_m);
        assert!((ship.width_m - 20.0).abs() < 15.0, "width {}", ship.width_m);
        assert!(
            crate::angle_difference(ship.orientation_deg, 60.0).abs() < 3.0,
            "{}",
            ship.orientation_deg
        );
        assert!((ship.contrast_db - 40.0).abs() < 3.0, "{}", ship.contrast_db);
        assert_eq!(found.ambiguities.len(), 1);
        assert!(!found.sidelobes.is_empty());
        // the ship stands far above every threshold: the target window, which only tests where
        // a single pixel cannot pass, changes nothing
        let windowed = CfarOptions {
            target_m: 50.0,
            ..CfarOptions::default()
        };
        assert_eq!(find_ships(image.view(), &g, &windowed).ships, found.ships);
    }

    /// A display stretch of 12 grey levels per dB around grey 130 puts the 4-look sea's
    /// deviation (2.3 dB: the log of a Gamma(4) variate) at 28 grey levels, so the grey scale's
    /// ceiling, 255, lies 4.5 of them above the sea and no pixel can pass the 6 deviations of
    /// P_fa 1e-9. A 150 x 40 m ship clipped at 255 is then found only with the target window,
    /// and the open sea around it gives no false ship either way.
    #[test]
    fn a_ship_clipped_at_a_display_ceiling_is_found_by_its_target_window() {
        let sea = sea(600, 3);
        let mean_db = sea.iter().map(|&v| 10.0 * (v as f64).log10()).sum::<f64>() / sea.len() as f64;
        let mut grey = sea.mapv(|v| {
            (130.0 + 12.0 * (10.0 * (v as f64).log10() - mean_db))
                .clamp(0.0, 255.0)
                .round()
        });
        grey.slice_mut(s![300..315, 300..304]).fill(255.0);
        // the display path reads grey levels as dB
        let image = grey.mapv(|g| 10f64.powf(g / 10.0) as f32);
        let g = geometry();
        let single = CfarOptions::with_pfa(1e-9);
        let windowed = CfarOptions {
            target_m: 50.0,
            ..single
        };
        assert!(find_ships(image.view(), &g, &single).ships.is_empty());
        let found = find_ships(image.view(), &g, &windowed).ships;
        assert_eq!(found.len(), 1, "{found:#?}");
        assert!(
            (found[0].row - 307.0).abs() < 2.0 && (found[0].col - 301.5).abs() < 2.0,
            "{:?}",
            found[0]
        );
        assert!((found[0].length_m - 150.0).abs() < 30.0, "length {}", found[0].length_m);
    }
}

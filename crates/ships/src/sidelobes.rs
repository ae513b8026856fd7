//! The directions of a scene's sidelobe streaks, measured on its bright targets.
//!
//! A point target's impulse response has its sidelobes along the SAR's two axes, range and
//! azimuth: an unweighted sinc's first sidelobe is 13.3 dB under its peak (Cumming & Wong 2005,
//! the peak sidelobe ratio), so a target 20-30 dB over the sea draws bright streaks hundreds of
//! metres long through itself. Every target in a scene draws them in the same two directions. In
//! a product in radar geometry these are the image's rows and columns; in a chip that was
//! geocoded or rotated (SSDD's, many display images) they lie at the track's angle to them,
//! 10-20 degrees off. Through a ship near an edge, or one whose streak runs on through other
//! targets on one side, such a streak looks one-sided, and the wake search took it for a bright
//! arm: on SSDD's ship chips most of the wakes reported were such streaks (docs/results.md).
//!
//! A streak runs both ways from its target, where a wake runs one way from its ship and a hull
//! ends after its length. So each bright target's profile is taken over directions: the
//! dimmer of the two rays either way, from beyond the hull's length outwards. A direction that
//! stands far above the profile's others (robust z at least [`MIN_Z`]) on two targets alike
//! (within [`AGREE_DEG`]) is a sidelobe axis of the scene. One target's two-way line is no
//! axis: a pier, a row of moored ships or another ship's wake through it run both ways too.

use crate::cfar::Ship;
use crate::line_difference;
use crate::radon::{robust_spread, Normalised};

use rayon::prelude::*;

/// The step of the directions measured (degrees).
const STEP_DEG: f64 = 0.5;

/// The length of each ray beyond the hull (pixels): a streak 1-2 pixels wide subtends under a
/// degree at its far end.
const RAY_PIXELS: f64 = 40.0;

/// How far to either side of a target's brightest pixel its streaks are sought (pixels).
const OFFSET_PIXELS: f64 = 3.0;

/// How many of the brightest targets are measured.
const MAX_TARGETS: usize = 12;

/// The least robust z of a direction on one target for it to be a sidelobe axis.
pub const MIN_Z: f64 = 6.0;

/// How closely (degrees) two targets' two-way lines must agree to be one of the scene's axes.
/// One target's two-way line may be anything that runs through it both ways: a pier, a row of
/// moored ships, a wake through a ship that follows in its lane (on a tuning image of a
/// shipping lane, four true arms were lost to such lines; docs/results.md). A sidelobe axis is
/// the same for every target in the scene.
pub const AGREE_DEG: f64 = 1.0;

/// Distinct peaks of one target's profile, and distinct axes, lie at least this far apart
/// (degrees).
const SEPARATION_DEG: f64 = 2.0;

/// How close (degrees, as lines) a bright arm may run to a sidelobe axis. A line a few degrees
/// off a streak through its ship stays on the streak for its first few hundred metres, and that
/// alone can lift the line's mean over its sides: on SSDD's chips the arms taken along streaks
/// ran 2-3 degrees off the axes measured on their targets.
pub const AXIS_TOLERANCE_DEG: f64 = 4.0;

/// The directions (degrees clockwise from up, in [0, 180)) along which streaks run both ways
/// through at least two of the brightest of `ships` in `image` (within [`AGREE_DEG`]),
/// strongest first.
pub fn sidelobe_axes(image: &Normalised, ships: &[Ship]) -> Vec<f64> {
    let mut brightest: Vec<&Ship> = ships.iter().collect();
    brightest.sort_by(|a, b| b.peak_db.total_cmp(&a.peak_db));
    brightest.truncate(MAX_TARGETS);
    let per_target: Vec<Vec<(f64, f64)>> = brightest.par_iter().map(|ship| two_way_peaks(image, ship)).collect();
    let mut found: Vec<(usize, f64, f64)> = per_target
        .iter()
        .enumerate()
        .flat_map(|(t, peaks)| peaks.iter().map(move |&(axis, z)| (t, axis, z)))
        .collect();
    found.sort_by(|a, b| b.2.total_cmp(&a.2));
    let mut axes: Vec<f64> = Vec::new();
    for &(t, axis, _) in &found {
        // the others' lines within AGREE_DEG of this one, as offsets from it (lines wrap at 180)
        let offsets: Vec<f64> = found
            .iter()
            .filter(|&&(u, other, _)| u != t && line_difference(axis, other) <= AGREE_DEG)
            .map(|&(_, other, _)| crate::angle_difference(2.0 * other, 2.0 * axis) / 2.0)
            .collect();
        if offsets.is_empty() {
            continue;
        }
        let mean = (axis + offsets.iter().sum::<f64>() / (offsets.len() + 1) as f64).rem_euclid(180.0);
        if axes.iter().all(|&a| line_difference(a, mean) > SEPARATION_DEG) {
            axes.push(mean);
        }
    }
    axes
}

/// Whether a line along `heading` (degrees) runs within [`AXIS_TOLERANCE_DEG`] of one of `axes`.
pub fn along_an_axis(heading: f64, axes: &[f64]) -> bool {
    axes.iter().any(|&a| line_difference(heading, a) <= AXIS_TOLERANCE_DEG)
}

/// The directions (in [0, 180)) and robust z of the lines running both ways through `ship`'s
/// brightest pixel that stand at least [`MIN_Z`] over the others: each a local maximum of the
/// profile, the strongest within [`SEPARATION_DEG`].
fn two_way_peaks(image: &Normalised, ship: &Ship) -> Vec<(f64, f64)> {
    let g = &image.geometry;
    let pixel = g.spacing.0.max(g.spacing.1);
    // from the brightest pixel, which may lie at one end of the hull, out past its length
    let near = ship.length_m + 2.0 * pixel;
    let far = near + RAY_PIXELS * pixel;
    let start = (ship.peak_row as f64, ship.peak_col as f64);
    let n = (180.0 / STEP_DEG).round() as usize;
    // the line through the brightest pixel, or one up to OFFSET_PIXELS to either side of it:
    // in a display image the return is clipped, and its brightest pixel is any of the clipped
    // ones, while the streaks run through the scatterer among them
    let offsets = crate::lines::span(-OFFSET_PIXELS * pixel, OFFSET_PIXELS * pixel, 0.5 * pixel);
    let profile: Vec<f64> = (0..n)
        .map(|k| {
            let h = k as f64 * STEP_DEG;
            offsets
                .iter()
                .map(|&x| {
                    let (a, _) = image.ray_mean(start, h, (near, far), x, 0.0);
                    let (b, _) = image.ray_mean(start, h + 180.0, (near, far), -x, 0.0);
                    a.min(b)
                })
                .fold(f64::NAN, f64::max)
        })
        .collect();
    let finite: Vec<f64> = profile.iter().copied().filter(|v| v.is_finite()).collect();
    if finite.len() < n / 2 {
        return Vec::new();
    }
    let (m, sigma) = robust_spread(&finite);
    let z: Vec<f64> = profile
        .iter()
        .map(|&v| {
            if v.is_finite() {
                (v - m) / sigma
            } else {
                f64::NEG_INFINITY
            }
        })
        .collect();
    let reach = (SEPARATION_DEG / STEP_DEG).round() as usize;
    (0..n)
        .filter(|&k| z[k] >= MIN_Z && (1..=reach).all(|d| z[k] >= z[(k + d) % n] && z[k] >= z[(k + n - d) % n]))
        .map(|k| (k as f64 * STEP_DEG, z[k]))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cfar::{find_ships, CfarOptions};
    use crate::radon::SearchImage;
    use crate::Geometry;

    /// Two bright targets, (150, 150) and (260, 250), on 4-look speckle, 10 m pixels, and where
    /// `cross` is given, their sidelobes: 1-pixel streaks 3 dB over the sea for 1.5 km both
    /// ways along `cross` and `cross + 90` degrees, or one way only along the first where
    /// `one_way`.
    fn targets_with_streaks(cross: Option<f64>, one_way: bool, seed: u64) -> (ndarray::Array2<f32>, Geometry) {
        let g = Geometry::along_rows(10.0, 35.0, None);
        let mut image = crate::speckle(400, 400, 4, 0.01, seed);
        let targets = [(150usize, 150usize), (260, 250)];
        if let Some(axis) = cross {
            let streaks = if one_way {
                vec![(axis, 0)]
            } else {
                vec![(axis, -1500), (axis + 90.0, -1500)]
            };
            let mut on = std::collections::BTreeSet::new();
            for &(tr, tc) in &targets {
                for &(h, from) in &streaks {
                    let (ur, uc) = g.step(h);
                    for d in (from..=1500).step_by(5) {
                        let (r, c) = (tr as f64 + ur * d as f64, tc as f64 + uc * d as f64);
                        if (0.0..399.5).contains(&r) && (0.0..399.5).contains(&c) {
                            on.insert((r.round() as usize, c.round() as usize));
                        }
                    }
                }
            }
            for p in on {
                image[p] *= 2.0;
            }
        }
        for (tr, tc) in targets {
            image.slice_mut(ndarray::s![tr - 2..=tr + 2, tc - 1..=tc + 1]).fill(3.0);
        }
        (image, g)
    }

    /// Two targets' sidelobes 15 degrees off the image's axes (a rotated chip) give the scene's
    /// two axes within half a degree; streaks one way only (wakes) and plain speckle give none.
    #[test]
    fn a_rotated_chips_sidelobe_axes_are_measured_and_one_way_streaks_are_none() {
        for seed in 0..4 {
            for (cross, one_way) in [(Some(15.0), false), (Some(15.0), true), (None, false)] {
                let (image, g) = targets_with_streaks(cross, one_way, 40 + seed);
                let ships = find_ships(image.view(), &g, &CfarOptions::default());
                assert_eq!(ships.ships.len(), 2, "{:?}", ships.ships);
                let search = SearchImage::new(image.view(), &g, 2000.0);
                let axes = sidelobe_axes(&search.fine, &ships.ships);
                if cross.is_some() && !one_way {
                    assert_eq!(axes.len(), 2, "{axes:?}");
                    for want in [15.0, 105.0] {
                        assert!(axes.iter().any(|&a| line_difference(a, want) <= 0.5), "{axes:?}");
                    }
                } else {
                    assert!(axes.is_empty(), "{cross:?} one way {one_way}: {axes:?}");
                }
            }
        }
    }

    /// One target with a line through it both ways (a pier, a wake through a ship in its lane)
    /// makes no axis: an axis must run through two targets.
    #[test]
    fn one_targets_two_way_line_is_no_axis() {
        let (mut image, g) = targets_with_streaks(None, false, 3);
        let (ur, uc) = g.step(40.0);
        for d in (-1200..=1200).step_by(5) {
            let (r, c) = (150.0 + ur * d as f64, 150.0 + uc * d as f64);
            if (0.0..399.5).contains(&r) && (0.0..399.5).contains(&c) {
                image[[r.round() as usize, c.round() as usize]] = 0.02;
            }
        }
        let ships = find_ships(image.view(), &g, &CfarOptions::default());
        let search = SearchImage::new(image.view(), &g, 2000.0);
        let first = ships
            .ships
            .iter()
            .find(|s| (s.row - 150.0).abs() < 3.0)
            .expect("the target");
        assert!(two_way_peaks(&search.fine, first)
            .iter()
            .any(|&(a, _)| line_difference(a, 40.0) <= 0.5));
        assert!(sidelobe_axes(&search.fine, &ships.ships).is_empty());
    }

    /// A weaker target 1 km out along a brighter one's sidelobe streak (15 degrees off the
    /// image's axes): from it, the streak runs 1 km back through the brighter target and on,
    /// and only 500 m the other way, so it looks like a bright arm. Sought without the scene's
    /// axes it is taken for one; the search, which measures them on the targets, finds no wake.
    #[test]
    fn a_streak_through_a_weaker_target_is_no_arm_once_the_axes_are_measured() {
        let (mut image, g) = targets_with_streaks(Some(15.0), false, 7);
        let (ur, uc) = g.step(15.0);
        let weak = (
            (260.0 + ur * 1000.0).round() as usize,
            (250.0 + uc * 1000.0).round() as usize,
        );
        image
            .slice_mut(ndarray::s![weak.0 - 1..=weak.0 + 1, weak.1 - 1..=weak.1 + 1])
            .fill(1.0);
        let o = crate::wake::WakeOptions::default();
        let ships = find_ships(image.view(), &g, &CfarOptions::default());
        assert_eq!(ships.ships.len(), 3, "{:?}", ships.ships);
        let at_weak = ships
            .ships
            .iter()
            .position(|s| (s.row - weak.0 as f64).abs() < 3.0 && (s.col - weak.1 as f64).abs() < 3.0)
            .expect("the weaker target");
        let blind = SearchImage::new(image.view(), &g, crate::BACKGROUND_M);
        let arm = crate::wake::ship_wake(&blind, &ships.ships[at_weak], at_weak, &o).expect("the streak as an arm");
        assert!(line_difference(arm.axis_deg, 15.0) <= AXIS_TOLERANCE_DEG, "{arm:?}");
        let found = crate::search(image.view(), &g, &CfarOptions::default(), &o);
        assert!(found.wakes.is_empty(), "{:?}", found.wakes);
    }
}

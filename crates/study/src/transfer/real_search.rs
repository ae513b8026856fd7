//! The classic ship and wake search (`wakelab detect`'s, beside the CNN; issue 39, item 6) on the
//! images of `--real DIR`, scored against the wakes as the user drew them.
//!
//! A wake the search reports finds a drawn wake when the two lines come within
//! [`FOUND_WITHIN_M`] of each other and their axes differ by at most [`AXIS_WITHIN_DEG`]: the
//! CNN's rule of 500 m, with the direction a line adds (a line across the wake, through it, is
//! not the wake). Drawn wakes have no direction, so the axis error is taken modulo 180 degrees:
//! the search's course (ship at the apex) is not checked here. Every reported wake that finds
//! no drawn one is a false wake.

use crate::steps::calibration::FOUND_WITHIN_M;
use crate::steps::open_sea::distance_to_segment;
use serde::{Deserialize, Serialize};
use serde_json::Value;

/// Metres per degree of latitude (WGS 84's mean radius, 6,371 km).
pub(crate) const M_PER_DEGREE: f64 = 6_371_000.0 * std::f64::consts::PI / 180.0;

/// `p` in metres east and south of `origin`, both (column, row) pixels of `spacing` (m; rows,
/// columns), or with `lonlat` (longitude, latitude) on the plane tangent at `origin`.
pub(crate) fn metres_from(p: (f64, f64), origin: (f64, f64), lonlat: bool, spacing: (f64, f64)) -> (f64, f64) {
    if lonlat {
        let cos = origin.1.to_radians().cos();
        ((p.0 - origin.0) * cos * M_PER_DEGREE, (p.1 - origin.1) * M_PER_DEGREE)
    } else {
        ((p.0 - origin.0) * spacing.1, (p.1 - origin.1) * spacing.0)
    }
}

/// A reported wake's axis within this of a drawn wake's (degrees, modulo 180) finds it.
pub const AXIS_WITHIN_DEG: f64 = 20.0;

/// How the ship search did against the drawn ships of one image ([`super::real_ships`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct ShipScore {
    pub drawn: usize,
    pub found: usize,
    /// Reported ships that found no drawn one.
    pub false_ships: usize,
}

/// How the classic search did on one image.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct SearchScore {
    pub image: String,
    /// Wakes drawn, ships and wakes the search reported.
    pub wakes: usize,
    pub ships: usize,
    pub search_wakes: usize,
    /// Drawn wakes found, and the reported wakes that found none.
    pub found: usize,
    pub false_wakes: usize,
    /// Per drawn wake found, the least axis difference (degrees, modulo 180) of a reported wake
    /// that found it.
    pub axis_errors_deg: Vec<f64>,
    /// The ships against those drawn, where the image's ships are drawn
    /// ([`super::real_ships`]).
    #[serde(default)]
    pub drawn_ships: Option<ShipScore>,
    /// The area scanned (km^2; the first detector's scored cells).
    #[serde(default)]
    pub km2: f64,
    /// Reported wakes with a window of the first detector on their line (`detect`'s
    /// `cnn_windows`: seen by both searches), and those of them that found a drawn wake.
    #[serde(default)]
    pub seen_by_both: usize,
    #[serde(default)]
    pub seen_by_both_found: usize,
    /// The faint lines (a ship's best line refused for its significance alone, `faint_line` in
    /// its `no_wake`), those that find a drawn wake by the rule above, and the drawn wakes no
    /// reported wake found that a faint line does.
    #[serde(default)]
    pub faint_lines: usize,
    #[serde(default)]
    pub faint_on_wake: usize,
    #[serde(default)]
    pub missed_under_faint: usize,
    /// Reported wakes promoted from a faint line (`promoted`: the image's search found no
    /// other), and those of them that found a drawn wake.
    #[serde(default)]
    pub promoted: usize,
    #[serde(default)]
    pub promoted_found: usize,
    /// Why the image was not searched.
    pub skipped: Option<String>,
}

/// A line in metres on a plane: (x, y) of its ends.
type Segment = ((f64, f64), (f64, f64));

/// The least distance between two segments: zero where they cross, else the least of their
/// ends' distances to the other.
fn segments_apart(a: Segment, b: Segment) -> f64 {
    let cross = |o: (f64, f64), p: (f64, f64), q: (f64, f64)| (p.0 - o.0) * (q.1 - o.1) - (p.1 - o.1) * (q.0 - o.0);
    let (d1, d2) = (cross(b.0, b.1, a.0), cross(b.0, b.1, a.1));
    let (d3, d4) = (cross(a.0, a.1, b.0), cross(a.0, a.1, b.1));
    if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
        return 0.0;
    }
    [
        distance_to_segment(a.0, b),
        distance_to_segment(a.1, b),
        distance_to_segment(b.0, a),
        distance_to_segment(b.1, a),
    ]
    .into_iter()
    .fold(f64::INFINITY, f64::min)
}

/// The difference of two segments' axes (degrees, 0-90: a line has no direction).
fn axis_difference(a: Segment, b: Segment) -> f64 {
    let axis = |s: Segment| (s.1 .1 - s.0 .1).atan2(s.1 .0 - s.0 .0).to_degrees();
    wakelab_ships::line_difference(axis(a), axis(b))
}

/// A reported wake's ends as the annotation places them: (column, row) of the product's
/// pixels, or (longitude, latitude).
fn wake_ends(wake: &Value, lonlat: bool) -> Option<((f64, f64), (f64, f64))> {
    let point = |key: &str| -> Option<(f64, f64)> {
        let p = &wake[key];
        let (a, b) = (p.get(0)?.as_f64()?, p.get(1)?.as_f64()?);
        // product_* are [row, column]; lonlat_* [longitude, latitude]
        Some(if lonlat { (a, b) } else { (b, a) })
    };
    if lonlat {
        Some((point("lonlat_start")?, point("lonlat_end")?))
    } else {
        Some((point("product_start")?, point("product_end")?))
    }
}

/// The faint lines of `written`'s ships: the `faint_line` of each refused trough and arm.
fn faint_lines(written: &Value) -> impl Iterator<Item = &Value> {
    written["ships"].as_array().into_iter().flatten().flat_map(|ship| {
        ["trough", "bright_arm"]
            .into_iter()
            .map(move |kind| &ship["no_wake"][kind]["faint_line"])
            .filter(|line| line.is_object())
    })
}

/// Score the ships and wakes of `detections.json` (`written`) against the drawn `wakes`
/// (polylines of (column, row) pixels, or of (longitude, latitude) with `lonlat`); `spacing`
/// (m; rows, columns) scales the product's pixels.
pub fn score_search(wakes: &[Vec<(f64, f64)>], lonlat: bool, written: &Value, spacing: (f64, f64)) -> SearchScore {
    // metres on the plane tangent at `origin` (longitude and latitude), or pixels scaled
    let metres = |p: (f64, f64), origin: (f64, f64)| metres_from(p, origin, lonlat, spacing);
    // the drawn wakes a line finds, each with its axis difference
    let finds = |(start, end): ((f64, f64), (f64, f64))| -> Vec<(usize, f64)> {
        let line = (metres(start, start), metres(end, start));
        let mut found = Vec::new();
        for (i, drawn) in wakes.iter().enumerate() {
            for s in drawn.windows(2) {
                let segment = (metres(s[0], start), metres(s[1], start));
                let axis = axis_difference(line, segment);
                if segments_apart(line, segment) <= FOUND_WITHIN_M && axis <= AXIS_WITHIN_DEG {
                    found.push((i, axis));
                }
            }
        }
        found
    };
    // each reported wake's ends, whether a CNN window lies on it, and whether it is a
    // promoted faint line
    let reported: Vec<_> = written["wakes"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|w| {
            let windows = w["cnn_windows"].as_array().is_some_and(|l| !l.is_empty());
            let promoted = w["promoted"].as_bool() == Some(true);
            wake_ends(w, lonlat).map(|ends| (ends, windows, promoted))
        })
        .collect();
    let mut best: Vec<Option<f64>> = vec![None; wakes.len()];
    let (mut false_wakes, mut seen_by_both, mut seen_by_both_found) = (0, 0, 0);
    let (mut promoted, mut promoted_found) = (0, 0);
    for &(ends, windows, is_promoted) in &reported {
        let found = finds(ends);
        for &(i, axis) in &found {
            best[i] = Some(best[i].map_or(axis, |b: f64| b.min(axis)));
        }
        let found_one = !found.is_empty();
        false_wakes += usize::from(!found_one);
        seen_by_both += usize::from(windows);
        seen_by_both_found += usize::from(windows && found_one);
        promoted += usize::from(is_promoted);
        promoted_found += usize::from(is_promoted && found_one);
    }
    let faint: Vec<_> = faint_lines(written).filter_map(|l| wake_ends(l, lonlat)).collect();
    let mut under_faint = vec![false; wakes.len()];
    let mut faint_on_wake = 0;
    for &ends in &faint {
        let found = finds(ends);
        faint_on_wake += usize::from(!found.is_empty());
        for (i, _) in found {
            under_faint[i] = true;
        }
    }
    SearchScore {
        image: String::new(),
        wakes: wakes.len(),
        ships: written["ships"].as_array().map_or(0, Vec::len),
        search_wakes: reported.len(),
        found: best.iter().flatten().count(),
        false_wakes,
        missed_under_faint: best.iter().zip(&under_faint).filter(|(b, &u)| b.is_none() && u).count(),
        axis_errors_deg: best.into_iter().flatten().collect(),
        drawn_ships: None,
        km2: 0.0,
        seen_by_both,
        seen_by_both_found,
        faint_lines: faint.len(),
        faint_on_wake,
        promoted,
        promoted_found,
        skipped: None,
    }
}

/// What the search's scores add up to.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct SearchSummary {
    /// Images with a drawn wake, and those where the search found one of them.
    pub wake_images: usize,
    pub images_found: usize,
    /// Drawn wakes, and those found.
    pub wakes: usize,
    pub wakes_found: usize,
    pub false_wakes_per_wake_image: f64,
    /// Images without a drawn wake, and those where the search reported none.
    pub no_wake_images: usize,
    pub no_wake_images_clean: usize,
    pub ships_per_image: f64,
    /// The median axis error of the wakes found (degrees, modulo 180).
    pub median_axis_error_deg: Option<f64>,
    /// Over the images whose ships are drawn: how many, the ships drawn and found, and the
    /// false ships per image and per 100 km^2 scanned.
    #[serde(default)]
    pub ship_images: usize,
    #[serde(default)]
    pub drawn_ships: usize,
    #[serde(default)]
    pub ships_found: usize,
    #[serde(default)]
    pub false_ships_per_image: f64,
    #[serde(default)]
    /// None where no image with drawn ships was scanned (null in `real.json`).
    pub false_ships_per_100_km2: Option<f64>,
    /// Over the wake images: the reported wakes seen by both searches (a CNN window on their
    /// line) and those of them on a drawn wake; the wakes of the line search alone, and those
    /// on a drawn wake.
    #[serde(default)]
    pub seen_by_both: usize,
    #[serde(default)]
    pub seen_by_both_found: usize,
    #[serde(default)]
    pub line_search_only: usize,
    #[serde(default)]
    pub line_search_only_found: usize,
    /// Wake images with a wake found and at most one false wake (the transfer issue's target).
    #[serde(default)]
    pub images_found_one_false: usize,
    /// Over all images searched: the faint lines and those on a drawn wake; the wake images
    /// with a wake found or a drawn wake under a faint line; the no-wake images with a faint
    /// line.
    #[serde(default)]
    pub faint_lines: usize,
    #[serde(default)]
    pub faint_on_wake: usize,
    #[serde(default)]
    pub images_found_or_faint: usize,
    #[serde(default)]
    pub no_wake_images_with_faint: usize,
    /// Over all images searched: the wakes promoted from a faint line, and those on a drawn
    /// wake.
    #[serde(default)]
    pub promoted: usize,
    #[serde(default)]
    pub promoted_found: usize,
    /// Images not searched.
    pub skipped: usize,
}

/// The summary of `scores`.
pub fn summarise_search(scores: &[SearchScore]) -> SearchSummary {
    let searched: Vec<&SearchScore> = scores.iter().filter(|s| s.skipped.is_none()).collect();
    let with: Vec<&&SearchScore> = searched.iter().filter(|s| s.wakes > 0).collect();
    let without: Vec<&&SearchScore> = searched.iter().filter(|s| s.wakes == 0).collect();
    let mut errors: Vec<f64> = searched
        .iter()
        .flat_map(|s| s.axis_errors_deg.iter().copied())
        .collect();
    errors.sort_by(f64::total_cmp);
    let median = match errors.len() {
        0 => None,
        n if n % 2 == 1 => Some(errors[n / 2]),
        n => Some(0.5 * (errors[n / 2 - 1] + errors[n / 2])),
    };
    let drawn: Vec<(ShipScore, f64)> = searched.iter().filter_map(|s| Some((s.drawn_ships?, s.km2))).collect();
    let false_ships = drawn.iter().map(|(d, _)| d.false_ships as f64).sum::<f64>();
    let ship_km2: f64 = drawn.iter().map(|(_, km2)| km2).sum();
    SearchSummary {
        wake_images: with.len(),
        images_found: with.iter().filter(|s| s.found > 0).count(),
        wakes: with.iter().map(|s| s.wakes).sum(),
        wakes_found: with.iter().map(|s| s.found).sum(),
        false_wakes_per_wake_image: with.iter().map(|s| s.false_wakes as f64).sum::<f64>() / with.len().max(1) as f64,
        no_wake_images: without.len(),
        no_wake_images_clean: without.iter().filter(|s| s.search_wakes == 0).count(),
        ships_per_image: searched.iter().map(|s| s.ships as f64).sum::<f64>() / searched.len().max(1) as f64,
        median_axis_error_deg: median,
        ship_images: drawn.len(),
        drawn_ships: drawn.iter().map(|(d, _)| d.drawn).sum(),
        ships_found: drawn.iter().map(|(d, _)| d.found).sum(),
        false_ships_per_image: false_ships / drawn.len().max(1) as f64,
        false_ships_per_100_km2: (ship_km2 > 0.0).then(|| 100.0 * false_ships / ship_km2),
        seen_by_both: with.iter().map(|s| s.seen_by_both).sum(),
        seen_by_both_found: with.iter().map(|s| s.seen_by_both_found).sum(),
        line_search_only: with.iter().map(|s| s.search_wakes - s.seen_by_both).sum(),
        line_search_only_found: with
            .iter()
            .map(|s| (s.search_wakes - s.false_wakes) - s.seen_by_both_found)
            .sum(),
        images_found_one_false: with.iter().filter(|s| s.found > 0 && s.false_wakes <= 1).count(),
        faint_lines: searched.iter().map(|s| s.faint_lines).sum(),
        faint_on_wake: searched.iter().map(|s| s.faint_on_wake).sum(),
        images_found_or_faint: with.iter().filter(|s| s.found > 0 || s.missed_under_faint > 0).count(),
        no_wake_images_with_faint: without.iter().filter(|s| s.faint_lines > 0).count(),
        promoted: searched.iter().map(|s| s.promoted).sum(),
        promoted_found: searched.iter().map(|s| s.promoted_found).sum(),
        skipped: scores.len() - searched.len(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    /// Segments that cross are 0 apart; parallel ones their offset; one ending short of
    /// another, the distance from its end (a 3-4-5 triangle).
    #[test]
    fn segments_are_apart_by_their_nearest_points() {
        let horizontal = ((0.0, 0.0), (10.0, 0.0));
        assert_eq!(segments_apart(horizontal, ((5.0, -1.0), (5.0, 1.0))), 0.0);
        assert!((segments_apart(horizontal, ((0.0, 2.0), (10.0, 2.0))) - 2.0).abs() < 1e-12);
        assert!((segments_apart(horizontal, ((13.0, 4.0), (13.0, 9.0))) - 5.0).abs() < 1e-12);
        // axes: modulo 180, at most 90
        assert!((axis_difference(horizontal, ((10.0, 0.0), (0.0, 0.0)))).abs() < 1e-12);
        assert!((axis_difference(horizontal, ((0.0, 0.0), (1.0, 1.0))) - 45.0).abs() < 1e-12);
        assert!((axis_difference(horizontal, ((0.0, 0.0), (-1.0, 1.0))) - 45.0).abs() < 1e-12);
    }

    /// A reported wake 30 px (300 m at 10 m) beside a drawn one and 10 degrees off finds it;
    /// one across it (90 degrees) and one 80 px (800 m) away are false; the second drawn wake
    /// stays unfound.
    #[test]
    fn a_reported_wake_finds_a_drawn_one_near_and_along_it() {
        let drawn = [vec![(100.0, 100.0), (300.0, 100.0)], vec![(0.0, 500.0), (50.0, 500.0)]];
        let along = 200.0 * 10f64.to_radians().tan();
        // product_* are [row, column]
        // faint lines, product_* [row, column]: along the first drawn wake (found already),
        // along the second (found by none), and across the first
        let faint = |start: [f64; 2], end: [f64; 2]| json!({"product_start": start, "product_end": end});
        let written = json!({
            "ships": [
                {"no_wake": {"trough": {"faint_line": faint([110.0, 100.0], [110.0, 280.0])},
                             "bright_arm": {"faint_line": faint([510.0, 0.0], [505.0, 50.0])}}},
                {"no_wake": {"trough": {"faint_line": faint([0.0, 200.0], [400.0, 200.0])},
                             "bright_arm": {"faint_line": null}}},
            ],
            "wakes": [
                {"product_start": [130.0, 100.0], "product_end": [130.0 + along, 300.0], "cnn_windows": [0], "promoted": true},
                {"product_start": [50.0, 200.0], "product_end": [150.0, 200.0], "cnn_windows": [1, 2], "promoted": false},
                {"product_start": [180.0, 100.0], "product_end": [180.0, 300.0], "cnn_windows": [], "promoted": true},
            ]
        });
        let s = score_search(&drawn, false, &written, (10.0, 10.0));
        assert_eq!(
            (s.wakes, s.ships, s.search_wakes, s.found, s.false_wakes),
            (2, 2, 3, 1, 2)
        );
        assert_eq!(s.axis_errors_deg.len(), 1);
        assert!((s.axis_errors_deg[0] - 10.0).abs() < 1e-9, "{:?}", s.axis_errors_deg);
        // the first and the second have CNN windows on them; only the first found a drawn wake
        assert_eq!((s.seen_by_both, s.seen_by_both_found), (2, 1));
        // three faint lines, two on drawn wakes; the second drawn wake, missed, lies under one
        assert_eq!((s.faint_lines, s.faint_on_wake, s.missed_under_faint), (3, 2, 1));
        // two marked promoted: the first, on a drawn wake, and the third, 800 m off it
        assert_eq!((s.promoted, s.promoted_found), (2, 1));
    }

    /// The summary: images with a wake found, wakes found, false wakes per wake image, clean
    /// no-wake images, the median axis error, the drawn ships; skipped images left out.
    #[test]
    fn the_search_summary_adds_up() {
        let score = |wakes, found, false_wakes, errors: Vec<f64>| SearchScore {
            image: "x".into(),
            wakes,
            ships: 3,
            search_wakes: found + false_wakes,
            found,
            false_wakes,
            axis_errors_deg: errors,
            drawn_ships: None,
            km2: 4.0,
            // one wake seen by both in each, on a drawn wake where one was found
            seen_by_both: 1,
            seen_by_both_found: found.min(1),
            faint_lines: 0,
            faint_on_wake: 0,
            missed_under_faint: 0,
            promoted: 0,
            promoted_found: 0,
            skipped: None,
        };
        let ships = |drawn, found, false_ships| ShipScore {
            drawn,
            found,
            false_ships,
        };
        let scores = [
            SearchScore {
                drawn_ships: Some(ships(3, 2, 1)),
                promoted: 1,
                promoted_found: 1,
                ..score(2, 1, 1, vec![4.0])
            },
            SearchScore {
                drawn_ships: Some(ships(0, 0, 2)),
                ..score(1, 1, 0, vec![2.0])
            },
            SearchScore {
                faint_lines: 2,
                faint_on_wake: 1,
                missed_under_faint: 1,
                ..score(1, 0, 3, vec![])
            },
            SearchScore {
                faint_lines: 2,
                ..score(0, 0, 0, vec![])
            },
            score(0, 0, 1, vec![]),
            SearchScore {
                skipped: Some("unreadable".into()),
                ..score(1, 0, 0, vec![])
            },
        ];
        let s = summarise_search(&scores);
        assert_eq!((s.wake_images, s.images_found, s.wakes, s.wakes_found), (3, 2, 4, 2));
        assert!((s.false_wakes_per_wake_image - 4.0 / 3.0).abs() < 1e-12);
        assert_eq!((s.no_wake_images, s.no_wake_images_clean, s.skipped), (2, 1, 1));
        assert_eq!(s.median_axis_error_deg, Some(3.0));
        assert!((s.ships_per_image - 3.0).abs() < 1e-12);
        // ships: two images drawn (8 km^2), 2 of 3 found, 3 false ships
        assert_eq!((s.ship_images, s.drawn_ships, s.ships_found), (2, 3, 2));
        assert!((s.false_ships_per_image - 1.5).abs() < 1e-12);
        assert!((s.false_ships_per_100_km2.unwrap() - 37.5).abs() < 1e-12);
        // read with the CNN, over the three wake images: 3 wakes seen by both, 2 of them on a
        // drawn wake; 3 of the line search alone (6 reported), none of them on one
        assert_eq!((s.seen_by_both, s.seen_by_both_found), (3, 2));
        assert_eq!((s.line_search_only, s.line_search_only_found), (3, 0));
        // a wake found with at most one false wake: the first two wake images; found or under
        // a faint line: all three; the clean no-wake image holds two faint lines
        assert_eq!(s.images_found_one_false, 2);
        assert_eq!((s.faint_lines, s.faint_on_wake, s.images_found_or_faint), (4, 1, 3));
        assert_eq!(s.no_wake_images_with_faint, 1);
        assert_eq!((s.promoted, s.promoted_found), (1, 1));
        // without drawn ships there is no rate of false ships, and the summary still reads
        // back from real.json (a NaN was written as null and failed to read, which dropped
        // the section from later reports)
        let undrawn: Vec<SearchScore> = scores
            .iter()
            .map(|s| SearchScore {
                drawn_ships: None,
                ..s.clone()
            })
            .collect();
        let s = summarise_search(&undrawn);
        assert_eq!((s.ship_images, s.false_ships_per_100_km2), (0, None));
        let text = serde_json::to_string(&s).unwrap();
        assert_eq!(serde_json::from_str::<SearchSummary>(&text).unwrap(), s);
    }
}

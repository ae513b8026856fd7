//! The two wake detectors of `detect` read together: the CNN's flagged windows and the classic
//! line search's wakes (issue 39, item 2: "score both detectors on the same scenes, and fuse them
//! where that helps"). A window and a wake see the same wake when the window's centre lies within
//! [`REACH_M`] of the wake's line, the rule by which issue 38, item 7 counts a window as finding a
//! wake. Each wake then says which windows agree with it, each window which wake it lies on, and
//! the scene's evidence counts the wakes seen by both, by the line search alone and by the CNN
//! alone: what an analyst reads first.

use crate::steps::open_sea::distance_to_segment;
use serde::Serialize;
use wakelab_learn::detect::Found;
use wakelab_ships::wake::Wake;

/// How far (m) a window's centre may lie from a wake's line and still see it: issue 38, item 7's
/// 500 m.
pub const REACH_M: f64 = 500.0;

/// Which windows and wakes see the same wake.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Corroboration {
    /// For each wake, the indices of the flagged windows on its line.
    pub wake_windows: Vec<Vec<usize>>,
    /// For each flagged window, the wake it lies on (the nearest where several), if any.
    pub window_wake: Vec<Option<usize>>,
    /// The scene's evidence.
    pub evidence: Evidence,
}

/// The scene's wakes by who saw them.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct Evidence {
    /// Wakes of the line search with a flagged window on their line.
    pub both: usize,
    /// Wakes of the line search without one.
    pub line_search_only: usize,
    /// Flagged windows on no wake of the line search (neighbouring windows are one each).
    pub cnn_only: usize,
}

impl Evidence {
    /// "2 wake(s) seen by both, 1 by the line search alone, 0 CNN window(s) on no wake".
    pub fn describe(&self) -> String {
        format!(
            "{} wake(s) seen by both the line search and the CNN, {} by the line search alone, {} CNN window(s) on \
             no wake of the line search",
            self.both, self.line_search_only, self.cnn_only
        )
    }
}

/// Ground distance (m) from `p` to the segment `a`-`b`, all in pixels (row, column) of
/// `spacing` (m between rows, m between columns).
fn distance_m(p: (f64, f64), a: (f64, f64), b: (f64, f64), spacing: (f64, f64)) -> f64 {
    let to_m = |q: (f64, f64)| (q.0 * spacing.0, q.1 * spacing.1);
    distance_to_segment(to_m(p), (to_m(a), to_m(b)))
}

/// The windows `found` by the CNN and the `wakes` of the line search, both in the scanned
/// image's pixels of `spacing` (m between rows, between columns), read together.
pub fn corroborate(found: &[Found], wakes: &[Wake], spacing: (f64, f64)) -> Corroboration {
    let window_wake: Vec<Option<usize>> = found
        .iter()
        .map(|f| {
            wakes
                .iter()
                .enumerate()
                .map(|(k, w)| (k, distance_m((f.row, f.col), w.start, w.end, spacing)))
                .filter(|&(_, d)| d <= REACH_M)
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .map(|(k, _)| k)
        })
        .collect();
    let wake_windows: Vec<Vec<usize>> = wakes
        .iter()
        .map(|w| {
            found
                .iter()
                .enumerate()
                .filter(|(_, f)| distance_m((f.row, f.col), w.start, w.end, spacing) <= REACH_M)
                .map(|(k, _)| k)
                .collect()
        })
        .collect();
    let both = wake_windows.iter().filter(|w| !w.is_empty()).count();
    let evidence = Evidence {
        both,
        line_search_only: wakes.len() - both,
        cnn_only: window_wake.iter().filter(|w| w.is_none()).count(),
    };
    Corroboration {
        wake_windows,
        window_wake,
        evidence,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use wakelab_ships::wake::Signature;

    fn window(row: f64, col: f64) -> Found {
        Found {
            row,
            col,
            score: 0.99,
            area: 64,
            orientation: None,
            length: None,
        }
    }

    fn wake(start: (f64, f64), end: (f64, f64)) -> Wake {
        Wake {
            ship: None,
            signature: Signature::Trough,
            start,
            end,
            axis_deg: 0.0,
            course_deg: None,
            course_sigma_deg: None,
            length_m: 0.0,
            contrast: -1.0,
            z: 5.0,
            along_hull: false,
            arms: None,
            offset_m: None,
            speed: None,
            promoted: false,
        }
    }

    /// A window 490 m beside a wake's line (49 pixels of 10 m) sees it, one 510 m off does not;
    /// beyond the line's end the distance is to the end, not to the line extended (490 m past
    /// it in reach, 600 m not): the 500 m of issue 38, item 7, on the ground.
    #[test]
    fn a_window_sees_a_wake_within_500_m_of_its_line() {
        let wakes = [wake((100.0, 100.0), (100.0, 400.0))];
        let found = [
            window(149.0, 250.0),
            window(151.0, 250.0),
            window(100.0, 460.0),
            window(100.0, 449.0),
        ];
        let c = corroborate(&found, &wakes, (10.0, 10.0));
        assert_eq!(c.window_wake, vec![Some(0), None, None, Some(0)]);
        assert_eq!(c.wake_windows, vec![vec![0, 3]]);
        assert_eq!(
            c.evidence,
            Evidence {
                both: 1,
                line_search_only: 0,
                cnn_only: 2
            }
        );
        // at 20 m pixels the same window 49 pixels off lies 980 m away
        let coarse = corroborate(&found[..1], &wakes, (20.0, 20.0));
        assert_eq!(coarse.window_wake, vec![None]);
    }

    /// Pixels that are not square: the distance is taken on the ground, rows and columns each
    /// at their own spacing.
    #[test]
    fn the_distance_is_on_the_ground() {
        let wakes = [wake((0.0, 0.0), (0.0, 100.0)), wake((0.0, 300.0), (100.0, 300.0))];
        // 40 rows off the first (400 m at 10 m rows) and 60 columns off the second (1,200 m at 20 m columns)
        let found = [window(40.0, 50.0), window(50.0, 240.0)];
        let c = corroborate(&found, &wakes, (10.0, 20.0));
        assert_eq!(c.window_wake, vec![Some(0), None]);
        assert_eq!(
            c.evidence,
            Evidence {
                both: 1,
                line_search_only: 1,
                cnn_only: 1
            }
        );
    }

    /// A window near two wakes belongs to the nearer, and counts for both wakes' agreement.
    #[test]
    fn a_window_between_two_wakes_belongs_to_the_nearer() {
        let wakes = [wake((0.0, 0.0), (0.0, 100.0)), wake((60.0, 0.0), (60.0, 100.0))];
        let c = corroborate(&[window(40.0, 50.0)], &wakes, (10.0, 10.0));
        assert_eq!(c.window_wake, vec![Some(1)]);
        assert_eq!(c.wake_windows, vec![vec![0], vec![0]]);
        assert_eq!(c.evidence.both, 2);
    }
}

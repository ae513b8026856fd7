//! A scan's peak: which of its windows it is ([`PeakRule`]) and where that window places its
//! wake ([`Tile::place`]). The detections do not depend on the rule: they are the windows above
//! the threshold ([`crate::detect`]).

use crate::tile::Tile;
use serde::Serialize;
use std::fmt;
use std::str::FromStr;

/// Which of a scan's windows is its peak.
///
/// `Network` is the detector's own choice. `Line` is the classic detector's: the largest sum of
/// the Radon plane (Rey et al. 1990), taken over the scan's windows, which needs no training.
/// On 53 real wake images the line's peak lay on a wake more often than the shipped detectors'
/// own (35 against 29 at 1.28 km, 27 against 16 at 2.56 km) and as often as or more often than
/// five of six trained detectors' (docs/results.md, "The strongest line as `detect`'s peak").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum PeakRule {
    /// The most probable window (the first of equals, in scan order).
    #[default]
    Network,
    /// The window whose strongest line has the largest contrast |z| (the first of equals); the
    /// most probable window where no window has a line (a flat image).
    Line,
}

impl PeakRule {
    pub const ALL: [PeakRule; 2] = [PeakRule::Network, PeakRule::Line];

    pub fn name(self) -> &'static str {
        match self {
            PeakRule::Network => "network",
            PeakRule::Line => "line",
        }
    }
}

impl fmt::Display for PeakRule {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for PeakRule {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        PeakRule::ALL
            .into_iter()
            .find(|rule| rule.name() == s)
            .ok_or_else(|| format!("the peak's rule is `line` or `network`, not `{s}`"))
    }
}

/// Where the scan places its peak window's wake, as a detection is placed ([`Tile::place`]),
/// whether or not it passes the threshold: on that window's strongest line.
///
/// Not the map's largest cell: a cell in an image's corner is one window's probability and an
/// inner one the mean of up to four (at the default stride of half a window), so the largest
/// cell falls at the edges and corners more often than the windows' scores say: in 35 % of 244
/// scans of real images (61 images, four detectors), where corners are on average 11 % of an
/// image's cells. Nor the map's centroid over the window's cells (until 2026-12-07): that lies
/// within a cell of the window's centre, 600-900 m from a wake that crosses a 1.28 km window
/// off its middle. What the rule finds by chance, [`crate::peak_chance`] (docs/results.md,
/// "The peak placed on the strongest window's line").
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Peak {
    /// The place (pixels; row down, column right).
    pub row: f64,
    pub col: f64,
    /// The peak window's probability (under [`PeakRule::Network`], the image's
    /// [`crate::detect::Detection::probability`]).
    pub probability: f64,
    /// The direction of the window's strongest line, as [`crate::detect::Found::orientation`]
    /// (None for a flat window).
    pub orientation: Option<f64>,
    /// That line's contrast: its sum in the window's robust deviations over the root of its
    /// pixels, negative for a dark line (unit variance on uncorrelated noise).
    pub line_contrast: Option<f64>,
    /// The rule that chose the window: `line` falls back to `network` on a scan without lines.
    pub rule: PeakRule,
}

/// The scan's most probable window: the first of equals, row by row, as a scan gives them; a
/// window whose probability is NaN only where every one is.
pub(crate) fn most_probable(tiles: &[Tile]) -> &Tile {
    tiles
        .iter()
        .filter(|t| !t.probability.is_nan())
        .reduce(|best, t| if t.probability > best.probability { t } else { best })
        .or(tiles.first())
        .expect("a scan of at least one window")
}

/// The window whose strongest line has the largest contrast |z|, the first of equals; None
/// where no window has a line.
pub(crate) fn strongest_line_window(tiles: &[Tile]) -> Option<&Tile> {
    tiles
        .iter()
        .filter_map(|t| t.line.map(|l| (t, l.z.abs())))
        .reduce(|best, next| if next.1 > best.1 { next } else { best })
        .map(|(t, _)| t)
}

/// The scan's [`Peak`] by `rule`, of windows of side `n`.
pub fn peak_of(tiles: &[Tile], n: usize, rule: PeakRule) -> Peak {
    let (window, rule) = match rule {
        PeakRule::Line => match strongest_line_window(tiles) {
            Some(window) => (window, PeakRule::Line),
            None => (most_probable(tiles), PeakRule::Network),
        },
        PeakRule::Network => (most_probable(tiles), PeakRule::Network),
    };
    let (row, col) = window.place(n);
    Peak {
        row,
        col,
        probability: window.probability,
        orientation: window.line.map(|l| l.angle),
        line_contrast: window.line.map(|l| l.z),
        rule,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::window_line::WindowLine;

    fn tile(col: usize, probability: f64, z: Option<f64>) -> Tile {
        Tile {
            row: 0,
            col,
            probability,
            line: z.map(|z| WindowLine {
                row: 3.0,
                col: col as f64 + 2.0,
                angle: 10.0 * col as f64,
                length: 8.0,
                z,
            }),
        }
    }

    /// The network's rule takes the most probable window, the line's the window of the largest
    /// |z| (a dark line as a bright one), each placing it on its line; without lines the line's
    /// rule falls back to the network's and says so.
    #[test]
    fn each_rule_takes_its_window() {
        let tiles = [
            tile(0, 0.9, Some(2.0)),
            tile(8, 0.2, Some(-6.0)),
            tile(16, 0.5, Some(6.0)),
        ];
        let network = peak_of(&tiles, 8, PeakRule::Network);
        assert_eq!(
            (network.col, network.probability, network.rule),
            (2.0, 0.9, PeakRule::Network)
        );
        let line = peak_of(&tiles, 8, PeakRule::Line);
        assert_eq!((line.col, line.probability, line.rule), (10.0, 0.2, PeakRule::Line));
        assert_eq!((line.orientation, line.line_contrast), (Some(80.0), Some(-6.0)));
        let flat = [tile(0, 0.1, None), tile(8, 0.7, None)];
        let fallback = peak_of(&flat, 8, PeakRule::Line);
        assert_eq!((fallback.col, fallback.rule), (12.0, PeakRule::Network));
    }

    #[test]
    fn a_rule_is_read_by_its_name_and_a_wrong_one_is_refused() {
        for rule in PeakRule::ALL {
            assert_eq!(rule.to_string().parse::<PeakRule>(), Ok(rule));
            assert_eq!(serde_json::to_value(rule).unwrap(), rule.name());
        }
        let err = "strongest".parse::<PeakRule>().unwrap_err();
        assert!(
            err.contains("`line` or `network`") && err.contains("strongest"),
            "{err}"
        );
    }
}

//! How often a scan's peak would land on a target by chance: the same windows scored at random,
//! their peak placed as [`crate::detect`] does; and where a detector of lines alone would place
//! it ([`peak_by_line`]), the baseline a learnt detector has to beat besides chance.
//!
//! A peak is not a point drawn uniformly over the image: it is one of the scan's windows, placed
//! on that window's strongest line ([`crate::detect::Tile::place`]), so it stays inside a
//! window of the image's edges, and on an image not much larger than a window it falls near the
//! image's middle whatever the detector knows. The line is the image's own: a window crossed by
//! a wake's arm places its peak on the arm whichever detector picked it. Where annotated images
//! are cut around their ship (most chips of the field's datasets), the middle is near the wake,
//! and a count of peaks on a wake means nothing without this figure beside it.
//!
//! The null model is a detector whose window scores are independent and identically
//! distributed (continuous, so ties have no weight): its strongest window is each window with
//! equal probability, so the chance is exactly the share of windows whose place the target
//! accepts. No draws are needed.

use crate::detect::Tile;

/// The chance that a scan of the windows `tiles` (of side `n`) scored at random places its peak
/// where `on_target` (row, column in scanned pixels) accepts it: the share of the windows whose
/// place it accepts (see the module); 0 without windows.
pub fn peak_by_chance(tiles: &[Tile], n: usize, on_target: impl Fn(f64, f64) -> bool) -> f64 {
    if tiles.is_empty() {
        return 0.0;
    }
    let hits = tiles
        .iter()
        .filter(|t| {
            let (row, col) = t.place(n);
            on_target(row, col)
        })
        .count();
    hits as f64 / tiles.len() as f64
}

/// Where a detector that knows lines but not wakes places its peak: the place of the window
/// whose strongest line has the largest contrast |z| ([`crate::window_line`]; the first such in
/// scan order), the classic detector's choice of the Radon plane's largest sum (Rey et al.
/// 1990), made over the scan's windows. The network's peak beating it, not only chance, is
/// what its learning adds on real images. None where no window has a line.
pub fn peak_by_line(tiles: &[Tile], n: usize) -> Option<(f64, f64)> {
    crate::peak::strongest_line_window(tiles).map(|t| t.place(n))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::detect::PeakRule;
    use crate::peak::peak_of;
    use crate::window_line::WindowLine;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The window of the largest |z| wins, a dark line as a bright one, whatever the
    /// probabilities; the first of equals; none without a line.
    #[test]
    fn the_line_peak_is_the_strongest_lines_window() {
        let lined = |col: usize, z: f64, probability: f64| Tile {
            probability,
            line: Some(WindowLine {
                row: 3.0,
                col: col as f64 + 2.0,
                angle: 0.0,
                length: 8.0,
                z,
            }),
            ..tile(0, col, None)
        };
        let tiles = [
            lined(0, 4.0, 0.9),
            lined(8, -6.5, 0.1),
            tile(0, 16, None),
            lined(24, 6.5, 0.5),
        ];
        assert_eq!(peak_by_line(&tiles, 8), Some((3.0, 10.0)));
        assert_eq!(peak_by_line(&tiles[2..3], 8), None);
        assert_eq!(peak_by_line(&[], 8), None);
    }

    fn tile(row: usize, col: usize, line: Option<(f64, f64)>) -> Tile {
        Tile {
            row,
            col,
            probability: 0.0,
            line: line.map(|(row, col)| WindowLine {
                row,
                col,
                angle: 0.0,
                length: 8.0,
                z: 5.0,
            }),
        }
    }

    /// Four windows of 8 px apart, the last two with a line on the target (columns >= 8): by
    /// the share, 1/2; by drawing the windows' scores at random and placing the peak as a scan
    /// does, the same within three standard errors (0.024 in 4,000 draws); the windows without
    /// a line are placed at their centres.
    #[test]
    fn the_chance_is_the_share_of_windows_placed_on_the_target() {
        let mut four = vec![
            tile(0, 0, None),
            tile(8, 0, None),
            tile(0, 8, Some((2.0, 9.0))),
            tile(8, 8, Some((15.0, 10.0))),
        ];
        let on_target = |_: f64, c: f64| c >= 8.0;
        assert_eq!(peak_by_chance(&four, 8, on_target), 0.5);
        assert_eq!(peak_by_chance(&four, 8, |r, c| (r, c) == (12.0, 4.0)), 0.25);
        assert_eq!(peak_by_chance(&[], 8, on_target), 0.0);
        let mut rng = ChaCha8Rng::seed_from_u64(38);
        let draws = 4000;
        let hits = (0..draws)
            .filter(|_| {
                for t in four.iter_mut() {
                    t.probability = rng.random_range(0.0..1.0);
                }
                let peak = peak_of(&four, 8, PeakRule::Network);
                on_target(peak.row, peak.col)
            })
            .count();
        let drawn = hits as f64 / draws as f64;
        assert!((drawn - 0.5).abs() < 0.024, "{drawn}");
    }
}

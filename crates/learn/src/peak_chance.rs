//! How often a scan's peak would land on a target by chance: the same windows scored at random,
//! their map made and their peak placed as [`crate::detect`] does.
//!
//! A peak is not a point drawn uniformly over the image: it is one of the scan's windows, placed
//! by the map over that window's cells, so it stays about half a window inside the image's
//! edges, and on an image not much larger than a window it falls near the image's middle
//! whatever the detector knows. Where annotated images are cut around their ship (most chips of
//! the field's datasets), the middle is near the wake, and a count of peaks on a wake means
//! nothing without this figure beside it. The null model is a detector whose window scores are
//! independent and uniform: each draw gives every window a score, averages the map as a scan
//! does, and places the peak by the same rule ([`crate::detect::Peak`]).

use ndarray::Array2;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::detect::{mean_map, peak_of, window_cells, Tile};

/// The share of `draws` random scorings (from `seed`) of the windows `tiles` (of side `n`,
/// every `stride` pixels, on a map of `cells` (rows, columns) of `stride`-pixel cells) whose
/// peak (row, column in scanned pixels) `on_target` accepts.
pub fn peak_by_chance(
    tiles: &[Tile],
    cells: (usize, usize),
    n: usize,
    stride: usize,
    on_target: impl Fn(f64, f64) -> bool,
    draws: usize,
    seed: u64,
) -> f64 {
    if tiles.is_empty() || draws == 0 {
        return 0.0;
    }
    let shape = Array2::<f32>::zeros(cells);
    let covered: Vec<Vec<(usize, usize)>> = tiles.iter().map(|t| window_cells(t, &shape, n, stride)).collect();
    let mut count = Array2::<f32>::zeros(cells);
    for &cell in covered.iter().flatten() {
        count[cell] += 1.0;
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut drawn = tiles.to_vec();
    let mut hits = 0usize;
    for _ in 0..draws {
        let mut sum = Array2::<f32>::zeros(cells);
        for (tile, cells) in drawn.iter_mut().zip(&covered) {
            tile.probability = rng.random_range(0.0..1.0);
            for &cell in cells {
                sum[cell] += tile.probability as f32;
            }
        }
        // as a scan's map: the mean of the windows over each cell, no-data where none is
        let map = mean_map(&sum, &count);
        let peak = peak_of(&map, &drawn, n, stride);
        hits += usize::from(on_target(peak.row, peak.col));
    }
    hits as f64 / draws as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tiles(origins: &[(usize, usize)]) -> Vec<Tile> {
        origins
            .iter()
            .map(|&(row, col)| Tile {
                row,
                col,
                probability: 0.0,
            })
            .collect()
    }

    /// Four windows that do not overlap (stride = side): each window's cells hold its own
    /// score, so the peak is the strongest window's centre, each window's with probability 1/4.
    #[test]
    fn four_windows_apart_each_hold_the_peak_a_quarter_of_the_time() {
        let four = tiles(&[(0, 0), (0, 8), (8, 0), (8, 8)]);
        let draws = 4000;
        let top_left = peak_by_chance(&four, (2, 2), 8, 8, |r, c| r < 8.0 && c < 8.0, draws, 1);
        // three standard errors of a share of 1/4 in 4,000 draws: 0.021
        assert!((top_left - 0.25).abs() < 0.021, "{top_left}");
        let centres = peak_by_chance(
            &four,
            (2, 2),
            8,
            8,
            |r, c| [4.0, 12.0].contains(&r) && [4.0, 12.0].contains(&c),
            draws,
            1,
        );
        assert_eq!(centres, 1.0, "every peak at a window's centre");
        assert_eq!(
            top_left,
            peak_by_chance(&four, (2, 2), 8, 8, |r, c| r < 8.0 && c < 8.0, draws, 1)
        );
    }

    /// Three windows of 8 every 4 pixels along a row (cells 0-1, 1-2, 2-3): the left window's
    /// peak lies left of cell 1's centre (cell 0 weighs in), the right one's right of cell 2's,
    /// the middle one's between them; so the middle band holds it 1/3 of the time.
    #[test]
    fn overlapping_windows_place_the_peak_between_their_cells() {
        let three = tiles(&[(0, 0), (0, 4), (0, 8)]);
        let draws = 6000;
        let middle = peak_by_chance(&three, (2, 4), 8, 4, |_, c| c > 6.0 && c < 10.0, draws, 7);
        // three standard errors of 1/3 in 6,000 draws: 0.018
        assert!((middle - 1.0 / 3.0).abs() < 0.018, "{middle}");
        let inside = peak_by_chance(&three, (2, 4), 8, 4, |_, c| (2.0..=14.0).contains(&c), draws, 7);
        assert_eq!(inside, 1.0, "a peak stays within its window's cells' centres");
    }
}

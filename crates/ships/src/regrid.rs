//! A ship search's findings moved to another grid: from the image's own pixels to the coarser
//! grid its wakes are sought on (an image averaged over blocks of pixels), and into a tile of
//! that grid. Positions change; what is in metres or dB (a return's length, its peak) does not.

use crate::cfar::{Ship, ShipSearch};

/// The position on a grid `factor` (rows, columns) times coarser, by area averaging from the
/// first pixel, of the fine grid's `(row, col)`: block k holds the fine pixels k f to (k + 1) f,
/// whose middle is the fine position (k + 1/2) f - 1/2.
fn coarse_position((row, col): (f64, f64), factor: (f64, f64)) -> (f64, f64) {
    ((row + 0.5) / factor.0 - 0.5, (col + 0.5) / factor.1 - 0.5)
}

impl Ship {
    /// This ship on a grid `factor` times coarser: its centre moved, its brightest pixel the
    /// block that holds it; the peak's sigma0, its contrast and its pixels as the search found
    /// them on the fine grid.
    fn coarsened(mut self, factor: (f64, f64)) -> Ship {
        (self.row, self.col) = coarse_position((self.row, self.col), factor);
        self.peak_row = (self.peak_row as f64 / factor.0).floor() as usize;
        self.peak_col = (self.peak_col as f64 / factor.1).floor() as usize;
        self
    }

    fn shifted(mut self, origin: (usize, usize)) -> Ship {
        self.row -= origin.0 as f64;
        self.col -= origin.1 as f64;
        self.peak_row = self.peak_row.saturating_sub(origin.0);
        self.peak_col = self.peak_col.saturating_sub(origin.1);
        self
    }
}

impl ShipSearch {
    /// The findings of a search on an image's own pixels, placed on the grid of that image
    /// averaged over blocks of `factor` (rows, columns) pixels
    /// ([`wakelab_products`]' `area_average`, from the first pixel).
    pub fn coarsened(self, factor: (f64, f64)) -> ShipSearch {
        let points = |p: Vec<(f64, f64)>| p.into_iter().map(|q| coarse_position(q, factor)).collect();
        ShipSearch {
            ships: self.ships.into_iter().map(|s| s.coarsened(factor)).collect(),
            ambiguities: self.ambiguities.into_iter().map(|s| s.coarsened(factor)).collect(),
            sidelobes: points(self.sidelobes),
            too_long: points(self.too_long),
            on_land: points(self.on_land),
            ..self
        }
    }

    /// The findings whose centre lies in the tile of `size` (rows, columns) pixels from
    /// `origin`, in the tile's pixels.
    pub fn within(&self, origin: (usize, usize), size: (usize, usize)) -> ShipSearch {
        let inside = |(row, col): (f64, f64)| {
            let (r, c) = (row - origin.0 as f64, col - origin.1 as f64);
            (-0.5..size.0 as f64 - 0.5).contains(&r) && (-0.5..size.1 as f64 - 0.5).contains(&c)
        };
        let ships = |all: &[Ship]| {
            all.iter()
                .filter(|s| inside((s.row, s.col)))
                .map(|s| s.clone().shifted(origin))
                .collect()
        };
        let points = |all: &[(f64, f64)]| {
            all.iter()
                .filter(|&&p| inside(p))
                .map(|&(r, c)| (r - origin.0 as f64, c - origin.1 as f64))
                .collect()
        };
        ShipSearch {
            ships: ships(&self.ships),
            ambiguities: ships(&self.ambiguities),
            sidelobes: points(&self.sidelobes),
            too_long: points(&self.too_long),
            on_land: points(&self.on_land),
            threshold_sigmas: self.threshold_sigmas,
            options: self.options,
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::cfar::{find_ships, CfarOptions};
    use crate::Geometry;
    use ndarray::Array2;

    /// A ship found on 3 m pixels and placed on the 20 m grid of the same image averaged over
    /// blocks of 20/3 pixels lies where the 20 m image's own search finds it: the two centres
    /// are the same ground point, within a 20 m pixel's tenth.
    #[test]
    fn a_ship_found_on_fine_pixels_lies_where_the_coarse_grid_holds_it() {
        let (rows, cols) = (1200, 1000);
        let mut fine = crate::speckle(rows, cols, 4, 0.01, 7);
        // a return of 150 x 24 m, 30 dB over the sea, its centre at (600.5, 400.5) fine pixels
        for r in 575..625 {
            for c in 397..405 {
                fine[[r, c]] = 10.0;
            }
        }
        let factor = 20.0 / 3.0;
        let coarse = block_mean(&fine, factor);
        let options = CfarOptions {
            land: None,
            ..CfarOptions::default()
        };
        let on_fine = find_ships(fine.view(), &Geometry::along_rows(3.0, 35.0, None), &options);
        let on_coarse = find_ships(coarse.view(), &Geometry::along_rows(20.0, 35.0, None), &options);
        assert_eq!((on_fine.ships.len(), on_coarse.ships.len()), (1, 1));
        let moved = on_fine.coarsened((factor, factor));
        let (a, b) = (&moved.ships[0], &on_coarse.ships[0]);
        assert!(
            (a.row - b.row).abs() < 0.1 && (a.col - b.col).abs() < 0.1,
            "fine search moved to ({:.2}, {:.2}), coarse search ({:.2}, {:.2})",
            a.row,
            a.col,
            b.row,
            b.col
        );
        assert_eq!((a.peak_row, a.peak_col), (86, 59));
        // in a tile from (50, 40) it lies 50 rows and 40 columns nearer the origin; outside
        // one it is left out
        let tile = moved.within((50, 40), (100, 100));
        assert_eq!(tile.ships.len(), 1);
        assert!((tile.ships[0].row - (a.row - 50.0)).abs() < 1e-12);
        assert!(moved.within((0, 0), (50, 50)).ships.is_empty());
    }

    /// The mean over blocks of `factor` pixels from the first, fractional edges weighed (as
    /// `wakelab_products::resample::area_average`, which this crate does not depend on).
    fn block_mean(image: &Array2<f32>, factor: f64) -> Array2<f32> {
        let out = |n: usize| (n as f64 / factor).floor() as usize;
        let (rows, cols) = (out(image.nrows()), out(image.ncols()));
        let weights = |k: usize| {
            let (lo, hi) = (k as f64 * factor, (k + 1) as f64 * factor);
            (lo.floor() as usize..hi.ceil() as usize)
                .map(move |i| (i, (hi.min(i as f64 + 1.0) - lo.max(i as f64)).max(0.0)))
        };
        Array2::from_shape_fn((rows, cols), |(r, c)| {
            let (mut sum, mut total) = (0.0, 0.0);
            for (i, wr) in weights(r) {
                for (j, wc) in weights(c) {
                    sum += wr * wc * image[[i, j]] as f64;
                    total += wr * wc;
                }
            }
            (sum / total) as f32
        })
    }
}

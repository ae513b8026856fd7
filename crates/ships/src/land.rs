//! Land found in the image itself, for products that come without a land mask (a chip, a
//! display image, a product whose user gave no `--exclude`): the searches then leave it out as
//! they leave out no data.
//!
//! What makes false ships on land is what a CFAR sees there: bright point scatterers (buildings,
//! quays, slopes facing the radar) standing far above their neighbourhood, dense over areas
//! wider than any ship. The open sea's speckle, its wind fronts and its slicks change the sea's
//! level over kilometres but leave few pixels far above their own neighbourhood. So land is
//! read from texture and brightness, then an area rule (SNAP and Crisp 2004 mask land with a
//! coastline; this is for images without one, and its rules are this crate's own, tuned on the
//! real images below):
//!
//! 1. the image in dB is cut into cells of `cell_m` (at least 5 pixels a side); each cell's
//!    median and spread (1.4826 MAD) are taken, and the sea's spread is the median of the
//!    cells' (a pixel's speckle), at least 1 dB;
//! 2. each cell's reference is the median of the cell medians within `reference_m` of it;
//! 3. a cell is a land candidate when at least `density` of its pixels stand `level` spreads
//!    above its reference;
//! 4. candidates are closed over `closing_m` (the dark streets and shadows between bright
//!    blocks), and a connected region of them is land when it holds a disc of radius
//!    `min_radius_m` (400 m): far wider than the widest ship (about 70 m), so that a ship, bright
//!    as it is, with its sidelobes, is never land, and a ship moored against a quay is land with
//!    the quay;
//! 5. land grows by `buffer_m` into the sea (the shore's cells with too few bright pixels).
//!
//! Measured on 232 SSDD test chips, 30 real wake images and 5 CauchySAR images
//! (docs/results.md): land found in 26 of 46 inshore chips, and on no open sea of the wake
//! images; inshore false ships 2.15 -> 2.00 per chip.

use crate::Geometry;
use ndarray::{Array2, ArrayView2};
use rayon::prelude::*;
use serde::Serialize;

/// The land mask's settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LandOptions {
    /// Side of a cell (m), and the fewest pixels a side: a cell's median and spread are read
    /// from at least 25 pixels (at 20 m, 9 pixels of a near-black display sea spread by 0).
    pub cell_m: f64,
    pub min_cell_pixels: usize,
    /// Half-side of the window of cells whose medians make a cell's reference (m).
    pub reference_m: f64,
    /// How far above its reference a pixel stands to count (the sea's spreads in dB), the
    /// spread taken at least `min_spread_db`: speckle's is 2-6 dB in calibrated dB, while a
    /// display's near-black sea, quantised to a few grey levels, can read under 1.
    pub level: f64,
    pub min_spread_db: f64,
    /// The least share of a cell's pixels that stand so high for the cell to be land.
    pub density: f64,
    /// Gaps between land cells closed up to this radius (m).
    pub closing_m: f64,
    /// A region is land when it holds a disc of this radius (m).
    pub min_radius_m: f64,
    /// Land grows by this much (m) into the sea: the shore's cells that hold too few bright
    /// pixels to count, and the quays' edges (a coastline buffer, as masks from coastlines
    /// take one).
    pub buffer_m: f64,
}

impl Default for LandOptions {
    fn default() -> Self {
        Self {
            cell_m: 50.0,
            min_cell_pixels: 5,
            reference_m: 500.0,
            level: 5.0,
            min_spread_db: 1.0,
            density: 0.15,
            closing_m: 100.0,
            min_radius_m: 400.0,
            buffer_m: 50.0,
        }
    }
}

/// A pixel's value in dB; no data (NaN) and non-positive values are NaN.
fn db(v: f32) -> f32 {
    if v.is_finite() && v > 0.0 {
        10.0 * v.log10()
    } else {
        f32::NAN
    }
}

/// The median of `v` (reordered), NaN when it is empty.
fn median_of(v: &mut [f32]) -> f32 {
    if v.is_empty() {
        return f32::NAN;
    }
    let mid = v.len() / 2;
    *v.select_nth_unstable_by(mid, f32::total_cmp).1
}

/// The cells of `image` (`size` pixels a side, the last ones cut by the image's edge): each
/// cell's finite values in dB.
fn cell_values(image: ArrayView2<f32>, size: (usize, usize)) -> (Array2<Vec<f32>>, (usize, usize)) {
    let (h, w) = image.dim();
    let grid = (h.div_ceil(size.0), w.div_ceil(size.1));
    let rows: Vec<Vec<Vec<f32>>> = (0..grid.0)
        .into_par_iter()
        .map(|i| {
            (0..grid.1)
                .map(|j| {
                    let (r0, c0) = (i * size.0, j * size.1);
                    let (r1, c1) = ((r0 + size.0).min(h), (c0 + size.1).min(w));
                    image
                        .slice(ndarray::s![r0..r1, c0..c1])
                        .iter()
                        .map(|&v| db(v))
                        .filter(|v| v.is_finite())
                        .collect()
                })
                .collect()
        })
        .collect();
    let cells = Array2::from_shape_vec(grid, rows.into_iter().flatten().collect()).expect("the grid's shape");
    (cells, grid)
}

/// The land of `image` (linear sigma0, or a display's grey levels read as dB and made linear;
/// NaN for no data): true where a pixel is land.
pub fn land_mask(image: ArrayView2<f32>, geometry: &Geometry, o: &LandOptions) -> Array2<bool> {
    let (h, w) = image.dim();
    let size = (
        ((o.cell_m / geometry.spacing.0).round() as usize).max(o.min_cell_pixels.max(1)),
        ((o.cell_m / geometry.spacing.1).round() as usize).max(o.min_cell_pixels.max(1)),
    );
    let cell_m = 0.5 * (size.0 as f64 * geometry.spacing.0 + size.1 as f64 * geometry.spacing.1);
    let (cells, grid) = cell_values(image, size);
    // each cell's median and spread, counted where at least half its pixels hold data
    let stats: Vec<(f32, f32)> = cells
        .as_slice()
        .expect("standard layout")
        .par_iter()
        .map(|values| {
            let full = values.len() * 2 >= size.0 * size.1;
            if !full {
                return (f32::NAN, f32::NAN);
            }
            let mut v = values.clone();
            let m = median_of(&mut v);
            let mut dev: Vec<f32> = v.iter().map(|x| (x - m).abs()).collect();
            (m, 1.4826 * median_of(&mut dev))
        })
        .collect();
    let mut spreads: Vec<f32> = stats.iter().map(|s| s.1).filter(|s| s.is_finite()).collect();
    let spread = median_of(&mut spreads);
    if !spread.is_finite() {
        return Array2::from_elem((h, w), false);
    }
    let spread = spread.max(o.min_spread_db as f32);
    let medians = Array2::from_shape_vec(grid, stats.iter().map(|s| s.0).collect()).expect("the grid's shape");
    // each cell's reference: the median of the cell medians around it (every other cell of the
    // window: the same level, a quarter of the work)
    let reach = ((o.reference_m / cell_m).round() as usize).max(1);
    let candidates: Vec<bool> = (0..grid.0 * grid.1)
        .into_par_iter()
        .map(|k| {
            let (i, j) = (k / grid.1, k % grid.1);
            let mut around: Vec<f32> = (i.saturating_sub(reach)..(i + reach + 1).min(grid.0))
                .step_by(2)
                .flat_map(|a| {
                    (j.saturating_sub(reach)..(j + reach + 1).min(grid.1))
                        .step_by(2)
                        .map(move |b| (a, b))
                })
                .map(|(a, b)| medians[[a, b]])
                .filter(|m| m.is_finite())
                .collect();
            let reference = median_of(&mut around);
            let values = &cells[[i, j]];
            if !reference.is_finite() || values.is_empty() {
                return false;
            }
            let high = values
                .iter()
                .filter(|&&v| v > reference + o.level as f32 * spread)
                .count();
            high as f64 >= o.density * values.len() as f64
        })
        .collect();
    let candidates = Array2::from_shape_vec(grid, candidates).expect("the grid's shape");
    let closed = closing(&candidates, ((o.closing_m / cell_m).round() as usize).max(1));
    let land_cells = dilated(
        &wide_regions(&closed, o.min_radius_m / cell_m),
        (o.buffer_m / cell_m).round() as usize,
    );
    Array2::from_shape_fn((h, w), |(r, c)| land_cells[[r / size.0, c / size.1]])
}

/// The cells within `radius` cells of a set cell of `mask`.
fn dilated(mask: &Array2<bool>, radius: usize) -> Array2<bool> {
    let (h, w) = mask.dim();
    let r = radius as isize;
    Array2::from_shape_fn((h, w), |(i, j)| {
        (-r..=r).any(|a| {
            (-r..=r).any(|b| {
                let (y, x) = (i as isize + a, j as isize + b);
                a * a + b * b <= r * r
                    && y >= 0
                    && x >= 0
                    && y < h as isize
                    && x < w as isize
                    && mask[[y as usize, x as usize]]
            })
        })
    })
}

/// `mask` closed (dilated, then eroded) by a disc of `radius` cells; the grid's outside counts
/// as set for the erosion, so that land cut by the image's edge is not eaten from it.
fn closing(mask: &Array2<bool>, radius: usize) -> Array2<bool> {
    let (h, w) = mask.dim();
    let r = radius as isize;
    let disc: Vec<(isize, isize)> = (-r..=r)
        .flat_map(|a| (-r..=r).map(move |b| (a, b)))
        .filter(|(a, b)| a * a + b * b <= r * r)
        .collect();
    let at = |m: &Array2<bool>, i: isize, j: isize, outside: bool| {
        if i < 0 || j < 0 || i >= h as isize || j >= w as isize {
            outside
        } else {
            m[[i as usize, j as usize]]
        }
    };
    let grown = dilated(mask, radius);
    Array2::from_shape_fn((h, w), |(i, j)| {
        mask[[i, j]]
            || disc
                .iter()
                .all(|(a, b)| at(&grown, i as isize + a, j as isize + b, true))
    })
}

/// The 8-connected regions of `mask` that hold a disc of `radius` cells: the cells' distance
/// to the nearest unset cell (a two-pass chamfer distance, 3-4 weights, within 8 % of the
/// Euclidean; the grid's outside is not unset, so that land cut by the edge keeps its width).
fn wide_regions(mask: &Array2<bool>, radius: f64) -> Array2<bool> {
    let (h, w) = mask.dim();
    let far = f64::MAX / 4.0;
    let mut d = Array2::from_shape_fn((h, w), |p| if mask[p] { far } else { 0.0 });
    let steps_forward = [(-1isize, -1isize, 4.0), (-1, 0, 3.0), (-1, 1, 4.0), (0, -1, 3.0)];
    for pass in 0..2 {
        let order: Vec<(usize, usize)> = if pass == 0 {
            (0..h).flat_map(|i| (0..w).map(move |j| (i, j))).collect()
        } else {
            (0..h).rev().flat_map(|i| (0..w).rev().map(move |j| (i, j))).collect()
        };
        for (i, j) in order {
            if d[[i, j]] == 0.0 {
                continue;
            }
            for &(a, b, cost) in &steps_forward {
                let (a, b) = if pass == 0 { (a, b) } else { (-a, -b) };
                let (y, x) = (i as isize + a, j as isize + b);
                if y >= 0 && x >= 0 && y < h as isize && x < w as isize {
                    let v = d[[y as usize, x as usize]] + cost;
                    if v < d[[i, j]] {
                        d[[i, j]] = v;
                    }
                }
            }
        }
    }
    // a region wholly set (no unset cell in the grid) is as wide as the grid
    let d = d.mapv(|v| if v >= far { 3.0 * (h.max(w) as f64) } else { v / 3.0 });
    let mut label = Array2::from_elem((h, w), usize::MAX);
    let mut wide = Vec::new();
    for start in 0..h * w {
        let (si, sj) = (start / w, start % w);
        if !mask[[si, sj]] || label[[si, sj]] != usize::MAX {
            continue;
        }
        let id = wide.len();
        let mut stack = vec![(si, sj)];
        label[[si, sj]] = id;
        let mut widest = 0.0f64;
        while let Some((i, j)) = stack.pop() {
            widest = widest.max(d[[i, j]]);
            for a in -1isize..=1 {
                for b in -1isize..=1 {
                    let (y, x) = (i as isize + a, j as isize + b);
                    if y >= 0 && x >= 0 && y < h as isize && x < w as isize {
                        let (y, x) = (y as usize, x as usize);
                        if mask[[y, x]] && label[[y, x]] == usize::MAX {
                            label[[y, x]] = id;
                            stack.push((y, x));
                        }
                    }
                }
            }
        }
        wide.push(widest >= radius);
    }
    label.mapv(|l| l != usize::MAX && wide[l])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{city_beside_the_sea, speckle};

    /// Open sea at 10 m: a wind front (the right half 6 dB brighter), one-look and four-look
    /// speckle, and a ship 300 m long 30 dB over the sea. None of it is land: the front changes
    /// the level, not the share of pixels far above their neighbourhood, and the ship is
    /// narrower than any land.
    #[test]
    fn open_sea_with_a_wind_front_and_a_ship_is_no_land() {
        let g = Geometry::along_rows(10.0, 35.0, None);
        for looks in [1, 4] {
            let mut sea = speckle(600, 600, looks, 0.01, 11 + looks as u64);
            sea.slice_mut(ndarray::s![.., 300..]).mapv_inplace(|v| v * 4.0);
            sea.slice_mut(ndarray::s![285..315, 148..152]).fill(10.0);
            let land = land_mask(sea.view(), &g, &LandOptions::default());
            assert_eq!(land.iter().filter(|&&l| l).count(), 0, "{looks} look(s)");
        }
    }

    /// A city on the shore: the left half's mean 10 dB over the sea's, a fifth of its pixels
    /// (buildings) 20 dB over that, beside open sea of four looks. The city is land; the sea
    /// farther than 100 m from it is not.
    #[test]
    fn a_city_on_the_shore_is_land_and_the_sea_beside_it_is_not() {
        let g = Geometry::along_rows(10.0, 35.0, None);
        let image = city_beside_the_sea();
        let land = land_mask(image.view(), &g, &LandOptions::default());
        let city = land.slice(ndarray::s![.., ..300]);
        let share = city.iter().filter(|&&l| l).count() as f64 / city.len() as f64;
        assert!(share > 0.95, "{share}");
        let sea = land.slice(ndarray::s![.., 310..]);
        assert_eq!(sea.iter().filter(|&&l| l).count(), 0);
    }

    /// A display image's near-black sea (grey levels 0-6, read as dB) at 20 m with ten ships at
    /// grey 255: no land. Cells of 3 pixels there read the sea's spread as 0, and every ship
    /// and speck stood "far" above it: the whole chip was land (SSDD 001109, docs/results.md).
    #[test]
    fn a_near_black_display_sea_with_ships_is_no_land() {
        let g = Geometry::along_rows(20.0, 35.0, None);
        let mut grey = speckle(200, 300, 1, 1.5, 21).mapv(|v| v.floor().min(255.0));
        for k in 0..10 {
            let (r, c) = (15 + 18 * k, 20 + 26 * k);
            grey.slice_mut(ndarray::s![r..r + 8, c..c + 3]).fill(255.0);
        }
        let linear = grey.mapv(|v| 10f32.powf(v / 10.0));
        let land = land_mask(linear.view(), &g, &LandOptions::default());
        assert_eq!(land.iter().filter(|&&l| l).count(), 0);
        let three = LandOptions {
            min_cell_pixels: 3,
            min_spread_db: 0.0,
            ..LandOptions::default()
        };
        assert!(land_mask(linear.view(), &g, &three).iter().any(|&l| l));
    }

    /// No data stays out: an image all NaN, or too small for a cell, has no land.
    #[test]
    fn no_data_is_no_land() {
        let g = Geometry::along_rows(10.0, 35.0, None);
        for image in [Array2::from_elem((50, 50), f32::NAN), Array2::from_elem((1, 1), 0.01)] {
            assert!(!land_mask(image.view(), &g, &LandOptions::default()).iter().any(|&l| l));
        }
    }
}

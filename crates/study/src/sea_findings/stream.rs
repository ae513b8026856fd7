//! The searches over an image that arrives a band of rows at a time, with the margins that let
//! a wake crossing a band's edge be searched whole.

use super::SeaFindings;
use ndarray::ArrayView2;
use wakelab_ships::cfar::CfarOptions;
use wakelab_ships::wake::WakeOptions;
use wakelab_ships::Geometry;

/// How far (m) the searches reach from a row they own: a wake's searched length, the largest
/// azimuth offset of a return from its ship and half the normalisation's background (5 km by
/// default), so that a ship or wake near the edge of a band is searched as in the whole image.
pub fn sea_margin_m() -> f64 {
    let o = WakeOptions::default();
    o.length_m + o.max_offset_m + 0.5 * wakelab_ships::BACKGROUND_M
}

/// Rows and columns a tile of the searches owns: with its margins, a tile of a 10 m product is
/// 2,048 + 1,000 rows by 8,192 + 1,000 columns (on a whole Sentinel-1 IW product, 22 % more
/// time than searching bands without margins, measured: docs/results.md).
pub const TILE_ROWS: usize = 2048;
const TILE_COLUMNS: usize = 8192;

/// The ship and wake searches over an image that arrives a band of rows at a time (a product
/// streamed from disk): the rows are held until `margin` rows past a band of `own` rows have
/// arrived, then that band is searched with `margin` rows either side and keeps what lies in
/// its own rows. Memory holds one band and its margins; a wake that crosses a band's edge is
/// searched whole, not cut there.
pub struct SeaStream {
    findings: SeaFindings,
    own: usize,
    /// Margins in rows and in columns.
    margin: usize,
    margin_cols: usize,
    /// The rows held (and the cross-polarised band's), and the first of them in the whole image.
    held: ndarray::Array2<f32>,
    held_cross: Option<ndarray::Array2<f32>>,
    held_from: usize,
    /// Rows below this are owned by bands already searched.
    searched: usize,
}

impl SeaStream {
    /// A stream of images of `cols` columns at `geometry`, searched in bands of `own` rows, its
    /// ships with `cfar`; with the rows of the cross-polarised band `ships_polarisation`, where
    /// there is one, pushed beside them.
    pub fn new(
        geometry: Geometry,
        cfar: CfarOptions,
        cols: usize,
        own: usize,
        ships_polarisation: Option<String>,
    ) -> Self {
        Self {
            margin: (sea_margin_m() / geometry.spacing.0).ceil() as usize,
            margin_cols: (sea_margin_m() / geometry.spacing.1).ceil() as usize,
            held_cross: ships_polarisation.as_ref().map(|_| ndarray::Array2::zeros((0, cols))),
            findings: SeaFindings::empty(geometry, cfar, ships_polarisation),
            own: own.max(1),
            held: ndarray::Array2::zeros((0, cols)),
            held_from: 0,
            searched: 0,
        }
    }

    /// Cut the CNN's window of `side` scanned pixels around each ship as it is found
    /// ([`SeaFindings::ship_windows`]); None: cut none.
    pub fn with_ship_windows(mut self, side: Option<usize>) -> Self {
        self.findings.ship_window_side = side;
        self
    }

    fn held_to(&self) -> usize {
        self.held_from + self.held.nrows()
    }

    /// Rows `first..first + rows.nrows()` of the image and of its cross-polarised band (rows
    /// already held are skipped; the rows must follow on from those held, overlapping or not).
    pub fn push(&mut self, first: usize, rows: ArrayView2<f32>, cross: Option<ArrayView2<f32>>) {
        let skip = self.held_to().saturating_sub(first).min(rows.nrows());
        assert!(first <= self.held_to(), "rows pushed in order without a gap");
        let append = |held: &ndarray::Array2<f32>, rows: ArrayView2<f32>| {
            ndarray::concatenate(ndarray::Axis(0), &[held.view(), rows.slice(ndarray::s![skip.., ..])])
                .expect("same columns")
        };
        self.held = append(&self.held, rows);
        if let (Some(held), Some(cross)) = (self.held_cross.as_mut(), cross) {
            *held = append(held, cross);
        }
        while self.held_to() >= self.searched + self.own + self.margin {
            self.search_band(self.searched + self.own);
        }
    }

    /// Search the band of rows `searched..own_end` with its margins, then let go of the rows
    /// no later band reaches.
    fn search_band(&mut self, own_end: usize) {
        let from = self.searched.saturating_sub(self.margin).max(self.held_from);
        let to = (own_end + self.margin).min(self.held_to());
        let cols = self.held.ncols();
        // tiles of TILE_COLUMNS own columns across the band, each searched with its margins
        for c0 in (0..cols.max(1)).step_by(TILE_COLUMNS) {
            let c1 = (c0 + TILE_COLUMNS).min(cols);
            let (left, right) = (c0.saturating_sub(self.margin_cols), (c1 + self.margin_cols).min(cols));
            let tile = ndarray::s![from - self.held_from..to - self.held_from, left..right];
            let cross = self.held_cross.as_ref().map(|c| c.slice(tile));
            self.findings.add_tile(
                self.held.slice(tile),
                cross,
                (from, left),
                (self.searched..own_end, c0..c1),
            );
        }
        self.searched = own_end;
        let keep_from = self.searched.saturating_sub(self.margin).max(self.held_from);
        let kept = ndarray::s![keep_from - self.held_from.., ..];
        self.held = self.held.slice(kept).to_owned();
        if let Some(cross) = self.held_cross.as_mut() {
            *cross = cross.slice(kept).to_owned();
        }
        self.held_from = keep_from;
    }

    /// The findings, once every row has arrived.
    pub fn finish(mut self) -> SeaFindings {
        while self.searched < self.held_to() {
            let end = (self.searched + self.own).min(self.held_to());
            self.search_band(end);
        }
        self.findings
    }
}

#[cfg(test)]
mod tests {
    use super::super::scenes::{ship_scene, whole_search};
    use super::super::search_image;
    use super::*;
    use rand::{RngExt, SeedableRng};
    use wakelab_ships::cfar::Ship;
    use wakelab_ships::wake::Wake;

    /// The streamed or tiled findings hold the same ship and its wake, as long.
    fn assert_same(found: &SeaFindings, ship: &Ship, wake: &Wake) {
        assert_eq!(found.ships.len(), 1, "{:?}", found.ships);
        let b = &found.ships[0];
        assert!(
            (ship.row - b.row).abs() < 0.5 && (ship.col - b.col).abs() < 0.5,
            "{ship:?} {b:?}"
        );
        let w = found.wakes.iter().find(|w| w.ship == Some(0)).expect("its wake");
        assert!(
            (w.length_m - wake.length_m).abs() < 0.05 * wake.length_m,
            "{w:?} against {wake:?}"
        );
        assert!((w.start.1 - wake.start.1).abs() < 1.0 && (w.start.0 - wake.start.0).abs() < 1.0);
    }

    /// Streamed in bands of 200 rows (pushed as a scan does, overlapping), the searches find
    /// what the whole image holds: the ship, and its wake whole though it crosses the bands'
    /// edges at rows 800 and 1000. Without the margins the wake is cut there.
    #[test]
    fn a_streamed_search_finds_what_the_whole_image_holds() {
        let image = ship_scene(1600, 300, (700, 150), 0);
        let g = Geometry::along_rows(10.0, 35.0, None);
        let (ship, wake) = whole_search(&image, &g);
        let mut stream = SeaStream::new(g, CfarOptions::default(), 300, 200, None);
        for start in (0..1600).step_by(150) {
            let end = (start + 170).min(1600);
            stream.push(start, image.slice(ndarray::s![start..end, ..]), None);
        }
        let streamed = stream.finish();
        assert_same(&streamed, &ship, &wake);
        // bands without margins (as before): the wake stops at the band's edge, 1 km behind
        let mut cut = SeaFindings::empty(g, CfarOptions::default(), None);
        for start in (0..1600).step_by(200) {
            cut.add_tile(
                image.slice(ndarray::s![start..start + 200, ..]),
                None,
                (start, 0),
                (start..start + 200, 0..300),
            );
        }
        let short = cut
            .wakes
            .iter()
            .filter(|w| w.ship.is_some())
            .map(|w| w.length_m)
            .fold(0.0, f64::max);
        assert!(short < 0.5 * wake.length_m, "{short} m against {} m", wake.length_m);
    }

    /// Land found in a streamed search is the land of the whole image, each pixel counted once
    /// though the bands overlap: a city (its mean 10 dB over the sea's, a fifth of its pixels
    /// 20 dB over that) on the left of a sea 1.6 km tall, streamed in bands of 200 rows.
    #[test]
    fn a_streamed_search_leaves_out_the_land_of_the_whole_image() {
        let mut image = ship_scene(1600, 300, (700, 250), 0);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
        for v in image.slice_mut(ndarray::s![.., ..120]).iter_mut() {
            *v *= if rng.random::<f64>() < 0.2 { 1000.0 } else { 10.0 };
        }
        let g = Geometry::along_rows(10.0, 35.0, None);
        let whole = wakelab_ships::land::land_mask(image.view(), &g, &Default::default());
        let expected = whole.iter().filter(|&&l| l).count();
        assert!(expected >= 1600 * 115, "{expected}");
        let mut stream = SeaStream::new(g, CfarOptions::default(), 300, 200, None);
        for start in (0..1600).step_by(150) {
            let end = (start + 170).min(1600);
            stream.push(start, image.slice(ndarray::s![start..end, ..]), None);
        }
        let streamed = stream.finish();
        assert_eq!(streamed.land_pixels(), expected);
        assert!(streamed
            .land
            .iter()
            .all(|&(r, a, b)| (0..b - a).all(|k| whole[[r, a + k]])));
        assert_eq!(streamed.ships.len(), 1, "{:?}", streamed.ships);
    }

    /// An image wider than a tile: the ship left of the tiles' edge (column 4,096) sailing
    /// left, its wake crossing the edge, is found once and its wake whole.
    #[test]
    fn a_wide_image_is_searched_tile_by_tile_as_a_whole() {
        let image = ship_scene(300, 4800, (150, 4000), 270);
        let g = Geometry::along_rows(10.0, 35.0, None);
        let (ship, wake) = whole_search(&image, &g);
        assert_same(
            &search_image(image.view(), None, g, CfarOptions::default(), None),
            &ship,
            &wake,
        );
    }

    /// Two bright targets astride the edge between two bands of rows ([`TILE_ROWS`]), with
    /// sidelobe streaks 3 dB over the sea at 15 and 105 degrees: both bands hold them in their
    /// margins and measure the same two axes, and the findings hold each once.
    #[test]
    fn a_scenes_sidelobe_axes_are_held_once() {
        let mut image = ship_scene(TILE_ROWS + 600, 300, (700, 150), 0);
        let g = Geometry::along_rows(10.0, 35.0, None);
        let targets = [(TILE_ROWS - 50, 120usize), (TILE_ROWS + 50, 200)];
        let mut on = std::collections::BTreeSet::new();
        for &(tr, tc) in &targets {
            for h in [15.0, 105.0] {
                let (ur, uc) = g.step(h);
                for d in (-1500..=1500).step_by(5) {
                    let (r, c) = (tr as f64 + ur * d as f64, tc as f64 + uc * d as f64);
                    if (0.0..299.5).contains(&c) {
                        on.insert((r.round() as usize, c.round() as usize));
                    }
                }
            }
        }
        for p in on {
            image[p] *= 2.0;
        }
        for (tr, tc) in targets {
            image.slice_mut(ndarray::s![tr - 2..=tr + 2, tc - 1..=tc + 1]).fill(3.0);
        }
        let found = search_image(image.view(), None, g, CfarOptions::default(), None);
        let axes = &found.sidelobe_axes_deg;
        assert_eq!(axes.len(), 2, "{axes:?}");
        for want in [15.0, 105.0] {
            assert!(
                axes.iter().any(|&a| wakelab_ships::line_difference(a, want) <= 0.5),
                "{axes:?}"
            );
        }
    }
}

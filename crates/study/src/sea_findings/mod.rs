//! `wakelab detect`'s ships and wakes: the classic searches ([`wakelab_ships`]) on the product
//! as scanned, with the geometry its metadata gives, and their findings placed on the ground for
//! the files users open (`detections.json`, `detections.geojson`, the overlay).
//!
//! A product in radar geometry (Sentinel-1 GRD, TerraSAR-X MGD, COSMO-SkyMed DGM) has its lines
//! in azimuth-time order and its columns in ground range: the flight runs down the image and
//! the radar looks towards the columns' increase. R/V is the product's mid-swath slant range
//! over its platform's speed where both are annotated. Other inputs state no orbit: their
//! azimuth is taken along the rows and the azimuth offset gives no speed (said in the notes).
//! Courses are given in the image (clockwise from up) and, on a georeferenced product, as true
//! bearings.

mod output;
#[cfg(test)]
mod scenes;
mod stream;

pub use output::wake_colour;
pub use stream::{sea_margin_m, SeaStream, TILE_ROWS};

use ndarray::ArrayView2;
use std::ops::Range;
use wakelab_products::ProductMeta;
use wakelab_ships::cfar::{CfarOptions, Ship};
use wakelab_ships::wake::{NoWake, Wake, WakeOptions};
use wakelab_ships::{search_polarised, Geometry};

/// The ships and wakes found in a scanned product, in the scanned grid's pixels, with the
/// geometry that placed them.
#[derive(Debug, Clone)]
pub struct SeaFindings {
    pub ships: Vec<Ship>,
    pub wakes: Vec<Wake>,
    /// For each ship, why no wake of it was reported (its best trough and bright arm, refused);
    /// None for a ship with a wake.
    pub no_wake: Vec<Option<NoWake>>,
    /// Targets rejected as azimuth ambiguities and sidelobes, and as too long for ships.
    pub ambiguities: usize,
    pub sidelobes: usize,
    /// The directions of the sidelobe streaks measured on the targets (degrees clockwise from
    /// up in the scanned image, in [0, 180)), each tile's, those within 2 degrees of one
    /// already held left out; no bright arm was sought along them.
    pub sidelobe_axes_deg: Vec<f64>,
    pub too_long: usize,
    /// Targets on the land found in the image (not ships).
    pub on_land: usize,
    /// The land found in the image and left out of the searches: runs of scanned pixels
    /// (row, first column, column past the last), so that a product's land costs a few numbers
    /// a row, not a mask.
    pub land: Vec<(usize, usize, usize)>,
    pub geometry: Geometry,
    /// The settings the ships were sought with.
    pub cfar: CfarOptions,
    /// The cross-polarised band the ships were sought in (VH, HV), where the product has one;
    /// None: the scanned band itself.
    pub ships_polarisation: Option<String>,
    /// The side (scanned pixels) of the CNN's window cut around each ship as it is found, and
    /// the windows, one per ship, centred on its return (NaN off the image): what `detect`
    /// scores them with ([`crate::product_scan`]). None: no windows cut.
    pub ship_window_side: Option<usize>,
    pub ship_windows: Vec<ndarray::Array2<f32>>,
    /// Each ship's window's wake probability by the CNN (None: not scored, as a scan scores no
    /// window more than half off the image); empty where no CNN scored them.
    pub ship_cnn: Vec<Option<f64>>,
}

/// The `side` x `side` window of `image` centred on (`row`, `col`) (fractional pixels), NaN
/// where it lies off the image.
pub fn window_around(image: ArrayView2<f32>, (row, col): (f64, f64), side: usize) -> ndarray::Array2<f32> {
    let origin = |centre: f64| (centre + 0.5 - 0.5 * side as f64).round() as isize;
    wakelab_learn::detect::window_at(image, (origin(row), origin(col)), side)
}

/// Whether `meta` is a product in radar geometry (lines in azimuth time, columns in range).
fn radar_geometry(meta: &ProductMeta) -> bool {
    ["Sentinel-1", "TerraSAR-X", "COSMO-SkyMed"]
        .iter()
        .any(|m| meta.format.contains(m))
}

/// The geometry of a product scanned at `spacing` (m between rows, columns), and what it had
/// to assume.
pub fn product_geometry(meta: &ProductMeta, spacing: (f64, f64)) -> (Geometry, Vec<String>) {
    let mut notes = Vec::new();
    let (azimuth_deg, look_deg) = if radar_geometry(meta) {
        (180.0, 90.0)
    } else {
        notes.push(
            "ships and wakes: the input states no orbit; the azimuth is taken along the rows and the ships' azimuth \
             offsets give no speed"
                .to_string(),
        );
        (0.0, 90.0)
    };
    if !meta.calibrated {
        notes.push(if meta.scale == Some(wakelab_products::InputScale::Dn) {
            "ships: no sigma0 or contrast in dB given (null): the input is not calibrated, its digital numbers are dB only up to an unknown offset"
                .into()
        } else {
            "ships: no sigma0 or contrast in dB given (null): the input is not calibrated, its grey levels are not dB"
                .into()
        });
    }
    let incidence_deg = match &meta.incidence {
        Some(i) => i.mid_deg,
        None => {
            notes.push("ships and wakes: no incidence angle annotated; 35 degrees assumed".into());
            35.0
        }
    };
    let range_over_velocity = match (meta.slant_range_mid, meta.platform_velocity) {
        (Some(r), Some(v)) if v > 0.0 && radar_geometry(meta) => Some(r / v),
        _ => {
            if radar_geometry(meta) {
                notes.push(
                    "ships and wakes: the product annotates no platform speed, so R/V and the speeds from azimuth \
                     offsets are unknown"
                        .into(),
                );
            }
            None
        }
    };
    (
        Geometry {
            spacing,
            azimuth_deg,
            look_deg,
            incidence_deg,
            range_over_velocity,
        },
        notes,
    )
}

/// The ship search's false-alarm probability on a display-stretched image unless one is given:
/// the CFAR's model (the sea's dB near Gaussian) holds for calibrated sigma0, not for a
/// display's grey levels, whose tail is heavier. Measured on 60 labelled real SSDD chips and 36
/// real wake images (docs/results.md): 1e-6 gave 2.4 false ships per offshore chip, 1e-9 1.0,
/// for 2 of 128 ships; and on the wake images fewer false wakes, none of their wakes lost.
pub const DISPLAY_SHIP_PFA: f64 = 1e-9;

/// The ship search's target window on a display-stretched image (m, SNAP's default): where a
/// stretch clips its ships at the grey scale's ceiling a few of its sea's deviations up, no
/// single pixel can pass the CFAR, and the window's mean is tested instead
/// ([`CfarOptions::target_m`]). Measured on 58 SSDD chips (109 ships drawn; docs/results.md):
/// 79 ships found against 76, 83 false against 81; the 30 tuning wake images unchanged.
/// Calibrated images keep single pixels, under which the simulated figures were made.
pub const DISPLAY_TARGET_M: f64 = 50.0;

/// How `detect` seeks ships and their wakes: the CFAR's false-alarm probability as the user
/// gave it (`--ship-pfa`), else SNAP's 1e-6 on calibrated images and [`DISPLAY_SHIP_PFA`] on
/// display-stretched ones; and whether land found in the image is left out (the default) or
/// searched too (`--no-land-mask`).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ShipSearch {
    pub pfa: Option<f64>,
    pub keep_land: bool,
}

impl ShipSearch {
    /// `--ship-pfa` and `--no-land-mask` as the user gave them.
    pub fn new(pfa: Option<f64>, keep_land: bool) -> Self {
        Self { pfa, keep_land }
    }

    /// The CFAR's settings for an image that is a `display` stretch or not (calibrated sigma0,
    /// or digital numbers of amplitude, whose dB are sigma0's up to an offset the CFAR does not
    /// see), and a note where the display's default was taken.
    pub fn cfar(&self, display: bool) -> (CfarOptions, Option<String>) {
        let (options, note) = match self.pfa {
            Some(pfa) => (CfarOptions::with_pfa(pfa), None),
            None if !display => (CfarOptions::default(), None),
            None => (
                CfarOptions::with_pfa(DISPLAY_SHIP_PFA),
                Some(format!(
                    "ships: sought at a false-alarm probability of {DISPLAY_SHIP_PFA:e}, not 1e-6: a display stretch's grey levels have a heavier tail than the CFAR's model of calibrated dB (--ship-pfa to choose); where the stretch's ceiling leaves a pixel no room to pass, the mean of a {DISPLAY_TARGET_M} m target window is tested"
                )),
            ),
        };
        let land = if self.keep_land { None } else { options.land };
        let target_m = if display { DISPLAY_TARGET_M } else { 0.0 };
        (
            CfarOptions {
                land,
                target_m,
                ..options
            },
            note,
        )
    }
}

/// A note where an uncalibrated image's brightest value stands fewer of its deviations over its
/// mean than the CFAR's threshold asks ([`wakelab_ships::cfar::ceiling_standing`]): a return
/// clipped at a display stretch's ceiling can then be missed, and the user should know why.
pub fn ceiling_note(image: ArrayView2<f32>, cfar: &CfarOptions) -> Option<String> {
    let standing = wakelab_ships::cfar::ceiling_standing(image)?;
    let threshold = wakelab_ships::cfar::sigmas_for(cfar.pfa);
    (standing < threshold).then(|| {
        format!(
            "ships: the image's brightest value stands {standing:.1} of its deviations over its mean (in dB, as searched), under the CFAR's {threshold:.1}: a return clipped at a display stretch's ceiling passes only by its {DISPLAY_TARGET_M} m target window and can be missed (a calibrated product, or a stretch that leaves its sea lower, avoids this)"
        )
    })
}

/// The searches on `image` (linear sigma0 as scanned), the ships sought (with `cfar`) in
/// `cross` (the product's cross-polarised band on the same grid, named `polarisation`) where one
/// is given: tile by tile as a streamed product's ([`SeaStream`]), so that memory holds one
/// tile's search.
pub fn search_image(
    image: ArrayView2<f32>,
    cross: Option<(ArrayView2<f32>, &str)>,
    geometry: Geometry,
    cfar: CfarOptions,
    ship_window: Option<usize>,
) -> SeaFindings {
    let mut stream = SeaStream::new(geometry, cfar, image.ncols(), TILE_ROWS, cross.map(|c| c.1.to_string()))
        .with_ship_windows(ship_window);
    stream.push(0, image, cross.map(|c| c.0));
    stream.finish()
}

impl SeaFindings {
    /// No findings yet, for a product searched a band at a time (its ships, sought with `cfar`,
    /// in the cross-polarised band `ships_polarisation` where it has one).
    pub fn empty(geometry: Geometry, cfar: CfarOptions, ships_polarisation: Option<String>) -> Self {
        Self {
            ships: Vec::new(),
            wakes: Vec::new(),
            no_wake: Vec::new(),
            ambiguities: 0,
            sidelobes: 0,
            sidelobe_axes_deg: Vec::new(),
            too_long: 0,
            on_land: 0,
            land: Vec::new(),
            geometry,
            cfar,
            ships_polarisation,
            ship_window_side: None,
            ship_windows: Vec::new(),
            ship_cnn: Vec::new(),
        }
    }

    /// Add the findings of a tile of the scanned image whose first pixel is `origin` (row,
    /// column) of the whole image, keeping the ships (and the targets rejected as ghosts) whose
    /// centre, and the free wakes whose middle, lies in its `own` rows and columns: the tiles
    /// overlap, and a finding belongs to the tile that owns its place. `cross` is the tile of
    /// the cross-polarised band where the product has one.
    pub fn add_tile(
        &mut self,
        tile: ArrayView2<f32>,
        cross: Option<ArrayView2<f32>>,
        origin: (usize, usize),
        own: (Range<usize>, Range<usize>),
    ) {
        let found = search_polarised(tile, cross, &self.geometry, &self.cfar, &WakeOptions::default());
        let shift = (origin.0 as f64, origin.1 as f64);
        let owned = |(row, col): (f64, f64)| {
            own.0.contains(&((row + shift.0).max(0.0) as usize)) && own.1.contains(&((col + shift.1).max(0.0) as usize))
        };
        let mut index = std::collections::BTreeMap::new();
        let mut no_wake: std::collections::BTreeMap<usize, NoWake> = found.no_wake.into_iter().collect();
        for (i, mut ship) in found.ships.ships.into_iter().enumerate() {
            if owned((ship.row, ship.col)) {
                if let Some(side) = self.ship_window_side {
                    self.ship_windows.push(window_around(tile, (ship.row, ship.col), side));
                }
                ship.row += shift.0;
                ship.col += shift.1;
                ship.peak_row += origin.0;
                ship.peak_col += origin.1;
                index.insert(i, self.ships.len());
                self.ships.push(ship);
                self.no_wake.push(no_wake.remove(&i).map(|n| n.shifted(shift)));
            }
        }
        for mut wake in found.wakes {
            let middle = (0.5 * (wake.start.0 + wake.end.0), 0.5 * (wake.start.1 + wake.end.1));
            let keep = match wake.ship {
                Some(i) => index.get(&i).copied().map(Some),
                None => owned(middle).then_some(None),
            };
            if let Some(ship) = keep {
                wake.ship = ship;
                wake.start = (wake.start.0 + shift.0, wake.start.1 + shift.1);
                wake.end = (wake.end.0 + shift.0, wake.end.1 + shift.1);
                self.wakes.push(wake);
            }
        }
        let count = |places: Vec<(f64, f64)>| places.into_iter().filter(|&p| owned(p)).count();
        self.ambiguities += count(found.ships.ambiguities.iter().map(|a| (a.row, a.col)).collect());
        self.sidelobes += count(found.ships.sidelobes);
        for axis in found.sidelobe_axes_deg {
            if self
                .sidelobe_axes_deg
                .iter()
                .all(|&a| wakelab_ships::line_difference(a, axis) > 2.0)
            {
                self.sidelobe_axes_deg.push(axis);
            }
        }
        self.too_long += count(found.ships.too_long);
        self.on_land += count(found.ships.on_land);
        if let Some(land) = &found.land {
            // the land of the tile's own rows and columns, as runs of the whole image
            for (r, row) in land.outer_iter().enumerate() {
                let whole_row = r + origin.0;
                if !own.0.contains(&whole_row) {
                    continue;
                }
                let mut start = None;
                for c in 0..=row.len() {
                    let is_land = c < row.len() && row[c] && own.1.contains(&(c + origin.1));
                    match (is_land, start) {
                        (true, None) => start = Some(c),
                        (false, Some(s)) => {
                            self.land.push((whole_row, s + origin.1, c + origin.1));
                            start = None;
                        }
                        _ => {}
                    }
                }
            }
        }
    }

    /// How many scanned pixels of land were left out of the searches.
    pub fn land_pixels(&self) -> usize {
        self.land.iter().map(|&(_, a, b)| b - a).sum()
    }

    /// "2 ship(s), 1 wake(s) (1 of a ship, 0 free)", how many of them are promoted faint lines,
    /// and where ships have none, how many and where to read why.
    pub fn describe(&self) -> String {
        let anchored = self.wakes.iter().filter(|w| w.ship.is_some()).count();
        let without = self.no_wake.iter().filter(|n| n.is_some()).count();
        let faint = self.faint_lines().len();
        let why = match (without, faint) {
            (0, _) => String::new(),
            (_, 0) => format!("; {without} ship(s) without a wake (why: each ship's `no_wake` in detections.json)"),
            _ => format!(
                "; {without} ship(s) without a wake (why: each ship's `no_wake` in detections.json), {faint} faint line(s) below significance among them (`faint_line`)"
            ),
        };
        let promoted = match self.wakes.iter().filter(|w| w.promoted).count() {
            0 => String::new(),
            n => format!("; {n} promoted from a faint line, no other wake found (`promoted`)"),
        };
        format!(
            "{} ship(s), {} wake(s) ({anchored} of a ship, {} free{promoted}){why}",
            self.ships.len(),
            self.wakes.len(),
            self.wakes.len() - anchored
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ship's window is centred on its return, its pixels where the image has them and NaN
    /// off the image.
    #[test]
    fn a_ships_window_is_centred_on_it() {
        let image = ndarray::Array2::from_shape_fn((10, 12), |(r, c)| (100 * r + c) as f32);
        let w = window_around(image.view(), (5.0, 6.0), 4);
        // pixel centres 4-7 (rows) and 5-8 (columns): (5, 6) is the centre's pixel
        assert_eq!(w[[0, 0]], 405.0);
        assert_eq!(w[[3, 3]], 708.0);
        let edge = window_around(image.view(), (0.0, 11.0), 4);
        assert!(edge[[0, 0]].is_nan() && edge[[1, 3]].is_nan());
        assert_eq!(edge[[2, 1]], 11.0);
        assert_eq!(edge.iter().filter(|v| v.is_nan()).count(), 16 - 4);
        // wholly off the image, on either side: all no-data
        for centre in [(-20.0, 5.0), (5.0, 40.0)] {
            assert!(window_around(image.view(), centre, 4).iter().all(|v| v.is_nan()));
        }
    }

    /// The ship search's false-alarm probability: the user's where given; else SNAP's 1e-6 on a
    /// calibrated image and 1e-9 on a display stretch, with a note saying why; the target window
    /// on display stretches only.
    #[test]
    fn the_false_alarm_probability_follows_the_input() {
        let given = ShipSearch {
            pfa: Some(1e-4),
            ..ShipSearch::default()
        };
        assert_eq!(given.cfar(false), (CfarOptions::with_pfa(1e-4), None));
        // a display stretch's ships are also tested by their target window, whatever the P_fa
        let windowed = CfarOptions {
            target_m: DISPLAY_TARGET_M,
            ..CfarOptions::with_pfa(1e-4)
        };
        assert_eq!(given.cfar(true), (windowed, None));
        let unset = ShipSearch::default();
        assert_eq!(unset.cfar(false), (CfarOptions::default(), None));
        assert_eq!(CfarOptions::default().pfa, 1e-6);
        let (display, note) = unset.cfar(true);
        assert_eq!((display.pfa, display.target_m), (1e-9, 50.0));
        assert!(note.unwrap().contains("1e-9, not 1e-6"));
        // land found in the image is left out unless the user keeps it (--no-land-mask)
        assert!(unset.cfar(false).0.land.is_some());
        let keep = ShipSearch {
            keep_land: true,
            ..ShipSearch::default()
        };
        assert_eq!(keep.cfar(true).0.land, None);
    }

    /// A Sentinel-1 product's geometry: flight down the lines, look along the columns, R/V from
    /// its slant range and platform speed; a bare array's: rows, no R/V, and notes saying so.
    #[test]
    fn geometry_follows_the_product() {
        let s1 = ProductMeta {
            format: "Sentinel-1 SAFE".into(),
            slant_range_mid: Some(850_000.0),
            platform_velocity: Some(7400.0),
            calibrated: true,
            ..Default::default()
        };
        let (g, notes) = product_geometry(&s1, (10.0, 10.0));
        assert_eq!((g.azimuth_deg, g.look_deg), (180.0, 90.0));
        assert!((g.range_over_velocity.unwrap() - 114.86).abs() < 0.01);
        assert_eq!(notes.len(), 1, "{notes:?}"); // the incidence, not annotated here
        let bare = ProductMeta {
            calibrated: true,
            ..Default::default()
        };
        let (g, notes) = product_geometry(&bare, (10.0, 10.0));
        assert!(g.range_over_velocity.is_none() && notes.len() == 2, "{notes:?}");
        // an uncalibrated one (a display stretch) says its ships have no sigma0
        let (_, notes) = product_geometry(&ProductMeta::default(), (10.0, 10.0));
        assert!(notes.len() == 3 && notes[1].contains("not calibrated"), "{notes:?}");
    }
}

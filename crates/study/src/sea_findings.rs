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

use image::{Rgb, RgbImage};
use ndarray::ArrayView2;
use serde_json::{json, Map, Value};
use std::ops::Range;
use wakelab_products::geojson::{Finding, Kind};
use wakelab_products::ProductMeta;
use wakelab_ships::cfar::{CfarOptions, Ship};
use wakelab_ships::wake::{Signature, Wake, WakeOptions};
use wakelab_ships::{search_polarised, Geometry};

/// The ships and wakes found in a scanned product, in the scanned grid's pixels, with the
/// geometry that placed them.
#[derive(Debug, Clone)]
pub struct SeaFindings {
    pub ships: Vec<Ship>,
    pub wakes: Vec<Wake>,
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
    let (r0, c0) = (origin(row), origin(col));
    let (h, w) = image.dim();
    ndarray::Array2::from_shape_fn((side, side), |(i, j)| {
        let (r, c) = (r0 + i as isize, c0 + j as isize);
        if r >= 0 && c >= 0 && (r as usize) < h && (c as usize) < w {
            image[[r as usize, c as usize]]
        } else {
            f32::NAN
        }
    })
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
        notes.push(
            "ships: no sigma0 or contrast in dB given (null): the input is not calibrated, its grey levels are not dB"
                .into(),
        );
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

    /// The CFAR's settings for an image that is `calibrated` or not, and a note where the
    /// display's default was taken.
    pub fn cfar(&self, calibrated: bool) -> (CfarOptions, Option<String>) {
        let (options, note) = match self.pfa {
            Some(pfa) => (CfarOptions::with_pfa(pfa), None),
            None if calibrated => (CfarOptions::default(), None),
            None => (
                CfarOptions::with_pfa(DISPLAY_SHIP_PFA),
                Some(format!(
                    "ships: sought at a false-alarm probability of {DISPLAY_SHIP_PFA:e}, not 1e-6: a display stretch's grey levels have a heavier tail than the CFAR's model of calibrated dB (--ship-pfa to choose); where the stretch's ceiling leaves a pixel no room to pass, the mean of a {DISPLAY_TARGET_M} m target window is tested"
                )),
            ),
        };
        let land = if self.keep_land { None } else { options.land };
        let target_m = if calibrated { 0.0 } else { DISPLAY_TARGET_M };
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

    /// "2 ship(s), 1 wake(s) (1 of a ship, 0 free)".
    pub fn describe(&self) -> String {
        let anchored = self.wakes.iter().filter(|w| w.ship.is_some()).count();
        format!(
            "{} ship(s), {} wake(s) ({anchored} of a ship, {} free)",
            self.ships.len(),
            self.wakes.len(),
            self.wakes.len() - anchored
        )
    }

    /// The points to place on the ground: every ship's centre, then every wake's start, end and
    /// a point 100 m along its course from its start (for the bearing), in scanned pixels
    /// (row, column).
    pub fn points(&self) -> Vec<(f64, f64)> {
        let g = &self.geometry;
        let mut points: Vec<(f64, f64)> = self.ships.iter().map(|s| (s.row, s.col)).collect();
        for w in &self.wakes {
            let course = w.course_deg.unwrap_or(w.axis_deg);
            let (ur, uc) = g.step(course);
            points.extend([w.start, w.end, (w.start.0 + 100.0 * ur, w.start.1 + 100.0 * uc)]);
        }
        points
    }

    /// The findings as JSON entries for `detections.json` and as GeoJSON findings, given where
    /// each of [`Self::points`] lies in the product's pixels and on the ground (lon, lat). An
    /// input that is not `calibrated` (a display stretch) gives its ships no sigma0 or contrast:
    /// its grey levels read as dB are not dB.
    pub fn entries(
        &self,
        product: &[(f64, f64)],
        lonlat: Option<&[(f64, f64)]>,
        calibrated: bool,
    ) -> (Value, Value, Vec<Finding>) {
        let in_db = |v: f64| if calibrated { json!(v) } else { Value::Null };
        let at = |k: usize| (product[k], lonlat.map(|l| l[k]));
        let mut findings = Vec::new();
        let ships: Vec<Value> = self
            .ships
            .iter()
            .enumerate()
            .map(|(k, s)| {
                let ((row, col), ll) = at(k);
                let mut properties = Map::new();
                properties.insert("length_m".into(), json!(s.length_m));
                properties.insert("width_m".into(), json!(s.width_m));
                properties.insert("peak_sigma0_db".into(), in_db(s.peak_db));
                properties.insert("contrast_db".into(), in_db(s.contrast_db));
                properties.insert("ship".into(), json!(k));
                properties.insert("found_in".into(), json!(self.ships_polarisation));
                // the CNN's wake probability of the window centred on its return; null: not
                // scored (no CNN, or the window more than half off the image)
                let cnn = self.ship_cnn.get(k).copied().flatten();
                properties.insert("cnn_probability".into(), json!(cnn));
                findings.push(Finding {
                    kind: Kind::Ship,
                    row,
                    col,
                    properties: properties.clone(),
                    line: None,
                });
                let mut entry = serde_json::to_value(s).expect("a ship serialises");
                if !calibrated {
                    for key in ["peak_sigma0", "peak_db", "background_db", "contrast_db"] {
                        entry[key] = Value::Null;
                    }
                }
                entry["product_row"] = json!(row);
                // the cross-polarised band the ship was found in; null: the scanned band
                entry["found_in"] = json!(self.ships_polarisation);
                entry["product_col"] = json!(col);
                entry["lon"] = json!(ll.map(|p| p.0));
                entry["lat"] = json!(ll.map(|p| p.1));
                entry["cnn_probability"] = json!(cnn);
                entry
            })
            .collect();
        let first = self.ships.len();
        let wakes: Vec<Value> = self
            .wakes
            .iter()
            .enumerate()
            .map(|(k, w)| {
                let (start, ll_start) = at(first + 3 * k);
                let (end, ll_end) = at(first + 3 * k + 1);
                let (_, ll_ahead) = at(first + 3 * k + 2);
                let bearing = ll_start.zip(ll_ahead).map(|(a, b)| bearing(a, b));
                let entry = wake_entry(w, start, end, ll_start, ll_end, bearing);
                let mut properties = Map::new();
                for key in [
                    "ship",
                    "signature",
                    "course_image_deg",
                    "course_deg",
                    "course_sigma_deg",
                    "length_m",
                    "speed_offset_ms",
                    "speed_kelvin_ms",
                ] {
                    properties.insert(key.into(), entry[key].clone());
                }
                findings.push(Finding {
                    kind: Kind::Wake,
                    row: start.0,
                    col: start.1,
                    properties,
                    line: Some(vec![start, end]),
                });
                entry
            })
            .collect();
        (Value::Array(ships), Value::Array(wakes), findings)
    }

    /// Draw the land left out (tinted brown), the ships (cyan squares) and the wakes (yellow
    /// lines from their start, the ship's end marked) on an overlay picture of `scale` scanned pixels per picture pixel.
    pub fn draw(&self, picture: &mut RgbImage, scale: f64) {
        let (w, h) = (picture.width() as i64, picture.height() as i64);
        // land left out: tinted brown, half over the image (each picture row from the first
        // scanned row it holds, so that a row is tinted once)
        for &(row, from, to) in &self.land {
            let r = (row as f64 / scale).floor() as i64;
            if !(0..h).contains(&r) || (r as f64 * scale).ceil() as usize != row {
                continue;
            }
            let (c0, c1) = ((from as f64 / scale).round() as i64, (to as f64 / scale).round() as i64);
            for c in c0.max(0)..c1.min(w) {
                let p = picture.get_pixel_mut(c as u32, r as u32);
                for (k, tint) in [150u16, 90, 40].iter().enumerate() {
                    p.0[k] = ((p.0[k] as u16 + tint) / 2) as u8;
                }
            }
        }
        let mut put = |r: f64, c: f64, colour: Rgb<u8>| {
            let (r, c) = ((r / scale).round() as i64, (c / scale).round() as i64);
            if (0..h).contains(&r) && (0..w).contains(&c) {
                picture.put_pixel(c as u32, r as u32, colour);
            }
        };
        for wake in &self.wakes {
            let colour = wake_colour(wake.signature);
            let steps = ((wake.end.0 - wake.start.0).hypot(wake.end.1 - wake.start.1) / scale * 2.0)
                .ceil()
                .max(1.0);
            for i in 0..=steps as usize {
                let t = i as f64 / steps;
                put(
                    wake.start.0 + t * (wake.end.0 - wake.start.0),
                    wake.start.1 + t * (wake.end.1 - wake.start.1),
                    colour,
                );
            }
        }
        let cyan = Rgb([0, 255, 255]);
        for ship in &self.ships {
            for d in -4..=4 {
                let d = d as f64 * scale;
                let side = 4.0 * scale;
                put(ship.row - side, ship.col + d, cyan);
                put(ship.row + side, ship.col + d, cyan);
                put(ship.row + d, ship.col - side, cyan);
                put(ship.row + d, ship.col + side, cyan);
            }
        }
    }
}

/// A wake's line on the overlay: yellow for a dark trough, green for a bright arm.
pub fn wake_colour(signature: Signature) -> Rgb<u8> {
    match signature {
        Signature::Trough => Rgb([255, 230, 0]),
        Signature::BrightArm => Rgb([0, 230, 0]),
    }
}

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

/// The true bearing (degrees clockwise from north) from `a` to `b`, both (lon, lat) in degrees:
/// the initial course of the great circle.
fn bearing(a: (f64, f64), b: (f64, f64)) -> f64 {
    let (l1, p1, l2, p2) = (a.0.to_radians(), a.1.to_radians(), b.0.to_radians(), b.1.to_radians());
    let y = (l2 - l1).sin() * p2.cos();
    let x = p1.cos() * p2.sin() - p1.sin() * p2.cos() * (l2 - l1).cos();
    y.atan2(x).to_degrees().rem_euclid(360.0)
}

/// A wake as `detections.json` holds it.
fn wake_entry(
    w: &Wake,
    start: (f64, f64),
    end: (f64, f64),
    ll_start: Option<(f64, f64)>,
    ll_end: Option<(f64, f64)>,
    bearing: Option<f64>,
) -> Value {
    let (mut offset, mut kelvin) = (json!({}), json!({}));
    if let Some(s) = &w.speed {
        offset = match &s.offset {
            Ok(v) => json!({ "speed_ms": v.value, "sigma_ms": v.sigma }),
            Err(why) => json!({ "unknown": why }),
        };
        kelvin = match &s.kelvin {
            Ok(k) => json!({ "speed_ms": k.speed.value, "sigma_ms": k.speed.sigma, "wavelength_m": k.wavelength_m }),
            Err(why) => json!({ "unknown": why }),
        };
    }
    json!({
        "ship": w.ship,
        "kind": if w.ship.is_some() { "ship's wake" } else { "free wake (its ship not found: the course is 180 degrees ambiguous)" },
        "signature": w.signature,
        "product_start": [start.0, start.1],
        "product_end": [end.0, end.1],
        "lonlat_start": ll_start.map(|p| [p.0, p.1]),
        "lonlat_end": ll_end.map(|p| [p.0, p.1]),
        "axis_image_deg": w.axis_deg,
        "course_image_deg": w.course_deg,
        "course_deg": if w.course_deg.is_some() { bearing } else { None },
        "course_sigma_deg": w.course_sigma_deg,
        "length_m": w.length_m,
        "contrast": w.contrast,
        "z": w.z,
        "arms": w.arms,
        "azimuth_offset_m": w.offset_m,
        "speed_offset": offset,
        "speed_kelvin": kelvin,
        "speed_offset_ms": w.speed.as_ref().and_then(|s| s.offset.as_ref().ok()).map(|v| v.value),
        "speed_kelvin_ms": w.speed.as_ref().and_then(|s| s.kelvin.as_ref().ok()).map(|k| k.speed.value),
    })
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
    }
    use rand::{RngExt, SeedableRng};

    /// 4-look speckle at 10 m of `rows` x `cols`, a ship at `ship` (3 pixels across, 12
    /// along its course) sailing along `course` (0: up, 270: left), its trough 3 dB dark and 60
    /// m wide for 3 km behind it.
    fn ship_scene(rows: usize, cols: usize, ship: (usize, usize), course: u32) -> ndarray::Array2<f32> {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let mut image = ndarray::Array2::from_shape_fn((rows, cols), |_| {
            let s: f64 = (0..4).map(|_| -(1.0 - rng.random::<f64>()).ln()).sum();
            (0.01 * s / 4.0) as f32
        });
        let (r, c) = ship;
        let (hull, trough) = match course {
            0 => (
                ndarray::s![r - 6..r + 6, c - 1..c + 2],
                ndarray::s![r + 6..r + 306, c - 3..c + 3],
            ),
            270 => (
                ndarray::s![r - 1..r + 2, c - 6..c + 6],
                ndarray::s![r - 3..r + 3, c + 6..c + 306],
            ),
            _ => unreachable!("the tests' courses"),
        };
        image.slice_mut(trough).mapv_inplace(|v| v * 0.5);
        image.slice_mut(hull).fill(3.0);
        image
    }

    /// What the search of the whole image at once finds: one ship and its wake.
    fn whole_search(image: &ndarray::Array2<f32>, g: &Geometry) -> (Ship, Wake) {
        let whole = wakelab_ships::search(image.view(), g, &CfarOptions::default(), &WakeOptions::default());
        assert_eq!(whole.ships.ships.len(), 1, "{:?}", whole.ships.ships);
        let wake = whole.wakes.iter().find(|w| w.ship == Some(0)).expect("the ship's wake");
        assert!(wake.length_m > 2500.0, "{wake:?}");
        (whole.ships.ships[0].clone(), wake.clone())
    }

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

    /// Each wake's `signature` in `detections.json` is written in words: the synthetic ship's
    /// 3 dB trough is a "dark trough", and an arm is a "bright arm".
    #[test]
    fn a_wakes_signature_is_written_in_words() {
        let image = ship_scene(1600, 300, (700, 150), 0);
        let g = Geometry::along_rows(10.0, 35.0, None);
        let (_, wake) = whole_search(&image, &g);
        let entry = wake_entry(&wake, wake.start, wake.end, None, None, None);
        assert_eq!(entry["signature"], "dark trough");
        assert_eq!(json!(Signature::BrightArm), "bright arm");
        assert_ne!(wake_colour(Signature::Trough), wake_colour(Signature::BrightArm));
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

    /// The ship search's false-alarm probability: the user's where given; else SNAP's 1e-6 on a
    /// calibrated image and 1e-9 on a display stretch, with a note saying why; the target window
    /// on display stretches only.
    #[test]
    fn the_false_alarm_probability_follows_the_input() {
        let given = ShipSearch {
            pfa: Some(1e-4),
            ..ShipSearch::default()
        };
        assert_eq!(given.cfar(true), (CfarOptions::with_pfa(1e-4), None));
        // a display stretch's ships are also tested by their target window, whatever the P_fa
        let windowed = CfarOptions {
            target_m: DISPLAY_TARGET_M,
            ..CfarOptions::with_pfa(1e-4)
        };
        assert_eq!(given.cfar(false), (windowed, None));
        let unset = ShipSearch::default();
        assert_eq!(unset.cfar(true), (CfarOptions::default(), None));
        assert_eq!(CfarOptions::default().pfa, 1e-6);
        let (display, note) = unset.cfar(false);
        assert_eq!((display.pfa, display.target_m), (1e-9, 50.0));
        assert!(note.unwrap().contains("1e-9, not 1e-6"));
        // land found in the image is left out unless the user keeps it (--no-land-mask)
        assert!(unset.cfar(true).0.land.is_some());
        let keep = ShipSearch {
            keep_land: true,
            ..ShipSearch::default()
        };
        assert_eq!(keep.cfar(false).0.land, None);
    }

    #[test]
    fn bearings_follow_the_compass() {
        assert!((bearing((0.0, 0.0), (0.0, 1.0)) - 0.0).abs() < 1e-9);
        assert!((bearing((0.0, 0.0), (1.0, 0.0)) - 90.0).abs() < 1e-9);
        assert!((bearing((10.0, 50.0), (10.0, 49.0)) - 180.0).abs() < 1e-9);
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

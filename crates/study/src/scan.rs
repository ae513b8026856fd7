//! `wakelab detect` on a whole scene: the detector scanned over the product
//! ([`wakelab_learn::detect::detect_image`]) and its results written where a user opens them:
//! the wake-probability map as a Cloud-Optimised GeoTIFF on the product's ground (its CRS, or
//! its GCPs, coarsened to the map's cells), the detections as GeoJSON in longitude and latitude
//! (RFC 7946; the one schema of every finding, `kind` = window here) and as JSON with their
//! pixel and ground coordinates, a PNG of the image with the map over it, and the U-Net's mask
//! where there is one.

use crate::corroboration::{corroborate, Evidence};
use crate::sea_findings::{wake_colour, SeaFindings};
use anyhow::Result;
use image::{Rgb, RgbImage};
use rayon::prelude::*;
use serde::Serialize;
use serde_json::{json, Map, Value};
use std::path::{Path, PathBuf};
use wakelab_core::io::atomic::{write_atomically, AtomicFile};
use wakelab_core::io::geotiff::quantile;
use wakelab_learn::data::RadarScale;
use wakelab_learn::detect::{Detection, Found, Peak};
use wakelab_products::cog::{write_cog, BandInfo};
use wakelab_products::frame::Placement;
use wakelab_products::geojson::{feature_collection, Finding, Kind};
use wakelab_products::{Frame, ProductMeta};
use wakelab_schema::band::Band;
use wakelab_ships::wake::Signature;

/// Longest side of the overlay PNG; larger scenes are block-averaged down to it.
const OVERLAY_SIDE: usize = 2048;

/// A detection with its place on the ground.
#[derive(Debug, Serialize)]
struct Located<'a, T> {
    #[serde(flatten)]
    found: &'a T,
    /// Its (row, col) in the product's pixels (before any resampling to the detector's
    /// spacing).
    product_row: f64,
    product_col: f64,
    /// Model coordinates in the product's CRS (a product placed by a geotransform).
    x: Option<f64>,
    y: Option<f64>,
    /// Longitude and latitude (degrees, WGS 84) by GDAL's transformer.
    lon: Option<f64>,
    lat: Option<f64>,
}

/// A CNN window as `detections.json` holds it: placed, and the line search's wake it lies on
/// ([`crate::corroboration`]; null: none, or no line search).
#[derive(Debug, Serialize)]
struct WindowEntry<'a> {
    #[serde(flatten)]
    located: Located<'a, Found>,
    on_wake: Option<usize>,
}

/// A point's product pixel (row, column), model coordinates and longitude and latitude.
type Place = (f64, f64, Option<(f64, f64)>, Option<(f64, f64)>);

/// The detections file: the scene's verdict and every detection.
#[derive(Debug, Serialize)]
struct DetectionsFile<'a> {
    image: String,
    model: String,
    band: Band,
    product: &'a ProductMeta,
    probability: f64,
    wake: bool,
    threshold: f64,
    window: usize,
    stride: usize,
    windows: usize,
    georeferenced: bool,
    /// Product pixels per scanned pixel (rows, columns): 1 unless the product was averaged to
    /// the detector's spacing.
    resampled: (f64, f64),
    notes: &'a [String],
    /// The scan's peak: where its strongest window places the wake (on that window's strongest
    /// line, [`Peak`]), with the line's direction and contrast.
    peak: Located<'a, Peak>,
    detections: Vec<WindowEntry<'a>>,
    /// The ships and wakes the classic searches found (null for infrared), and the targets
    /// they rejected. Each wake lists the CNN windows on its line (`cnn_windows`).
    ships: Value,
    wakes: Value,
    /// The wakes by who saw them: the line search and the CNN, either alone (null for infrared).
    evidence: Option<Evidence>,
    ghosts: Option<Value>,
    /// The land found in the image and left out of the ship and wake searches (pixels, km^2).
    land: Option<Value>,
    /// The ship search's settings (`--ship-pfa` and the rest) and its threshold in background
    /// deviations.
    ship_search: Option<Value>,
}

/// What a scan wrote.
pub struct ScanFiles {
    pub map: PathBuf,
    pub overlay: PathBuf,
    pub detections: PathBuf,
    pub geojson: PathBuf,
    /// Every window: its probability and strongest line ([`crate::scan_windows`]).
    pub windows: PathBuf,
    pub mask: Option<PathBuf>,
}

/// Where `wakelab detect` writes the scan of `image` unless told: `detect-<image name>` in the
/// current directory.
pub fn default_scan_dir(image: &Path) -> PathBuf {
    let name = image
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let stem = name.split('.').next().filter(|s| !s.is_empty()).unwrap_or("image");
    PathBuf::from(format!("detect-{stem}"))
}

/// `detect --mask PATH`: the U-Net's stitched mask of `detection` as a PNG at `path`; a note
/// when the detector (of `architecture`, read from `model`) draws no mask.
pub fn write_asked_mask(
    path: &Path,
    detection: &Detection,
    model: &Path,
    architecture: &str,
) -> Result<Option<String>> {
    Ok(match &detection.mask {
        Some(m) => {
            crate::learning::write_mask_png(path, &m.mapv(|v| if v.is_nan() { 0.0 } else { v }))?;
            None
        }
        None => Some(format!(
            "--mask needs a \"unet\" detector; {} is \"{architecture}\"",
            model.display()
        )),
    })
}

/// What was scanned: the product (its path, metadata and placement), the grid the detector saw
/// (the product's, or the averaged one) and the overlay's block means of it.
pub struct Scanned<'a> {
    pub path: &'a Path,
    pub meta: &'a ProductMeta,
    pub product_frame: &'a Frame,
    pub frame: &'a Frame,
    pub overlay: &'a OverlayMeans,
    /// Product pixels per scanned pixel (rows, columns).
    pub factor: (f64, f64),
    pub band: Band,
    pub model: &'a Path,
    /// What the user should know (reading, resampling).
    pub notes: &'a [String],
    /// The ships and wakes found (radar images).
    pub sea: Option<&'a SeaFindings>,
}

impl Scanned<'_> {
    /// A scanned pixel position in the product's pixels.
    pub(crate) fn in_product(&self, row: f64, col: f64) -> (f64, f64) {
        (row * self.factor.0, col * self.factor.1)
    }
}

/// The scan `detection` of `scanned`, written into `dir`.
pub fn write_scan(dir: &Path, scanned: &Scanned, detection: &Detection) -> Result<ScanFiles> {
    std::fs::create_dir_all(dir).map_err(|e| anyhow::anyhow!("cannot create {}: {e}", dir.display()))?;
    let meta = scanned.meta;
    let (rows, cols) = detection.map.dim();
    let files = ScanFiles {
        map: dir.join("probability.tif"),
        overlay: dir.join("overlay.png"),
        detections: dir.join("detections.json"),
        geojson: dir.join("detections.geojson"),
        windows: dir.join("windows.csv"),
        mask: detection.mask.as_ref().map(|_| dir.join("mask.tif")),
    };
    let stride = detection.stride as f64;
    let model = scanned.model.display().to_string();
    let metadata = vec![
        ("WAKELAB_IMAGE".to_string(), scanned.path.display().to_string()),
        ("WAKELAB_PRODUCT_ID".to_string(), meta.product_id.clone()),
        ("WAKELAB_MODEL".to_string(), model.clone()),
        ("WAKELAB_WINDOW".to_string(), detection.window.to_string()),
        ("WAKELAB_CELL".to_string(), detection.stride.to_string()),
    ];
    write_cog(
        &files.map,
        &detection.map,
        &scanned.frame.scaled(stride, stride, (rows, cols)),
        &BandInfo {
            description: "wake probability: mean over the detector's windows covering the cell",
            unit: "1",
            metadata: metadata.clone(),
        },
    )?;
    if let (Some(path), Some(mask)) = (&files.mask, &detection.mask) {
        write_cog(
            path,
            mask,
            scanned.frame,
            &BandInfo {
                description: "U-Net wake mask: per-pixel wake probability, overlapping windows averaged",
                unit: "1",
                metadata,
            },
        )?;
    }
    let picture = AtomicFile::new(&files.overlay)?;
    let mut drawn = scanned.overlay.picture(detection);
    let scale = scanned.overlay.scale();
    draw_detections(&mut drawn, detection, scale);
    let mut legend = vec![
        (Rgb([255, 0, 0]), "red tint: wake probability".to_string()),
        (
            DETECTION_COLOUR,
            format!(
                "box: detection, a {0} x {0} px window around where it places the wake; line: its direction",
                detection.window
            ),
        ),
    ];
    if let Some(sea) = scanned.sea {
        sea.draw(&mut drawn, scale);
        legend.push((Rgb([0, 255, 255]), "square: ship".into()));
        legend.push((wake_colour(Signature::Trough), "line: wake, dark trough".into()));
        legend.push((wake_colour(Signature::BrightArm), "line: wake, bright arm".into()));
        if let Some(promoted) = sea.wakes.iter().find(|w| w.promoted) {
            legend.push((
                wake_colour(promoted.signature),
                "dashed: faint line promoted, no other wake found".into(),
            ));
        }
        if !sea.faint_lines().is_empty() {
            legend.push((
                wake_colour(Signature::Trough),
                "dotted: faint line, below significance".into(),
            ));
        }
    }
    let drawn = with_legend(&drawn, &legend);
    drawn.save_with_format(picture.temporary_path(), image::ImageFormat::Png)?;
    picture.commit()?;

    // every point placed at once: GDAL's transformer is built once per call
    let mut points: Vec<(f64, f64)> = detection.detections.iter().map(|f| (f.row, f.col)).collect();
    points.push((detection.peak.row, detection.peak.col));
    let sea_first = points.len();
    points.extend(scanned.sea.map(SeaFindings::points).unwrap_or_default());
    let in_product: Vec<(f64, f64)> = points.iter().map(|&(r, c)| scanned.in_product(r, c)).collect();
    let frame = scanned.product_frame;
    let lonlat = frame.lonlat(&in_product.iter().map(|&(r, c)| (c, r)).collect::<Vec<_>>());
    let model_xy = |row: f64, col: f64| match &frame.placement {
        Placement::Transform { transform: t, .. } => {
            Some((t[0] + col * t[1] + row * t[2], t[3] + col * t[4] + row * t[5]))
        }
        _ => None,
    };
    let place = |k: usize| {
        let (row, col) = in_product[k];
        let xy = model_xy(row, col);
        let ll = lonlat.as_ref().map(|l| l[k]);
        (row, col, xy, ll)
    };
    fn located<T>(found: &T, (row, col, xy, ll): Place) -> Located<'_, T> {
        Located {
            found,
            product_row: row,
            product_col: col,
            x: xy.map(|p| p.0),
            y: xy.map(|p| p.1),
            lon: ll.map(|p| p.0),
            lat: ll.map(|p| p.1),
        }
    }
    let corroboration = scanned
        .sea
        .map(|sea| corroborate(&detection.detections, &sea.wakes, sea.geometry.spacing));
    let sea_entries = match scanned.sea {
        Some(sea) => {
            let (ships, mut wakes, mut found) = sea.entries(
                &in_product[sea_first..],
                lonlat.as_deref().map(|l| &l[sea_first..]),
                meta.calibrated,
            );
            let agreeing = corroboration
                .as_ref()
                .map(|c| c.wake_windows.as_slice())
                .unwrap_or_default();
            if let Some(entries) = wakes.as_array_mut() {
                for (entry, windows) in entries.iter_mut().zip(agreeing) {
                    entry["cnn_windows"] = json!(windows);
                }
            }
            let wake_findings = found.iter_mut().filter(|f| f.kind == Kind::Wake);
            for (finding, windows) in wake_findings.zip(agreeing) {
                finding.properties.insert("cnn_windows".into(), json!(windows.len()));
            }
            (ships, wakes, found)
        }
        None => (Value::Null, Value::Null, Vec::new()),
    };
    let on_wake = |k: usize| corroboration.as_ref().and_then(|c| c.window_wake[k]);
    let detections: Vec<WindowEntry> = detection
        .detections
        .iter()
        .enumerate()
        .map(|(k, found)| WindowEntry {
            located: located(found, place(k)),
            on_wake: on_wake(k),
        })
        .collect();
    let report = DetectionsFile {
        image: scanned.path.display().to_string(),
        model: model.clone(),
        band: scanned.band,
        product: meta,
        probability: detection.probability,
        wake: detection.wake,
        threshold: detection.threshold,
        window: detection.window,
        stride: detection.stride,
        windows: detection.tiles.len(),
        georeferenced: lonlat.is_some(),
        resampled: scanned.factor,
        notes: scanned.notes,
        peak: located(&detection.peak, place(sea_first - 1)),
        detections,
        ships: sea_entries.0,
        wakes: sea_entries.1,
        evidence: corroboration.as_ref().map(|c| c.evidence),
        ghosts: scanned.sea.map(|s| {
            json!({
                "azimuth_ambiguities": s.ambiguities,
                "sidelobes": s.sidelobes,
                "sidelobe_axes_deg": s.sidelobe_axes_deg,
                "too_long_for_ships": s.too_long,
                "on_land": s.on_land,
            })
        }),
        land: scanned.sea.map(|s| {
            let g = &s.geometry;
            json!({
                "pixels": s.land_pixels(),
                "km2": s.land_pixels() as f64 * g.spacing.0 * g.spacing.1 / 1e6,
            })
        }),
        ship_search: scanned.sea.map(|s| {
            let mut settings = json!(s.cfar);
            settings["threshold_sigmas"] = json!(wakelab_ships::cfar::sigmas_for(s.cfar.pfa));
            settings
        }),
    };
    write_atomically(&files.detections, serde_json::to_string_pretty(&report)?.as_bytes())?;

    let findings: Vec<Finding> = detection
        .detections
        .iter()
        .zip(&in_product)
        .enumerate()
        .map(|(k, (found, &(row, col)))| {
            let mut properties = Map::new();
            properties.insert("probability".into(), json!(found.score));
            properties.insert("on_wake".into(), json!(on_wake(k)));
            properties.insert("orientation_deg".into(), json!(found.orientation));
            properties.insert("length_px".into(), json!(found.length));
            Finding {
                kind: Kind::Window,
                row,
                col,
                properties,
                line: None,
            }
        })
        .collect();
    let mut common = Map::new();
    common.insert("detector".into(), Value::String(model));
    common.insert("band".into(), json!(scanned.band));
    common.insert("product_id".into(), json!(meta.product_id));
    common.insert("acquisition_time".into(), json!(meta.acquisition_time));
    common.insert("polarisation".into(), json!(meta.polarisation));
    let mut findings = findings;
    findings.extend(sea_entries.2);
    let collection = feature_collection(frame, &findings, &common);
    write_atomically(&files.geojson, serde_json::to_string_pretty(&collection)?.as_bytes())?;
    crate::scan_windows::write_windows(&files.windows, detection, |r, c| scanned.in_product(r, c))?;
    Ok(files)
}

/// The colour of a detection's box on the overlay.
const DETECTION_COLOUR: Rgb<u8> = Rgb([255, 0, 255]);

/// Each detection's window as a box around its centre, on an overlay of `scale` scanned pixels
/// per picture pixel.
fn draw_detections(picture: &mut RgbImage, detection: &Detection, scale: f64) {
    let (w, h) = (picture.width() as i64, picture.height() as i64);
    let half = (0.5 * detection.window as f64 / scale).max(2.0);
    for found in &detection.detections {
        let (r, c) = (found.row / scale, found.col / scale);
        let (top, bottom) = ((r - half).round() as i64, (r + half).round() as i64);
        let (left, right) = ((c - half).round() as i64, (c + half).round() as i64);
        let mut put = |row: i64, col: i64| {
            if (0..h).contains(&row) && (0..w).contains(&col) {
                picture.put_pixel(col as u32, row as u32, DETECTION_COLOUR);
            }
        };
        for col in left..=right {
            put(top, col);
            put(bottom, col);
        }
        for row in top..=bottom {
            put(row, left);
            put(row, right);
        }
        // the wake's direction and length as the detection measured them, through its place
        if let (Some(angle), Some(length)) = (found.orientation, found.length) {
            let (sin, cos) = angle.to_radians().sin_cos();
            let half_length = 0.5 * length / scale;
            let steps = (2.0 * half_length).ceil().max(1.0) as i64;
            for k in 0..=steps {
                let t = -half_length + 2.0 * half_length * k as f64 / steps as f64;
                // angle anticlockwise from the column axis with y up the image: rows go down
                put((r - t * sin).round() as i64, (c + t * cos).round() as i64);
            }
        }
    }
}

/// The picture with a legend strip beneath it: a swatch and a line of text per entry, the
/// canvas widened where the text is wider than the picture.
fn with_legend(picture: &RgbImage, entries: &[(Rgb<u8>, String)]) -> RgbImage {
    let line = 12u32;
    let text_width = entries.iter().map(|(_, t)| 8 * t.len() as u32 + 20).max().unwrap_or(0);
    let width = picture.width().max(text_width + 8);
    let height = picture.height() + 4 + line * entries.len() as u32;
    let mut out = RgbImage::from_pixel(width, height, Rgb([255, 255, 255]));
    image::imageops::replace(&mut out, picture, 0, 0);
    for (k, (colour, text)) in entries.iter().enumerate() {
        let y = picture.height() + 4 + line * k as u32;
        for dy in 1..9 {
            for dx in 4..14 {
                out.put_pixel(dx, y + dy, *colour);
            }
        }
        wakelab_core::io::picture::draw_text(&mut out, 20, y + 1, text, 1, Rgb([0, 0, 0]));
    }
    out
}

/// The overlay's picture of the scanned image: the image in grey (radar in dB; no-data black)
/// block-averaged to at most [`OVERLAY_SIDE`] pixels, gathered a band of rows at a time.
pub struct OverlayMeans {
    /// Image pixels per picture pixel along each side.
    factor: usize,
    size: (usize, usize),
    out: (usize, usize),
    sums: Vec<f64>,
    counts: Vec<u32>,
    radar: bool,
}

impl OverlayMeans {
    /// Image pixels per picture pixel.
    pub fn scale(&self) -> f64 {
        self.factor as f64
    }

    /// For an image of `size` (rows, columns) in `band`.
    pub fn new(size: (usize, usize), band: Band) -> Self {
        let (h, w) = size;
        let factor = h.max(w).div_ceil(OVERLAY_SIDE).max(1);
        let out = (h.div_ceil(factor), w.div_ceil(factor));
        Self {
            factor,
            size,
            out,
            sums: vec![0.0; out.0 * out.1],
            counts: vec![0; out.0 * out.1],
            radar: band.is_radar(),
        }
    }

    /// Add image rows `start..start + rows.nrows()` (each row once).
    pub fn add(&mut self, start: usize, rows: ndarray::ArrayView2<f32>) {
        let scale = RadarScale::Linear;
        let (factor, ow, radar) = (self.factor, self.out.1, self.radar);
        // picture rows in parallel, each summing its image rows of this band
        let first = start / factor;
        let last = (start + rows.nrows()).div_ceil(factor);
        let sums = &mut self.sums[first * ow..last * ow];
        let counts = &mut self.counts[first * ow..last * ow];
        sums.par_chunks_mut(ow)
            .zip(counts.par_chunks_mut(ow))
            .enumerate()
            .for_each(|(k, (sum, count))| {
                let block = (first + k) * factor;
                let from = block.max(start) - start;
                let to = (block + factor).min(start + rows.nrows()) - start;
                for r in from..to {
                    for (c, &v) in rows.row(r).iter().enumerate() {
                        if v.is_nan() {
                            continue;
                        }
                        let d = if radar { scale.decibels(v) } else { v };
                        if d.is_finite() {
                            sum[c / factor] += d as f64;
                            count[c / factor] += 1;
                        }
                    }
                }
            });
    }

    /// The block means stretched between their 2 % and 98 % quantiles, with the probability
    /// map of `detection` laid over them in red (opacity 0.6 p).
    pub fn picture(&self, detection: &Detection) -> RgbImage {
        let (oh, ow) = self.out;
        let means: Vec<f32> = self
            .sums
            .iter()
            .zip(&self.counts)
            .map(|(&s, &n)| if n == 0 { f32::NAN } else { (s / n as f64) as f32 })
            .collect();
        let (lo, hi) = (quantile(&means, 0.02), quantile(&means, 0.98));
        let span = (hi - lo).max(1e-12);
        let factor = self.factor;
        debug_assert!(self.size.0 <= oh * factor && self.size.1 <= ow * factor);
        let mut out = RgbImage::new(ow as u32, oh as u32);
        for (k, &m) in means.iter().enumerate() {
            let (r, c) = (k / ow, k % ow);
            let g = ((m as f64 - lo) / span).clamp(0.0, 1.0) * 255.0;
            let cell = (
                ((r * factor) / detection.stride).min(detection.map.nrows() - 1),
                ((c * factor) / detection.stride).min(detection.map.ncols() - 1),
            );
            let p = detection.map[cell] as f64;
            let a = if p.is_nan() { 0.0 } else { 0.6 * p.clamp(0.0, 1.0) };
            let blend = |target: f64| (g * (1.0 - a) + target * a).round() as u8;
            out.put_pixel(c as u32, r as u32, Rgb([blend(255.0), blend(0.0), blend(0.0)]));
        }
        out
    }
}

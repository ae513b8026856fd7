//! `wakelab detect` on a whole scene: the detector scanned over the image
//! ([`wakelab_learn::detect::detect_image`]) and its results written where a user opens them: the
//! wake-probability map as a float32 GeoTIFF on the input's ground (a GeoTIFF input's CRS and
//! mapping kept, coarsened to the map's cells; a plain image's pixel grid otherwise) with its JSON
//! sidecar, a PNG of the image with the map over it, the U-Net's mask where there is one, and the
//! detections as JSON with their map coordinates.

use anyhow::Result;
use image::{Rgb, RgbImage};
use ndarray::Array2;
use rayon::prelude::*;
use serde::Serialize;
use std::path::{Path, PathBuf};
use wakelab_core::io::atomic::{write_atomically, AtomicFile};
use wakelab_core::io::geotiff::{quantile, write_georeferenced_tiff, Georeference};
use wakelab_learn::data::RadarScale;
use wakelab_learn::detect::{Detection, Found, Peak};
use wakelab_schema::band::Band;

/// Longest side of the overlay PNG; larger scenes are block-averaged down to it.
const OVERLAY_SIDE: usize = 2048;

/// A detection with its place on the input's ground.
#[derive(Debug, Serialize)]
struct Located<'a, T> {
    #[serde(flatten)]
    found: &'a T,
    /// Model coordinates of its (row, col) in the input's CRS (GeoTIFF inputs only).
    x: Option<f64>,
    y: Option<f64>,
}

/// The detections file: the scene's verdict and every detection.
#[derive(Debug, Serialize)]
struct DetectionsFile<'a> {
    image: String,
    model: String,
    band: Band,
    scale: &'a str,
    probability: f64,
    wake: bool,
    threshold: f64,
    window: usize,
    stride: usize,
    windows: usize,
    georeferenced: bool,
    /// The map's strongest cell, with its model coordinates for a GeoTIFF input.
    peak: Located<'a, Peak>,
    detections: Vec<Located<'a, Found>>,
}

/// The probability map's sidecar.
#[derive(Debug, Serialize)]
struct MapSidecar {
    quantity: &'static str,
    units: &'static str,
    image: String,
    model: String,
    /// Side of a map cell in input pixels.
    cell: usize,
    window: usize,
    rows: usize,
    cols: usize,
    georeferenced: bool,
}

/// What a scan wrote.
pub struct ScanFiles {
    pub map: PathBuf,
    pub overlay: PathBuf,
    pub detections: PathBuf,
    pub mask: Option<PathBuf>,
}

/// Where `wakelab detect` writes the scan of `image` unless told: `detect-<image name>` in the
/// current directory.
pub fn default_scan_dir(image: &Path) -> PathBuf {
    let stem = image.file_stem().map(|s| s.to_string_lossy().into_owned());
    PathBuf::from(format!("detect-{}", stem.unwrap_or_else(|| "image".into())))
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
            crate::learning::write_mask_png(path, m)?;
            None
        }
        None => Some(format!(
            "note: --mask needs a \"unet\" detector; {} is \"{architecture}\"",
            model.display()
        )),
    })
}

/// The scan of `image` (read from `image_path`, band `band`, radar pixels in `scale`) by
/// `model`, written into `dir`.
pub fn write_scan(
    dir: &Path,
    image_path: &Path,
    model: &Path,
    image: &Array2<f32>,
    band: Band,
    scale: RadarScale,
    detection: &Detection,
) -> Result<ScanFiles> {
    std::fs::create_dir_all(dir).map_err(|e| anyhow::anyhow!("cannot create {}: {e}", dir.display()))?;
    let tiff = matches!(
        image_path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref(),
        Some("tif" | "tiff")
    );
    let input_geo = if tiff { Georeference::read(image_path)? } else { None };
    let georeferenced = input_geo.is_some();
    // a plain image: its pixel grid, x right and y up, one unit per pixel (not metres)
    let geo = input_geo.unwrap_or_else(Georeference::pixel_grid);
    let (rows, cols) = detection.map.dim();
    let files = ScanFiles {
        map: dir.join("probability.tif"),
        overlay: dir.join("overlay.png"),
        detections: dir.join("detections.json"),
        mask: detection.mask.as_ref().map(|_| dir.join("mask.tif")),
    };
    let values: Vec<f32> = detection.map.iter().copied().collect();
    write_georeferenced_tiff(&files.map, &values, rows, cols, &geo.coarsened(detection.stride as f64))?;
    let sidecar = MapSidecar {
        quantity: "wake probability: mean over the detector's windows covering the cell",
        units: "1",
        image: image_path.display().to_string(),
        model: model.display().to_string(),
        cell: detection.stride,
        window: detection.window,
        rows,
        cols,
        georeferenced,
    };
    write_atomically(
        dir.join("probability.json"),
        serde_json::to_string_pretty(&sidecar)?.as_bytes(),
    )?;
    if let (Some(path), Some(mask)) = (&files.mask, &detection.mask) {
        let (h, w) = mask.dim();
        let values: Vec<f32> = mask.iter().copied().collect();
        write_georeferenced_tiff(path, &values, h, w, &geo)?;
        let sidecar = MapSidecar {
            quantity: "U-Net wake mask: per-pixel wake probability, overlapping windows averaged",
            cell: 1,
            rows: h,
            cols: w,
            ..sidecar
        };
        write_atomically(
            path.with_extension("json"),
            serde_json::to_string_pretty(&sidecar)?.as_bytes(),
        )?;
    }
    let picture = AtomicFile::new(&files.overlay)?;
    overlay(image, band, scale, detection).save_with_format(picture.temporary_path(), image::ImageFormat::Png)?;
    picture.commit()?;
    let locate = |row: f64, col: f64| georeferenced.then(|| geo.model_xy(col, row)).flatten();
    let located = detection
        .detections
        .iter()
        .map(|found| {
            let xy = locate(found.row, found.col);
            Located {
                found,
                x: xy.map(|p| p.0),
                y: xy.map(|p| p.1),
            }
        })
        .collect();
    let xy = locate(detection.peak.row, detection.peak.col);
    let peak = Located {
        found: &detection.peak,
        x: xy.map(|p| p.0),
        y: xy.map(|p| p.1),
    };
    let report = DetectionsFile {
        image: image_path.display().to_string(),
        model: model.display().to_string(),
        band,
        scale: scale.name(),
        probability: detection.probability,
        wake: detection.wake,
        threshold: detection.threshold,
        window: detection.window,
        stride: detection.stride,
        windows: detection.tiles.len(),
        georeferenced,
        peak,
        detections: located,
    };
    write_atomically(&files.detections, serde_json::to_string_pretty(&report)?.as_bytes())?;
    Ok(files)
}

/// The image in grey (radar in dB), stretched between its 2 % and 98 % quantiles and
/// block-averaged to at most [`OVERLAY_SIDE`] pixels, with the probability map laid over it in
/// red (opacity 0.6 p).
fn overlay(image: &Array2<f32>, band: Band, scale: RadarScale, detection: &Detection) -> RgbImage {
    let (h, w) = image.dim();
    let factor = h.max(w).div_ceil(OVERLAY_SIDE).max(1);
    let (oh, ow) = (h.div_ceil(factor), w.div_ceil(factor));
    let display = |v: f32| if band.is_radar() { scale.decibels(v) } else { v };
    // block means, a row of blocks per task; each block sums its pixels row by row
    let means: Vec<f32> = (0..oh)
        .into_par_iter()
        .flat_map_iter(|block_row| {
            let (mut grey, mut count) = (vec![0.0f64; ow], vec![0u32; ow]);
            for r in block_row * factor..((block_row + 1) * factor).min(h) {
                for (c, &v) in image.row(r).iter().enumerate() {
                    let d = display(v);
                    if d.is_finite() {
                        grey[c / factor] += d as f64;
                        count[c / factor] += 1;
                    }
                }
            }
            grey.into_iter().zip(count).map(|(s, n)| (s / n.max(1) as f64) as f32)
        })
        .collect();
    let (lo, hi) = (quantile(&means, 0.02), quantile(&means, 0.98));
    let span = (hi - lo).max(1e-12);
    let mut out = RgbImage::new(ow as u32, oh as u32);
    for (k, &m) in means.iter().enumerate() {
        let (r, c) = (k / ow, k % ow);
        let g = ((m as f64 - lo) / span).clamp(0.0, 1.0) * 255.0;
        let cell = (
            ((r * factor) / detection.stride).min(detection.map.nrows() - 1),
            ((c * factor) / detection.stride).min(detection.map.ncols() - 1),
        );
        let a = 0.6 * (detection.map[cell] as f64).clamp(0.0, 1.0);
        let blend = |target: f64| (g * (1.0 - a) + target * a).round() as u8;
        out.put_pixel(c as u32, r as u32, Rgb([blend(255.0), blend(0.0), blend(0.0)]));
    }
    out
}

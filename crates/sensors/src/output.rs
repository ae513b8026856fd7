//! Sensor images on disk: float32 GeoTIFF (linear sigma0 or radiance), a JSON sidecar with the
//! image's metadata, and an 8-bit PNG quicklook with its stretch stated in the sidecar.

use crate::sar_image::SarImage;
use serde::Serialize;
use std::path::{Path, PathBuf};
use wakelab_core::io::geotiff::{quantile, write_float_tiff, write_quicklook, Placement};
use wakelab_core::io::write_atomically;
use wakelab_core::{WakelabConfig, WakelabError};
use wakelab_surface::scene::SceneGrid;

/// The sidecar of one image.
#[derive(Debug, Serialize)]
pub struct Sidecar<'a, I: Serialize> {
    pub scene_id: String,
    pub seed: u64,
    pub quantity: &'a str,
    pub units: &'a str,
    pub rows: usize,
    pub cols: usize,
    pub pixel_spacing_m: f64,
    /// Easting and northing (m from the stern) of the top-left pixel's corner.
    pub top_left_m: (f64, f64),
    pub along_track_m: f64,
    pub cross_track_m: f64,
    /// The ship's course in the image, degrees clockwise from up.
    pub heading_deg: f64,
    pub quicklook: Stretch,
    pub sensor: &'a I,
}

/// The linear stretch of a quicklook: `min` maps to 0, `max` to 255.
#[derive(Debug, Serialize, Clone, Copy)]
pub struct Stretch {
    pub quantity: &'static str,
    pub min: f64,
    pub max: f64,
}

/// Write one image's TIFF, sidecar and quicklook; `display` is what the quicklook stretches
/// (for SAR, sigma0 in dB) between its 2nd and 98th percentiles.
#[allow(clippy::too_many_arguments)]
pub fn write_image<I: Serialize>(
    dir: &Path,
    stem: &str,
    config: &WakelabConfig,
    grid: &SceneGrid,
    values: &[f32],
    display: &[f32],
    display_quantity: &'static str,
    quantity: &str,
    units: &str,
    sensor: &I,
) -> Result<Vec<PathBuf>, WakelabError> {
    let n = grid.size();
    let d = grid.pixel_spacing;
    let top_left = (grid.x[0] - 0.5 * d, grid.y[0] + 0.5 * d);
    let tif = dir.join(format!("{stem}.tif"));
    write_float_tiff(
        &tif,
        values,
        n,
        n,
        Placement {
            top_left,
            pixel_spacing: d,
        },
    )?;
    let stretch = Stretch {
        quantity: display_quantity,
        min: quantile(display, 0.02),
        max: quantile(display, 0.98),
    };
    let png = dir.join(format!("{stem}_quicklook.png"));
    write_quicklook(&png, display, n, n, stretch.min, stretch.max)?;
    let sidecar = Sidecar {
        scene_id: config.scene_id(),
        seed: config.seed,
        quantity,
        units,
        rows: n,
        cols: n,
        pixel_spacing_m: d,
        top_left_m: top_left,
        along_track_m: config.scene.along_track,
        cross_track_m: config.scene.cross_track,
        heading_deg: config.scene.heading,
        quicklook: stretch,
        sensor,
    };
    let json = dir.join(format!("{stem}.json"));
    write_atomically(
        &json,
        serde_json::to_string_pretty(&sidecar).expect("serialisable").as_bytes(),
    )?;
    Ok(vec![tif, json, png])
}

/// Write a SAR image: linear sigma0 in the TIFF, dB in the quicklook.
pub fn write_sar(
    dir: &Path,
    config: &WakelabConfig,
    grid: &SceneGrid,
    image: &SarImage,
) -> Result<Vec<PathBuf>, WakelabError> {
    let values: Vec<f32> = image.sigma0.iter().map(|&v| v as f32).collect();
    let db: Vec<f32> = image.sigma0.iter().map(|&v| crate::sar::to_db(v) as f32).collect();
    let stem = format!("sar_{}_{}", image.band.name(), image.info.polarisation.to_lowercase());
    write_image(
        dir,
        &stem,
        config,
        grid,
        &values,
        &db,
        "sigma0_dB",
        "sigma0",
        "1 (linear)",
        &image.info,
    )
}

/// Write an IR image: radiance in one TIFF, brightness temperature in a second, each with its
/// sidecar and a quicklook of brightness temperature.
pub fn write_ir(
    dir: &Path,
    config: &WakelabConfig,
    grid: &SceneGrid,
    image: &crate::ir_image::IrImage,
) -> Result<Vec<PathBuf>, WakelabError> {
    let radiance: Vec<f32> = image.radiance.iter().map(|&v| v as f32).collect();
    let bt: Vec<f32> = image.brightness_temperature.iter().map(|&v| v as f32).collect();
    let stem = format!("ir_{}", image.info.band.to_lowercase());
    let mut files = write_image(
        dir,
        &format!("{stem}_radiance"),
        config,
        grid,
        &radiance,
        &bt,
        "brightness_temperature_K",
        "band radiance",
        "W m-2 sr-1",
        &image.info,
    )?;
    // the brightness-temperature image is an image like any other: TIFF, sidecar and quicklook
    files.extend(write_image(
        dir,
        &format!("{stem}_brightness_temperature"),
        config,
        grid,
        &bt,
        &bt,
        "brightness_temperature_K",
        "brightness temperature",
        "K",
        &image.info,
    )?);
    Ok(files)
}

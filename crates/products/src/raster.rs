//! Any single-band raster GDAL reads (GeoTIFF, Cloud-Optimised GeoTIFF, PNG, ...) and
//! RADARSAT-2 products through GDAL's calibrated subdataset: the band's values, its nodata
//! value and mask band, the scale its unit states, and its georeference.

use crate::scale::{from_unit, to_linear_sigma0, InputScale, MIN_SIGMA0};
use crate::{gdal_error, Frame, PixelSpacing, Product, ProductMeta, Quantity, ReadOptions, ReadReport, SpacingSource};
use gdal::raster::GdalDataType;
use gdal::{Dataset, Metadata};
use ndarray::Array2;
use std::path::Path;
use wakelab_core::{ConfigError, WakelabError};

fn raster_error(path: &Path, message: impl ToString) -> WakelabError {
    WakelabError::Image {
        path: path.display().to_string(),
        message: message.to_string(),
    }
}

/// Open a raster with GDAL; a file GDAL does not recognise is "not an image GDAL reads", and
/// a product GDAL recognises but wakelab does not calibrate names GDAL's driver.
pub fn open_dataset(path: &Path) -> Result<Dataset, WakelabError> {
    let dataset = Dataset::open(path).map_err(|e| {
        raster_error(
            path,
            format!(
                "not an image GDAL reads (npy, GeoTIFF, COG, PNG, a Sentinel-1 SAFE, ...){}",
                crate::gdal_reason(&e)
            ),
        )
    })?;
    let driver = dataset.driver().short_name();
    let unsupported = match driver.as_str() {
        "SAFE" => None, // reached only through manifest.safe, handled by the Sentinel-1 reader
        "TSX" => Some("TerraSAR-X: wakelab calibrates MGD products passed as their directory (TSX1_SAR__MGD_...) or main XML under its own name"),
        "HDF5" | "HDF5Image" | "CSK" => Some("an HDF5 file that is no COSMO-SkyMed first-generation product (Mission ID CSK or KMPS), which wakelab calibrates: pass a GeoTIFF of sigma0"),
        "RS2" if !path.to_string_lossy().starts_with("RADARSAT_2_CALIB:") => {
            Some("RADARSAT-2: pass GDAL's calibrated subdataset, RADARSAT_2_CALIB:SIGMA0:<product.xml>")
        }
        "RCM" => Some("RADARSAT Constellation: pass GDAL's calibrated subdataset (RCM_CALIB:SIGMA0:<product.xml>, GDAL >= 3.11)"),
        _ => None,
    };
    if let Some(why) = unsupported {
        return Err(raster_error(
            path,
            format!("GDAL's {driver} driver reads it, but {why}"),
        ));
    }
    Ok(dataset)
}

/// The first band of a one-band raster as f32, with its nodata mask (true = no data) from the
/// nodata value and the mask band, and its unit. Several bands are refused (which band?).
pub fn read_band(path: &Path, options: &ReadOptions) -> Result<(Array2<f32>, Array2<bool>, Dataset), WakelabError> {
    let dataset = open_dataset(path)?;
    let count = dataset.raster_count();
    if count == 0 {
        let subdatasets = dataset.metadata_domain("SUBDATASETS").unwrap_or_default();
        let names: Vec<&str> = subdatasets
            .iter()
            .filter_map(|s| s.split_once("_NAME=").map(|(_, v)| v))
            .collect();
        return Err(raster_error(
            path,
            if names.is_empty() {
                "holds no raster band".to_string()
            } else {
                format!("holds subdatasets; pass one of: {}", names.join(", "))
            },
        ));
    }
    if count > 1 && options.quantity == Quantity::Sigma0 && !grey_stored_as_colour(&dataset, path)? {
        return Err(raster_error(
            path,
            format!(
                "has {count} bands that differ; wakelab reads single-band images (a grey picture saved as RGB, \
                 its three bands equal, is read as one): write one band (gdal_translate -b N)"
            ),
        ));
    }
    let band = dataset.rasterband(1).map_err(|e| gdal_error(path, "band 1", e))?;
    let (cols, rows) = band.size();
    let buffer = band
        .read_as::<f32>((0, 0), (cols, rows), (cols, rows), None)
        .map_err(|e| gdal_error(path, "reading band 1", e))?;
    let values = Array2::from_shape_vec((rows, cols), buffer.data().to_vec()).map_err(|e| raster_error(path, e))?;
    let mut masked = Array2::from_elem((rows, cols), false);
    if let Some(nodata) = band.no_data_value() {
        masked.zip_mut_with(&values, |m, &v| {
            *m |= v == nodata as f32 || (nodata.is_nan() && v.is_nan())
        });
    }
    let flags = band.mask_flags().map_err(|e| gdal_error(path, "mask flags", e))?;
    if !flags.is_all_valid() && !flags.is_nodata() {
        let mask = band.open_mask_band().map_err(|e| gdal_error(path, "mask band", e))?;
        let m = mask
            .read_as::<u8>((0, 0), (cols, rows), (cols, rows), None)
            .map_err(|e| gdal_error(path, "reading the mask band", e))?;
        for (flag, &v) in masked.iter_mut().zip(m.data()) {
            *flag |= v == 0;
        }
    }
    Ok((values, masked, dataset))
}

/// Whether a raster of several bands is a grey picture saved as colour: three bands (red, green,
/// blue; a fourth only as their alpha, which GDAL gives band 1 as its mask) whose values are
/// equal pixel for pixel, as SAR quick-looks and datasets' chips (HRSID's PNGs, JPEGs decoded
/// from grey) often are. Its band 1 is then the picture.
fn grey_stored_as_colour(dataset: &Dataset, path: &Path) -> Result<bool, WakelabError> {
    use gdal::raster::ColorInterpretation;
    let count = dataset.raster_count();
    let alpha = |k: usize| {
        dataset
            .rasterband(k)
            .map(|b| b.color_interpretation() == ColorInterpretation::AlphaBand)
            .unwrap_or(false)
    };
    if !(count == 3 || (count == 4 && alpha(4))) {
        return Ok(false);
    }
    // compared a band of rows at a time, so that a large product never holds three bands at once
    let bands: Vec<_> = (1..=3)
        .map(|k| dataset.rasterband(k).map_err(|e| gdal_error(path, "a colour band", e)))
        .collect::<Result<_, _>>()?;
    let (cols, rows) = bands[0].size();
    let read = |band: &gdal::raster::RasterBand, row: usize, height: usize| {
        band.read_as::<f64>((0, row as isize), (cols, height), (cols, height), None)
            .map(|b| b.data().to_vec())
            .map_err(|e| gdal_error(path, "reading a colour band", e))
    };
    const ROWS_AT_ONCE: usize = 512;
    for row in (0..rows).step_by(ROWS_AT_ONCE) {
        let height = ROWS_AT_ONCE.min(rows - row);
        let red = read(&bands[0], row, height)?;
        for band in &bands[1..] {
            if read(band, row, height)? != red {
                return Ok(false);
            }
        }
    }
    Ok(true)
}

/// Mask (NaN) the no-data pixels of `raw` (`masked` from the file, plus NaN, infinities and
/// zeros reaching the border), then, for radar values, convert from `scale` to linear sigma0
/// with the scale's checks, floored at `floor` (or [`MIN_SIGMA0`]).
#[allow(clippy::too_many_arguments)]
pub(crate) fn mask_and_scale(
    mut raw: Array2<f32>,
    masked: Option<Array2<bool>>,
    floor: Option<&(dyn Fn(usize, usize) -> f64 + Sync)>,
    options: &ReadOptions,
    scale: InputScale,
    is_byte: bool,
    report: &mut ReadReport,
    path: &Path,
) -> Result<Array2<f32>, WakelabError> {
    let mut masked = masked.unwrap_or_else(|| Array2::from_elem(raw.dim(), false));
    let infinite = raw
        .iter()
        .zip(masked.iter())
        .filter(|(v, &m)| v.is_infinite() && !m)
        .count();
    if infinite > 0 {
        return Err(raster_error(
            path,
            format!("{infinite} infinite pixel(s): an overflow, not a value (NaN or the nodata value mark no-data)"),
        ));
    }
    crate::mask::border_zeros(&raw, &mut masked);
    raw.zip_mut_with(&masked, |v, &m| {
        if m {
            *v = f32::NAN;
        }
    });
    if options.quantity == Quantity::Sigma0 {
        if is_byte && scale != InputScale::Display {
            return Err(ConfigError::new(
                "--scale",
                scale.name(),
                format!("{} holds 8-bit grey levels, a display stretch, not {scale} sigma0: pass --scale display (its probabilities are then uncalibrated)", path.display()),
            )
            .into());
        }
        let constant = |_: usize, _: usize| MIN_SIGMA0;
        let floor = floor.unwrap_or(&constant);
        report.floored = to_linear_sigma0(&mut raw, scale, floor)?;
        if report.floored > 0 && scale == InputScale::Dn {
            report.notes.push(format!(
                "{} pixel(s) of digital number zero raised to half a step",
                report.floored
            ));
        } else if report.floored > 0 {
            report.floor = Some(floor(0, 0));
            report.notes.push(format!(
                "{} pixel(s) at or below zero (noise subtraction) raised to a floor of {:.1} dB",
                report.floored,
                10.0 * floor(0, 0).log10()
            ));
        }
        if scale == InputScale::Display {
            report.notes.push(
                "a display-stretched image: read as dB up to an unknown gain and offset; its probabilities are uncalibrated".into(),
            );
        }
        if scale == InputScale::Dn {
            report.notes.push(
                "digital numbers: read as amplitude up to an unknown gain, one offset in dB that the detector's normalisation and the ship and wake searches cancel; no sigma0 in dB is given".into(),
            );
        }
    }
    Ok(raw)
}

/// Any GDAL raster as a product: its scale from its band's unit (or `--scale`, refused where
/// the two disagree; linear when neither says), its georeference and ground spacing.
pub fn read(path: &Path, options: &ReadOptions) -> Result<Product, WakelabError> {
    let (raw, masked, dataset) = read_band(path, options)?;
    let band = dataset.rasterband(1).map_err(|e| gdal_error(path, "band 1", e))?;
    let stated = from_unit(&band.unit())
        .or_else(|| band.metadata_item("units", "").as_deref().and_then(from_unit))
        .or_else(|| dataset.metadata_item("units", "").as_deref().and_then(from_unit));
    let is_byte = band.band_type() == GdalDataType::UInt8;
    let scale = match (stated, options.scale) {
        (Some(s), Some(u)) if s != u && options.quantity == Quantity::Sigma0 => {
            return Err(ConfigError::new(
                "--scale",
                u.name(),
                format!(
                    "{}'s band unit says {s}: drop --scale or pass --scale {s}",
                    path.display()
                ),
            )
            .into())
        }
        (Some(s), _) => s,
        (None, Some(u)) => u,
        (None, None) => InputScale::Linear,
    };
    let mut report = ReadReport::default();
    if dataset.raster_count() > 1 && options.quantity == Quantity::Sigma0 {
        report.notes.push(format!(
            "{} bands of equal values (a grey picture saved as colour): read as one",
            dataset.raster_count().min(3)
        ));
    }
    if stated.is_none() && options.scale.is_none() && options.quantity == Quantity::Sigma0 {
        report
            .notes
            .push("the file states no scale (band unit): read as linear sigma0".into());
    }
    let image = mask_and_scale(raw, Some(masked), None, options, scale, is_byte, &mut report, path)?;
    let frame = Frame::of_dataset(&dataset);
    report.notes.extend(frame.no_crs_note(&dataset));
    let stated = |key| dataset.metadata_item(key, "").and_then(|v| v.parse::<f64>().ok());
    let spacing = match (stated(crate::cog::SPACING_ROWS), stated(crate::cog::SPACING_COLUMNS)) {
        (Some(rows), Some(columns)) => Some(PixelSpacing {
            columns,
            rows,
            source: SpacingSource::Metadata,
        }),
        _ => frame.ground_spacing().map(|(columns, rows)| PixelSpacing {
            columns,
            rows,
            source: SpacingSource::Georeference,
        }),
    };
    let stem = crate::stem_of(path);
    let driver = dataset.driver();
    Ok(Product {
        path: path.to_path_buf(),
        image,
        frame,
        meta: ProductMeta {
            format: driver.long_name(),
            product_id: stem,
            mission: dataset.metadata_item("WAKELAB_MISSION", ""),
            band: dataset
                .metadata_item(crate::band::BAND_ITEM, "")
                .and_then(|b| b.trim().parse().ok()),
            acquisition_time: dataset
                .metadata_item("TIFFTAG_DATETIME", "")
                .or_else(|| dataset.metadata_item("ACQUISITION_START_TIME", "")),
            scale: (options.quantity == Quantity::Sigma0).then_some(scale),
            calibrated: scale.calibrated(),
            pixel_spacing: spacing,
            // one angle for the image (a simulated scene's): no grid to interpolate
            incidence: stated(crate::cog::INCIDENCE)
                .filter(|i| (0.0..90.0).contains(i))
                .map(|i| crate::Incidence {
                    near_deg: i,
                    mid_deg: i,
                    far_deg: i,
                    grid: Vec::new(),
                }),
            ..Default::default()
        },
        report,
    })
}

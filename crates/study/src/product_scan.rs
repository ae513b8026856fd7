//! `wakelab detect` on a real product: read it ([`wakelab_products::open`]: calibrated, masked,
//! on its ground), bring it to the pixel spacing the detector was trained on (area averaging,
//! [`wakelab_products::resample`]), and scan it ([`wakelab_learn::detect::detect_image`]; no-data
//! windows are not scored). What was assumed is said in the scan's notes.

use anyhow::Result;
use ndarray::Array2;
use std::path::Path;
use wakelab_core::ConfigError;
use wakelab_learn::data::RadarScale;
use wakelab_learn::detect::{detect_image, Detection, ScanOptions};
use wakelab_learn::device::Device;
use wakelab_learn::store::{Detector, ModelInfo};
use wakelab_products::{Frame, Product, Quantity, ReadOptions, SpacingSource};
use wakelab_schema::band::Band;

/// Spacing ratios (detector / input) within this of 1 are scanned as they are.
const SAME_SPACING: f64 = 0.05;

/// Ratios within this share of a whole number are that number: a map projection's scale factor
/// (UTM's 0.9996-1.0010) changes the ground spacing of a grid without changing its resolution,
/// and whole factors keep the averaged pixels aligned with the product's.
const WHOLE_FACTOR: f64 = 0.01;

/// The coarsest input accepted against the detector's spacing (input pixels at most 25 %
/// larger): a coarser image would have to be interpolated, which invents texture the detector
/// never saw.
const MIN_RATIO: f64 = 0.8;

/// A scanned product.
pub struct ProductScan {
    /// The product read (its image moved to `image` when that is scanned as it is).
    pub product: Product,
    /// The image the detector saw, and its frame.
    pub image: Array2<f32>,
    pub frame: Frame,
    /// Product pixels per scanned pixel (rows, columns).
    pub factor: (f64, f64),
    pub band: Band,
    pub notes: Vec<String>,
    pub detection: Detection,
}

/// Product pixels per detector pixel along (rows, columns), and notes on what was assumed.
fn spacing_factor(product: &Product, info: &ModelInfo) -> Result<((f64, f64), Vec<String>)> {
    let mut notes = Vec::new();
    let Some(trained) = info.pixel_spacing else {
        notes.push(
            "the detector records no pixel spacing (a file from an earlier wakelab): the input is scanned at its own pixels"
                .into(),
        );
        return Ok(((1.0, 1.0), notes));
    };
    let Some(spacing) = product.meta.pixel_spacing else {
        notes.push(format!(
            "the input states no pixel spacing: taken at the detector's {trained} m (pass --pixel-spacing M for a bare array)"
        ));
        return Ok(((1.0, 1.0), notes));
    };
    let source = match spacing.source {
        SpacingSource::Annotation => "the product's annotation",
        SpacingSource::Georeference => "its georeference",
        SpacingSource::User => "--pixel-spacing",
    };
    let ratio = |d: f64| trained / d;
    let (r, c) = (ratio(spacing.rows), ratio(spacing.columns));
    if r < MIN_RATIO || c < MIN_RATIO {
        return Err(ConfigError::new(
            "IMAGE pixel spacing",
            format!("{:.2} x {:.2} m (from {source})", spacing.rows, spacing.columns),
            format!(
                "at most {:.1} m, the detector's {trained} m plus 25 %: this detector was trained on finer pixels; use one trained at the input's spacing",
                trained / MIN_RATIO
            ),
        )
        .into());
    }
    let snap = |f: f64| {
        if (f - 1.0).abs() <= SAME_SPACING || f < 1.0 {
            1.0
        } else if (f - f.round()).abs() <= WHOLE_FACTOR * f {
            f.round()
        } else {
            f
        }
    };
    let factor = (snap(r), snap(c));
    if factor == (1.0, 1.0) {
        if r < 1.0 - SAME_SPACING || c < 1.0 - SAME_SPACING {
            notes.push(format!(
                "the input's pixels ({:.2} x {:.2} m) are coarser than the detector's {trained} m: scanned as they are",
                spacing.rows, spacing.columns
            ));
        }
    } else {
        notes.push(format!(
            "area-averaged from {:.2} x {:.2} m (from {source}) to the detector's {trained} m ({:.2} x {:.2} input pixels per scanned pixel)",
            spacing.rows, spacing.columns, factor.0, factor.1
        ));
    }
    Ok((factor, notes))
}

/// How a scan reports progress: rows of the product read, then windows scored (done, total).
pub struct ScanProgress<'a> {
    pub reading: &'a mut dyn FnMut(usize, usize),
    pub scanning: &'a mut dyn FnMut(usize, usize),
}

/// Read the product at `path` and scan `detector` over it.
pub fn scan_product(
    path: &Path,
    read: &ReadOptions,
    detector: &Detector,
    info: &ModelInfo,
    options: ScanOptions,
    device: &Device,
    progress: ScanProgress,
) -> Result<ProductScan> {
    let Some(band) = info.bands.as_single() else {
        return Err(ConfigError::new(
            "--model",
            format!("a detector of {} bands ({})", info.image_channels(), info.bands),
            "a single-band detector",
        )
        .into());
    };
    let read = ReadOptions {
        quantity: if band.is_radar() {
            Quantity::Sigma0
        } else {
            Quantity::BrightnessTemperature
        },
        ..read.clone()
    };
    let mut product = wakelab_products::open_with_progress(path, &read, progress.reading)?;
    let (factor, mut notes) = spacing_factor(&product, info)?;
    notes.splice(0..0, product.report.notes.iter().cloned());
    if product.report.masked > 0 {
        notes.push(format!(
            "{} no-data pixel(s) masked; windows more than half no-data are not scored",
            product.report.masked
        ));
    }
    // the scanned image is the product's own where no averaging is needed (a whole product is
    // not held twice)
    let (image, frame) = if factor == (1.0, 1.0) {
        (std::mem::take(&mut product.image), product.frame.clone())
    } else {
        let image = wakelab_products::resample::area_average(&product.image, factor.0, factor.1);
        let frame = product.frame.scaled(factor.0, factor.1, image.dim());
        (image, frame)
    };
    // the product's values are linear sigma0 (or kelvin) whatever the file's scale was
    let options = ScanOptions {
        scale: RadarScale::Linear,
        ..options
    };
    let detection = detect_image(detector, info, &image, options, device, progress.scanning)?;
    Ok(ProductScan {
        product,
        image,
        frame,
        factor,
        band,
        notes,
        detection,
    })
}

//! Sentinel-1 GRD products: the `.SAFE` directory, its `manifest.safe`, or the `.zip` ESA
//! distributes (read in place through GDAL's `/vsizip/`). sigma0 is wakelab's own calibration,
//! per pixel, as ESA's calibration note (ESA-EOPG-CSCOP-TN-0002, Eq. 1) and thermal-denoising
//! note (MPC-0392, Eq. 1) give it:
//!
//! sigma0 = (|DN|^2 - eta) / A^2,
//!
//! A the calibration's `sigmaNought` and eta the thermal noise ([`annotation::Noise`]), both
//! bilinear in line and pixel ([`lut`]). Noise removal is on unless `keep_noise`; a pixel left
//! at or below zero by it is raised to the noise-equivalent sigma0 there (eta / A^2) and
//! counted. GDAL's own `SENTINEL1_CALIB:SIGMA0` subdataset is not used: it looks the LUT up once
//! per block of lines, removes no noise, and GDAL 3.6 opens it for no GRD product.
//!
//! [`Sentinel1::strip`] calibrates any band of rows from the measurement's digital numbers, so a
//! scan can hold one band of a product ([`read`] assembles the whole image). The zeros outside
//! the swath are no-data: each row's leading and trailing zeros (the swath edge of a GRD image
//! is one run per row end). Files and polarisations: [`SafeLocation`]; one line's calibration:
//! [`Calibration`].

pub mod annotation;
mod calibration;
pub mod lut;
mod safe;
pub mod synthetic;

pub use calibration::Calibration;
pub use safe::SafeLocation;

use crate::frame::{Gcp, Placement};
use crate::{gdal_error, Frame, Incidence, InputScale, PixelSpacing, Product, ProductMeta, ReadOptions, ReadReport};
use annotation::ProductAnnotation;
use gdal::Dataset;
use ndarray::{s, Array2, Axis};
use rayon::prelude::*;
use safe::{choose_files, safe_error};
use wakelab_core::WakelabError;

/// Speed of light (m/s), for slant range from the annotation's two-way time.
const SPEED_OF_LIGHT: f64 = 299_792_458.0;

/// Rows of digital numbers read at once.
const STRIP_ROWS: usize = 256;

/// The product's geolocation grid as GCPs in WGS 84 (longitude, latitude, height).
fn grid_frame(annotation: &ProductAnnotation, rows: usize, cols: usize) -> Frame {
    let wkt = gdal::spatial_ref::SpatialRef::from_epsg(4326)
        .and_then(|s| s.to_wkt())
        .unwrap_or_default();
    Frame {
        rows,
        cols,
        placement: Placement::Gcps {
            // the grid's (line, pixel) are pixel centres; GDAL's GCP pixel coordinates count
            // from the pixel's corner
            gcps: annotation
                .grid
                .iter()
                .map(|g| Gcp {
                    pixel: g.pixel + 0.5,
                    line: g.line + 0.5,
                    x: g.longitude,
                    y: g.latitude,
                    z: g.height,
                })
                .collect(),
            wkt,
        },
    }
}

/// An opened Sentinel-1 GRD product: its annotation read, its calibration ready, its
/// measurement open; [`Sentinel1::strip`] calibrates rows on demand, so a whole product can be
/// scanned a band at a time.
pub struct Sentinel1 {
    safe: SafeLocation,
    annotation: ProductAnnotation,
    polarisation: String,
    polarisations: Vec<String>,
    noise_format: Option<String>,
    calibration: Calibration,
    dataset: Dataset,
    pub rows: usize,
    pub cols: usize,
}

impl Sentinel1 {
    /// Open the product's files for `options.polarisation` (VV, else HH, by default).
    pub fn open(safe: &SafeLocation, options: &ReadOptions) -> Result<Self, WakelabError> {
        let files = choose_files(safe, options.polarisation.as_deref())?;
        let at = |relative: String| -> Result<String, WakelabError> { safe.read_text(&relative) };
        let xml_error = |file: &str, e: String| safe_error(&safe.input, format!("{file}: {e}"));
        let product_file = format!("annotation/{}.xml", files.stem);
        let calibration_file = format!("annotation/calibration/calibration-{}.xml", files.stem);
        let noise_file = format!("annotation/calibration/noise-{}.xml", files.stem);
        let annotation = annotation::product(&at(product_file.clone())?).map_err(|e| xml_error(&product_file, e))?;
        if annotation.product_type != "GRD" {
            return Err(safe_error(
                &safe.input,
                format!(
                    "a {} product; wakelab reads ground range detected (GRD) products",
                    annotation.product_type
                ),
            ));
        }
        let sigma =
            annotation::sigma_nought(&at(calibration_file.clone())?).map_err(|e| xml_error(&calibration_file, e))?;
        let noise = if options.keep_noise {
            None
        } else {
            Some(annotation::noise(&at(noise_file.clone())?).map_err(|e| xml_error(&noise_file, e))?)
        };
        let measurement = safe.file(&format!("measurement/{}.tiff", files.stem));
        let dataset = Dataset::open(&measurement).map_err(|e| {
            safe_error(
                &safe.input,
                format!(
                    "the product lacks its measurement measurement/{}.tiff{}",
                    files.stem,
                    crate::gdal_reason(&e)
                ),
            )
        })?;
        let (cols, rows) = dataset.raster_size();
        if (rows, cols) != (annotation.lines, annotation.samples) {
            return Err(safe_error(
                &safe.input,
                format!(
                    "its measurement is {rows} x {cols} pixels, its annotation says {} x {}",
                    annotation.lines, annotation.samples
                ),
            ));
        }
        Ok(Self {
            safe: safe.clone(),
            polarisation: files.polarisation,
            polarisations: files.available,
            noise_format: noise.as_ref().map(|n| n.format().to_string()),
            calibration: Calibration::new(&sigma, noise.as_ref(), cols),
            annotation,
            dataset,
            rows,
            cols,
        })
    }

    /// sigma0 of image rows `start..start + n` (NaN on no-data) and how many pixels of each
    /// row were floored at the noise-equivalent sigma0.
    pub fn strip(&self, start: usize, n: usize) -> Result<(Array2<f32>, Vec<usize>), WakelabError> {
        let cols = self.cols;
        let band = self
            .dataset
            .rasterband(1)
            .map_err(|e| gdal_error(&self.safe.input, "measurement band", e))?;
        let mut out = Array2::<f32>::zeros((n, cols));
        let mut floored = vec![0; n];
        let calibration = &self.calibration;
        for first in (0..n).step_by(STRIP_ROWS) {
            let m = STRIP_ROWS.min(n - first);
            let dn = band
                .read_as::<u16>((0, (start + first) as isize), (cols, m), (cols, m), None)
                .map_err(|e| gdal_error(&self.safe.input, "reading the measurement", e))?;
            let dn = dn.data();
            out.slice_mut(s![first..first + m, ..])
                .axis_iter_mut(Axis(0))
                .into_par_iter()
                .zip(floored[first..first + m].par_iter_mut())
                .enumerate()
                .for_each(|(i, (mut row, count))| {
                    let row = row.as_slice_mut().expect("rows of a standard array are contiguous");
                    *count = calibration.row(start + first + i, &dn[i * cols..(i + 1) * cols], row);
                });
        }
        Ok((out, floored))
    }

    /// The product's placement: its geolocation grid as GCPs.
    pub fn frame(&self) -> Frame {
        grid_frame(&self.annotation, self.rows, self.cols)
    }

    /// What the product says of itself.
    pub fn meta(&self) -> ProductMeta {
        let annotation = &self.annotation;
        let grid = &annotation.grid;
        let first_line = grid.iter().map(|g| g.line).fold(f64::MAX, f64::min);
        let mut on_first: Vec<_> = grid.iter().filter(|g| g.line == first_line).collect();
        on_first.sort_by(|a, b| a.pixel.total_cmp(&b.pixel));
        let mid = on_first[on_first.len() / 2];
        let incidence = Incidence {
            near_deg: on_first[0].incidence_deg,
            mid_deg: mid.incidence_deg,
            far_deg: on_first[on_first.len() - 1].incidence_deg,
            grid: grid.iter().map(|g| (g.line, g.pixel, g.incidence_deg)).collect(),
        };
        ProductMeta {
            format: "Sentinel-1 SAFE".into(),
            product_id: self.safe.name.clone(),
            mission: Some(annotation.mission.clone()),
            band: Some(wakelab_schema::band::Band::C),
            acquisition_time: Some(annotation.start_time.clone()),
            polarisation: Some(self.polarisation.clone()),
            polarisations: self.polarisations.clone(),
            pixel_spacing: Some(PixelSpacing::annotated(
                annotation.azimuth_spacing,
                annotation.range_spacing,
            )),
            looks: match (annotation.range_looks, annotation.azimuth_looks) {
                (Some(r), Some(a)) => Some(r * a),
                (r, a) => r.or(a),
            },
            scale: Some(InputScale::Linear),
            calibrated: true,
            incidence: Some(incidence),
            orbit_direction: (!annotation.pass.is_empty()).then(|| annotation.pass.to_ascii_uppercase()),
            look_side: Some("RIGHT".into()),
            slant_range_mid: Some(mid.slant_range_time * SPEED_OF_LIGHT / 2.0),
            platform_velocity: annotation.platform_speed,
            noise_removed: self.noise_format.clone(),
        }
    }
}

/// Read a whole Sentinel-1 GRD product as calibrated sigma0 (module doc);
/// `progress(rows done, rows)` follows the measurement's strips.
pub fn read(
    safe: &SafeLocation,
    options: &ReadOptions,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Product, WakelabError> {
    let product = Sentinel1::open(safe, options)?;
    let (rows, cols) = (product.rows, product.cols);
    let mut image = Array2::<f32>::zeros((rows, cols));
    let mut floored = 0;
    for start in (0..rows).step_by(STRIP_ROWS) {
        let n = STRIP_ROWS.min(rows - start);
        let (strip, counts) = product.strip(start, n)?;
        image.slice_mut(s![start..start + n, ..]).assign(&strip);
        floored += counts.iter().sum::<usize>();
        progress(start + n, rows);
    }
    Ok(Product {
        path: safe.input.clone(),
        image,
        frame: product.frame(),
        meta: product.meta(),
        report: ReadReport::floored_after_noise_removal(floored),
    })
}

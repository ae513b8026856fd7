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
//! The measurement is read in strips of rows, so memory holds the sigma0 image and one strip of
//! digital numbers. The zeros outside the swath are no-data: each row's leading and trailing
//! zeros (the swath edge of a GRD image is one run per row end).

pub mod annotation;
pub mod lut;
pub mod synthetic;

use crate::frame::{Gcp, Placement};
use crate::{
    gdal_error, Frame, Incidence, InputScale, PixelSpacing, Product, ProductMeta, ReadOptions, ReadReport,
    SpacingSource,
};
use annotation::{AzimuthBlock, Noise, ProductAnnotation};
use gdal::Dataset;
use ndarray::{s, Array2, Axis};
use rayon::prelude::*;
use std::ffi::CString;
use std::path::{Path, PathBuf};
use wakelab_core::WakelabError;

/// Speed of light (m/s), for slant range from the annotation's two-way time.
const SPEED_OF_LIGHT: f64 = 299_792_458.0;

/// Rows of digital numbers read at once.
const STRIP_ROWS: usize = 256;

/// Where a SAFE product's files are: a directory, or a folder inside a zip (GDAL's VSI path).
#[derive(Debug, Clone)]
pub struct SafeLocation {
    /// What the user passed.
    pub input: PathBuf,
    /// The SAFE folder as GDAL opens it (`/vsizip/...` inside a zip).
    pub root: String,
    /// Its name without `.SAFE` (the product identifier).
    pub name: String,
}

fn safe_error(path: &Path, message: impl ToString) -> WakelabError {
    WakelabError::Image {
        path: path.display().to_string(),
        message: message.to_string(),
    }
}

impl SafeLocation {
    /// The SAFE product at `path` (a `.SAFE` directory, its `manifest.safe` or a `.zip` holding
    /// one), or None when `path` is none of these.
    pub fn find(path: &Path) -> Result<Option<Self>, WakelabError> {
        let root = if path.is_dir() && path.join("manifest.safe").is_file() {
            path.to_string_lossy().into_owned()
        } else if path.file_name().is_some_and(|n| n == "manifest.safe") {
            path.parent().unwrap_or(Path::new(".")).to_string_lossy().into_owned()
        } else if crate::extension(path) == "zip" {
            let zip = format!("/vsizip/{}", path.display());
            let entries = gdal::vsi::read_dir(&zip, true)
                .map_err(|e| safe_error(path, format!("not a zip GDAL can read: {e}")))?;
            let manifest = entries
                .iter()
                .find(|e| e.file_name().is_some_and(|n| n == "manifest.safe"))
                .ok_or_else(|| safe_error(path, "a zip without a manifest.safe: not a Sentinel-1 SAFE product"))?;
            let folder = manifest
                .parent()
                .map(|p| p.to_string_lossy().into_owned())
                .unwrap_or_default();
            if folder.is_empty() {
                zip
            } else {
                format!("{zip}/{folder}")
            }
        } else {
            return Ok(None);
        };
        let trimmed = root.trim_end_matches('/');
        let folder = trimmed.rsplit('/').next().unwrap_or(trimmed);
        let name = folder.strip_suffix(".SAFE").unwrap_or(folder).to_string();
        Ok(Some(Self {
            input: path.to_path_buf(),
            root: trimmed.to_string(),
            name,
        }))
    }

    fn file(&self, relative: &str) -> String {
        format!("{}/{relative}", self.root)
    }

    /// The names in a folder of the product.
    fn list(&self, folder: &str) -> Vec<String> {
        gdal::vsi::read_dir(self.file(folder), false)
            .unwrap_or_default()
            .iter()
            .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
            .collect()
    }

    /// A file of the product as text, read through GDAL's virtual file system.
    fn read_text(&self, relative: &str) -> Result<String, WakelabError> {
        let name = self.file(relative);
        let c = CString::new(name.clone()).map_err(|e| safe_error(&self.input, e))?;
        let mut data: *mut u8 = std::ptr::null_mut();
        let mut size: u64 = 0;
        // SAFETY: GDAL allocates `data` (NUL-terminated, `size` bytes before the NUL), which is
        // copied and then freed with VSIFree.
        let ok = unsafe { gdal_sys::VSIIngestFile(std::ptr::null_mut(), c.as_ptr(), &mut data, &mut size, 1 << 30) };
        if ok == 0 || data.is_null() {
            return Err(safe_error(
                &self.input,
                format!("the product lacks {relative} (ESA's SAFE layout requires it)"),
            ));
        }
        let bytes = unsafe { std::slice::from_raw_parts(data, size as usize) }.to_vec();
        unsafe { gdal_sys::VSIFree(data as *mut std::ffi::c_void) };
        String::from_utf8(bytes).map_err(|_| safe_error(&self.input, format!("{relative} is not UTF-8 text")))
    }
}

/// The polarisation of an annotation or measurement file name
/// (`s1a-iw-grd-vv-<start>-<stop>-<orbit>-<take>-<image>.xml`), in capitals.
fn polarisation_of(name: &str) -> Option<String> {
    let parts: Vec<&str> = name.split('-').collect();
    (parts.len() >= 9 && parts[0].starts_with("s1")).then(|| parts[3].to_ascii_uppercase())
}

/// The per-pixel noise along one image line, eta in DN^2.
fn noise_row(noise: &NoiseRows, line: usize, out: &mut [f64]) {
    match noise {
        NoiseRows::Range(rows) => rows.row_into(line, out),
        NoiseRows::RangeAzimuth(rows, blocks) => {
            rows.row_into(line, out);
            for block in blocks {
                if line < block.first_line || line > block.last_line {
                    continue;
                }
                let factor = block.at(line as f64);
                let end = (block.last_sample + 1).min(out.len());
                for v in &mut out[block.first_sample.min(end)..end] {
                    *v *= factor;
                }
            }
        }
    }
}

/// [`Noise`] expanded across the image's width.
enum NoiseRows {
    Range(lut::LutRows),
    RangeAzimuth(lut::LutRows, Vec<AzimuthBlock>),
}

/// The calibration of one product: sigma0 from digital numbers, row by row.
pub struct Calibration {
    sigma: lut::LutRows,
    noise: Option<NoiseRows>,
    width: usize,
}

impl Calibration {
    /// From the calibration's `sigmaNought` LUT and, to remove noise, the noise annotation.
    pub fn new(sigma: &lut::SparseLut, noise: Option<&Noise>, width: usize) -> Self {
        let noise = noise.map(|n| match n {
            Noise::Range(r) => NoiseRows::Range(r.rows(width)),
            Noise::RangeAzimuth { range, azimuth } => NoiseRows::RangeAzimuth(range.rows(width), azimuth.clone()),
        });
        Self {
            sigma: sigma.rows(width),
            noise,
            width,
        }
    }

    /// sigma0 of image line `line` from its digital numbers `dn` into `out`: NaN on the row's
    /// leading and trailing zeros (no data), the noise-equivalent sigma0 where noise removal
    /// leaves zero or less; returns how many pixels were floored.
    pub fn row(&self, line: usize, dn: &[u16], out: &mut [f32]) -> usize {
        let mut a = vec![0.0; self.width];
        let mut eta = vec![0.0; self.width];
        self.sigma.row_into(line, &mut a);
        if let Some(noise) = &self.noise {
            noise_row(noise, line, &mut eta);
        }
        let first = dn.iter().position(|&v| v != 0).unwrap_or(dn.len());
        let last = dn.iter().rposition(|&v| v != 0).map_or(first, |p| p + 1);
        let mut floored = 0;
        for (p, o) in out.iter_mut().enumerate() {
            if p < first || p >= last {
                *o = f32::NAN;
                continue;
            }
            let power = dn[p] as f64 * dn[p] as f64;
            let gain = a[p] * a[p];
            let sigma0 = (power - eta[p]) / gain;
            *o = if sigma0 > 0.0 {
                sigma0 as f32
            } else {
                floored += 1;
                let nesz = eta[p] / gain;
                (if nesz > 0.0 { nesz } else { crate::scale::MIN_SIGMA0 }) as f32
            };
        }
        floored
    }
}

/// The files of one polarisation and the polarisations the product has.
struct Files {
    stem: String,
    polarisation: String,
    available: Vec<String>,
}

fn choose_files(safe: &SafeLocation, wanted: Option<&str>) -> Result<Files, WakelabError> {
    let annotations: Vec<String> = safe
        .list("annotation")
        .into_iter()
        .filter(|n| n.ends_with(".xml") && polarisation_of(n).is_some())
        .collect();
    if annotations.is_empty() {
        return Err(safe_error(
            &safe.input,
            "no product annotation (annotation/s1?-*.xml): not a complete Sentinel-1 SAFE product",
        ));
    }
    let mut available: Vec<String> = annotations.iter().filter_map(|n| polarisation_of(n)).collect();
    available.sort();
    available.dedup();
    let polarisation = match wanted {
        Some(p) => {
            let p = p.to_ascii_uppercase();
            if !available.contains(&p) {
                return Err(wakelab_core::ConfigError::new(
                    "--pol",
                    p,
                    format!("a polarisation the product holds: {}", available.join(", ")),
                )
                .into());
            }
            p
        }
        None => ["VV", "HH"]
            .into_iter()
            .find(|p| available.iter().any(|a| a == p))
            .map(str::to_string)
            .ok_or_else(|| {
                wakelab_core::ConfigError::new(
                    "--pol",
                    "VV or HH (the default)",
                    format!(
                        "a polarisation the product holds: {} (pass it with --pol)",
                        available.join(", ")
                    ),
                )
            })?,
    };
    let name = annotations
        .iter()
        .find(|n| polarisation_of(n).as_deref() == Some(polarisation.as_str()))
        .expect("chosen among the annotations");
    Ok(Files {
        stem: name.trim_end_matches(".xml").to_string(),
        polarisation,
        available,
    })
}

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
            acquisition_time: Some(annotation.start_time.clone()),
            polarisation: Some(self.polarisation.clone()),
            polarisations: self.polarisations.clone(),
            pixel_spacing: Some(PixelSpacing {
                columns: annotation.range_spacing,
                rows: annotation.azimuth_spacing,
                source: SpacingSource::Annotation,
            }),
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
        report: floored_report(floored),
    })
}

/// The read report of `floored` pixels floored at the noise-equivalent sigma0.
pub fn floored_report(floored: usize) -> ReadReport {
    let mut report = ReadReport {
        floored,
        ..Default::default()
    };
    if floored > 0 {
        report.notes.push(format!(
            "{floored} pixel(s) at or below zero after noise removal raised to the noise-equivalent sigma0 there"
        ));
    }
    report
}

#[cfg(test)]
mod tests {
    use super::*;
    use lut::{LutVector, SparseLut};

    #[test]
    fn file_names_give_their_polarisation() {
        assert_eq!(
            polarisation_of("s1a-iw-grd-vh-20210119t031653-20210119t031718-036201-043ed0-002.xml").as_deref(),
            Some("VH")
        );
        assert_eq!(polarisation_of("calibration"), None);
    }

    /// One row by hand: sigma0 = (DN^2 - eta) / A^2 with A = 500 and eta = 100 x 2 (range LUT
    /// times the azimuth block's factor); border zeros are no data; a pixel below the noise is
    /// floored at eta / A^2.
    #[test]
    fn a_row_is_calibrated_as_esa_defines_it() {
        let flat = |value: f64| {
            SparseLut::new(vec![LutVector {
                line: 0.0,
                pixels: vec![0.0, 5.0],
                values: vec![value, value],
            }])
            .unwrap()
        };
        let noise = Noise::RangeAzimuth {
            range: flat(100.0),
            azimuth: vec![AzimuthBlock {
                first_line: 0,
                last_line: 10,
                first_sample: 0,
                last_sample: 5,
                lines: vec![0.0, 10.0],
                values: vec![2.0, 2.0],
            }],
        };
        let calibration = Calibration::new(&flat(500.0), Some(&noise), 6);
        let dn = [0u16, 300, 10, 1000, 0, 0];
        let mut out = [0.0f32; 6];
        let floored = calibration.row(3, &dn, &mut out);
        assert!(out[0].is_nan() && out[4].is_nan() && out[5].is_nan());
        assert_eq!(out[1], ((300.0f64 * 300.0 - 200.0) / 250_000.0) as f32);
        assert_eq!(out[3], ((1e6f64 - 200.0) / 250_000.0) as f32);
        assert_eq!(floored, 1);
        assert_eq!(out[2], (200.0f64 / 250_000.0) as f32);
        let raw = Calibration::new(&flat(500.0), None, 6);
        raw.row(3, &dn, &mut out);
        assert_eq!(out[2], (100.0f64 / 250_000.0) as f32);
    }
}

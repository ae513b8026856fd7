//! COSMO-SkyMed (first generation) products in HDF5, through GDAL's HDF5 driver: the image of
//! swath S0k (`//S0k/SBI`) and the product's calibration attributes, which GDAL reports as
//! metadata (spaces as underscores). e-GEOS, "COSMO-SkyMed Image Calibration" (the
//! calibration note; SNAP's CosmoSkymedCalibrator applies the same):
//!
//! sigma0 = |DN|^2 R_ref^(2 R_exp) sin(alpha_ref) / (F^2 K),
//!
//! |DN|^2 = DN^2 for detected (DGM) and I^2 + Q^2 for complex (SCS) products, F the `Rescaling
//! Factor`, K the swath's `Calibration Constant`, R_ref and R_exp the `Reference Slant Range`
//! and its exponent, alpha_ref the `Reference Incidence Angle`; each factor applied only where
//! the product says its processing compensated for it (`Range Spreading Loss Compensation
//! Geometry`, `Incidence Angle Compensation Geometry` not NONE; `Calibration Constant
//! Compensation Flag` 0). No noise model is published for the first generation; the second
//! (CSG) has no public radiometric note, and is refused.

use crate::{Frame, InputScale, PixelSpacing, Product, ProductMeta, ReadOptions, ReadReport};
use gdal::{Dataset, Metadata};
use ndarray::Array2;
use std::path::Path;
use wakelab_core::WakelabError;

fn csk_error(path: &Path, message: impl ToString) -> WakelabError {
    WakelabError::Image {
        path: path.display().to_string(),
        message: message.to_string(),
    }
}

/// A metadata number (GDAL writes HDF5 numbers with a trailing space).
fn number(dataset: &Dataset, key: &str) -> Option<f64> {
    dataset.metadata_item(key, "")?.trim().parse().ok()
}

/// The COSMO-SkyMed product at `path` (an HDF5 file) read as sigma0, or None when the file is
/// not one (another HDF5 or raster).
pub fn read(path: &Path, options: &ReadOptions) -> Result<Option<Product>, WakelabError> {
    if !matches!(crate::extension(path).as_str(), "h5" | "hdf5" | "he5") {
        return Ok(None);
    }
    let err = |m: String| csk_error(path, m);
    let file =
        Dataset::open(path).map_err(|e| err(format!("not an HDF5 file GDAL reads{}", crate::gdal_reason(&e))))?;
    let mission = file.metadata_item("Mission_ID", "").unwrap_or_default();
    match mission.trim() {
        "CSK" | "KMPS" => {}
        "CSG" => {
            return Err(err(
                "a COSMO-SkyMed Second Generation product: its radiometric calibration is not publicly documented; calibrate it in SNAP and pass the GeoTIFF".into(),
            ))
        }
        _ => return Ok(None),
    }
    // the swaths' polarisations (S01_Polarisation = HH, ...)
    let swaths: Vec<(String, String)> = (1..=4)
        .filter_map(|k| {
            let swath = format!("S0{k}");
            let pol = file.metadata_item(&format!("{swath}_Polarisation"), "")?;
            Some((swath, pol.trim().to_ascii_uppercase()))
        })
        .collect();
    let available: Vec<String> = swaths.iter().map(|s| s.1.clone()).collect();
    let wanted = options.polarisation.as_ref().map(|p| p.to_ascii_uppercase());
    let chosen = match &wanted {
        Some(p) => swaths.iter().find(|s| &s.1 == p),
        None => ["VV", "HH"]
            .iter()
            .find_map(|p| swaths.iter().find(|s| s.1 == *p))
            .or(swaths.first()),
    };
    let Some((swath, pol)) = chosen.cloned() else {
        return Err(wakelab_core::ConfigError::new(
            "--pol",
            wanted.unwrap_or_else(|| "VV or HH (the default)".into()),
            format!("a polarisation the product holds: {}", available.join(", ")),
        )
        .into());
    };
    // the swath's image: the file itself when it holds one dataset, else its subdataset
    let image = if file.raster_count() > 0 {
        file
    } else {
        let name = format!("HDF5:\"{}\"://{swath}/SBI", path.display());
        Dataset::open(&name).map_err(|e| err(format!("no image {swath}/SBI{}", crate::gdal_reason(&e))))?
    };
    let product_type = image.metadata_item("Product_Type", "").unwrap_or_default();
    let flag = |key: &str| image.metadata_item(key, "").map(|v| v.trim().to_ascii_uppercase());
    let need = |key: &str| number(&image, key).ok_or_else(|| err(format!("no {} attribute", key.replace('_', " "))));
    let rescaling = need("Rescaling_Factor")?;
    let constant = need(&format!("{swath}_Calibration_Constant"))?;
    let mut factor = 1.0 / (rescaling * rescaling);
    if flag("Range_Spreading_Loss_Compensation_Geometry").is_some_and(|g| g != "NONE") {
        factor *= need("Reference_Slant_Range")?.powf(2.0 * need("Reference_Slant_Range_Exponent")?);
    }
    if flag("Incidence_Angle_Compensation_Geometry").is_some_and(|g| g != "NONE") {
        factor *= need("Reference_Incidence_Angle")?.to_radians().sin();
    }
    if number(&image, "Calibration_Constant_Compensation_Flag") == Some(0.0) {
        factor /= constant;
    }
    let (cols, rows) = image.raster_size();
    let band_power = |k: usize| -> Result<Vec<f64>, WakelabError> {
        let band = image
            .rasterband(k)
            .map_err(|e| crate::gdal_error(path, "image band", e))?;
        let v = band
            .read_as::<f64>((0, 0), (cols, rows), (cols, rows), None)
            .map_err(|e| crate::gdal_error(path, "reading the image", e))?;
        Ok(v.data().iter().map(|x| x * x).collect())
    };
    // detected: one band of DN; complex: I and Q as two bands
    let mut power = band_power(1)?;
    if image.raster_count() == 2 {
        for (p, q) in power.iter_mut().zip(band_power(2)?) {
            *p += q;
        }
    }
    let raw = Array2::from_shape_vec((rows, cols), power.iter().map(|&p| p as f32).collect())
        .map_err(|e| err(e.to_string()))?;
    let mut masked = Array2::from_elem((rows, cols), false);
    crate::mask::border_zeros(&raw, &mut masked);
    let image_values =
        ndarray::Zip::from(&raw)
            .and(&masked)
            .map_collect(|&p, &m| if m { f32::NAN } else { (p as f64 * factor) as f32 });
    let spacing = |key: &str| {
        image
            .rasterband(1)
            .ok()?
            .metadata_item(&format!("{swath}_SBI_{key}"), "")?
            .trim()
            .parse::<f64>()
            .ok()
    };
    let mut report = ReadReport::default();
    report
        .notes
        .push("COSMO-SkyMed: no thermal noise model is published for the first generation; none removed".into());
    Ok(Some(Product {
        path: path.to_path_buf(),
        image: image_values,
        frame: Frame::of_dataset(&image),
        meta: ProductMeta {
            format: format!("COSMO-SkyMed {}", product_type.trim()),
            product_id: crate::stem_of(path),
            mission: Some(mission.trim().to_string()),
            band: Some(wakelab_schema::band::Band::X),
            acquisition_time: image.metadata_item("Scene_Sensing_Start_UTC", ""),
            polarisation: Some(pol),
            polarisations: available,
            pixel_spacing: spacing("Line_Spacing")
                .zip(spacing("Column_Spacing"))
                .map(|(r, c)| PixelSpacing::annotated(r, c)),
            scale: Some(InputScale::Linear),
            calibrated: true,
            ..Default::default()
        },
        report,
    }))
}

//! Cloud-Optimised GeoTIFFs through GDAL's COG driver (GDAL >= 3.1): tiled, DEFLATE-compressed
//! with the floating-point predictor, internal overviews by averaging, the nodata value, the
//! band's description and unit, and the frame's georeference (geotransform and CRS, or GCPs).
//! Written to a temporary path and renamed, so a failed write leaves no half-written file.

use crate::Frame;
use gdal::cpl::CslStringList;
use gdal::{DriverManager, Metadata};
use ndarray::Array2;
use std::ffi::CString;
use std::path::{Path, PathBuf};
use wakelab_core::io::atomic::AtomicFile;
use wakelab_core::WakelabError;

/// Metadata keys of the pixel spacing (m) `wakelab calibrate` writes and the raster reader
/// takes before the georeference's ground distances.
pub const SPACING_ROWS: &str = "WAKELAB_PIXEL_SPACING_ROWS";
pub const SPACING_COLUMNS: &str = "WAKELAB_PIXEL_SPACING_COLUMNS";

/// What a COG's one band holds.
#[derive(Debug, Clone)]
pub struct BandInfo<'a> {
    /// The band's description (GDAL's band description, shown by QGIS).
    pub description: &'a str,
    /// Its unit ("1", "dB", "K").
    pub unit: &'a str,
    /// Dataset metadata items (key, value).
    pub metadata: Vec<(String, String)>,
}

fn cog_error(path: &Path, e: impl std::fmt::Display) -> WakelabError {
    WakelabError::Image {
        path: path.display().to_string(),
        message: format!("writing the COG: {e}"),
    }
}

/// Write `values` (NaN = nodata) on `frame` as a single-band float32 COG at `path`.
pub fn write_cog(path: &Path, values: &Array2<f32>, frame: &Frame, band: &BandInfo) -> Result<PathBuf, WakelabError> {
    crate::quiet_gdal();
    let (rows, cols) = values.dim();
    let err = |e: gdal::errors::GdalError| cog_error(path, e);
    if !values.is_standard_layout() {
        return Err(cog_error(path, "the image is not in row-major order"));
    }
    let mem = DriverManager::get_driver_by_name("MEM").map_err(err)?;
    let mut dataset = mem.create_with_band_type::<f32, _>("", cols, rows, 0).map_err(err)?;
    // the band reads `values` in place (MEM's DATAPOINTER): a whole product is not copied
    let mut band_options = CslStringList::new();
    band_options
        .add_name_value("DATAPOINTER", &format!("{:p}", values.as_ptr()))
        .map_err(err)?;
    // SAFETY: `values` (rows x cols f32, row-major) outlives `dataset`, which only reads it
    let added = unsafe {
        gdal_sys::GDALAddBand(
            dataset.c_dataset(),
            gdal_sys::GDALDataType::GDT_Float32,
            band_options.as_ptr(),
        )
    };
    if added != gdal_sys::CPLErr::CE_None {
        return Err(cog_error(path, "GDAL's MEM driver could not wrap the image"));
    }
    frame.apply(&mut dataset).map_err(err)?;
    for (key, value) in &band.metadata {
        dataset.set_metadata_item(key, value, "").map_err(err)?;
    }
    {
        let mut raster = dataset.rasterband(1).map_err(err)?;
        raster.set_no_data_value(Some(f64::NAN)).map_err(err)?;
        raster.set_description(band.description).map_err(err)?;
        let unit = CString::new(band.unit).map_err(|e| cog_error(path, e))?;
        // SAFETY: the band handle is valid while `raster` lives; GDAL copies the string.
        unsafe { gdal_sys::GDALSetRasterUnitType(raster.c_rasterband(), unit.as_ptr()) };
    }
    let mut options = CslStringList::new();
    for (k, v) in [
        ("COMPRESS", "DEFLATE"),
        ("PREDICTOR", "YES"),
        ("BLOCKSIZE", "256"),
        ("OVERVIEWS", "AUTO"),
        ("RESAMPLING", "AVERAGE"),
        ("NUM_THREADS", "ALL_CPUS"),
    ] {
        options.add_name_value(k, v).map_err(err)?;
    }
    let cog = DriverManager::get_driver_by_name("COG").map_err(err)?;
    let file = AtomicFile::new(path)?;
    dataset
        .create_copy(&cog, file.temporary_path(), &options)
        .map_err(err)?
        .close()
        .map_err(err)?;
    file.commit()
}

/// `wakelab calibrate`: the product's calibrated, masked sigma0 (linear, or dB with `db`) as a
/// COG on its ground, with what the product says of itself in the file's metadata.
pub fn write_sigma0(mut product: crate::Product, path: &Path, db: bool) -> Result<PathBuf, WakelabError> {
    let meta = product.meta.clone();
    if !meta.calibrated {
        return Err(cog_error(
            path,
            format!(
                "{} is a display-stretched image: it holds no sigma0 to write",
                product.path.display()
            ),
        ));
    }
    if db {
        product.image.par_mapv_inplace(|v| 10.0 * v.log10());
    }
    let pol = meta.polarisation.clone().unwrap_or_default();
    let noise = match &meta.noise_removed {
        Some(format) => format!("thermal noise removed ({format})"),
        None => "thermal noise kept".into(),
    };
    let description = format!("sigma0 {pol} ({}), {noise}", if db { "dB" } else { "linear" });
    let mut metadata = vec![
        ("WAKELAB_INPUT".to_string(), product.path.display().to_string()),
        ("WAKELAB_PRODUCT_ID".to_string(), meta.product_id.clone()),
        ("WAKELAB_FLOORED_PIXELS".to_string(), product.report.floored.to_string()),
        ("WAKELAB_MASKED_PIXELS".to_string(), product.report.masked.to_string()),
    ];
    let optional = [
        ("WAKELAB_MISSION", meta.mission.clone()),
        ("WAKELAB_ACQUISITION_TIME", meta.acquisition_time.clone()),
        ("WAKELAB_POLARISATION", meta.polarisation.clone()),
        ("WAKELAB_ORBIT_DIRECTION", meta.orbit_direction.clone()),
    ];
    metadata.extend(optional.into_iter().filter_map(|(k, v)| v.map(|v| (k.to_string(), v))));
    if let Some(spacing) = meta.pixel_spacing {
        // the product's own spacing: a GCP grid's ground distances only approximate it
        metadata.push((SPACING_ROWS.to_string(), spacing.rows.to_string()));
        metadata.push((SPACING_COLUMNS.to_string(), spacing.columns.to_string()));
    }
    write_cog(
        path,
        &product.image,
        &product.frame,
        &BandInfo {
            description: &description,
            unit: if db { "dB" } else { "1" },
            metadata,
        },
    )
}

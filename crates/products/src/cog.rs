//! Cloud-Optimised GeoTIFFs through GDAL's COG driver (GDAL >= 3.1): tiled, DEFLATE-compressed
//! with the floating-point predictor, internal overviews by averaging, the nodata value, the
//! band's description and unit, and the frame's georeference (geotransform and CRS, or GCPs).
//! Written to a temporary path and renamed, so a failed write leaves no half-written file.

use crate::Frame;
use gdal::cpl::CslStringList;
use gdal::{Dataset, DriverManager, Metadata};
use ndarray::Array2;
use std::ffi::CString;
use std::path::{Path, PathBuf};
use wakelab_core::io::atomic::AtomicFile;
use wakelab_core::WakelabError;

/// Metadata keys of the pixel spacing (m) `wakelab calibrate` writes and the raster reader
/// takes before the georeference's ground distances.
pub const SPACING_ROWS: &str = "WAKELAB_PIXEL_SPACING_ROWS";
pub const SPACING_COLUMNS: &str = "WAKELAB_PIXEL_SPACING_COLUMNS";
/// Metadata key of the incidence angle at the image centre (degrees), for images that carry no
/// incidence grid (wakelab's simulated scenes).
pub const INCIDENCE: &str = "WAKELAB_INCIDENCE_DEG";

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
    describe(&mut dataset, frame, band).map_err(err)?;
    copy_as_cog(&dataset, path)
}

/// Rewrite the single-band float32 GeoTIFF at `path` as a COG on `frame` with `band`'s
/// description, unit and metadata, in place (through a temporary path).
pub fn rewrite_as_cog(path: &Path, frame: &Frame, band: &BandInfo) -> Result<PathBuf, WakelabError> {
    crate::quiet_gdal();
    let err = |e: gdal::errors::GdalError| cog_error(path, e);
    let values = {
        let source = Dataset::open(path).map_err(err)?;
        let (cols, rows) = source.raster_size();
        let buffer = source
            .rasterband(1)
            .map_err(err)?
            .read_as::<f32>((0, 0), (cols, rows), (cols, rows), None)
            .map_err(err)?;
        Array2::from_shape_vec((rows, cols), buffer.data().to_vec()).map_err(|e| cog_error(path, e))?
    };
    write_cog(path, &values, frame, band)
}

/// Give a one-band dataset its placement, metadata, nodata (NaN), description and unit.
fn describe(dataset: &mut Dataset, frame: &Frame, band: &BandInfo) -> gdal::errors::Result<()> {
    frame.apply(dataset)?;
    for (key, value) in &band.metadata {
        dataset.set_metadata_item(key, value, "")?;
    }
    let mut raster = dataset.rasterband(1)?;
    raster.set_no_data_value(Some(f64::NAN))?;
    raster.set_description(band.description)?;
    let unit = CString::new(band.unit).unwrap_or_default();
    // SAFETY: the band handle is valid while `raster` lives; GDAL copies the string.
    unsafe { gdal_sys::GDALSetRasterUnitType(raster.c_rasterband(), unit.as_ptr()) };
    Ok(())
}

/// `source` copied by GDAL's COG driver to `path` (through a temporary path).
fn copy_as_cog(source: &Dataset, path: &Path) -> Result<PathBuf, WakelabError> {
    let err = |e: gdal::errors::GdalError| cog_error(path, e);
    let mut options = CslStringList::new();
    for (k, v) in [
        ("COMPRESS", "DEFLATE"),
        ("PREDICTOR", "YES"),
        ("BLOCKSIZE", "256"),
        ("OVERVIEWS", "AUTO"),
        ("RESAMPLING", "AVERAGE"),
        ("NUM_THREADS", "ALL_CPUS"),
        ("BIGTIFF", "IF_SAFER"),
    ] {
        options.add_name_value(k, v).map_err(err)?;
    }
    let cog = DriverManager::get_driver_by_name("COG").map_err(err)?;
    let file = AtomicFile::new(path)?;
    source
        .create_copy(&cog, file.temporary_path(), &options)
        .map_err(err)?
        .close()
        .map_err(err)?;
    file.commit()
}

/// The sigma0 COG's band description and metadata: what the product says of itself and what
/// reading did.
fn sigma0_band(
    meta: &crate::ProductMeta,
    path: &Path,
    report: &crate::ReadReport,
    db: bool,
) -> (String, Vec<(String, String)>) {
    let pol = meta.polarisation.clone().unwrap_or_default();
    let noise = match &meta.noise_removed {
        Some(format) => format!("thermal noise removed ({format})"),
        None => "thermal noise kept".into(),
    };
    let description = format!("sigma0 {pol} ({}), {noise}", if db { "dB" } else { "linear" });
    let mut metadata = vec![
        ("WAKELAB_INPUT".to_string(), path.display().to_string()),
        ("WAKELAB_PRODUCT_ID".to_string(), meta.product_id.clone()),
        ("WAKELAB_FLOORED_PIXELS".to_string(), report.floored.to_string()),
        ("WAKELAB_MASKED_PIXELS".to_string(), report.masked.to_string()),
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
    (description, metadata)
}

/// `wakelab calibrate`: the product's calibrated, masked sigma0 (linear, or dB with `db`) as a
/// COG on its ground, with what the product says of itself in the file's metadata.
pub fn write_sigma0(mut product: crate::Product, path: &Path, db: bool) -> Result<PathBuf, WakelabError> {
    if !product.meta.calibrated {
        return Err(cog_error(
            path,
            format!(
                "{} is not calibrated ({}): it holds no sigma0 to write",
                product.path.display(),
                product.meta.scale.map_or("uncalibrated", |s| match s {
                    crate::InputScale::Dn => "digital numbers",
                    _ => "a display stretch",
                })
            ),
        ));
    }
    if db {
        product.image.par_mapv_inplace(|v| 10.0 * v.log10());
    }
    let (description, metadata) = sigma0_band(&product.meta, &product.path, &product.report, db);
    let band = BandInfo {
        description: &description,
        unit: if db { "dB" } else { "1" },
        metadata,
    };
    write_cog(path, &product.image, &product.frame, &band)
}

/// [`write_sigma0`] of a product read a band of rows at a time: the bands go to an untiled
/// float32 GeoTIFF beside `path` (removed afterwards), which GDAL's COG driver then copies, so
/// memory holds one band. Returns what reading did; `progress(rows done, rows)`.
pub fn write_sigma0_rows(
    source: &crate::RowSource,
    path: &Path,
    db: bool,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<(PathBuf, crate::ReadReport), WakelabError> {
    crate::quiet_gdal();
    let err = |e: gdal::errors::GdalError| cog_error(path, e);
    let (rows, cols) = source.dim();
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".rows.tif");
    let staging = AtomicFile::new(path.with_file_name(name))?;
    let mut options = CslStringList::new();
    options.add_name_value("BIGTIFF", "IF_SAFER").map_err(err)?;
    let gtiff = DriverManager::get_driver_by_name("GTiff").map_err(err)?;
    let mut dataset = gtiff
        .create_with_band_type_with_options::<f32, _>(staging.temporary_path(), cols, rows, 1, &options)
        .map_err(err)?;
    let (mut floored, mut masked) = (0, 0);
    for start in (0..rows).step_by(1024) {
        let n = 1024.min(rows - start);
        let (mut strip, counts) = source.rows(start, n)?;
        floored += counts.iter().sum::<usize>();
        masked += strip.iter().filter(|v| v.is_nan()).count();
        if db {
            strip.par_mapv_inplace(|v| 10.0 * v.log10());
        }
        let data: Vec<f32> = strip.into_raw_vec_and_offset().0;
        let mut buffer = gdal::raster::Buffer::new((cols, n), data);
        dataset
            .rasterband(1)
            .map_err(err)?
            .write((0, start as isize), (cols, n), &mut buffer)
            .map_err(err)?;
        progress(start + n, rows);
    }
    let mut report = crate::ReadReport::floored_after_noise_removal(floored);
    report.masked = masked;
    let (description, metadata) = sigma0_band(&source.meta, &source.path, &report, db);
    let band = BandInfo {
        description: &description,
        unit: if db { "dB" } else { "1" },
        metadata,
    };
    describe(&mut dataset, &source.frame, &band).map_err(err)?;
    dataset.flush_cache().map_err(err)?;
    let written = copy_as_cog(&dataset, path)?;
    Ok((written, report))
}

//! Real SAR products in: a Sentinel-1 GRD product (`.SAFE` directory, its `manifest.safe` or
//! the `.zip`), a TerraSAR-X MGD product (its directory), a COSMO-SkyMed HDF5 product, a
//! RADARSAT-2 product (GDAL's calibrated subdataset), any GeoTIFF or
//! Cloud-Optimised GeoTIFF of sigma0 or brightness temperature (linear, dB, amplitude or
//! display-stretched; any CRS or GCPs; its nodata value and mask band honoured), or a bare `.npy`
//! array, read through GDAL into one [`Product`]: the image in linear sigma0 (or kelvin), NaN
//! where it holds no data, with its georeferencing ([`Frame`]) and what the product says of its
//! acquisition ([`ProductMeta`]). wakelab's detectors and `calibrate` read every input through
//! [`open`]; nothing here knows physics or networks.

pub mod band;
pub mod cog;
pub mod cosmo;
pub mod exclude;
pub mod frame;
pub mod geojson;
pub mod mask;
pub mod npy;
pub mod raster;
pub mod resample;
pub mod scale;
pub mod sentinel1;
pub mod terrasar;

pub use frame::Frame;
pub use scale::InputScale;

use ndarray::Array2;
use serde::Serialize;
use std::path::{Path, PathBuf};
use wakelab_core::WakelabError;

/// What the image's pixels are.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Quantity {
    /// Radar backscatter: read in the input's scale and turned into linear sigma0.
    Sigma0,
    /// Infrared brightness temperature (K): read as it is.
    BrightnessTemperature,
}

/// How to read an input.
#[derive(Debug, Clone)]
pub struct ReadOptions {
    pub quantity: Quantity,
    /// The scale the user states (`--scale`); None: the metadata's, else linear.
    pub scale: Option<InputScale>,
    /// Polarisation of a multi-polarisation product (`--pol`); None: VV, else HH.
    pub polarisation: Option<String>,
    /// Keep the thermal noise in (`--keep-noise`); removed by default.
    pub keep_noise: bool,
    /// Pixels to ignore (`--exclude`): a raster of the input's size, non-zero where excluded.
    pub exclude: Option<PathBuf>,
    /// Pixel spacing of a bare array (`--pixel-spacing`, metres).
    pub pixel_spacing: Option<f64>,
}

impl Default for ReadOptions {
    fn default() -> Self {
        Self {
            quantity: Quantity::Sigma0,
            scale: None,
            polarisation: None,
            keep_noise: false,
            exclude: None,
            pixel_spacing: None,
        }
    }
}

/// Where a pixel spacing came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SpacingSource {
    /// The product's annotation.
    Annotation,
    /// The georeferencing (ground distance between neighbouring pixels at the image centre).
    Georeference,
    /// The file's metadata (a COG written by `wakelab calibrate` keeps its product's).
    Metadata,
    /// `--pixel-spacing`.
    User,
}

/// Ground distance between pixels (metres).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PixelSpacing {
    /// Along a row (range, for a product in radar geometry).
    pub columns: f64,
    /// Down a column (azimuth).
    pub rows: f64,
    pub source: SpacingSource,
}

impl PixelSpacing {
    /// The spacing a product's annotation states.
    pub fn annotated(rows: f64, columns: f64) -> Self {
        Self {
            columns,
            rows,
            source: SpacingSource::Annotation,
        }
    }
}

/// Incidence angle over the image: a bilinear fit to the product's geolocation grid.
#[derive(Debug, Clone, Serialize)]
pub struct Incidence {
    /// Its value at the near, middle and far range of the first line (degrees).
    pub near_deg: f64,
    pub mid_deg: f64,
    pub far_deg: f64,
    #[serde(skip)]
    pub grid: Vec<(f64, f64, f64)>,
}

impl Incidence {
    /// The grid's value at (line, pixel): linear in pixel along the two grid lines around
    /// `line`, then linear between them (the grid is regular in every product); the middle
    /// value where there is no grid (one angle for the image).
    pub fn at(&self, line: f64, pixel: f64) -> f64 {
        if self.grid.is_empty() {
            return self.mid_deg;
        }
        let mut lines: Vec<f64> = self.grid.iter().map(|g| g.0).collect();
        lines.sort_by(f64::total_cmp);
        lines.dedup();
        let along = |grid_line: f64| {
            let mut row: Vec<(f64, f64)> = self
                .grid
                .iter()
                .filter(|g| g.0 == grid_line)
                .map(|g| (g.1, g.2))
                .collect();
            row.sort_by(|a, b| a.0.total_cmp(&b.0));
            let pixels: Vec<f64> = row.iter().map(|r| r.0).collect();
            let (j, t) = sentinel1::lut::bracket(&pixels, pixel);
            if t == 0.0 {
                row[j].1
            } else {
                row[j].1 * (1.0 - t) + row[j + 1].1 * t
            }
        };
        let (i, t) = sentinel1::lut::bracket(&lines, line);
        if t == 0.0 {
            along(lines[i])
        } else {
            along(lines[i]) * (1.0 - t) + along(lines[i + 1]) * t
        }
    }
}

/// What a product says of its acquisition (absent fields: the input does not say).
#[derive(Debug, Clone, Default, Serialize)]
pub struct ProductMeta {
    /// What read it: "Sentinel-1 SAFE", "GeoTIFF", "npy", ...
    pub format: String,
    /// The product's identifier (a SAFE's name, else the file's stem).
    pub product_id: String,
    pub mission: Option<String>,
    /// The band the image was taken in, where its metadata names it ([`band::BAND_ITEM`]).
    pub band: Option<wakelab_schema::band::Band>,
    pub acquisition_time: Option<String>,
    pub polarisation: Option<String>,
    /// The polarisations the product holds.
    pub polarisations: Vec<String>,
    pub pixel_spacing: Option<PixelSpacing>,
    pub looks: Option<f64>,
    /// The scale the file's values were in.
    pub scale: Option<InputScale>,
    /// Whether the values are calibrated (a display-stretched image is not).
    pub calibrated: bool,
    pub incidence: Option<Incidence>,
    /// ASCENDING or DESCENDING.
    pub orbit_direction: Option<String>,
    /// Side the radar looks to (Sentinel-1: right).
    pub look_side: Option<String>,
    /// Slant range at mid swath (m).
    pub slant_range_mid: Option<f64>,
    /// Platform speed (m/s).
    pub platform_velocity: Option<f64>,
    /// Thermal noise removed from the values: Some(format) when it was.
    pub noise_removed: Option<String>,
}

impl ProductMeta {
    /// Whether the values are a display stretch (grey levels, `--scale display`): such an image's
    /// grey levels are not sigma0's statistics, so its ships are sought at a lower false-alarm
    /// probability, and its ceiling can hide them.
    pub fn is_display_stretch(&self) -> bool {
        self.scale == Some(InputScale::Display)
    }
}

/// What reading did to the pixels.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ReadReport {
    /// Pixels with no data (NaN in the image): border zeros, NaN, the nodata value, the mask
    /// band and `--exclude`.
    pub masked: usize,
    /// Pixels slightly below zero (after noise removal) raised to `floor`.
    pub floored: usize,
    /// The floor they were raised to (linear sigma0): the noise-equivalent sigma0 where the
    /// product gives it, else [`scale::MIN_SIGMA0`].
    pub floor: Option<f64>,
    /// Anything the user should know (shown by the commands).
    pub notes: Vec<String>,
}

impl ReadReport {
    /// The report of `floored` pixels raised to the noise-equivalent sigma0 after noise removal.
    pub fn floored_after_noise_removal(floored: usize) -> Self {
        let mut report = Self {
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
}

/// A product's identifier where it names none: its file's stem.
pub(crate) fn stem_of(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// A product read: the image (linear sigma0 or kelvin; NaN where masked) on its ground.
#[derive(Debug)]
pub struct Product {
    pub path: PathBuf,
    pub image: Array2<f32>,
    pub frame: Frame,
    pub meta: ProductMeta,
    pub report: ReadReport,
}

fn product_error(path: &Path, message: impl ToString) -> WakelabError {
    WakelabError::Image {
        path: path.display().to_string(),
        message: message.to_string(),
    }
}

/// GDAL's messages go to its quiet handler: every failure reaches the user once, in wakelab's
/// error naming the file, and GDAL's "ERROR 4: ..." lines on stderr would say it twice.
pub(crate) fn quiet_gdal() {
    static QUIET: std::sync::Once = std::sync::Once::new();
    // SAFETY: installs GDAL's own quiet handler, once, before any other GDAL call of wakelab
    QUIET.call_once(|| {
        unsafe { gdal_sys::CPLSetErrorHandler(Some(gdal_sys::CPLQuietErrorHandler)) };
        // GDAL's block cache defaults to 5 % of the machine's memory; wakelab holds its images
        // itself, so GDAL's blocks only pass through (a whole product's write stays bounded)
        if std::env::var_os("GDAL_CACHEMAX").is_none() {
            let _ = gdal::config::set_config_option("GDAL_CACHEMAX", "32");
        }
    });
}

/// Read any supported input (module doc) into a [`Product`].
pub fn open(path: &Path, options: &ReadOptions) -> Result<Product, WakelabError> {
    open_with_progress(path, options, &mut |_, _| {})
}

/// [`open`], calling `progress(rows done, rows)` as a whole product's rows are read.
pub fn open_with_progress(
    path: &Path,
    options: &ReadOptions,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Product, WakelabError> {
    quiet_gdal();
    if !path.exists() && !is_subdataset(path) {
        return Err(product_error(path, "no such file or directory"));
    }
    let mut product = if let Some(safe) = sentinel1::SafeLocation::find(path)? {
        if options.quantity != Quantity::Sigma0 {
            return Err(product_error(
                path,
                "a Sentinel-1 product holds radar backscatter: use a radar (S, C or X band) detector",
            ));
        }
        sentinel1::read(&safe, options, progress)?
    } else if let Some(xml) = terrasar::find(path) {
        if options.quantity != Quantity::Sigma0 {
            return Err(product_error(
                path,
                "a TerraSAR-X product holds radar backscatter: use a radar (S, C or X band) detector",
            ));
        }
        terrasar::read(&xml, options)?
    } else if let Some(product) = cosmo::read(path, options)? {
        product
    } else {
        if let Some(pol) = &options.polarisation {
            return Err(wakelab_core::ConfigError::new(
                "--pol",
                pol,
                format!(
                    "a polarisation of a multi-polarisation product (a Sentinel-1 SAFE); {} holds one band: drop --pol",
                    path.display()
                ),
            )
            .into());
        }
        if extension(path) == "npy" {
            npy::read(path, options)?
        } else {
            raster::read(path, options)?
        }
    };
    if let Some(exclude) = &options.exclude {
        let excluded = exclude::exclude(&mut product.image, exclude)?;
        product
            .report
            .notes
            .push(format!("{excluded} pixel(s) excluded by {}", exclude.display()));
    }
    product.report.masked = product.image.iter().filter(|v| v.is_nan()).count();
    if product.report.masked == product.image.len() {
        return Err(product_error(
            path,
            "every pixel is masked (no data, nodata value, mask band or --exclude): nothing to scan",
        ));
    }
    let mut valid = product.image.iter().filter(|v| !v.is_nan());
    let first = valid.next().copied().unwrap_or_default();
    if valid.all(|&v| v == first) {
        return Err(product_error(
            path,
            format!(
                "every valid pixel is {first}: a constant image holds no wake to find (a blank or masked product?)"
            ),
        ));
    }
    if product.meta.pixel_spacing.is_none() {
        product.meta.pixel_spacing = options.pixel_spacing.map(|d| PixelSpacing {
            columns: d,
            rows: d,
            source: SpacingSource::User,
        });
    }
    Ok(product)
}

/// Whether `path` names a GDAL subdataset (`RADARSAT_2_CALIB:SIGMA0:product.xml`): an
/// upper-case driver prefix before a colon.
pub(crate) fn is_subdataset(path: &Path) -> bool {
    path.to_str()
        .and_then(|s| s.split_once(':'))
        .is_some_and(|(prefix, _)| {
            prefix.len() > 1
                && prefix
                    .chars()
                    .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_')
        })
}

/// A product that can be read a band of rows at a time (a whole Sentinel-1 product need not be
/// held), or one read whole.
pub enum Source {
    Rows(Box<RowSource>),
    Whole(Box<Product>),
}

/// A product read on demand: its metadata and placement now, its calibrated rows when asked.
pub struct RowSource {
    pub path: PathBuf,
    pub meta: ProductMeta,
    pub frame: Frame,
    product: sentinel1::Sentinel1,
}

impl RowSource {
    /// (rows, columns).
    pub fn dim(&self) -> (usize, usize) {
        (self.product.rows, self.product.cols)
    }

    /// sigma0 of rows `start..start + n` (NaN on no-data), and how many of each row's pixels
    /// were floored at the noise-equivalent sigma0.
    pub fn rows(&self, start: usize, n: usize) -> Result<(Array2<f32>, Vec<usize>), WakelabError> {
        self.product.strip(start, n)
    }

    /// The product's cross-polarised band on the same grid (VH beside VV, HV beside HH), read
    /// with the same `options` (noise removal), where the product holds one and this source
    /// reads a co-polarised band; None otherwise.
    pub fn cross_polarised(&self, options: &ReadOptions) -> Result<Option<RowSource>, WakelabError> {
        let partner = match self.meta.polarisation.as_deref() {
            Some("VV") => "VH",
            Some("HH") => "HV",
            _ => return Ok(None),
        };
        if !self.meta.polarisations.iter().any(|p| p == partner) {
            return Ok(None);
        }
        let Some(safe) = sentinel1::SafeLocation::find(&self.path)? else {
            return Ok(None);
        };
        let options = ReadOptions {
            polarisation: Some(partner.into()),
            ..options.clone()
        };
        let product = sentinel1::Sentinel1::open(&safe, &options)?;
        if (product.rows, product.cols) != self.dim() {
            return Err(product_error(
                &self.path,
                format!(
                    "its {partner} band is {} x {} pixels and its co-polarised band {} x {}: not one grid",
                    product.rows,
                    product.cols,
                    self.dim().0,
                    self.dim().1
                ),
            ));
        }
        Ok(Some(RowSource {
            path: self.path.clone(),
            meta: product.meta(),
            frame: product.frame(),
            product,
        }))
    }

    /// The whole product.
    pub fn read_all(self, progress: &mut dyn FnMut(usize, usize)) -> Result<Product, WakelabError> {
        let (rows, _) = self.dim();
        let mut parts = Vec::new();
        let mut floored = 0;
        for start in (0..rows).step_by(1024) {
            let n = 1024.min(rows - start);
            let (strip, counts) = self.rows(start, n)?;
            floored += counts.iter().sum::<usize>();
            parts.push(strip);
            progress(start + n, rows);
        }
        let views: Vec<_> = parts.iter().map(|p| p.view()).collect();
        let image = ndarray::concatenate(ndarray::Axis(0), &views).map_err(|e| product_error(&self.path, e))?;
        let mut report = ReadReport::floored_after_noise_removal(floored);
        report.masked = image.iter().filter(|v| v.is_nan()).count();
        Ok(Product {
            path: self.path,
            image,
            frame: self.frame,
            meta: self.meta,
            report,
        })
    }
}

/// Open `path` for reading by rows where it can be (a Sentinel-1 product without `--exclude`),
/// else read it whole ([`open`]).
pub fn open_source(
    path: &Path,
    options: &ReadOptions,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Source, WakelabError> {
    quiet_gdal();
    if options.exclude.is_none() && options.quantity == Quantity::Sigma0 {
        if let Some(safe) = sentinel1::SafeLocation::find(path)? {
            let product = sentinel1::Sentinel1::open(&safe, options)?;
            return Ok(Source::Rows(Box::new(RowSource {
                path: path.to_path_buf(),
                meta: product.meta(),
                frame: product.frame(),
                product,
            })));
        }
    }
    open_with_progress(path, options, progress).map(|p| Source::Whole(Box::new(p)))
}

/// A path's extension in lower case ("" without one).
pub fn extension(path: &Path) -> String {
    path.extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase()
}

/// GDAL's own words on a failure, as ": <message>", or nothing where it said nothing.
pub(crate) fn gdal_reason(e: &gdal::errors::GdalError) -> String {
    match e {
        gdal::errors::GdalError::NullPointer { msg, .. } if msg.trim().is_empty() => String::new(),
        gdal::errors::GdalError::NullPointer { msg, .. } => format!(": {msg}"),
        other => format!(": {other}"),
    }
}

/// GDAL's error as text for a message.
pub(crate) fn gdal_error(path: &Path, what: &str, e: gdal::errors::GdalError) -> WakelabError {
    product_error(path, format!("{what}{}", gdal_reason(&e)))
}

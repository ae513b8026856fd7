//! `wakelab detect` on a real product: read it ([`wakelab_products::open_source`]: calibrated,
//! masked, on its ground), bring it to the pixel spacing the detector was trained on (area
//! averaging, [`wakelab_products::resample`]), and scan it ([`wakelab_learn::detect::Scan`]; no-data
//! windows are not scored). A Sentinel-1 product at the detector's spacing, or at a whole
//! fraction of it (averaged over whole blocks), is read and scanned a
//! band of rows at a time, so memory holds one band, not the product. What was assumed is said in
//! the scan's notes.

use crate::sea_findings::{
    ceiling_note, product_geometry, search_image, SeaFindings, SeaStream, ShipSearch, TILE_ROWS,
};
use anyhow::Result;
use std::path::Path;
use wakelab_core::ConfigError;
use wakelab_learn::data::RadarScale;
use wakelab_learn::detect::{Detection, Scan, ScanOptions};
use wakelab_learn::device::Device;
use wakelab_learn::store::{Detector, ModelInfo};
use wakelab_products::{Frame, ProductMeta, Quantity, ReadOptions, ReadReport, RowSource, Source, SpacingSource};
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

/// Rows of a band read and scanned at once (beyond the window's own), when a product is read a
/// band at a time: 1024 rows of an IW product are 100 MB of sigma0.
const BAND_ROWS: usize = 1024;

/// A scanned product.
pub struct ProductScan {
    pub path: std::path::PathBuf,
    pub meta: ProductMeta,
    pub report: ReadReport,
    /// The product's placement, and that of the scanned grid (the product's, or the averaged
    /// one).
    pub product_frame: Frame,
    pub frame: Frame,
    /// What the overlay shows: the scanned image's block means.
    pub overlay: crate::scan::OverlayMeans,
    /// Whether the product was read a band at a time.
    pub streamed: bool,
    /// Product pixels per scanned pixel (rows, columns).
    pub factor: (f64, f64),
    pub band: Band,
    pub notes: Vec<String>,
    pub detection: Detection,
    /// Ships and wakes (radar images), in the scanned grid's pixels.
    pub sea: Option<SeaFindings>,
}

/// The ground spacing (m between rows, columns) of the grid scanned at `factor` product pixels
/// per pixel: the product's, else the detector's.
fn scanned_spacing(meta: &ProductMeta, info: &ModelInfo, factor: (f64, f64)) -> (f64, f64) {
    match (&meta.pixel_spacing, info.pixel_spacing) {
        (Some(s), _) => (s.rows * factor.0, s.columns * factor.1),
        (None, Some(p)) => (p, p),
        (None, None) => (10.0, 10.0),
    }
}

/// Product pixels per detector pixel along (rows, columns), and notes on what was assumed.
fn spacing_factor(meta: &ProductMeta, info: &ModelInfo) -> Result<((f64, f64), Vec<String>)> {
    let mut notes = Vec::new();
    let Some(trained) = info.pixel_spacing else {
        notes.push(
            "the detector records no pixel spacing (a file from an earlier wakelab): the input is scanned at its own pixels"
                .into(),
        );
        return Ok(((1.0, 1.0), notes));
    };
    let Some(spacing) = meta.pixel_spacing else {
        notes.push(format!(
            "the input states no pixel spacing: taken at the detector's {trained} m (pass --pixel-spacing M for a bare array)"
        ));
        return Ok(((1.0, 1.0), notes));
    };
    let source = match spacing.source {
        SpacingSource::Annotation => "the product's annotation",
        SpacingSource::Georeference => "its georeference",
        SpacingSource::Metadata => "its metadata",
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

/// The input's band against the detector's `band`: an error naming both where they differ
/// (unless `force`), a note where the input does not say its band.
fn check_band(path: &Path, band: Band, force: bool) -> Result<Option<String>> {
    let sensor = |b: Band| {
        if b.is_radar() {
            format!("{b}-band SAR")
        } else {
            format!("{b} infrared")
        }
    };
    match wakelab_products::band::peek(path) {
        Some((input, _)) if input == band => Ok(None),
        Some((input, how)) if force => Ok(Some(format!(
            "scanned with --force: the input is {} (from {how}), the detector is for {}; its scores mean little",
            sensor(input),
            sensor(band)
        ))),
        Some((input, how)) => Err(anyhow::anyhow!(
            "{}: the input is {} (from {how}), but the detector was trained on {}: use a detector of the \
             input's band (--model), or --force to scan anyway",
            path.display(),
            sensor(input),
            sensor(band)
        )),
        None => Ok(Some(format!(
            "the input does not say its band; the detector is for {}",
            sensor(band)
        ))),
    }
}

/// How a scan reports progress: rows of the product read, then windows scored (done, total).
pub struct ScanProgress<'a> {
    pub reading: &'a mut dyn FnMut(usize, usize),
    pub scanning: &'a mut dyn FnMut(usize, usize),
}

/// A detector and how to run it.
#[derive(Clone, Copy)]
pub struct Scanner<'a> {
    pub detector: &'a Detector,
    pub info: &'a ModelInfo,
    pub options: ScanOptions,
    pub device: &'a Device,
    /// Scan an input whose band is not the detector's.
    pub force: bool,
    /// Seek ships (at this false-alarm probability, or the input's default) and their wakes in
    /// a radar image (the classic searches beside the CNN); None: no search.
    pub search_sea: Option<ShipSearch>,
}

/// A product opened for a detector of `band`: its source, how it was read, and what the band
/// check had to say.
pub struct OpenedProduct {
    pub source: Source,
    read: ReadOptions,
    band_note: Option<String>,
}

impl OpenedProduct {
    /// The product's metadata (its pixel spacing, mission, polarisation).
    pub fn meta(&self) -> &ProductMeta {
        match &self.source {
            Source::Rows(rows) => &rows.meta,
            Source::Whole(product) => &product.meta,
        }
    }
}

/// Open the product at `path` for a detector of `band`: radar images are read as sigma0,
/// infrared as brightness temperature; an input of another band is refused unless `force`.
pub fn open_product(
    path: &Path,
    read: &ReadOptions,
    band: Band,
    force: bool,
    reading: &mut dyn FnMut(usize, usize),
) -> Result<OpenedProduct> {
    let read = ReadOptions {
        quantity: if band.is_radar() {
            Quantity::Sigma0
        } else {
            Quantity::BrightnessTemperature
        },
        ..read.clone()
    };
    // before the pixels are read: an infrared image read as sigma0 fails the scale's checks
    let band_note = check_band(path, band, force)?;
    let source = wakelab_products::open_source(path, &read, reading)?;
    Ok(OpenedProduct {
        source,
        read,
        band_note,
    })
}

/// Read the product at `path` and scan the detector over it.
pub fn scan_product(path: &Path, read: &ReadOptions, scanner: Scanner, progress: ScanProgress) -> Result<ProductScan> {
    let band = scanner.info.single_band()?;
    let opened = open_product(path, read, band, scanner.force, progress.reading)?;
    scan_opened(opened, scanner, progress)
}

/// Scan the detector over an opened product (of the detector's band).
pub fn scan_opened(opened: OpenedProduct, scanner: Scanner, progress: ScanProgress) -> Result<ProductScan> {
    let (info, device) = (scanner.info, scanner.device);
    let band = info.single_band()?;
    // the product's values are linear sigma0 (or kelvin) whatever the file's scale was
    let scanner = Scanner {
        options: ScanOptions {
            scale: RadarScale::Linear,
            ..scanner.options
        },
        ..scanner
    };
    let OpenedProduct {
        source,
        read,
        band_note,
    } = opened;
    let meta = match &source {
        Source::Rows(rows) => &rows.meta,
        Source::Whole(product) => &product.meta,
    };
    let (factor, mut notes) = spacing_factor(meta, info)?;
    notes.extend(band_note);
    // the ships are sought in the cross-polarised band where the product has one
    let cross = match (&source, band.is_radar()) {
        (Source::Rows(rows), true) => rows.cross_polarised(&read)?,
        _ => None,
    };
    let (product, cross) = match source {
        Source::Rows(rows) if factor.0.fract() == 0.0 && factor.1.fract() == 0.0 => {
            return scan_by_bands(*rows, cross, band, factor, notes, scanner, progress)
        }
        Source::Rows(rows) => {
            let cross = cross.map(|c| c.read_all(&mut |_, _| {})).transpose()?;
            (rows.read_all(progress.reading)?, cross)
        }
        Source::Whole(product) => (*product, None),
    };
    let cross = cross.map(|c| {
        let pol = c.meta.polarisation.unwrap_or_default();
        let image = if factor == (1.0, 1.0) {
            c.image
        } else {
            wakelab_products::resample::area_average(&c.image, factor.0, factor.1)
        };
        (image, pol)
    });
    let masked = product.report.masked;
    let read = product.image.dim();
    let (image, frame) = if factor == (1.0, 1.0) {
        (product.image, product.frame.clone())
    } else {
        let image = wakelab_products::resample::area_average(&product.image, factor.0, factor.1);
        let frame = product.frame.scaled(factor.0, factor.1, image.dim());
        (image, frame)
    };
    notes.extend(fits_the_detector(read, image.dim(), info)?);
    let mut scan = Scan::new(scanner.detector, info, image.dim(), scanner.options)?;
    scan.feed(0, image.view(), device, progress.scanning);
    let mut overlay = crate::scan::OverlayMeans::new(image.dim(), band);
    overlay.add(0, image.view());
    let sea = scanner.search_sea.filter(|_| band.is_radar()).map(|search| {
        let (geometry, sea_notes) = product_geometry(&product.meta, scanned_spacing(&product.meta, info, factor));
        notes.extend(sea_notes);
        let display = product.meta.is_display_stretch();
        let (cfar, pfa_note) = search.cfar(display);
        notes.extend(pfa_note);
        if display {
            notes.extend(ceiling_note(cross.as_ref().map_or(image.view(), |c| c.0.view()), &cfar));
        }
        notes.extend(cross.as_ref().map(|c| cross_note(&c.1)));
        search_image(
            image.view(),
            cross.as_ref().map(|c| (c.0.view(), c.1.as_str())),
            geometry,
            cfar,
            Some(info.input_size),
        )
    });
    let sea = sea.map(|s| score_ship_windows(s, &scanner)).transpose()?;
    notes.splice(0..0, product.report.notes.iter().cloned());
    masked_note(&mut notes, masked);
    land_note(&mut notes, sea.as_ref());
    Ok(ProductScan {
        path: product.path,
        meta: product.meta,
        report: product.report,
        product_frame: product.frame,
        frame,
        overlay,
        streamed: false,
        factor,
        band,
        notes,
        detection: scan.finish()?,
        sea,
    })
}

/// The CNN's wake probability of the window centred on each ship's return (issue 39's CNN on
/// ship-centred windows, beside the line search from each ship), the windows let go.
fn score_ship_windows(mut sea: SeaFindings, scanner: &Scanner) -> Result<SeaFindings> {
    let windows = std::mem::take(&mut sea.ship_windows);
    sea.ship_cnn = wakelab_learn::detect::score_windows(
        scanner.detector,
        scanner.info,
        &windows,
        scanner.options,
        scanner.device,
    )?;
    Ok(sea)
}

/// What the notes say of ships sought in the cross-polarised band `pol`.
fn cross_note(pol: &str) -> String {
    format!(
        "ships sought in the product's cross-polarised {pol} band (the sea is darker there), wakes in the scanned band"
    )
}

fn masked_note(notes: &mut Vec<String>, masked: usize) {
    if masked > 0 {
        notes.push(format!(
            "{masked} no-data pixel(s) masked; windows more than half no-data are not scored"
        ));
    }
}

/// What the notes say of the land the ship and wake searches found and left out.
fn land_note(notes: &mut Vec<String>, sea: Option<&SeaFindings>) {
    if let Some(sea) = sea.filter(|s| !s.land.is_empty()) {
        let g = &sea.geometry;
        notes.push(format!(
            "ships and wakes: {:.2} km^2 of land found in the image ({} scanned pixels) left out of their searches (--no-land-mask to search it)",
            sea.land_pixels() as f64 * g.spacing.0 * g.spacing.1 / 1e6,
            sea.land_pixels()
        ));
    }
}

/// Whether the image, `read` pixels (rows, columns) as read and `scanned` once averaged to the
/// detector's spacing, fills at least half of one of the detector's windows
/// ([`wakelab_learn::detect::fills_half_a_window`]; the scan takes the rest of a smaller image's
/// window as no-data); else an error that gives both sizes and the window's side on the ground,
/// so that a user whose chip is larger than the window in its own pixels sees why it is refused.
/// A note where the image is smaller than the window.
fn fits_the_detector(read: (usize, usize), scanned: (usize, usize), info: &ModelInfo) -> Result<Option<String>> {
    let n = info.input_size;
    let sizes = match info.pixel_spacing {
        Some(spacing) if read != scanned => format!(
            "{} x {} pixels, {} x {} once averaged to the detector's {spacing} m",
            read.0, read.1, scanned.0, scanned.1
        ),
        _ => format!("{} x {} pixels", read.0, read.1),
    };
    let side = info
        .pixel_spacing
        .map(|spacing| format!(", {:.2} km a side", n as f64 * spacing / 1000.0))
        .unwrap_or_default();
    if !wakelab_learn::detect::fills_half_a_window(scanned, n) {
        let rule = wakelab_learn::detect::half_a_window(n);
        return Err(ConfigError::new(
            "IMAGE",
            sizes,
            format!(
                "{rule}{}: a larger image, or a detector of finer pixels (--model)",
                side.replacen(", ", "; the window is ", 1)
            ),
        )
        .into());
    }
    Ok((scanned.0 < n || scanned.1 < n).then(|| {
        format!(
            "the image ({sizes}) is smaller than the detector's {n} x {n}-pixel window{side}: its window is scored with the part past the image taken as no-data (set to the window's median, as at a no-data border), so the wake probability rests on less sea than the detector was trained on"
        )
    }))
}

/// Scan a product read a band of rows at a time, averaged over whole `factor`s to the
/// detector's spacing: each band starts at the first window row not yet scored and holds about
/// [`BAND_ROWS`] more product rows (the window's rows past the stride are read twice), so
/// memory holds one band; the ship and wake searches ([`SeaStream`]) hold theirs with 5 km of
/// rows either side, so that a wake crossing a band's edge is searched whole.
fn scan_by_bands(
    source: RowSource,
    cross: Option<RowSource>,
    band: Band,
    factor: (f64, f64),
    mut notes: Vec<String>,
    scanner: Scanner,
    progress: ScanProgress,
) -> Result<ProductScan> {
    let (info, device) = (scanner.info, scanner.device);
    // whole factors: a band of product rows starting at a multiple of the row factor averages
    // to exactly the rows the whole image's average has there
    let (fr, fc) = (factor.0 as usize, factor.1 as usize);
    let (rows, cols) = source.dim();
    let scanned = ((rows / fr).max(1), (cols / fc).max(1));
    notes.extend(fits_the_detector((rows, cols), scanned, info)?);
    let mut scan = Scan::new(scanner.detector, info, scanned, scanner.options)?;
    let (n, stride) = scan.window_and_stride();
    let height = n + BAND_ROWS.div_ceil(stride * fr) * stride;
    let mut overlay = crate::scan::OverlayMeans::new(scanned, band);
    let mut sea = scanner.search_sea.filter(|_| band.is_radar()).map(|search| {
        let (geometry, sea_notes) = product_geometry(&source.meta, scanned_spacing(&source.meta, info, factor));
        notes.extend(sea_notes);
        let (cfar, pfa_note) = search.cfar(source.meta.is_display_stretch());
        notes.extend(pfa_note);
        let pol = cross.as_ref().map(|c| c.meta.polarisation.clone().unwrap_or_default());
        notes.extend(pol.as_deref().map(cross_note));
        SeaStream::new(geometry, cfar, scanned.1, TILE_ROWS, pol).with_ship_windows(Some(info.input_size))
    });
    // scanned rows counted (masked, floored, overlay) so far: a band's overlap with the last
    // is not
    let (mut counted, mut masked, mut floored) = (0, 0, 0);
    while let Some(next) = scan.next_rows() {
        let (start, end) = (next.start, (next.start + height).min(scanned.0));
        // the product rows of the last scanned row run to the product's end, as in the whole
        // image's average
        let last = if end == scanned.0 { rows } else { end * fr };
        let (strip, floored_per_row) = source.rows(start * fr, last - start * fr)?;
        let fresh = counted.max(start) - start;
        let product_rows = strip.slice(ndarray::s![fresh * fr.., ..]);
        masked += product_rows.iter().filter(|v| v.is_nan()).count();
        floored += floored_per_row[fresh * fr..].iter().sum::<usize>();
        let average = |strip: ndarray::Array2<f32>| {
            if (fr, fc) == (1, 1) {
                strip
            } else {
                wakelab_products::resample::area_average(&strip, fr as f64, fc as f64)
            }
        };
        let strip = average(strip);
        let strip = strip.slice(ndarray::s![..end - start, ..]);
        let cross_strip = match (&cross, &sea) {
            (Some(c), Some(_)) => Some(average(c.rows(start * fr, last - start * fr)?.0)),
            _ => None,
        };
        overlay.add(start + fresh, strip.slice(ndarray::s![fresh.., ..]));
        if let Some(sea) = sea.as_mut() {
            sea.push(
                start,
                strip,
                cross_strip.as_ref().map(|c| c.slice(ndarray::s![..end - start, ..])),
            );
        }
        counted = end;
        (progress.reading)(last, rows);
        scan.feed(start, strip, device, progress.scanning);
    }
    let mut report = wakelab_products::ReadReport::floored_after_noise_removal(floored);
    report.masked = masked;
    notes.splice(0..0, report.notes.iter().cloned());
    masked_note(&mut notes, masked);
    let detection = scan.finish()?;
    let sea = sea.map(|s| score_ship_windows(s.finish(), &scanner)).transpose()?;
    land_note(&mut notes, sea.as_ref());
    Ok(ProductScan {
        frame: source.frame.scaled(factor.0, factor.1, scanned),
        product_frame: source.frame,
        path: source.path,
        meta: source.meta,
        report,
        overlay,
        streamed: true,
        factor,
        band,
        notes,
        detection,
        sea,
    })
}

//! `wakelab detect` and `wakelab calibrate` on a user's product, from the paths and options the
//! command line gives to the files written: the binary only draws the progress and prints.

use crate::product_scan::{open_product, scan_opened, ScanProgress, Scanner};
use crate::scan::{default_scan_dir, write_asked_mask, write_scan, ScanFiles, Scanned};
use crate::shipped::{choose, shipped_note, SHIPPED_BAND};
use anyhow::Result;
use std::path::{Path, PathBuf};
use wakelab_core::ConfigError;
use wakelab_learn::detect::{Detection, ScanOptions};
use wakelab_learn::device::parse_device;
use wakelab_learn::store::{load_detector, load_detector_bytes};
use wakelab_products::cog::{write_sigma0, write_sigma0_rows};
use wakelab_products::{ProductMeta, Quantity, ReadOptions, ReadReport, Source};

/// What `wakelab detect` scans, with what and where it writes.
pub struct DetectRequest<'a> {
    pub image: &'a Path,
    /// The detector file; None: the shipped detector for the image's spacing ([`crate::shipped`]).
    pub model: Option<&'a Path>,
    pub read: ReadOptions,
    pub options: ScanOptions,
    /// Backend name (`cpu`, `wgpu`, `cuda`).
    pub device: &'a str,
    /// Output folder (None: `detect-<image name>`).
    pub out: Option<PathBuf>,
    /// Where to write the U-Net's mask as a PNG (`--mask`).
    pub mask: Option<&'a Path>,
    /// Scan an input of another band than the detector's (`--force`).
    pub force: bool,
    /// Seek ships and their wakes (radar images) beside the detector's scan.
    pub search_sea: Option<crate::sea_findings::ShipSearch>,
}

/// A finished `wakelab detect`: the detection, what the user should know, and the files.
pub struct Detected {
    pub detection: Detection,
    pub notes: Vec<String>,
    pub files: ScanFiles,
    /// The ships and wakes found (radar images).
    pub sea: Option<crate::sea_findings::SeaFindings>,
}

impl Detected {
    /// The detection as `detect --json` prints it: the verdict, the detections, and the ships and
    /// wakes as `detections.json` holds them; every window's probability only with `windows`
    /// (a 4096² image has tens of thousands).
    pub fn json(&self, windows: bool) -> Result<serde_json::Value> {
        let mut out = serde_json::to_value(&self.detection)?;
        if !windows {
            if let Some(map) = out.as_object_mut() {
                let count = map.remove("tiles").and_then(|t| t.as_array().map(Vec::len));
                map.insert("windows".into(), serde_json::json!(count));
            }
        }
        let path = &self.files.detections;
        let text = std::fs::read_to_string(path).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
        let written: serde_json::Value = serde_json::from_str(&text)?;
        out["ships"] = written["ships"].clone();
        out["wakes"] = written["wakes"].clone();
        out["evidence"] = written["evidence"].clone();
        out["ship_search"] = written["ship_search"].clone();
        Ok(out)
    }
}

impl Detected {
    /// What `detect` prints: the verdict, the ships and wakes, and the files written.
    pub fn describe(&self, image: &Path) -> String {
        let files = &self.files;
        let mut text = format!("{}: {}\n", image.display(), self.detection.describe());
        if let Some(sea) = &self.sea {
            text += &format!("ships and wakes: {}\n", sea.describe());
            let spacing = sea.geometry.spacing;
            let evidence = crate::corroboration::corroborate(&self.detection.detections, &sea.wakes, spacing).evidence;
            text += &format!("wake evidence: {}\n", evidence.describe());
        }
        text + &format!(
            "wrote {} (map), {}, {}, {} and {} (every window)",
            files.map.display(),
            files.geojson.display(),
            files.overlay.display(),
            files.detections.display(),
            files.windows.display()
        )
    }
}

/// Load the detector (the user's, or the shipped one for the image's spacing), read and scan the
/// product, and write the scan's files.
pub fn detect(request: DetectRequest, progress: ScanProgress) -> Result<Detected> {
    if let Some(pfa) = request
        .search_sea
        .and_then(|s| s.pfa)
        .filter(|p| !(*p > 0.0 && *p <= 0.01))
    {
        return Err(ConfigError::new(
            "--ship-pfa",
            pfa,
            "above 0 and at most 0.01 (a false-alarm probability per pixel)",
        )
        .into());
    }
    let device = parse_device(request.device)?;
    let (image, force) = (request.image, request.force);
    let (detector, info, model, opened, chosen) = match request.model {
        Some(path) => {
            let (detector, info) = load_detector(path, None, &device)?;
            let opened = open_product(image, &request.read, info.single_band()?, force, progress.reading)?;
            (detector, info, path.to_path_buf(), opened, None)
        }
        None => {
            let opened = open_product(image, &request.read, SHIPPED_BAND, force, progress.reading)?;
            let shipped = choose(image, opened.meta().pixel_spacing.as_ref())?;
            let (detector, info) = load_detector_bytes(shipped.bytes.to_vec(), &shipped.path(), None, &device)?;
            let note = shipped_note(shipped, &info);
            (detector, info, shipped.path(), opened, Some(note))
        }
    };
    let scanner = Scanner {
        detector: &detector,
        info: &info,
        options: request.options,
        device: &device,
        force,
        search_sea: request.search_sea,
    };
    let mut scan = scan_opened(opened, scanner, progress)?;
    scan.notes.splice(0..0, chosen);
    scan.notes.extend(info.calibration_note());
    scan.notes.extend(info.input_note());
    let dir = request.out.unwrap_or_else(|| default_scan_dir(request.image));
    let scanned = Scanned {
        path: &scan.path,
        meta: &scan.meta,
        product_frame: &scan.product_frame,
        frame: &scan.frame,
        overlay: &scan.overlay,
        factor: scan.factor,
        band: scan.band,
        model: &model,
        notes: &scan.notes,
        sea: scan.sea.as_ref(),
    };
    let files = write_scan(&dir, &scanned, &scan.detection)?;
    let mut notes = scan.notes;
    if let Some(path) = request.mask {
        let architecture = info.architecture.to_string();
        notes.extend(write_asked_mask(path, &scan.detection, &model, &architecture)?);
    }
    Ok(Detected {
        detection: scan.detection,
        notes,
        files,
        sea: scan.sea,
    })
}

/// A finished `wakelab calibrate`: the product's metadata, what reading it did, its size
/// (rows, columns) and the COG written.
pub struct Calibrated {
    pub meta: ProductMeta,
    pub report: ReadReport,
    pub dim: (usize, usize),
    pub path: PathBuf,
}

impl Calibrated {
    /// What `calibrate --json` prints: the file written, the product's metadata and what reading did.
    pub fn json(&self) -> serde_json::Value {
        serde_json::json!({ "out": self.path, "product": self.meta, "read": self.report })
    }

    /// What `calibrate` prints.
    pub fn describe(&self, product: &Path) -> String {
        let (rows, cols) = self.dim;
        format!(
            "{}: {} {rows} x {cols} px, {} no-data, {} floored; wrote {}",
            product.display(),
            self.meta.format,
            self.report.masked,
            self.report.floored,
            self.path.display()
        )
    }
}

/// The calibrated, masked sigma0 of `product` as a COG at `out` (in dB with `db`); a Sentinel-1
/// product is written a band of rows at a time, reporting `progress` (rows done, total).
pub fn calibrate(
    product: &Path,
    read: ReadOptions,
    out: &Path,
    db: bool,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Calibrated> {
    let read = ReadOptions {
        quantity: Quantity::Sigma0,
        ..read
    };
    Ok(match wakelab_products::open_source(product, &read, &mut |_, _| {})? {
        Source::Rows(source) => {
            let (path, report) = write_sigma0_rows(&source, out, db, progress)?;
            Calibrated {
                meta: source.meta.clone(),
                report,
                dim: source.dim(),
                path,
            }
        }
        Source::Whole(product) => {
            let (meta, report, dim) = (product.meta.clone(), product.report.clone(), product.image.dim());
            Calibrated {
                meta,
                report,
                dim,
                path: write_sigma0(*product, out, db)?,
            }
        }
    })
}

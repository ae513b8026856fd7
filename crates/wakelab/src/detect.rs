//! `wakelab detect` and `wakelab calibrate`: a user's own image or SAR product, read by the
//! products crate; detect scans a saved detector over it.

use crate::cli::{CalibrateArgs, DetectArgs};
use crate::Result;
use wakelab_learn::detect::ScanOptions;
use wakelab_learn::device::parse_device;
use wakelab_learn::store::load_detector;
use wakelab_products::cog::write_sigma0_rows;
use wakelab_products::{Quantity, ReadOptions, Source};
use wakelab_study::product_scan::{scan_product, ScanProgress, Scanner};
use wakelab_study::scan::{default_scan_dir, write_asked_mask, write_scan, Scanned};

/// `wakelab detect`: a saved single-band detector scanned over a product of any size.
pub fn run_detect(args: &DetectArgs) -> Result<()> {
    let device = parse_device(&args.device)?;
    let (detector, info) = load_detector(&args.model, None, &device)?;
    let options = ScanOptions {
        stride: args.stride,
        threshold: args.threshold,
        ..ScanOptions::default()
    };
    // one bar: the product's rows as they are read and calibrated, then the windows scored
    let template = "{spinner} detect: {msg} [{bar:30}] {pos}/{len} | {elapsed_precise}, {eta} left";
    let bar = wakelab_study::progress_bar(args.quiet, 0, template);
    let follow = |what: &'static str| {
        let bar = bar.clone();
        move |done: usize, total: usize| {
            if bar.message() != what {
                bar.set_message(what);
                bar.reset();
            }
            bar.set_length(total as u64);
            bar.set_position(done as u64);
        }
    };
    let progress = ScanProgress {
        reading: &mut follow("rows read"),
        scanning: &mut follow("windows scored"),
    };
    let read = args.read.options(args.scale, args.pixel_spacing);
    let scanner = Scanner {
        detector: &detector,
        info: &info,
        options,
        device: &device,
    };
    let scan = scan_product(&args.image, &read, scanner, progress)?;
    bar.finish_and_clear();
    let dir = args.out.clone().unwrap_or_else(|| default_scan_dir(&args.image));
    let scanned = Scanned {
        path: &scan.path,
        meta: &scan.meta,
        product_frame: &scan.product_frame,
        frame: &scan.frame,
        overlay: &scan.overlay,
        factor: scan.factor,
        band: scan.band,
        model: &args.model,
        notes: &scan.notes,
    };
    let files = write_scan(&dir, &scanned, &scan.detection)?;
    if let Some(path) = &args.mask {
        let architecture = info.architecture.to_string();
        if let Some(note) = write_asked_mask(path, &scan.detection, &args.model, &architecture)? {
            eprintln!("{note}");
        }
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&scan.detection)?);
    } else {
        for note in &scan.notes {
            eprintln!("note: {note}");
        }
        println!("{}: {}", args.image.display(), scan.detection.describe());
        println!(
            "wrote {} (map), {}, {} and {}",
            files.map.display(),
            files.geojson.display(),
            files.overlay.display(),
            files.detections.display()
        );
    }
    Ok(())
}

/// `wakelab calibrate`: a product's calibrated, masked sigma0 as a COG.
pub fn run_calibrate(args: &CalibrateArgs) -> Result<()> {
    let read = ReadOptions {
        quantity: Quantity::Sigma0,
        ..args.read.options(args.scale, None)
    };
    let (meta, report, (rows, cols), path) = match wakelab_products::open_source(&args.product, &read, &mut |_, _| {})?
    {
        // a Sentinel-1 product: written a band of rows at a time
        Source::Rows(source) => {
            let bar = wakelab_study::progress_bar(
                args.quiet,
                0,
                "{spinner} calibrate: rows [{bar:30}] {pos}/{len} | {elapsed_precise}, {eta} left",
            );
            let (path, report) = write_sigma0_rows(&source, &args.out, args.db, &mut |done, total| {
                bar.set_length(total as u64);
                bar.set_position(done as u64);
            })?;
            bar.finish_and_clear();
            (source.meta.clone(), report, source.dim(), path)
        }
        Source::Whole(product) => {
            let (meta, report, dim) = (product.meta.clone(), product.report.clone(), product.image.dim());
            (
                meta,
                report,
                dim,
                wakelab_products::cog::write_sigma0(*product, &args.out, args.db)?,
            )
        }
    };
    if args.json {
        let out = serde_json::json!({ "out": path, "product": meta, "read": report });
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        for note in &report.notes {
            eprintln!("note: {note}");
        }
        println!(
            "{}: {} {} x {} px, {} no-data, {} floored; wrote {}",
            args.product.display(),
            meta.format,
            rows,
            cols,
            report.masked,
            report.floored,
            path.display()
        );
    }
    Ok(())
}

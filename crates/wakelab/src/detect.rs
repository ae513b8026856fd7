//! `wakelab detect` and `wakelab calibrate`: a user's own image or SAR product; the study crate
//! reads, scans and writes ([`wakelab_study::products`]), this draws the progress and prints.

use crate::{cli::CalibrateArgs, cli::DetectArgs, Result};
use wakelab_learn::detect::ScanOptions;
use wakelab_study::products::{calibrate, detect, DetectRequest};
use wakelab_study::{product_scan::ScanProgress, sea_findings::ShipSearch};

/// `wakelab detect`: a saved single-band detector scanned over a product of any size.
pub fn run_detect(args: &DetectArgs, quiet: bool) -> Result<()> {
    // one bar: the product's rows as they are read and calibrated, then the windows scored
    let template = "{spinner} detect: {msg} [{bar:30}] {pos}/{len} | {elapsed_precise}, {eta} left";
    let bar = wakelab_study::progress_bar(quiet, 0, template);
    let request = DetectRequest {
        image: &args.image,
        model: args.model.as_deref(),
        read: args.read.options(),
        options: ScanOptions {
            stride: args.stride,
            threshold: args.threshold,
            peak: args.peak,
            ..ScanOptions::default()
        },
        device: &args.device,
        out: args.out.clone(),
        mask: args.mask.as_deref(),
        force: args.force,
        search_sea: Some(ShipSearch::new(args.ship_pfa, args.no_land_mask)),
    };
    let progress = ScanProgress {
        reading: &mut wakelab_study::follow_on(&bar, "rows read"),
        scanning: &mut wakelab_study::follow_on(&bar, "windows scored"),
    };
    let found = detect(request, progress)?;
    bar.finish_and_clear();
    for note in &found.notes {
        eprintln!("note: {note}");
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&found.json(args.windows)?)?);
    } else {
        println!("{}", found.describe(&args.image));
    }
    Ok(())
}

/// `wakelab calibrate`: a product's calibrated, masked sigma0 as a COG.
pub fn run_calibrate(args: &CalibrateArgs, quiet: bool) -> Result<()> {
    let template = "{spinner} calibrate: rows [{bar:30}] {pos}/{len} | {elapsed_precise}, {eta} left";
    let bar = wakelab_study::progress_bar(quiet, 0, template);
    let rows = &mut wakelab_study::follow_on(&bar, "rows");
    let done = calibrate(&args.product, args.read.options(), &args.out, args.db, rows)?;
    bar.finish_and_clear();
    if args.json {
        println!("{}", serde_json::to_string_pretty(&done.json())?);
    } else {
        for note in &done.report.notes {
            eprintln!("note: {note}");
        }
        println!("{}", done.describe(&args.product));
    }
    Ok(())
}

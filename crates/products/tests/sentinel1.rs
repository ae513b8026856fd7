//! Sentinel-1 GRD products read as ESA defines their calibration: a product in the SAFE layout
//! written by the test (tests/common) reads back as (DN^2 - eta) / A^2 at every pixel, from the
//! directory, its manifest and the zip alike, in both noise formats; GDAL's SAFE driver opens
//! the same product; the reader's failures name what is wrong.

use wakelab_products::sentinel1::synthetic::*;
use wakelab_products::{open, ReadOptions};

fn read(path: &std::path::Path, keep_noise: bool) -> wakelab_products::Product {
    open(
        path,
        &ReadOptions {
            keep_noise,
            ..Default::default()
        },
    )
    .unwrap()
}

/// Every pixel against the closed form, to float precision (f32: relative 1e-6).
fn assert_calibrated(product: &wakelab_products::Product, remove_noise: bool, since_2_9: bool) {
    let s = Synthetic::small(since_2_9);
    assert_eq!(product.image.dim(), (LINES, SAMPLES));
    let mut checked = 0;
    for l in 0..LINES {
        for p in 0..SAMPLES {
            let got = product.image[[l, p]];
            match expected_sigma0(&s, l, p, remove_noise) {
                None => assert!(got.is_nan(), "({l}, {p}) is no-data, read {got}"),
                Some(want) => {
                    assert!(
                        ((got as f64) - want).abs() <= 1e-6 * want,
                        "({l}, {p}): {got} against {want}"
                    );
                    checked += 1;
                }
            }
        }
    }
    assert_eq!(checked + product.report.masked, LINES * SAMPLES);
}

#[test]
fn sigma0_is_dn_squared_less_noise_over_a_squared_at_every_pixel() {
    let dir = tempfile::tempdir().unwrap();
    let safe = write_safe(dir.path(), &Synthetic::small(true));
    let product = read(&safe, false);
    assert_calibrated(&product, true, true);
    // the left border (4 columns) and the lower right corner (8 rows x 2 columns) are no data
    assert_eq!(product.report.masked, LINES * 4 + 8 * 2);
    // DN 10 at (20, 30) is below the noise: raised to eta / A^2 there, and counted
    assert_eq!(product.report.floored, 1);
    let meta = &product.meta;
    assert_eq!(meta.polarisation.as_deref(), Some("VV"));
    assert_eq!(meta.polarisations, vec!["VV".to_string()]);
    assert_eq!(meta.noise_removed.as_deref(), Some("range x azimuth LUTs (IPF >= 2.9)"));
    assert_eq!(meta.orbit_direction.as_deref(), Some("ASCENDING"));
    assert_eq!(meta.looks, Some(5.0));
    let spacing = meta.pixel_spacing.unwrap();
    assert_eq!((spacing.rows, spacing.columns), (10.0, 10.0));
    let angles = meta.incidence.as_ref().unwrap();
    assert_eq!((angles.near_deg, angles.far_deg), (incidence_at(0), incidence_at(63)));
    assert!((angles.at(10.0, 31.5) - incidence(31.5)).abs() < 1e-9);
    // |v| of the orbit state vector (7000, 2000, 1000) m/s
    assert!((meta.platform_velocity.unwrap() - 54e6f64.sqrt()).abs() < 1e-6);
    // two-way time 5.3e-3 s + 1e-7 x 42 at the grid's middle pixel: c t / 2
    let mid = (5.3e-3 + 1e-7 * 42.0) * 299_792_458.0 / 2.0;
    assert!((meta.slant_range_mid.unwrap() - mid).abs() < 1e-6);

    // kept noise: DN^2 / A^2
    assert_calibrated(&read(&safe, true), false, true);
    // the manifest and the zip give the same bytes as the directory
    let via_manifest = read(&safe.join("manifest.safe"), false);
    let zip = write_zip(dir.path(), &Synthetic::small(true));
    let via_zip = read(&zip, false);
    for other in [&via_manifest, &via_zip] {
        assert!(product
            .image
            .iter()
            .zip(other.image.iter())
            .all(|(a, b)| a.to_bits() == b.to_bits()));
    }
    assert_eq!(via_zip.meta.product_id, SAFE.trim_end_matches(".SAFE"));
}

fn incidence_at(p: usize) -> f64 {
    incidence(p as f64)
}

#[test]
fn products_before_ipf_2_9_remove_their_range_noise() {
    let dir = tempfile::tempdir().unwrap();
    let safe = write_safe(dir.path(), &Synthetic::small(false));
    let product = read(&safe, false);
    assert_calibrated(&product, true, false);
    assert_eq!(product.meta.noise_removed.as_deref(), Some("range LUT (IPF < 2.9)"));
}

/// The geolocation grid places every pixel centre where the grid's (affine) latitude and
/// longitude put it, through GDAL's GCP transformer.
#[test]
fn pixels_are_placed_by_the_geolocation_grid() {
    let dir = tempfile::tempdir().unwrap();
    let product = read(&write_safe(dir.path(), &Synthetic::small(true)), false);
    let points = [(0.5, 0.5), (30.5, 20.5), (63.5, 47.5)];
    let lonlat = product.frame.lonlat(&points).unwrap();
    for ((col, row), (lon, lat)) in points.iter().zip(lonlat) {
        assert!((lon - longitude(col - 0.5)).abs() < 1e-9, "{lon} at column {col}");
        assert!((lat - latitude(row - 0.5)).abs() < 1e-9, "{lat} at row {row}");
    }
}

/// GDAL's SAFE driver opens the product (its layout is ESA's) and reads the same digital
/// numbers. Where the installed GDAL also opens it calibrated (SENTINEL1_CALIB:SIGMA0), the
/// noise-free sigma0 agrees to 1e-5 away from the LUT's last line and pixel (GDAL looks the
/// table up per block and extrapolates past the last knot); GDAL 3.6 opens no GRD product so.
#[test]
fn gdal_reads_the_same_product() {
    let dir = tempfile::tempdir().unwrap();
    let safe = write_safe(dir.path(), &Synthetic::small(true));
    let manifest = safe.join("manifest.safe");
    let uncalibrated = format!("SENTINEL1_CALIB:UNCALIB:{}:IW_VV:AMPLITUDE", manifest.display());
    let dataset = gdal::Dataset::open(&uncalibrated).expect("GDAL's SAFE driver opens the product");
    let band = dataset.rasterband(1).unwrap();
    let values = band
        .read_as::<u16>((0, 0), (SAMPLES, LINES), (SAMPLES, LINES), None)
        .unwrap();
    for l in 0..LINES {
        for p in 0..SAMPLES {
            assert_eq!(values.data()[l * SAMPLES + p], dn(l, p));
        }
    }
    let calibrated = format!("SENTINEL1_CALIB:SIGMA0:{}:IW_VV:INTENSITY", manifest.display());
    match gdal::Dataset::open(&calibrated) {
        Err(e) => eprintln!(
            "GDAL {} opens no calibrated GRD ({e}): cross-check skipped",
            gdal::version::version_info("RELEASE_NAME")
        ),
        Ok(gdal_sigma0) => {
            let ours = read(&safe, true);
            let theirs = gdal_sigma0
                .rasterband(1)
                .unwrap()
                .read_as::<f32>((0, 0), (SAMPLES, LINES), (SAMPLES, LINES), None)
                .unwrap();
            for l in 0..LINES - 1 {
                for p in 4..SAMPLES - 1 {
                    let (a, b) = (ours.image[[l, p]] as f64, theirs.data()[l * SAMPLES + p] as f64);
                    if a.is_finite() {
                        assert!((a - b).abs() <= 1e-5 * a.abs(), "({l}, {p}): ours {a}, GDAL's {b}");
                    }
                }
            }
        }
    }
}

#[test]
fn a_product_without_its_files_or_polarisation_says_which() {
    let dir = tempfile::tempdir().unwrap();
    let safe = write_safe(dir.path(), &Synthetic::small(true));
    let err = open(
        &safe,
        &ReadOptions {
            polarisation: Some("HH".into()),
            ..Default::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("--pol") && err.contains("HH") && err.contains("holds: VV"),
        "{err}"
    );

    std::fs::remove_file(safe.join(format!("annotation/calibration/calibration-{STEM}.xml"))).unwrap();
    let err = open(&safe, &ReadOptions::default()).unwrap_err().to_string();
    assert!(
        err.contains(&format!("lacks annotation/calibration/calibration-{STEM}.xml")),
        "{err}"
    );

    std::fs::write(
        safe.join(format!("annotation/calibration/calibration-{STEM}.xml")),
        "<calibration>",
    )
    .unwrap();
    let err = open(&safe, &ReadOptions::default()).unwrap_err().to_string();
    assert!(err.contains("not well-formed XML"), "{err}");

    std::fs::write(
        safe.join(format!("annotation/calibration/calibration-{STEM}.xml")),
        calibration_xml(&Synthetic::small(true)),
    )
    .unwrap();
    std::fs::remove_file(safe.join(format!("measurement/{STEM}.tiff"))).unwrap();
    let err = open(&safe, &ReadOptions::default()).unwrap_err().to_string();
    assert!(
        err.contains(&format!("lacks its measurement measurement/{STEM}.tiff")),
        "{err}"
    );
}

/// A dual-polarisation product (VV and VH): the co-polarised source offers its VH band on the
/// same grid, calibrated by VH's own files, every pixel as the closed form of VH's numbers; a
/// product of VV alone offers none.
#[test]
fn a_dual_polarisation_product_offers_its_cross_polarised_band() {
    let dir = tempfile::tempdir().unwrap();
    let vv = Synthetic::small(true);
    let safe = write_safe(dir.path(), &vv);
    let options = ReadOptions::default();
    let single = match wakelab_products::open_source(&safe, &options, &mut |_, _| {}).unwrap() {
        wakelab_products::Source::Rows(rows) => rows,
        _ => panic!("a Sentinel-1 product reads by rows"),
    };
    assert!(single.cross_polarised(&options).unwrap().is_none());
    let vh_dn = |l: usize, p: usize| dn(l, p) / 4;
    let vh = Synthetic {
        dn: &vh_dn,
        ..Synthetic::small(true)
    };
    add_polarisation(&safe, &vh, "VH");
    let co = match wakelab_products::open_source(&safe, &options, &mut |_, _| {}).unwrap() {
        wakelab_products::Source::Rows(rows) => rows,
        _ => panic!("a Sentinel-1 product reads by rows"),
    };
    assert_eq!(co.meta.polarisation.as_deref(), Some("VV"));
    assert_eq!(co.meta.polarisations, ["VH", "VV"]);
    let cross = co.cross_polarised(&options).unwrap().expect("its VH band");
    assert_eq!(cross.meta.polarisation.as_deref(), Some("VH"));
    assert_eq!(cross.dim(), co.dim());
    let (image, _) = cross.rows(0, LINES).unwrap();
    for l in 0..LINES {
        for p in 0..SAMPLES {
            let got = image[[l, p]];
            match expected_sigma0(&vh, l, p, true) {
                None => assert!(got.is_nan(), "({l}, {p})"),
                Some(want) => assert!(
                    ((got as f64) - want).abs() <= 1e-6 * want,
                    "({l}, {p}): {got} against {want}"
                ),
            }
        }
    }
}

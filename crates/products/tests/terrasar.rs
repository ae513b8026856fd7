//! TerraSAR-X MGD products calibrated as DLR defines it (TSXX-ITD-TN-0049): a product in the
//! mission's layout written by the test (main XML, IMAGEDATA GeoTIFF of digital numbers), which
//! GDAL's TSX driver also opens, reads back as (ks DN^2 - NEBN) sin(theta) at every pixel.

use gdal::raster::Buffer;
use gdal::DriverManager;
use std::path::{Path, PathBuf};
use wakelab_products::{open, ReadOptions};

const NAME: &str = "TSX1_SAR__MGD_SE___SM_S_SRA_20100101T000000_20100101T000002";
const ROWS: usize = 20;
const COLS: usize = 31;
const CAL_FACTOR: f64 = 1e-5;
const FIRST_TAU: f64 = 3.6e-3;
const LAST_TAU: f64 = 3.600174e-3;
const TAU_REF: f64 = 3.600087e-3;
const NOISE: [f64; 3] = [100.0, 1.0e4, 1.0e10];

fn dn(r: usize, c: usize) -> u16 {
    if c == 0 && r < 3 {
        return 0; // a no-data corner
    }
    if (r, c) == (5, 1) {
        return 3; // below the noise there
    }
    (300 + (r * 37 + c * 11) % 400) as u16
}

/// Incidence across the columns: 34.9 degrees at the first, 35.1 at the last (the corners),
/// 35.0 at the centre column.
fn theta(c: usize) -> f64 {
    34.9 + 0.2 * c as f64 / (COLS - 1) as f64
}

fn tau(c: usize) -> f64 {
    FIRST_TAU + (LAST_TAU - FIRST_TAU) * c as f64 / (COLS - 1) as f64
}

/// NEBN / ks at column c: the noise polynomial in tau - tau_ref.
fn noise(c: usize) -> f64 {
    let x = tau(c) - TAU_REF;
    NOISE[0] + NOISE[1] * x + NOISE[2] * x * x
}

fn write_product(dir: &Path, variant: &str, with_calibration: bool) -> PathBuf {
    let name = NAME.replace("MGD", variant);
    let root = dir.join(&name);
    std::fs::create_dir_all(root.join("IMAGEDATA")).unwrap();
    let corner = |name: &str, row: usize, col: usize, lat: f64, lon: f64| {
        format!(
            "<sceneCornerCoord name=\"{name}\"><refRow>{row}</refRow><refColumn>{col}</refColumn><lat>{lat}</lat><lon>{lon}</lon><rangeTime>{}</rangeTime><incidenceAngle>{}</incidenceAngle></sceneCornerCoord>",
            tau(col - 1),
            theta(col - 1)
        )
    };
    let calibration = if with_calibration {
        format!("<calibration><calibrationConstant layerIndex=\"1\"><polLayer>HH</polLayer><DRAoffset>SRA</DRAoffset><calFactor>{CAL_FACTOR:e}</calFactor></calibrationConstant></calibration>")
    } else {
        String::new()
    };
    let xml = format!(
        "<level1Product>
  <productComponents>
    <imageData layerIndex=\"1\"><polLayer>HH</polLayer><file><location><host>.</host><path>IMAGEDATA</path><filename>IMAGE_HH_SRA_strip_005.tif</filename></location></file></imageData>
  </productComponents>
  <productInfo>
    <missionInfo><mission>TSX-1</mission><absOrbit>12345</absOrbit><orbitDirection>ASCENDING</orbitDirection></missionInfo>
    <acquisitionInfo><imagingMode>SM</imagingMode><lookDirection>RIGHT</lookDirection></acquisitionInfo>
    <productVariantInfo><productVariant>{variant}</productVariant></productVariantInfo>
    <imageDataInfo><imageDataType>DETECTED</imageDataType>
      <imageRaster><numberOfRows>{ROWS}</numberOfRows><numberOfColumns>{COLS}</numberOfColumns><rowSpacing units=\"m\">2.75</rowSpacing><columnSpacing units=\"m\">2.75</columnSpacing><azimuthLooks>1.0</azimuthLooks><rangeLooks>1.0</rangeLooks></imageRaster>
    </imageDataInfo>
    <sceneInfo>
      <start><timeUTC>2010-01-01T00:00:00.000000Z</timeUTC></start>
      <stop><timeUTC>2010-01-01T00:00:02.000000Z</timeUTC></stop>
      <rangeTime><firstPixel>{FIRST_TAU:e}</firstPixel><lastPixel>{LAST_TAU:e}</lastPixel></rangeTime>
      <sceneCenterCoord><refRow>10</refRow><refColumn>16</refColumn><lat>45.0</lat><lon>10.0</lon><rangeTime>{}</rangeTime><incidenceAngle>{}</incidenceAngle></sceneCenterCoord>
      {}{}{}{}
    </sceneInfo>
  </productInfo>
  {calibration}
  <noise layerIndex=\"1\"><polLayer>HH</polLayer><numberOfNoiseRecords>1</numberOfNoiseRecords>
    <imageNoise><timeUTC>2010-01-01T00:00:01.000000Z</timeUTC><noiseEstimate><validityRangeMin>{FIRST_TAU:e}</validityRangeMin><validityRangeMax>{LAST_TAU:e}</validityRangeMax><referencePoint>{TAU_REF:e}</referencePoint><polynomialDegree>2</polynomialDegree><coefficient exponent=\"0\">{:e}</coefficient><coefficient exponent=\"1\">{:e}</coefficient><coefficient exponent=\"2\">{:e}</coefficient></noiseEstimate></imageNoise>
  </noise>
</level1Product>
",
        tau(15),
        theta(15),
        corner("UPPER_LEFT", 1, 1, 45.001, 9.999),
        corner("UPPER_RIGHT", 1, COLS, 45.001, 10.001),
        corner("LOWER_LEFT", ROWS, 1, 44.999, 9.999),
        corner("LOWER_RIGHT", ROWS, COLS, 44.999, 10.001),
        NOISE[0],
        NOISE[1],
        NOISE[2],
    );
    std::fs::write(root.join(format!("{name}.xml")), xml).unwrap();
    let tif = root.join("IMAGEDATA/IMAGE_HH_SRA_strip_005.tif");
    let ds = DriverManager::get_driver_by_name("GTiff")
        .unwrap()
        .create_with_band_type::<u16, _>(&tif, COLS, ROWS, 1)
        .unwrap();
    let data: Vec<u16> = (0..ROWS).flat_map(|r| (0..COLS).map(move |c| dn(r, c))).collect();
    ds.rasterband(1)
        .unwrap()
        .write((0, 0), (COLS, ROWS), &mut Buffer::new((COLS, ROWS), data))
        .unwrap();
    root
}

#[test]
fn sigma0_is_ks_dn_squared_less_the_noise_times_sin_theta() {
    let dir = tempfile::tempdir().unwrap();
    let root = write_product(dir.path(), "MGD", true);
    // GDAL's TSX driver recognises the layout
    let gdal_view = gdal::Dataset::open(&root).expect("GDAL's TSX driver opens the product");
    assert_eq!(gdal_view.driver().short_name(), "TSX");

    let product = open(&root, &ReadOptions::default()).unwrap();
    assert_eq!(product.image.dim(), (ROWS, COLS));
    for r in 0..ROWS {
        for c in 0..COLS {
            let d = dn(r, c) as f64;
            let got = product.image[[r, c]] as f64;
            if d == 0.0 {
                assert!(got.is_nan(), "({r}, {c})");
                continue;
            }
            let sin = theta(c).to_radians().sin();
            let want = (CAL_FACTOR * d * d - CAL_FACTOR * noise(c)) * sin;
            let want = if want > 0.0 { want } else { CAL_FACTOR * noise(c) * sin };
            assert!((got - want).abs() <= 1e-6 * want, "({r}, {c}): {got} against {want}");
        }
    }
    assert_eq!((product.report.masked, product.report.floored), (3, 1));
    // DN 500 at the first column, worked out apart (plain arithmetic): 1.429792542284957
    let first = (CAL_FACTOR * 500.0 * 500.0 - CAL_FACTOR * noise(0)) * theta(0).to_radians().sin();
    assert!((first - 1.429_792_542_284_957).abs() < 1e-12, "{first}");
    let meta = &product.meta;
    assert_eq!(meta.polarisation.as_deref(), Some("HH"));
    assert_eq!(meta.pixel_spacing.map(|s| (s.rows, s.columns)), Some((2.75, 2.75)));
    assert_eq!(meta.orbit_direction.as_deref(), Some("ASCENDING"));
    // the scene's centre placed where its coordinates say (its pixel's centre)
    let centre = product.frame.lonlat(&[(15.5, 9.5)]).unwrap()[0];
    assert!(
        (centre.0 - 10.0).abs() < 1e-4 && (centre.1 - 45.0).abs() < 1e-4,
        "{centre:?}"
    );

    // --keep-noise: ks DN^2 sin(theta)
    let kept = open(
        &root,
        &ReadOptions {
            keep_noise: true,
            ..Default::default()
        },
    )
    .unwrap();
    let want = CAL_FACTOR * (dn(7, 9) as f64).powi(2) * theta(9).to_radians().sin();
    assert!(((kept.image[[7, 9]] as f64) - want).abs() <= 1e-6 * want);
}

#[test]
fn products_it_cannot_calibrate_say_why() {
    let dir = tempfile::tempdir().unwrap();
    let ssc = write_product(dir.path(), "SSC", true);
    let err = open(&ssc, &ReadOptions::default()).unwrap_err().to_string();
    assert!(err.contains("a SSC product") && err.contains("MGD"), "{err}");
    let uncalibrated = write_product(&dir.path().join("u"), "MGD", false);
    let err = open(&uncalibrated, &ReadOptions::default()).unwrap_err().to_string();
    assert!(err.contains("no calFactor for HH"), "{err}");
    let err = open(
        &write_product(&dir.path().join("p"), "MGD", true),
        &ReadOptions {
            polarisation: Some("VV".into()),
            ..Default::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("holds: HH"), "{err}");
}

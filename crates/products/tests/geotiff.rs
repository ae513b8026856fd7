//! GeoTIFFs as users have them: any CRS (a UTM image's pixels placed as GDAL's own coordinate
//! transformation places them), a scale stated by the band's unit or refused when it is wrong,
//! the nodata value and the mask band honoured, and wrong files named for what is wrong. The
//! COGs wakelab writes pass GDAL's COG validation.

use gdal::raster::Buffer;
use gdal::spatial_ref::{AxisMappingStrategy, CoordTransform, SpatialRef};
use gdal::{DriverManager, Metadata};
use ndarray::Array2;
use std::path::{Path, PathBuf};
use wakelab_products::cog::{write_cog, BandInfo};
use wakelab_products::geojson::{feature_collection, Finding, Kind};
use wakelab_products::{open, InputScale, ReadOptions};

const ROWS: usize = 40;
const COLS: usize = 50;
/// UTM zone 32N (EPSG:32632), 10 m pixels from (500,000 E, 6,000,000 N).
const TRANSFORM: [f64; 6] = [500_000.0, 10.0, 0.0, 6_000_000.0, 0.0, -10.0];

/// A sea-like sigma0 field (linear, around -20 dB).
fn sea(r: usize, c: usize) -> f32 {
    0.01 * (1.0 + 0.5 * (((r * 31 + c * 17) % 23) as f32 / 23.0))
}

/// Write one band at `path` with GDAL's GTiff driver in UTM 32N.
fn write_tiff(path: &Path, values: &[f32], unit: Option<&str>, nodata: Option<f64>) {
    let driver = DriverManager::get_driver_by_name("GTiff").unwrap();
    let mut ds = driver.create_with_band_type::<f32, _>(path, COLS, ROWS, 1).unwrap();
    ds.set_geo_transform(&TRANSFORM).unwrap();
    ds.set_spatial_ref(&SpatialRef::from_epsg(32632).unwrap()).unwrap();
    let mut band = ds.rasterband(1).unwrap();
    band.write((0, 0), (COLS, ROWS), &mut Buffer::new((COLS, ROWS), values.to_vec()))
        .unwrap();
    band.set_no_data_value(nodata).unwrap();
    if let Some(u) = unit {
        let u = std::ffi::CString::new(u).unwrap();
        unsafe { gdal_sys::GDALSetRasterUnitType(band.c_rasterband(), u.as_ptr()) };
    }
}

fn linear() -> Vec<f32> {
    (0..ROWS).flat_map(|r| (0..COLS).map(move |c| sea(r, c))).collect()
}

fn db() -> Vec<f32> {
    linear().iter().map(|v| 10.0 * v.log10()).collect()
}

fn temp(dir: &tempfile::TempDir, name: &str) -> PathBuf {
    dir.path().join(name)
}

/// GDAL's own coordinate transformation of a pixel centre's model coordinates (the geotransform
/// applied by hand, then UTM 32N to WGS 84 by OGR).
fn gdal_lonlat(col: f64, row: f64) -> (f64, f64) {
    let x = TRANSFORM[0] + col * TRANSFORM[1];
    let y = TRANSFORM[3] + row * TRANSFORM[5];
    let utm = SpatialRef::from_epsg(32632).unwrap();
    let mut wgs = SpatialRef::from_epsg(4326).unwrap();
    wgs.set_axis_mapping_strategy(AxisMappingStrategy::TraditionalGisOrder);
    let t = CoordTransform::new(&utm, &wgs).unwrap();
    let (mut xs, mut ys, mut zs) = ([x], [y], [0.0]);
    t.transform_coords(&mut xs, &mut ys, &mut zs).unwrap();
    (xs[0], ys[0])
}

#[test]
fn a_utm_geotiff_places_findings_where_gdal_does() {
    let dir = tempfile::tempdir().unwrap();
    let path = temp(&dir, "utm.tif");
    write_tiff(&path, &linear(), None, None);
    let product = open(&path, &ReadOptions::default()).unwrap();
    assert_eq!(product.image[[3, 7]], sea(3, 7));
    let spacing = product.meta.pixel_spacing.unwrap();
    // 10 m of UTM grid 250 m from the central meridian (9 E) is 10 / k0 = 10 / 0.9996 m of
    // ground (the scale factor grows by x^2 / 2R^2, 8e-10, over those 250 m)
    let ground = 10.0 / 0.9996;
    assert!(
        (spacing.rows - ground).abs() < 1e-3 && (spacing.columns - ground).abs() < 1e-3,
        "{spacing:?}"
    );
    let findings: Vec<Finding> = [(12.5, 20.5), (0.5, 0.5), (39.5, 49.5)]
        .iter()
        .map(|&(row, col)| Finding {
            kind: Kind::Window,
            row,
            col,
            properties: Default::default(),
            line: None,
        })
        .collect();
    let collection = feature_collection(&product.frame, &findings, &Default::default());
    // a wake's line: a LineString through its vertices, each where GDAL places it
    let wake = Finding {
        kind: Kind::Wake,
        row: 5.5,
        col: 6.5,
        properties: Default::default(),
        line: Some(vec![(5.5, 6.5), (30.5, 40.5)]),
    };
    let lines = feature_collection(&product.frame, std::slice::from_ref(&wake), &Default::default());
    let geometry = &lines["features"][0]["geometry"];
    assert_eq!(geometry["type"], "LineString");
    for (vertex, &(row, col)) in geometry["coordinates"]
        .as_array()
        .unwrap()
        .iter()
        .zip(wake.line.as_ref().unwrap())
    {
        let (lon, lat) = (vertex[0].as_f64().unwrap(), vertex[1].as_f64().unwrap());
        let (want_lon, want_lat) = gdal_lonlat(col, row);
        assert!(
            (lon - want_lon).abs() < 1e-7 && (lat - want_lat).abs() < 1e-7,
            "{vertex:?}"
        );
    }
    for (f, feature) in findings.iter().zip(collection["features"].as_array().unwrap()) {
        let xy = feature["geometry"]["coordinates"].as_array().unwrap();
        let (lon, lat) = (xy[0].as_f64().unwrap(), xy[1].as_f64().unwrap());
        let (want_lon, want_lat) = gdal_lonlat(f.col, f.row);
        // GeoJSON's 7 decimals: 1e-7 degrees
        assert!(
            (lon - want_lon).abs() < 1e-7 && (lat - want_lat).abs() < 1e-7,
            "{lon} {lat}"
        );
        assert_eq!(feature["properties"]["kind"], "window");
    }
}

/// An image with one stated incidence angle (wakelab's scene COGs) reads with it; an angle
/// outside 0-90 degrees is not taken.
/// Write [`linear`] at `path` with the geotransform `transform` and no CRS.
fn write_without_crs(path: &Path, transform: [f64; 6]) {
    let driver = DriverManager::get_driver_by_name("GTiff").unwrap();
    let mut ds = driver.create_with_band_type::<f32, _>(path, COLS, ROWS, 1).unwrap();
    ds.set_geo_transform(&transform).unwrap();
    let mut band = ds.rasterband(1).unwrap();
    band.write((0, 0), (COLS, ROWS), &mut Buffer::new((COLS, ROWS), linear()))
        .unwrap();
}

/// A geotransform with no CRS (a Sentinel-1 measurement TIFF cut out of its product holds one
/// that counts pixels from 4000): not placed on the Earth, where GDAL alone would read its
/// coordinates as degrees and its pixels as 111 km; its spacing is the user's. One whose
/// coordinates are longitudes and latitudes with pixels of 1/11132 degree (a float GeoTIFF off
/// Mumbai that lost its EPSG:4326) is taken as WGS 84: 10 m pixels (the published length of a
/// degree at 19.3 N by NGA's series: 110,696 m of latitude, 105,102 m of longitude), a note says so.
#[test]
fn a_geotransform_without_a_crs_is_no_place_on_the_earth() {
    let dir = tempfile::tempdir().unwrap();
    let path = temp(&dir, "no_crs.tif");
    write_without_crs(&path, [4000.0, 1.0, 0.0, 4000.0, 0.0, 1.0]);
    let product = open(&path, &ReadOptions::default()).unwrap();
    assert!(!product.frame.is_georeferenced());
    assert_eq!(product.frame.lonlat(&[(0.0, 0.0)]), None);
    assert!(product.meta.pixel_spacing.is_none(), "{:?}", product.meta.pixel_spacing);
    assert!(
        product.report.notes.iter().any(|n| n.contains("no CRS")),
        "{:?}",
        product.report.notes
    );
    let given = ReadOptions {
        pixel_spacing: Some(10.0),
        ..ReadOptions::default()
    };
    let spacing = open(&path, &given).unwrap().meta.pixel_spacing.unwrap();
    assert_eq!((spacing.rows, spacing.columns), (10.0, 10.0));
    // the same grid in UTM 32N is on the Earth
    let placed = temp(&dir, "utm.tif");
    write_tiff(&placed, &linear(), Some("linear"), None);
    assert!(open(&placed, &ReadOptions::default()).unwrap().frame.is_georeferenced());
    // degrees that lost their CRS
    let step = 1.0 / 11_132.0;
    let mumbai = temp(&dir, "mumbai.tif");
    write_without_crs(&mumbai, [72.19, step, 0.0, 19.3, 0.0, -step]);
    let product = open(&mumbai, &ReadOptions::default()).unwrap();
    let corner = product.frame.lonlat(&[(0.0, 0.0)]).expect("placed as WGS 84")[0];
    assert!(
        (corner.0 - 72.19).abs() < 1e-9 && (corner.1 - 19.3).abs() < 1e-9,
        "{corner:?}"
    );
    let spacing = product.meta.pixel_spacing.unwrap();
    let (columns, rows) = (105_102.0 * step, 110_696.0 * step);
    assert!(
        (spacing.columns - columns).abs() < 0.01 && (spacing.rows - rows).abs() < 0.01,
        "{spacing:?} against {columns} x {rows}"
    );
    assert!(
        product.report.notes.iter().any(|n| n.contains("taken as WGS 84")),
        "{:?}",
        product.report.notes
    );
}

/// Ground control points in no CRS (GDAL's GCP projection empty; the gdal crate cannot write
/// such GCPs, GDAL's C API can): the image is read, placed nowhere, with a note, and its
/// findings can be written (before, writing the probability map failed on the GCPs after the
/// whole scan).
#[test]
fn ground_control_points_without_a_crs_place_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let path = temp(&dir, "gcps_no_crs.tif");
    {
        let driver = DriverManager::get_driver_by_name("GTiff").unwrap();
        let ds = driver.create_with_band_type::<f32, _>(&path, COLS, ROWS, 1).unwrap();
        let mut band = ds.rasterband(1).unwrap();
        band.write((0, 0), (COLS, ROWS), &mut Buffer::new((COLS, ROWS), linear()))
            .unwrap();
        let (id, info) = (
            std::ffi::CString::new("1").unwrap(),
            std::ffi::CString::new("").unwrap(),
        );
        let corners = [
            (0.0, 0.0),
            (COLS as f64, 0.0),
            (0.0, ROWS as f64),
            (COLS as f64, ROWS as f64),
        ];
        let gcps: Vec<gdal_sys::GDAL_GCP> = corners
            .iter()
            .map(|&(pixel, line)| gdal_sys::GDAL_GCP {
                pszId: id.as_ptr() as *mut _,
                pszInfo: info.as_ptr() as *mut _,
                dfGCPPixel: pixel,
                dfGCPLine: line,
                dfGCPX: 4000.0 + pixel,
                dfGCPY: 4000.0 + line,
                dfGCPZ: 0.0,
            })
            .collect();
        let none = std::ffi::CString::new("").unwrap();
        // SAFETY: the dataset is open for writing; the GCP array and its strings outlive the call,
        // which copies them
        let err = unsafe { gdal_sys::GDALSetGCPs(ds.c_dataset(), gcps.len() as i32, gcps.as_ptr(), none.as_ptr()) };
        assert_eq!(err, gdal_sys::CPLErr::CE_None);
    }
    assert_eq!(
        gdal::Dataset::open(&path).unwrap().gcps().len(),
        4,
        "GDAL kept the GCPs"
    );
    let product = open(&path, &ReadOptions::default()).unwrap();
    assert!(!product.frame.is_georeferenced());
    assert_eq!(product.frame.lonlat(&[(0.0, 0.0)]), None);
    assert!(
        product
            .report
            .notes
            .iter()
            .any(|n| n.contains("4 ground control points have no CRS")),
        "{:?}",
        product.report.notes
    );
    let out = temp(&dir, "out.tif");
    write_cog(
        &out,
        &product.image,
        &product.frame,
        &BandInfo {
            description: "sigma0",
            unit: "linear",
            metadata: vec![],
        },
    )
    .expect("a frame placed nowhere is written");
}

#[test]
fn a_stated_incidence_angle_is_read() {
    let dir = tempfile::tempdir().unwrap();
    for (stated, read) in [("32.5", Some(32.5)), ("95", None)] {
        let path = temp(&dir, &format!("incidence_{stated}.tif"));
        write_tiff(&path, &linear(), Some("linear"), None);
        let mut ds = gdal::Dataset::open_ex(
            &path,
            gdal::DatasetOptions {
                open_flags: gdal::GdalOpenFlags::GDAL_OF_UPDATE,
                ..Default::default()
            },
        )
        .unwrap();
        ds.set_metadata_item(wakelab_products::cog::INCIDENCE, stated, "")
            .unwrap();
        drop(ds);
        let product = open(&path, &ReadOptions::default()).unwrap();
        let incidence = product.meta.incidence.as_ref();
        assert_eq!(incidence.map(|i| i.mid_deg), read);
        assert_eq!(incidence.map(|i| i.at(10.0, 20.0)), read);
    }
}

#[test]
fn the_band_unit_states_the_scale_and_a_wrong_scale_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let stated = temp(&dir, "db_stated.tif");
    write_tiff(&stated, &db(), Some("dB"), None);
    let product = open(&stated, &ReadOptions::default()).unwrap();
    assert_eq!(product.meta.scale, Some(InputScale::Db));
    assert!((product.image[[5, 5]] - sea(5, 5)).abs() < 1e-8);
    // --scale linear against the file's "dB"
    let err = open(
        &stated,
        &ReadOptions {
            scale: Some(InputScale::Linear),
            ..Default::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("band unit says db"), "{err}");

    // the same dB values with no unit, read as the default linear: refused, with the count
    let bare = temp(&dir, "db_bare.tif");
    write_tiff(&bare, &db(), None, None);
    let err = open(&bare, &ReadOptions::default()).unwrap_err().to_string();
    assert!(
        err.contains(&format!("{n} of {n} valid pixels are negative", n = ROWS * COLS)),
        "{err}"
    );
    assert!(err.contains("--scale db"), "{err}");
    let told = open(
        &bare,
        &ReadOptions {
            scale: Some(InputScale::Db),
            ..Default::default()
        },
    )
    .unwrap();
    assert!((told.image[[5, 5]] - sea(5, 5)).abs() < 1e-8);
}

#[test]
fn nodata_values_mask_bands_and_border_zeros_are_masked() {
    let dir = tempfile::tempdir().unwrap();
    let mut values = linear();
    // the left third zero (a GRD's no-data border), one pixel at the nodata value -999
    for r in 0..ROWS {
        for c in 0..COLS / 3 {
            values[r * COLS + c] = 0.0;
        }
    }
    values[20 * COLS + 40] = -999.0;
    let path = temp(&dir, "nodata.tif");
    write_tiff(&path, &values, None, Some(-999.0));
    let product = open(&path, &ReadOptions::default()).unwrap();
    assert!(product.image[[10, 0]].is_nan() && product.image[[20, 40]].is_nan());
    assert_eq!(product.report.masked, ROWS * (COLS / 3) + 1);
    assert_eq!(product.report.floored, 0);

    // an internal mask band (GDAL's per-dataset mask) masks its zeros
    let masked = temp(&dir, "mask_band.tif");
    write_tiff(&masked, &linear(), None, None);
    {
        let ds = gdal::Dataset::open_ex(
            &masked,
            gdal::DatasetOptions {
                open_flags: gdal::GdalOpenFlags::GDAL_OF_UPDATE,
                ..Default::default()
            },
        )
        .unwrap();
        let mut band = ds.rasterband(1).unwrap();
        band.create_mask_band(true).unwrap();
        let mut mask = band.open_mask_band().unwrap();
        let m: Vec<u8> = (0..ROWS * COLS).map(|k| if k % COLS < 5 { 0 } else { 255 }).collect();
        mask.write((0, 0), (COLS, ROWS), &mut Buffer::new((COLS, ROWS), m))
            .unwrap();
    }
    let product = open(&masked, &ReadOptions::default()).unwrap();
    assert_eq!(product.report.masked, ROWS * 5);
    assert!(product.image[[0, 4]].is_nan() && !product.image[[0, 5]].is_nan());

    // --exclude: a raster of the input's size
    let land = temp(&dir, "land.tif");
    let excluded: Vec<f32> = (0..ROWS * COLS).map(|k| (k / COLS >= 30) as u8 as f32).collect();
    write_tiff(&land, &excluded, None, None);
    let product = open(
        &temp(&dir, "mask_band.tif"),
        &ReadOptions {
            exclude: Some(land),
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(product.report.masked, ROWS * 5 + 10 * (COLS - 5));
}

/// An 8 x 8 GeoTIFF of one byte band per `offsets` entry, each the ramp 0..64 plus its offset.
fn write_bands(path: &Path, offsets: &[u8]) {
    let ds = DriverManager::get_driver_by_name("GTiff")
        .unwrap()
        .create_with_band_type::<u8, _>(path, 8, 8, offsets.len())
        .unwrap();
    for (k, offset) in offsets.iter().enumerate() {
        let data: Vec<u8> = (0..64).map(|v| offset + v as u8).collect();
        ds.rasterband(k + 1)
            .unwrap()
            .write((0, 0), (8, 8), &mut Buffer::new((8, 8), data))
            .unwrap();
    }
}

#[test]
fn wrong_files_say_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    let text = temp(&dir, "notes.tif");
    std::fs::write(&text, "not a tiff at all").unwrap();
    let err = open(&text, &ReadOptions::default()).unwrap_err().to_string();
    assert!(err.contains("not an image GDAL reads"), "{err}");

    // a colour picture: which band would be the radar's?
    let rgb = temp(&dir, "rgb.tif");
    write_bands(&rgb, &[60, 60, 61]);
    let err = open(&rgb, &ReadOptions::default()).unwrap_err().to_string();
    assert!(
        err.contains("has 3 bands that differ") && err.contains("gdal_translate -b N"),
        "{err}"
    );
    // a grey picture saved as colour (three equal bands, as HRSID's chips and grey JPEGs are)
    // is that picture, read as one band
    let grey_rgb = temp(&dir, "grey_rgb.tif");
    write_bands(&grey_rgb, &[60, 60, 60]);
    let display = ReadOptions {
        scale: Some(InputScale::Display),
        ..Default::default()
    };
    let read = open(&grey_rgb, &display).unwrap();
    assert!(
        read.report.notes.iter().any(|n| n.contains("3 bands of equal values")),
        "{:?}",
        read.report.notes
    );
    // the same picture saved as one band reads to the same values
    let one_band = temp(&dir, "one_band.tif");
    write_bands(&one_band, &[60]);
    let alone = open(&one_band, &display).unwrap();
    assert_eq!(read.image, alone.image);
    // the bands are compared a block of rows at a time: a difference in the last of 600 rows,
    // past the first block, is still seen
    let tall = temp(&dir, "tall.tif");
    {
        let ds = DriverManager::get_driver_by_name("GTiff")
            .unwrap()
            .create_with_band_type::<u8, _>(&tall, 2, 600, 3)
            .unwrap();
        for k in 1..=3 {
            let mut data = vec![80u8; 1200];
            if k == 3 {
                data[1199] = 81;
            }
            ds.rasterband(k)
                .unwrap()
                .write((0, 0), (2, 600), &mut Buffer::new((2, 600), data))
                .unwrap();
        }
    }
    let err = open(&tall, &display).unwrap_err().to_string();
    assert!(err.contains("has 3 bands that differ"), "{err}");

    // an 8-bit display stretch needs --scale display
    let grey = temp(&dir, "grey.tif");
    {
        let ds = DriverManager::get_driver_by_name("GTiff")
            .unwrap()
            .create_with_band_type::<u8, _>(&grey, 8, 8, 1)
            .unwrap();
        let data: Vec<u8> = (0..64).map(|k| 60 + k as u8).collect();
        ds.rasterband(1)
            .unwrap()
            .write((0, 0), (8, 8), &mut Buffer::new((8, 8), data))
            .unwrap();
    }
    let err = open(&grey, &ReadOptions::default()).unwrap_err().to_string();
    assert!(err.contains("--scale display"), "{err}");
    let shown = open(
        &grey,
        &ReadOptions {
            scale: Some(InputScale::Display),
            ..Default::default()
        },
    )
    .unwrap();
    assert!(!shown.meta.calibrated);
    assert!(shown.report.notes.iter().any(|n| n.contains("uncalibrated")));
}

#[test]
fn written_cogs_pass_gdals_validation_and_keep_their_place() {
    let dir = tempfile::tempdir().unwrap();
    let path = temp(&dir, "utm.tif");
    write_tiff(&path, &linear(), None, None);
    let product = open(&path, &ReadOptions::default()).unwrap();
    let mut values = Array2::from_shape_fn((600, 700), |(r, c)| ((r + c) % 7) as f32 / 7.0);
    values[[0, 0]] = f32::NAN;
    let frame = product.frame.scaled(40.0 / 600.0, 50.0 / 700.0, (600, 700));
    let out = temp(&dir, "map.tif");
    write_cog(
        &out,
        &values,
        &frame,
        &BandInfo {
            description: "wake probability",
            unit: "1",
            metadata: vec![("WAKELAB_MODEL".into(), "m.safetensors".into())],
        },
    )
    .unwrap();
    let check = std::process::Command::new("/usr/bin/python3")
        .args(["-m", "osgeo_utils.samples.validate_cloud_optimized_geotiff"])
        .arg(&out)
        .output()
        .expect("python3-gdal's COG validator (apt-get install python3-gdal)");
    let said = String::from_utf8_lossy(&check.stdout).to_string() + &String::from_utf8_lossy(&check.stderr);
    assert!(
        check.status.success() && said.contains("is a valid cloud optimized GeoTIFF"),
        "{said}"
    );
    let back = gdal::Dataset::open(&out).unwrap();
    let want = [
        500_000.0,
        10.0 * 50.0 / 700.0,
        0.0,
        6_000_000.0,
        0.0,
        -10.0 * 40.0 / 600.0,
    ];
    for (got, want) in back.geo_transform().unwrap().iter().zip(want) {
        assert!((got - want).abs() < 1e-9, "{got} against {want}");
    }
    let band = back.rasterband(1).unwrap();
    assert!(band.no_data_value().unwrap().is_nan());
    assert_eq!(band.description().unwrap(), "wake probability");
    assert_eq!(band.unit(), "1");
    assert_eq!(
        back.metadata_item("WAKELAB_MODEL", "").as_deref(),
        Some("m.safetensors")
    );
    assert!(band.overview_count().unwrap() >= 1, "no overviews");
    assert!(!std::fs::read_dir(dir.path()).unwrap().any(|e| e
        .unwrap()
        .file_name()
        .to_string_lossy()
        .ends_with(".tmp")));
}

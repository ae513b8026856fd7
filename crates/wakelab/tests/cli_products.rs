//! `wakelab detect` and `wakelab calibrate` on the products users have: a Sentinel-1 SAFE
//! product, GeoTIFFs in UTM (linear, dB, at another pixel spacing), an array with a no-data
//! border. The same sea scores the same whatever its file's scale or spacing; findings come back
//! where GDAL places their pixels; no-data is never scored.

mod common;

use common::*;
use gdal::spatial_ref::{AxisMappingStrategy, CoordTransform, SpatialRef};
use ndarray::Array2;
use std::path::{Path, PathBuf};
use wakelab_products::cog::{write_cog, BandInfo};
use wakelab_products::frame::{Frame, Placement};
use wakelab_products::sentinel1::synthetic::{
    add_polarisation, expected_sigma0, latitude, longitude, write_safe, Synthetic,
};

const SIDE: usize = 160;
/// UTM zone 33N, 10 m pixels.
const TRANSFORM: [f64; 6] = [400_000.0, 10.0, 0.0, 6_100_000.0, 0.0, -10.0];

/// Fully developed 1-look speckle over a mean sigma0 of 0.01 (-20 dB): exponential, from a
/// fixed-seed generator.
fn sea() -> Array2<f32> {
    sea_of(SIDE)
}

/// [`sea`] of `rows` rows.
fn sea_of(rows: usize) -> Array2<f32> {
    let mut x = 0x9E37_79B9_7F4A_7C15u64;
    Array2::from_shape_fn((rows, SIDE), |_| {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        let u = (x >> 11) as f64 / (1u64 << 53) as f64;
        (-(1.0 - u).ln() * 0.01).max(1e-6) as f32
    })
}

fn utm(transform: [f64; 6], (rows, cols): (usize, usize)) -> Frame {
    Frame {
        rows,
        cols,
        placement: Placement::Transform {
            transform,
            wkt: SpatialRef::from_epsg(32633).unwrap().to_wkt().unwrap(),
        },
    }
}

fn write_tif(path: &Path, values: &Array2<f32>, frame: &Frame, unit: &str) {
    let band = BandInfo {
        description: "sigma0",
        unit,
        metadata: Vec::new(),
    };
    write_cog(path, values, frame, &band).unwrap();
}

/// A C-band detector trained briefly on a small dataset at 10 m.
fn detector(dir: &Path) -> PathBuf {
    detector_at(dir, 10.0)
}

/// A C-band detector trained briefly on a small dataset at `spacing` metres.
fn detector_at(dir: &Path, spacing: f64) -> PathBuf {
    let study = dir.join(format!("study_{spacing}.toml"));
    let axes =
        format!("wind_speed = [5.0, 8.0]\nimage_size = [32]\npixel_spacing = [{spacing:.1}]\nalong_track = [2000.0]");
    std::fs::write(&study, study_text("p", 2, 0.34, "[\"C\"]", &axes)).unwrap();
    let data = dir.join(format!("data_{spacing}"));
    let o = dataset(&study, &data, &["--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let model = dir.join(format!("c_base_{spacing}.safetensors"));
    let o = wakelab(&[
        "train",
        data.to_str().unwrap(),
        "--bands",
        "C",
        "--epochs",
        "1",
        "--model",
        model.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    model
}

/// `detect IMAGE --out DIR --quiet more...`: how it ended.
fn detect_output(image: &Path, out: &Path, more: &[&str]) -> std::process::Output {
    let mut args = vec![
        "detect",
        image.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ];
    args.extend_from_slice(more);
    wakelab(&args)
}

/// `detect IMAGE --model MODEL --out DIR more...`: its detections.json.
fn detect(image: &Path, model: &Path, out: &Path, more: &[&str]) -> serde_json::Value {
    let o = detect_output(image, out, &[&["--model", model.to_str().unwrap()], more].concat());
    assert!(o.status.success(), "{}: {}", image.display(), stderr(&o));
    serde_json::from_str(&std::fs::read_to_string(out.join("detections.json")).unwrap()).unwrap()
}

/// The scan's windows.csv, each row by its header's names (an empty field as NaN).
fn windows_csv(scan: &Path) -> Vec<std::collections::HashMap<String, f64>> {
    let mut csv = csv::Reader::from_path(scan.join("windows.csv")).unwrap();
    let header = csv.headers().unwrap().clone();
    csv.records()
        .map(|r| {
            let r = r.unwrap();
            header
                .iter()
                .zip(r.iter())
                .map(|(k, v)| (k.to_string(), v.parse().unwrap_or(f64::NAN)))
                .collect()
        })
        .collect()
}

fn probability(v: &serde_json::Value) -> f64 {
    v["probability"].as_f64().unwrap()
}

/// GDAL's coordinate transformation of a product pixel position (column, row) on `TRANSFORM`.
fn gdal_lonlat(col: f64, row: f64) -> (f64, f64) {
    let mut wgs = SpatialRef::from_epsg(4326).unwrap();
    wgs.set_axis_mapping_strategy(AxisMappingStrategy::TraditionalGisOrder);
    let t = CoordTransform::new(&SpatialRef::from_epsg(32633).unwrap(), &wgs).unwrap();
    let (mut x, mut y, mut z) = (
        [TRANSFORM[0] + col * TRANSFORM[1]],
        [TRANSFORM[3] + row * TRANSFORM[5]],
        [0.0],
    );
    t.transform_coords(&mut x, &mut y, &mut z).unwrap();
    (x[0], y[0])
}

#[test]
fn real_inputs_score_the_same_sea_alike_and_land_where_gdal_puts_them() {
    let root = tempfile::tempdir().unwrap();
    let dir = root.path();
    let model = detector(dir);
    let sea = sea();

    // linear in UTM: every window a detection at threshold 0, each placed as GDAL places it
    let linear = dir.join("sea.tif");
    write_tif(&linear, &sea, &utm(TRANSFORM, sea.dim()), "1");
    let scan = dir.join("scan_linear");
    let base = detect(&linear, &model, &scan, &["--threshold", "0"]);
    assert_eq!(base["georeferenced"], true);
    let geojson: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(scan.join("detections.geojson")).unwrap()).unwrap();
    let features = geojson["features"].as_array().unwrap();
    assert!(features.len() >= 4, "{} features", features.len());
    for f in features {
        let p = &f["properties"];
        let (want_lon, want_lat) = gdal_lonlat(p["col"].as_f64().unwrap(), p["row"].as_f64().unwrap());
        let xy = f["geometry"]["coordinates"].as_array().unwrap();
        assert!((xy[0].as_f64().unwrap() - want_lon).abs() < 1e-7, "{f}");
        assert!((xy[1].as_f64().unwrap() - want_lat).abs() < 1e-7, "{f}");
        assert_eq!(p["kind"], "window");
        assert!(p["detector"].as_str().unwrap().ends_with("c_base_10.safetensors"));
    }
    // the map: a COG (GDAL's validator says so) in the input's CRS, its cells the stride's
    // multiple of the input's pixels
    assert_valid_cog(&scan.join("probability.tif"));
    let map = gdal::Dataset::open(scan.join("probability.tif")).unwrap();
    let stride = base["stride"].as_f64().unwrap();
    let t = map.geo_transform().unwrap();
    assert_eq!((t[0], t[1], t[5]), (TRANSFORM[0], 10.0 * stride, -10.0 * stride));
    assert_eq!(map.spatial_ref().unwrap().auth_code().unwrap(), 32633);

    // the same sea in dB, the file's unit saying so: the same probability
    let db = dir.join("sea_db.tif");
    write_tif(&db, &sea.mapv(|v| 10.0 * v.log10()), &utm(TRANSFORM, sea.dim()), "dB");
    let in_db = detect(&db, &model, &dir.join("scan_db"), &[]);
    assert!((probability(&in_db) - probability(&base)).abs() < 1e-4, "{in_db}");
    assert_eq!(in_db["product"]["scale"], "db");

    // the same sea at 5 m (each pixel split in four): averaged back to the detector's 10 m
    let fine = sea.view().insert_axis(ndarray::Axis(1)).insert_axis(ndarray::Axis(3));
    let fine = fine
        .broadcast((SIDE, 2, SIDE, 2))
        .unwrap()
        .to_owned()
        .into_shape_with_order((2 * SIDE, 2 * SIDE))
        .unwrap();
    let half = [TRANSFORM[0], 5.0, 0.0, TRANSFORM[3], 0.0, -5.0];
    let five = dir.join("sea_5m.tif");
    write_tif(&five, &fine, &utm(half, fine.dim()), "1");
    let resampled = detect(&five, &model, &dir.join("scan_5m"), &[]);
    let factor: Vec<f64> = serde_json::from_value(resampled["resampled"].clone()).unwrap();
    assert!(factor.iter().all(|f| (f - 2.0).abs() < 1e-3), "{factor:?}");
    assert!(
        (probability(&resampled) - probability(&base)).abs() < 1e-4,
        "{resampled}"
    );
    assert!(resampled["notes"].to_string().contains("area-averaged"));
    // windows.csv: every window, in the product's pixels (the 5 m scan's twice the 10 m
    // scan's). The peak is placed as its window places the wake: by default the window of the
    // strongest line's contrast, with `--peak network` the most probable one; the image's
    // probability and its detections are the same under both rules
    let ten = windows_csv(&scan);
    let five_m = windows_csv(&dir.join("scan_5m"));
    assert_eq!(ten.len() as u64, base["windows"].as_u64().unwrap());
    assert_eq!(five_m.len(), ten.len());
    let largest = |key: &str| {
        let of = |w: &std::collections::HashMap<String, f64>| if w[key].is_nan() { 0.0 } else { w[key].abs() };
        ten.iter().max_by(|a, b| of(a).total_cmp(&of(b))).unwrap().clone()
    };
    let by_network = detect(
        &linear,
        &model,
        &dir.join("scan_network"),
        &["--threshold", "0", "--peak", "network"],
    );
    assert_eq!(probability(&by_network), probability(&base));
    assert_eq!(by_network["detections"], base["detections"]);
    assert_eq!(largest("probability")["probability"], probability(&base));
    for (scanned, key, rule) in [(&base, "line_z", "line"), (&by_network, "probability", "network")] {
        let window = largest(key);
        assert_eq!(scanned["peak"]["rule"], rule);
        for (key, want) in [("place_row", "product_row"), ("place_col", "product_col")] {
            let place = scanned["peak"][want].as_f64().unwrap();
            assert!(
                (window[key] - place).abs() < 1e-9,
                "{rule}: {window:?} {}",
                scanned["peak"]
            );
        }
    }
    for (a, b) in ten.iter().zip(&five_m) {
        assert_eq!(
            (b["window_row"], b["window_col"]),
            (2.0 * a["window_row"], 2.0 * a["window_col"])
        );
        assert!((a["probability"] - b["probability"]).abs() < 1e-4, "{a:?} {b:?}");
    }

    // a no-data border (the left third zero): its windows are not scored, its cells are nodata
    let mut border = sea.clone();
    border.slice_mut(ndarray::s![.., ..SIDE / 3]).fill(0.0);
    let npy = dir.join("border.npy");
    ndarray_npy::write_npy(&npy, &border).unwrap();
    let scan = dir.join("scan_border");
    let masked = detect(&npy, &model, &scan, &["--pixel-spacing", "10"]);
    let windows = masked["windows"].as_u64().unwrap();
    assert!(windows < base["windows"].as_u64().unwrap());
    let map = gdal::Dataset::open(scan.join("probability.tif")).unwrap();
    let cells = map
        .rasterband(1)
        .unwrap()
        .read_as::<f32>((0, 0), (1, 1), (1, 1), None)
        .unwrap();
    assert!(cells.data()[0].is_nan(), "the border's first cell was scored");
    assert!(masked["notes"].to_string().contains("no-data pixel(s) masked"));
    // a bare array without its spacing is taken at the detector's, and says so
    let bare = detect(&npy, &model, &dir.join("scan_bare"), &[]);
    assert!(bare["notes"].to_string().contains("taken at the detector's 10 m"));
}

#[test]
fn a_sentinel1_product_is_calibrated_and_scanned_on_its_ground() {
    let root = tempfile::tempdir().unwrap();
    let dir = root.path();
    // tall enough to be read and scanned in three bands of rows
    let lines = 2500;
    let mut sea = sea_of(lines);
    // a ship, 150 m long and 30 dB over the sea, 1 km into the product: read band by band, its
    // window is cut from the search of the rows held and scored as when the product is read whole
    sea.slice_mut(ndarray::s![1020..1035, 100..103]).fill(10.0);
    // digital numbers whose calibrated sigma0 is the sea: DN = A sqrt(sigma0) (noise kept)
    let luts = Synthetic {
        lines,
        samples: SIDE,
        since_2_9: true,
        dn: &|_, _| 0,
    };
    let dn = |l: usize, p: usize| -> u16 {
        let a = luts.gain(l as f64, p as f64);
        (a * (sea[[l, p]] as f64).sqrt()).round().clamp(1.0, 65535.0) as u16
    };
    let product = Synthetic { dn: &dn, ..luts };
    let safe = write_safe(dir, &product);

    // calibrate: the COG holds (DN^2 - eta) / A^2 on the product's GCPs
    let out = dir.join("sigma0.tif");
    let o = wakelab(&["calibrate", safe.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_valid_cog(&out);
    // written a band of rows at a time through a staging file, which is gone
    let leftovers: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp") || n.contains(".rows."))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
    let cog = gdal::Dataset::open(&out).unwrap();
    assert_eq!(cog.gcps().len(), 12);
    let values = cog
        .rasterband(1)
        .unwrap()
        .read_as::<f32>((0, 0), (SIDE, lines), (SIDE, lines), None)
        .unwrap();
    for (k, &v) in values.data().iter().enumerate() {
        let want = expected_sigma0(&product, k / SIDE, k % SIDE, true).unwrap();
        assert!(
            ((v as f64) - want).abs() <= 1e-6 * want,
            "pixel {k}: {v} against {want}"
        );
    }
    let o = wakelab(&[
        "calibrate",
        safe.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--db",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let said = json_of(&o);
    assert_eq!(said["product"]["polarisation"], "VV");
    assert_eq!(gdal::Dataset::open(&out).unwrap().rasterband(1).unwrap().unit(), "dB");

    // detect: findings in longitude and latitude from the geolocation grid
    let model = detector(dir);
    let scan = dir.join("scan");
    let found = detect(&safe, &model, &scan, &["--threshold", "0", "--keep-noise"]);
    assert_eq!(found["product"]["format"], "Sentinel-1 SAFE");
    let geojson: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(scan.join("detections.geojson")).unwrap()).unwrap();
    let first = &geojson["features"][0];
    let xy = first["geometry"]["coordinates"].as_array().unwrap();
    let col = first["properties"]["col"].as_f64().unwrap();
    let row = first["properties"]["row"].as_f64().unwrap();
    // the synthetic grid, affine in line and pixel (its values at pixel centres)
    assert!((xy[0].as_f64().unwrap() - longitude(col - 0.5)).abs() < 1e-7, "{first}");
    assert!((xy[1].as_f64().unwrap() - latitude(row - 0.5)).abs() < 1e-7, "{first}");
    assert_eq!(first["properties"]["acquisition_time"], "2020-01-01T00:00:00.000000");
    assert_eq!(
        gdal::Dataset::open(scan.join("probability.tif")).unwrap().gcps().len(),
        12
    );

    // the product read and scanned band by band scores as its calibrated image read whole
    let kept = dir.join("sigma0_kept.tif");
    let o = wakelab(&[
        "calibrate",
        safe.to_str().unwrap(),
        "--out",
        kept.to_str().unwrap(),
        "--keep-noise",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let whole = detect(&kept, &model, &dir.join("scan_whole"), &["--threshold", "0"]);
    assert_eq!(found["windows"], whole["windows"]);
    assert_eq!(found["probability"], whole["probability"]);
    let read_map = |scan: &str| {
        let map = gdal::Dataset::open(dir.join(scan).join("probability.tif")).unwrap();
        let (cols, rows) = map.raster_size();
        let band = map.rasterband(1).unwrap();
        band.read_as::<f32>((0, 0), (cols, rows), (cols, rows), None)
            .unwrap()
            .data()
            .to_vec()
    };
    let (banded, read_whole) = (read_map("scan"), read_map("scan_whole"));
    assert!(banded.iter().zip(&read_whole).all(|(a, b)| a.to_bits() == b.to_bits()));
    // the ship, found and its window scored in both
    let ships = |r: &serde_json::Value| -> Vec<(f64, f64, f64)> {
        r["ships"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| {
                let at = |k: &str| s[k].as_f64().unwrap();
                (at("product_row"), at("product_col"), at("cnn_probability"))
            })
            .collect()
    };
    let (streamed, read_whole) = (ships(&found), ships(&whole));
    assert_eq!(streamed.len(), 1, "{streamed:?}");
    assert!((streamed[0].0 - 1027.0).abs() < 2.0, "{streamed:?}");
    assert_eq!(streamed, read_whole);

    // a detector trained at 20 m: the product averaged over 2 x 2 band by band scores as its
    // calibrated image averaged whole
    let coarse = detector_at(dir, 20.0);
    let banded = detect(
        &safe,
        &coarse,
        &dir.join("scan_20"),
        &["--threshold", "0", "--keep-noise"],
    );
    let whole = detect(&kept, &coarse, &dir.join("scan_20_whole"), &["--threshold", "0"]);
    assert_eq!(banded["resampled"], serde_json::json!([2.0, 2.0]));
    assert_eq!(banded["windows"], whole["windows"]);
    assert_eq!(banded["probability"], whole["probability"]);
    let (banded, read_whole) = (read_map("scan_20"), read_map("scan_20_whole"));
    assert_eq!(banded.len(), (lines / 2).div_ceil(16) * (SIDE / 2).div_ceil(16));
    assert!(banded.iter().zip(&read_whole).all(|(a, b)| a.to_bits() == b.to_bits()));
}

/// The ship of [`a_ship_and_its_wake_come_out_as_geojson`] on its 400-row sea: the image and the
/// ship's (row, column).
fn ship_image() -> (Array2<f32>, (f64, f64)) {
    let side = 400;
    let looks: Vec<Array2<f32>> = (0..4).map(|k| sea_of(side * (k + 1))).collect();
    let mut image = Array2::from_shape_fn((side, SIDE.max(side)), |(r, c)| {
        looks
            .iter()
            .enumerate()
            .map(|(k, l)| l[[side * k + r, c % SIDE]])
            .sum::<f32>()
            / 4.0
    });
    let (ship_r, ship_c) = (300.0, 100.0);
    let course = 45f64.to_radians();
    let (north, east) = (course.cos(), course.sin());
    for d in 6..250 {
        for x in -2..=2 {
            // behind the ship: minus the course, across: the course turned right
            let r = ship_r + d as f64 * north - x as f64 * east;
            let c = ship_c - d as f64 * east - x as f64 * north;
            if r >= 0.0 && c >= 0.0 && (r as usize) < side && (c as usize) < image.ncols() {
                image[[r as usize, c as usize]] *= 0.5;
            }
        }
    }
    for d in -7..=7 {
        let (r, c) = (ship_r - d as f64 * north, ship_c + d as f64 * east);
        image[[r.round() as usize, c.round() as usize]] = 10.0;
    }
    (image, (ship_r, ship_c))
}

/// A ship and its wake on a UTM GeoTIFF (4-look speckle, a 150 m return 30 dB over the sea, a
/// trough 3 dB dark and 40 m wide for 2.5 km behind it, course 45 degrees): `detect` finds the
/// ship where it is and the wake's course, and writes them as a GeoJSON Point and LineString
/// (the wake's vertices where GDAL places them) and in `detect --json`; a GeoTIFF states no orbit,
/// so the azimuth offset gives no speed, and the notes say so.
#[test]
fn a_ship_and_its_wake_come_out_as_geojson() {
    let dir = tempfile::tempdir().unwrap();
    let (image, (ship_r, ship_c)) = ship_image();
    let tif = dir.path().join("ship.tif");
    write_tif(&tif, &image, &utm(TRANSFORM, image.dim()), "linear");
    let model = detector(dir.path());
    let out = dir.path().join("scan");
    let report = detect(&tif, &model, &out, &[]);
    let calibrated = report.clone();
    let ships = report["ships"].as_array().unwrap();
    assert_eq!(ships.len(), 1, "{ships:?}");
    let ship = &ships[0];
    let (row, col) = (
        ship["product_row"].as_f64().unwrap(),
        ship["product_col"].as_f64().unwrap(),
    );
    assert!((row - ship_r).abs() < 2.0 && (col - ship_c).abs() < 2.0, "{ship}");
    // calibrated: the return's brightest pixel is sigma0 10, 10 dB
    assert!((ship["peak_db"].as_f64().unwrap() - 10.0).abs() < 0.01, "{ship}");
    let wake = &report["wakes"].as_array().unwrap()[0];
    assert_eq!(wake["ship"], 0, "{wake}");
    // a ship with a wake has no reason for having none
    assert!(ship["no_wake"].is_null(), "{ship}");
    // the return is drawn along the course, so the wake runs along the hull
    assert_eq!(wake["along_hull"], true, "{wake}");
    let image_course = wake["course_image_deg"].as_f64().unwrap();
    assert!((image_course - 45.0).abs() < 2.0, "{wake}");
    // UTM 33N at 13.45 E, 55 N: grid north is 1.3 degrees east of true north there
    assert!((wake["course_deg"].as_f64().unwrap() - 45.0).abs() < 2.0, "{wake}");
    // it leaves the image 1.41 km behind the ship
    assert!(wake["length_m"].as_f64().unwrap() > 1200.0, "{wake}");
    assert!(
        wake["speed_offset"]["unknown"].as_str().unwrap().contains("R/V"),
        "{wake}"
    );
    let notes = report["notes"].as_array().unwrap();
    assert!(
        notes.iter().any(|n| n.as_str().unwrap().contains("no orbit")),
        "{notes:?}"
    );
    let geojson: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("detections.geojson")).unwrap()).unwrap();
    let features = geojson["features"].as_array().unwrap();
    let point = features
        .iter()
        .find(|f| f["properties"]["kind"] == "ship")
        .expect("a ship");
    assert_eq!(point["geometry"]["type"], "Point");
    let line = features
        .iter()
        .find(|f| f["properties"]["kind"] == "wake")
        .expect("a wake");
    assert_eq!(line["geometry"]["type"], "LineString");
    let start = &line["geometry"]["coordinates"][0];
    let (want_lon, want_lat) = gdal_lonlat(
        wake["product_start"][1].as_f64().unwrap(),
        wake["product_start"][0].as_f64().unwrap(),
    );
    assert!(
        (start[0].as_f64().unwrap() - want_lon).abs() < 1e-6 && (start[1].as_f64().unwrap() - want_lat).abs() < 1e-6
    );
    // detect --json carries the same ships and wakes
    let o = wakelab(&[
        "detect",
        tif.to_str().unwrap(),
        "--model",
        model.to_str().unwrap(),
        "--out",
        dir.path().join("again").to_str().unwrap(),
        "--json",
        "-q",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let printed: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(printed["ships"], report["ships"]);
    assert_eq!(printed["wakes"], report["wakes"]);
    // the two searches read together: each wake lists the windows on it, each window names
    // its wake, and the evidence counts agree with both
    assert_eq!(printed["evidence"], report["evidence"]);
    let windows = report["detections"].as_array().unwrap();
    let wakes = report["wakes"].as_array().unwrap();
    for (k, w) in wakes.iter().enumerate() {
        for j in w["cnn_windows"].as_array().unwrap() {
            let window = &windows[j.as_u64().unwrap() as usize];
            assert!(window["on_wake"].is_u64(), "{window}");
        }
        let listed = w["cnn_windows"].as_array().unwrap().len();
        let in_geojson = features
            .iter()
            .filter(|f| f["properties"]["kind"] == "wake")
            .nth(k)
            .unwrap();
        assert_eq!(in_geojson["properties"]["cnn_windows"], listed, "{in_geojson}");
    }
    let evidence = &report["evidence"];
    let seen_by_both = wakes
        .iter()
        .filter(|w| !w["cnn_windows"].as_array().unwrap().is_empty())
        .count();
    assert_eq!(evidence["both"], seen_by_both, "{evidence}");
    assert_eq!(evidence["line_search_only"], wakes.len() - seen_by_both, "{evidence}");
    let off_wakes = windows.iter().filter(|w| w["on_wake"].is_null()).count();
    assert_eq!(evidence["cnn_only"], off_wakes, "{evidence}");
    // the CNN on the ship's own window: the probability `detect` gives the 32 x 32 window
    // centred on its return when that window is the whole image, in the JSON and the GeoJSON
    let cnn = ship["cnn_probability"].as_f64().expect("the ship's window is scored");
    let point = features.iter().find(|f| f["properties"]["kind"] == "ship").unwrap();
    assert_eq!(point["properties"]["cnn_probability"].as_f64(), Some(cnn));
    let origin = |centre: f64| (centre + 0.5 - 16.0).round() as usize;
    let (r0, c0) = (origin(row), origin(col));
    let window = image.slice(ndarray::s![r0..r0 + 32, c0..c0 + 32]).to_owned();
    let alone = dir.path().join("ship_window.tif");
    write_tif(&alone, &window, &utm(TRANSFORM, window.dim()), "linear");
    let by_itself = detect(&alone, &model, &dir.path().join("ship_window"), &[]);
    assert!(
        (probability(&by_itself) - cnn).abs() < 1e-6,
        "{cnn} against {by_itself}"
    );
    // the ship search states its settings: P_fa 1e-6 is 4.753 standard normal deviations
    assert_eq!(printed["ship_search"], report["ship_search"]);
    assert_eq!(report["ship_search"]["pfa"], 1e-6);
    let sigmas = report["ship_search"]["threshold_sigmas"].as_f64().unwrap();
    assert!((sigmas - 4.7534).abs() < 1e-3, "{sigmas}");
    // --ship-pfa 1e-12 (7.03 deviations) still finds the ship 30 dB over the sea
    let strict = detect(&tif, &model, &dir.path().join("strict"), &["--ship-pfa", "1e-12"]);
    assert_eq!(strict["ships"].as_array().unwrap().len(), 1, "{}", strict["ships"]);
    let sigmas = strict["ship_search"]["threshold_sigmas"].as_f64().unwrap();
    assert!((sigmas - 7.0345).abs() < 1e-3, "{sigmas}");

    // the same scene as a display stretch (4 grey levels per dB): the ship is found where it
    // is, but its grey levels are not dB, so it has no sigma0 or contrast, and the notes say why
    let grey = image.mapv(|v| (128.0 + 4.0 * 10.0 * v.log10()).clamp(0.0, 255.0).round());
    let shown = dir.path().join("shown.tif");
    write_tif(&shown, &grey, &utm(TRANSFORM, image.dim()), "");
    let report = detect(&shown, &model, &dir.path().join("shown"), &["--scale", "display"]);
    let ships = report["ships"].as_array().unwrap();
    assert_eq!(ships.len(), 1, "{ships:?}");
    let ship = &ships[0];
    assert!((ship["product_row"].as_f64().unwrap() - ship_r).abs() < 2.0, "{ship}");
    for key in ["peak_sigma0", "peak_db", "background_db", "contrast_db"] {
        assert!(ship[key].is_null(), "{key}: {ship}");
    }
    let notes = report["notes"].as_array().unwrap();
    assert!(
        notes.iter().any(|n| n.as_str().unwrap().contains("not calibrated")),
        "{notes:?}"
    );
    // its ships are sought at the display's false-alarm probability, and a note says why
    assert_eq!(report["ship_search"]["pfa"], 1e-9);
    assert!(
        notes.iter().any(|n| n.as_str().unwrap().contains("heavier tail")),
        "{notes:?}"
    );
    // its ceiling (the ship, 255) stands far over its sea: no note that ships may be missed
    let stands = |notes: &[serde_json::Value]| {
        notes.iter().find_map(|n| {
            n.as_str()
                .unwrap()
                .split("brightest value stands ")
                .nth(1)
                .map(str::to_owned)
        })
    };
    assert_eq!(stands(notes), None, "{notes:?}");
    // the same stretch with its sea 170 grey levels higher: the ship is clipped at 255, a few
    // of the sea's deviations up, and a note says by how many (the grey levels' own mean and
    // deviation, read as dB)
    let high = image.mapv(|v| (170.0 + 128.0 + 4.0 * 10.0 * v.log10()).clamp(0.0, 255.0).round());
    let n = high.len() as f64;
    let mean = high.sum() as f64 / n;
    let deviation = (high.mapv(|g| (g as f64 - mean).powi(2)).sum() / n).sqrt();
    let expected = (255.0 - mean) / deviation;
    let high_path = dir.path().join("high.tif");
    write_tif(&high_path, &high, &utm(TRANSFORM, image.dim()), "");
    let report = detect(&high_path, &model, &dir.path().join("high"), &["--scale", "display"]);
    let notes = report["notes"].as_array().unwrap();
    let said = stands(notes).unwrap_or_else(|| panic!("no ceiling note: {notes:?}"));
    let said: f64 = said.split(' ').next().unwrap().parse().unwrap();
    assert!(
        expected < 6.0 && (said - expected).abs() < 0.06,
        "{said} against {expected}"
    );

    // the same scene as digital numbers of amplitude, DN = 3000 sqrt(sigma0) in whole numbers
    // (a Sentinel-1 GRD measurement TIFF read alone): refused as sigma0 with the flag to pass;
    // read as `dn`, the same ship and wake as the calibrated scene (the gain is one offset in
    // dB, which the searches do not see), at the calibrated CFAR's P_fa, without sigma0
    let dn = image.mapv(|v| (3000.0 * v.sqrt()).round());
    let dn_path = dir.path().join("dn.tif");
    write_tif(&dn_path, &dn, &utm(TRANSFORM, image.dim()), "");
    let refused = dir.path().join("dn_as_sigma0");
    let o = detect_output(&dn_path, &refused, &["--model", model.to_str().unwrap()]);
    assert!(
        !o.status.success() && stderr(&o).contains("pass --scale dn"),
        "{}",
        stderr(&o)
    );
    assert!(!refused.exists());
    let report = detect(&dn_path, &model, &dir.path().join("dn"), &["--scale", "dn"]);
    let (ships, wakes) = (report["ships"].as_array().unwrap(), report["wakes"].as_array().unwrap());
    let want = calibrated["wakes"].as_array().unwrap();
    assert_eq!((ships.len(), wakes.len()), (1, want.len()), "{ships:?} {wakes:?}");
    for key in ["product_row", "product_col"] {
        let (got, was) = (
            ships[0][key].as_f64().unwrap(),
            calibrated["ships"][0][key].as_f64().unwrap(),
        );
        assert!((got - was).abs() < 0.5, "{key}: {got} against {was}");
    }
    for key in ["peak_sigma0", "peak_db", "background_db", "contrast_db"] {
        assert!(ships[0][key].is_null(), "{key}: {}", ships[0]);
    }
    for (got, was) in wakes.iter().zip(want) {
        let course = |w: &serde_json::Value| w["course_image_deg"].as_f64().unwrap();
        assert!((course(got) - course(was)).abs() < 1.0, "{got} against {was}");
        assert_eq!(got["signature"], was["signature"]);
    }
    assert_eq!(report["ship_search"]["pfa"], 1e-6);
    // the CNN normalises each window by its median in dB: the gain cancels there too
    let (got, was) = (probability(&report), probability(&calibrated));
    assert!((got - was).abs() < 0.01, "{got} against {was}");
    let notes = report["notes"].as_array().unwrap();
    let says = |needle: &str| notes.iter().any(|n| n.as_str().unwrap().contains(needle));
    assert!(says("digital numbers") && !says("heavier tail"), "{notes:?}");
}

/// A dual-polarisation Sentinel-1 product of 2,500 lines (read in three bands): a ship 3 dB over
/// a 4-look VV sea, its trough 3 dB dark for 2.5 km behind it across the first band's edge, and
/// 25 dB over the VH sea. Scanned with VV alone, the CFAR cannot see the ship; with its VH band
/// beside it, `detect` finds the ship in VH, says so, and finds its whole wake in VV.
#[test]
fn a_dual_polarisation_product_shows_its_ships_in_cross_polarisation() {
    let root = tempfile::tempdir().unwrap();
    let dir = root.path();
    let lines = 2500;
    let looks: Vec<Array2<f32>> = (0..4).map(|k| sea_of(lines * (k + 1))).collect();
    let (ship_r, ship_c) = (900usize, 80usize);
    let vv = Array2::from_shape_fn((lines, SIDE), |(r, c)| {
        let mean = looks
            .iter()
            .enumerate()
            .map(|(k, l)| l[[lines * k + r, c]])
            .sum::<f32>()
            / 4.0;
        let trough = (ship_r + 6..ship_r + 256).contains(&r) && c.abs_diff(ship_c) <= 2;
        let ship = r.abs_diff(ship_r) <= 6 && c.abs_diff(ship_c) <= 1;
        mean * if trough {
            0.5
        } else if ship {
            2.0
        } else {
            1.0
        }
    });
    let vh = Array2::from_shape_fn((lines, SIDE), |(r, c)| {
        let ship = r.abs_diff(ship_r) <= 6 && c.abs_diff(ship_c) <= 1;
        if ship {
            3.0
        } else {
            0.01 * looks[1][[r, c]]
        }
    });
    let luts = Synthetic {
        lines,
        samples: SIDE,
        since_2_9: true,
        dn: &|_, _| 0,
    };
    // digital numbers whose sigma0 (noise kept) is the image: DN = A sqrt(sigma0)
    let numbers = |image: &Array2<f32>, l: usize, p: usize| -> u16 {
        let a = luts.gain(l as f64, p as f64);
        (a * (image[[l, p]] as f64).sqrt()).round().clamp(1.0, 65535.0) as u16
    };
    let (dn_vv, dn_vh) = (|l, p| numbers(&vv, l, p), |l, p| numbers(&vh, l, p));
    let safe = write_safe(dir, &Synthetic { dn: &dn_vv, ..luts });
    let model = detector(dir);
    let co = detect(&safe, &model, &dir.join("scan_vv"), &["--keep-noise"]);
    assert!(co["ships"].as_array().unwrap().is_empty(), "{}", co["ships"]);
    add_polarisation(&safe, &Synthetic { dn: &dn_vh, ..luts }, "VH");
    let dual = detect(&safe, &model, &dir.join("scan_dual"), &["--keep-noise"]);
    let ships = dual["ships"].as_array().unwrap();
    assert_eq!(ships.len(), 1, "{ships:?}");
    let ship = &ships[0];
    assert_eq!(ship["found_in"], "VH");
    let (row, col) = (
        ship["product_row"].as_f64().unwrap(),
        ship["product_col"].as_f64().unwrap(),
    );
    assert!(
        (row - ship_r as f64).abs() < 2.0 && (col - ship_c as f64).abs() < 2.0,
        "{ship}"
    );
    assert!(
        dual["notes"].to_string().contains("cross-polarised VH"),
        "{}",
        dual["notes"]
    );
    let wake = dual["wakes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|w| w["ship"] == 0)
        .expect("the ship's wake");
    // the ship sails up the image; its wake crosses the first band's last row (about 1,040)
    let course = wake["course_image_deg"].as_f64().unwrap();
    assert!(course.min(360.0 - course) < 3.0, "{wake}");
    assert!(wake["length_m"].as_f64().unwrap() > 2000.0, "{wake}");
}

/// Without `--model`, `detect` scans with the shipped C-band detector that fits the image's
/// pixel spacing (1.28 km windows at 20 m for a 10 m image, 2.56 km at 40 m for a 40 m one) and
/// says which; its strongest detection on the 10 m ship image lies within 500 m of the wake (the
/// issue's rule for a wake found). An image that states no spacing, or one coarser than 50 m, is
/// refused with the flag to pass.
#[test]
fn without_a_model_detect_takes_the_shipped_detector_for_the_spacing() {
    let dir = tempfile::tempdir().unwrap();
    let (image, (ship_r, ship_c)) = ship_image();
    let shipped = detect_output;
    let read = |out: &Path| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(out.join("detections.json")).unwrap()).unwrap()
    };
    let tif = dir.path().join("ship.tif");
    write_tif(&tif, &image, &utm(TRANSFORM, image.dim()), "linear");
    let out = dir.path().join("scan");
    let o = shipped(&tif, &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("the shipped detector C_transfer_1280m.safetensors"),
        "{}",
        stderr(&o)
    );
    let report = read(&out);
    let strongest = &report["detections"][0];
    let (row, col) = (
        strongest["product_row"].as_f64().unwrap(),
        strongest["product_col"].as_f64().unwrap(),
    );
    // the trough runs from the ship at course 45 degrees to the image's edge: 10 m pixels
    let along = ((row - ship_r) + (ship_c - col)) / 2f64.sqrt();
    let across = ((ship_c - col) - (row - ship_r)) / 2f64.sqrt();
    let from_wake = if along < 0.0 { along.hypot(across) } else { across.abs() } * 10.0;
    assert!(
        from_wake < 500.0,
        "strongest detection at ({row}, {col}), {from_wake} m from the wake: {report}"
    );
    let geojson = std::fs::read_to_string(out.join("detections.geojson")).unwrap();
    assert!(geojson.contains("shipped:C_transfer_1280m.safetensors"));

    // the same image at 40 m: the 2.56 km detector
    let coarse = dir.path().join("ship_40m.tif");
    let transform = [TRANSFORM[0], 40.0, 0.0, TRANSFORM[3], 0.0, -40.0];
    write_tif(&coarse, &image, &utm(transform, image.dim()), "linear");
    let o = shipped(&coarse, &dir.path().join("scan_40m"), &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("the shipped detector C_transfer_2560m.safetensors"),
        "{}",
        stderr(&o)
    );

    // a bare array says no spacing; 60 m is coarser than any shipped detector
    let npy = dir.path().join("ship.npy");
    ndarray_npy::write_npy(&npy, &image).unwrap();
    let o = shipped(&npy, &dir.path().join("scan_npy"), &[]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("--pixel-spacing"), "{}", stderr(&o));
    let o = shipped(&npy, &dir.path().join("scan_60m"), &["--pixel-spacing", "60"]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("coarser than the shipped detectors'"),
        "{}",
        stderr(&o)
    );

    // a 900 m chip of 3 m pixels is 300 pixels a side, but 45 once averaged to the 1.28 km
    // detector's 20 m, under half its 64 x 64 window (2,025 of 4,096 pixels): refused with both
    // sizes, and nothing written
    let chip = dir.path().join("chip.npy");
    ndarray_npy::write_npy(&chip, &image.slice(ndarray::s![..300, ..300]).to_owned()).unwrap();
    let out = dir.path().join("scan_chip");
    let o = shipped(&chip, &out, &["--pixel-spacing", "3"]);
    assert!(!o.status.success());
    for needle in [
        "`IMAGE` = 300 x 300 pixels, 45 x 45 once averaged to the detector's 20 m",
        "at least half of the detector's 64 x 64-pixel input in view (32 x 64, 46 x 46 or more pixels",
        "1.28 km a side",
    ] {
        assert!(stderr(&o).contains(needle), "{needle}: {}", stderr(&o));
    }
    assert!(!out.exists());

    // a 1 km chip of 10 m pixels around the ship, 50 x 50 at 20 m: more than half a window, so
    // scanned, the rest of its window taken as no-data and said; the ship is found where the
    // whole image's search finds it (within a 20 m pixel)
    let whole = read(&dir.path().join("scan"));
    let ship = |r: &serde_json::Value| {
        let s = &r["ships"][0];
        (s["product_row"].as_f64().unwrap(), s["product_col"].as_f64().unwrap())
    };
    let (whole_r, whole_c) = ship(&whole);
    let chip = dir.path().join("ship_chip.npy");
    ndarray_npy::write_npy(&chip, &image.slice(ndarray::s![250..350, 50..150]).to_owned()).unwrap();
    let out = dir.path().join("scan_ship_chip");
    let o = shipped(&chip, &out, &["--pixel-spacing", "10"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let report = read(&out);
    let notes = report["notes"].to_string();
    assert!(
        notes.contains("the image (100 x 100 pixels, 50 x 50 once averaged to the detector's 20 m) is smaller than the detector's 64 x 64-pixel window"),
        "{notes}"
    );
    let p = probability(&report);
    assert!((0.0..=1.0).contains(&p), "{report}");
    let (r, c) = ship(&report);
    assert!(
        (r + 250.0 - whole_r).abs() <= 2.0 && (c + 50.0 - whole_c).abs() <= 2.0,
        "chip's ship at ({r}, {c}), the whole image's at ({whole_r}, {whole_c})"
    );
}

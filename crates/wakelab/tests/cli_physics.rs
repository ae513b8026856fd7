//! The `wakelab` physics commands as a user runs them: the wake, the spectrum, the sensors.

mod common;

use common::*;
use std::path::Path;

#[test]
fn idp_json_has_every_scalar_the_issue_names() {
    let o = wakelab(&["idp", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("JSON");
    for key in [
        "Re", "Fr", "C_f", "C_D", "theta", "x_0", "y_h", "z_h", "U_f_max", "k_f_max", "R_wave", "U_w_max", "T", "r_h",
        "U_p_max", "k_p_max", "Q", "r_sh", "V_s_max", "a_r", "y_rh", "z_rh", "U_r_max",
    ] {
        assert!(v[key].is_number(), "missing {key}");
    }
    // Table 2.1
    assert!((v["Re"].as_f64().unwrap() / 9.94e8 - 1.0).abs() < 5e-3);
    assert!((v["Fr"].as_f64().unwrap() / 0.188 - 1.0).abs() < 5e-3);
}

#[test]
fn config_show_prints_a_configuration_that_reads_back() {
    let o = wakelab(&["config", "show", "--preset", "paper"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(
        text.contains("core_cells = 4001") && text.contains("depth_cells = 201"),
        "{text}"
    );
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("shown.toml");
    std::fs::write(&file, &text).unwrap();
    let again = wakelab(&["config", "show", "--config", file.to_str().unwrap()]);
    assert!(again.status.success(), "{}", stderr(&again));
    assert_eq!(stdout(&again), text);
}

#[test]
fn bad_values_are_refused_before_any_output() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    for (toml, field, allowed) in [
        ("[ship]\nspeed = 45.0\n", "ship.speed", "[0.1, 30]"),
        ("[grid]\ncore_cells = 2\n", "grid.core_cells", "[8, 20001]"),
        (
            "[environment.swell]\namplitude = -1.0\n",
            "environment.swell.amplitude",
            "[0, 10]",
        ),
        ("[time]\ncfl = 3.0\n", "time.cfl", "[0.01, 0.9]"),
        // UTM's range of latitudes (UPS beyond)
        (
            "[scene.centre]\nlatitude = 85.0\nlongitude = 10.0\n",
            "scene.centre.latitude",
            "[-80, 84]",
        ),
        ("[ship]\nbeem = 3.0\n", "beem", "unknown field"),
    ] {
        let file = dir.path().join("bad.toml");
        std::fs::write(&file, toml).unwrap();
        let o = scene(&file, &out, &["--quiet"]);
        assert!(!o.status.success(), "{toml} was accepted");
        let err = stderr(&o);
        assert!(err.contains(field) && err.contains(allowed), "{toml}: {err}");
        assert!(!out.exists(), "{toml}: output written despite the error");
    }
}

/// A text attribute of a NetCDF file (global) or of one of its variables.
fn text_attribute(path: &Path, variable: Option<&str>, name: &str) -> Option<String> {
    let file = netcdf::open(path).expect("readable NetCDF");
    let attribute = match variable {
        Some(v) => file.variable(v)?.attribute(name)?.value(),
        None => file.attribute(name)?.value(),
    };
    match attribute.ok()? {
        netcdf::AttributeValue::Str(s) => Some(s),
        _ => None,
    }
}

fn has_cf_conventions(path: &Path) -> bool {
    text_attribute(path, None, "Conventions").as_deref() == Some("CF-1.8")
}

/// Open each file named on the command line with xarray; every time variable must decode to
/// timedelta64 and every other variable to float32.
const XARRAY_CHECK: &str = r#"
import sys, xarray, numpy
for path in sys.argv[1:]:
    with xarray.open_dataset(path) as ds:
        for name, var in ds.variables.items():
            if name == "time":
                assert numpy.issubdtype(var.dtype, numpy.timedelta64), (path, name, var.dtype)
            else:
                assert var.dtype == numpy.float32, (path, name, var.dtype)
            if var.ndim > 1:
                assert var.encoding.get("zlib") and var.encoding.get("shuffle"), (path, name, var.encoding)
        if "time" in ds.variables:
            assert ds["time"].values[-1] > numpy.timedelta64(0, "s"), path
"#;

#[test]
fn wake_run_writes_netcdf_pictures_and_the_configuration() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("tiny.toml");
    std::fs::write(&cfg, TINY).unwrap();
    let out = dir.path().join("run");
    let o = scene(&cfg, &out, &["--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    for f in ["wake_sections.nc", "wake_surface.nc", "surface_map.nc"] {
        assert!(has_cf_conventions(&out.join(f)), "{f}");
    }
    let sections = out.join("wake_sections.nc");
    let time = netcdf::open(&sections)
        .unwrap()
        .variable("time")
        .unwrap()
        .get_values::<f64, _>(..)
        .unwrap();
    assert_eq!(time, vec![0.0, 60.0, 120.0]);
    assert_eq!(text_attribute(&sections, Some("U"), "units").as_deref(), Some("m s-1"));
    // CF time as a duration (CF-1.8 Sec. 4.4) that xarray decodes, and standard names where CF has them
    assert_eq!(
        text_attribute(&sections, Some("time"), "units").as_deref(),
        Some("seconds")
    );
    assert_eq!(
        text_attribute(&sections, Some("time"), "dtype").as_deref(),
        Some("timedelta64[s]")
    );
    assert_eq!(
        text_attribute(&sections, Some("W"), "standard_name").as_deref(),
        Some("upward_sea_water_velocity")
    );
    // every file of the run: NetCDF with CF's `source`, every image TIFF with its JSON sidecar
    // and a grid in metres (GeoTIFF ProjLinearUnits = 9001)
    let files: Vec<std::path::PathBuf> = std::fs::read_dir(&out).unwrap().map(|e| e.unwrap().path()).collect();
    let with_ext = |ext: &'static str| files.iter().filter(move |p| p.extension().is_some_and(|e| e == ext));
    assert!(with_ext("tif").count() >= 2 && with_ext("nc").count() >= 4);
    for nc in with_ext("nc") {
        let source = text_attribute(nc, None, "source");
        assert!(source.is_some_and(|s| s.starts_with("wakelab ")), "{}", nc.display());
        // NetCDF-4: an HDF5 file (its signature, HDF5 spec Sec. II.A)
        let head = std::fs::read(nc).unwrap();
        assert_eq!(&head[..8], b"\x89HDF\r\n\x1a\n", "{}", nc.display());
    }
    // xarray opens every file and decodes every variable to its type: time a timedelta64,
    // the fields float32
    let check = std::process::Command::new("/usr/bin/python3")
        .arg("-c")
        .arg(XARRAY_CHECK)
        .args(with_ext("nc"))
        .output()
        .expect("python3 with xarray and netCDF4 (apt-get install python3-xarray python3-netcdf4)");
    assert!(
        check.status.success(),
        "{}{}",
        String::from_utf8_lossy(&check.stdout),
        String::from_utf8_lossy(&check.stderr)
    );
    for tif in with_ext("tif") {
        assert!(tif.with_extension("json").is_file(), "{} has no sidecar", tif.display());
        let mut dec = tiff::decoder::Decoder::new(std::fs::File::open(tif).unwrap()).unwrap();
        let keys = dec.get_tag_u16_vec(tiff::tags::Tag::Unknown(34735)).unwrap();
        assert!(
            keys[4..].chunks(4).any(|k| k == [3076, 0, 1, 9001]),
            "{}: {keys:?}",
            tif.display()
        );
    }
    let map = netcdf::open(out.join("surface_map.nc")).unwrap();
    let x = map.variable("x").unwrap().get_values::<f32, _>(..).unwrap();
    // x = x_IDP + U_ship t, every map_dx = 25 m from 71 m up to 71 + 7 m/s * 120 s = 911 m
    assert!(
        (x[0] - 71.0).abs() < 1e-3 && (x[x.len() - 1] - 896.0).abs() < 1e-3,
        "{:?}",
        (x[0], x.last())
    );
    for f in [
        "surface_U.png",
        "surface_dT.png",
        "section_U_t00000.png",
        "config.toml",
        "idp.json",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let leftovers: Vec<_> = std::fs::read_dir(&out)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty());
    // the run's configuration reads back
    let shown = wakelab(&["config", "show", "--config", out.join("config.toml").to_str().unwrap()]);
    assert!(shown.status.success(), "{}", stderr(&shown));
}

#[test]
fn spectrum_json_reports_pierson_moskowitz_closed_forms_and_bragg_densities() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("pm.toml");
    // Pierson-Moskowitz with the power law joined far out, no swell
    std::fs::write(
        &cfg,
        "[sea]\nspectrum = \"pierson_moskowitz\"\nshort_wave_join = 1000.0\n[environment.swell]\ndirection = \"calm\"\n",
    )
    .unwrap();
    let o = wakelab(&[
        "spectrum",
        "--json",
        "--config",
        cfg.to_str().unwrap(),
        "--wind",
        "10",
        "--incidence",
        "30",
    ]);
    let v = json_of(&o);
    let hs = v["significant_wave_height"].as_f64().unwrap();
    assert!((hs / 2.133 - 1.0).abs() < 0.005, "Hs {hs}");
    let wp = v["peak_angular_frequency"].as_f64().unwrap();
    assert!((wp / (0.8772 * 9.81 / 10.0) - 1.0).abs() < 0.01, "omega_p {wp}");
    assert!(v["mss_upwind"].as_f64().unwrap() > v["mss_crosswind"].as_f64().unwrap());
    let bragg = v["bragg"].as_array().unwrap();
    assert_eq!(bragg.len(), 3);
    // C band at 30 degrees: the Bragg wavelength equals the radar wavelength, c / 5.3 GHz
    let c = &bragg[1];
    assert_eq!(c["band"], "C");
    assert!((c["bragg_wavelength_m"].as_f64().unwrap() - 299_792_458.0 / 5.3e9).abs() < 1e-9);
    assert!(c["density_towards"].as_f64().unwrap() > 0.0);
}

#[test]
fn a_scene_outside_the_simulated_wake_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("far.toml");
    std::fs::write(&cfg, "[scene]\nalong_track = 40000.0\n").unwrap();
    let o = wakelab(&[
        "scene",
        "--config",
        cfg.to_str().unwrap(),
        "--quiet",
        "--out",
        dir.path().join("r").to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(
        err.contains("scene.along_track") && err.contains("within the simulated wake"),
        "{err}"
    );
}

/// `wakelab sar sigma0 --json` with `args`, parsed.
fn sar_sigma0_json(args: &[&str]) -> serde_json::Value {
    let mut all = vec!["sar", "sigma0", "--json"];
    all.extend_from_slice(args);
    json_of(&wakelab(&all))
}

#[test]
fn sar_sigma0_and_optics_print_their_json() {
    let v = sar_sigma0_json(&[
        "--wind",
        "10",
        "--band",
        "X",
        "--polarisation",
        "hh",
        "--incidence",
        "40",
    ]);
    assert_eq!(v["band"], "X");
    assert_eq!(v["polarisation"], "HH");
    let db = v["sigma0_db"].as_f64().unwrap();
    assert!(db < -10.0 && db > -40.0, "{db}");
    let part = |k: &str| v[k].as_f64().unwrap();
    // (sigma_B + sigma_S)(1 - q) + q sigma_wb (KHCC03 Eq. 1)
    let parts =
        (part("sigma0_bragg") + part("sigma0_specular")) * (1.0 - part("breaking_fraction")) + part("sigma0_breaking");
    assert!((part("sigma0") - parts).abs() < 1e-12 * parts);
    assert!(v["cmod5n"].is_null(), "CMOD5.N is a C-band model");

    // C band looking up-wind: CMOD5.N beside wakelab's value, and near it
    let v = sar_sigma0_json(&["--wind", "10", "--incidence", "40", "--look", "180"]);
    let (ours, cmod) = (v["sigma0_db"].as_f64().unwrap(), v["cmod5n_db"].as_f64().unwrap());
    assert!((cmod - -12.947).abs() < 1e-3, "CMOD5.N {cmod}");
    assert!((ours - cmod).abs() < 2.0, "wakelab {ours} dB vs CMOD5.N {cmod} dB");

    // --cell: in CMOD5.N's 25 km cell every wave tilts the Bragg facets, which at 20 degrees
    // (where sigma0 curves upward with falling incidence) raises the mean over the 10 m pixels'
    let at_20 = ["--wind", "10", "--incidence", "20", "--look", "180"];
    let pixel = sar_sigma0_json(&at_20);
    let cell = sar_sigma0_json(&[&at_20[..], &["--cell", "25000"]].concat());
    assert_eq!(
        (pixel["cell_size_m"].as_f64(), cell["cell_size_m"].as_f64()),
        (Some(10.0), Some(25000.0))
    );
    let (p, c) = (
        pixel["sigma0_db"].as_f64().unwrap(),
        cell["sigma0_db"].as_f64().unwrap(),
    );
    assert!(c > p + 0.1, "25 km {c} dB vs 10 m {p} dB");
    let bad = wakelab(&["sar", "sigma0", "--cell", "0"]);
    assert!(!bad.status.success());
    assert!(
        stderr(&bad).contains("`--cell` = 0: in [0.1, 1000000] m"),
        "{}",
        stderr(&bad)
    );

    let o = wakelab(&[
        "optics",
        "--json",
        "--wavelength",
        "10",
        "--salinity",
        "0",
        "--temperature",
        "27",
        "--incidence",
        "0",
    ]);
    let v = json_of(&o);
    // pure water at 10 um (Hale & Querry 1973): n = 1.218, kappa = 0.0508
    assert!((v["n"].as_f64().unwrap() - 1.218).abs() < 1e-3);
    assert!((v["kappa"].as_f64().unwrap() - 0.0508).abs() < 1e-4);
    for key in ["rho_s", "rho_p", "rho", "emissivity"] {
        assert!(v[key].is_number(), "{key}");
    }
    // at normal incidence both polarisations reflect |(m - a) / (m + a)|^2 of m = n - i kappa
    // from air of index a = 1.0003 (Fresnel's closed form): of the printed index exactly, and
    // about 0.0101 (emissivity 0.9899) for the tabulated one
    let (n, k, a) = (v["n"].as_f64().unwrap(), v["kappa"].as_f64().unwrap(), 1.0003);
    let closed = ((n - a).powi(2) + k * k) / ((n + a).powi(2) + k * k);
    for key in ["rho_s", "rho_p", "rho"] {
        assert!(
            (v[key].as_f64().unwrap() - closed).abs() < 1e-9,
            "{key}: {} vs {closed}",
            v[key]
        );
    }
    assert!((closed - 0.01013).abs() < 1e-4, "{closed}");
    assert!((v["emissivity"].as_f64().unwrap() - (1.0 - closed)).abs() < 1e-9);
    assert_eq!(v["flat_sea_radiance"].as_array().unwrap().len(), 2);

    let bad = wakelab(&["sar", "sigma0", "--band", "K"]);
    assert!(!bad.status.success() && stderr(&bad).contains("'K' for '--band"));

    // negative numbers are numbers: a look of -45 degrees is 315, and a negative wind is refused
    // by the range check naming its field, not by the parser
    let minus = sar_sigma0_json(&["--wind", "8", "--look", "-45"]);
    let plus = sar_sigma0_json(&["--wind", "8", "--look", "315"]);
    assert!((minus["sigma0_db"].as_f64().unwrap() - plus["sigma0_db"].as_f64().unwrap()).abs() < 1e-9);
    let bad = wakelab(&["sar", "sigma0", "--wind", "-3"]);
    assert!(
        !bad.status.success() && stderr(&bad).contains("environment.wind.speed"),
        "{}",
        stderr(&bad)
    );
    // the human lines print numbers as a person writes them
    let text = stdout(&wakelab(&["sar", "sigma0", "--incidence", "35"]));
    assert!(text.contains("incidence_deg = 35\n"), "{text}");
}

/// The scene's images are COGs with nodata, band description and unit; placed by `scene.centre`
/// in its UTM zone, north up with the centre where the config puts it; else on a grid that says
/// it is local.
#[test]
fn scene_images_are_cogs_placed_in_utm_when_the_scene_has_a_centre() {
    use gdal::{Dataset, Metadata};
    let dir = tempfile::tempdir().unwrap();
    for (name, centre) in [
        ("local", ""),
        ("kiel", "[scene.centre]\nlatitude = 54.5\nlongitude = 10.3\n"),
    ] {
        let cfg = dir.path().join(format!("{name}.toml"));
        std::fs::write(&cfg, format!("{TINY}{centre}")).unwrap();
        let out = dir.path().join(name);
        let o = scene(&cfg, &out, &["--quiet"]);
        assert!(o.status.success(), "{}", stderr(&o));
        let tif = out.join("sar_C_vv.tif");
        assert_valid_cog(&tif);
        let ds = Dataset::open(&tif).unwrap();
        let band = ds.rasterband(1).unwrap();
        assert!(band.no_data_value().is_some_and(f64::is_nan));
        assert!(
            band.description().unwrap().starts_with("sigma0"),
            "{:?}",
            band.description()
        );
        assert_eq!(band.unit(), "1");
        assert_eq!(ds.metadata_item("WAKELAB_BAND", "").as_deref(), Some("C"));
        // the platform's incidence (the embedded default's 35 degrees), for detect's ship search
        assert_eq!(ds.metadata_item("WAKELAB_INCIDENCE_DEG", "").as_deref(), Some("35"));
        let lwir = Dataset::open(out.join("ir_lwir_brightness_temperature.tif")).unwrap();
        assert_eq!(lwir.rasterband(1).unwrap().unit(), "K");
        assert_eq!(lwir.metadata_item("WAKELAB_BAND", "").as_deref(), Some("LWIR"));
        let t = ds.geo_transform().unwrap();
        assert_eq!((t[1], t[5]), (5.0, -5.0), "north up at 5 m");
        let srs = ds.spatial_ref().unwrap();
        if centre.is_empty() {
            assert!(srs.to_wkt().unwrap().contains("not placed on the Earth"));
            assert!(ds.metadata_item("WAKELAB_GRID", "").unwrap().starts_with("local"));
        } else {
            // UTM zone 32N (6-12 E); the image's centre back in WGS 84 is the configured point
            assert_eq!(srs.auth_code().unwrap(), 32632);
            let mut wgs = gdal::spatial_ref::SpatialRef::from_epsg(4326).unwrap();
            wgs.set_axis_mapping_strategy(gdal::spatial_ref::AxisMappingStrategy::TraditionalGisOrder);
            let to_wgs = gdal::spatial_ref::CoordTransform::new(&srs, &wgs).unwrap();
            let (mut x, mut y) = ([t[0] + 32.0 * t[1]], [t[3] + 32.0 * t[5]]);
            to_wgs.transform_coords(&mut x, &mut y, &mut []).unwrap();
            assert!((x[0] - 10.3).abs() < 1e-6 && (y[0] - 54.5).abs() < 1e-6, "{x:?} {y:?}");
        }
    }
}

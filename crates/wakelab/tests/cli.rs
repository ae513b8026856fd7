//! The `wakelab` command as a user runs it.

use std::path::Path;
use std::process::{Command, Output};

fn wakelab(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_wakelab"))
        .args(args)
        .output()
        .expect("wakelab runs")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A grid small enough to simulate in a second.
const TINY: &str = r#"
[grid]
core_width = 200.0
depth = 30.0
core_cells = 60
depth_cells = 15
beach_width = 60.0
beach_cells = 6
[time]
duration = 120.0
surface_interval = 20.0
output_interval = 60.0
[scene]
pixel_spacing = 5.0
size = 64
along_track = 500.0
[sea]
window = 32
"#;

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
        ("[ship]\nbeem = 3.0\n", "beem", "unknown field"),
    ] {
        let file = dir.path().join("bad.toml");
        std::fs::write(&file, toml).unwrap();
        let o = wakelab(&[
            "scene",
            "--config",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ]);
        assert!(!o.status.success(), "{toml} was accepted");
        let err = stderr(&o);
        assert!(err.contains(field) && err.contains(allowed), "{toml}: {err}");
        assert!(!out.exists(), "{toml}: output written despite the error");
    }
}

fn has_cf_conventions(path: &Path) -> bool {
    let r = netcdf3::FileReader::open(path).expect("readable NetCDF");
    r.data_set().get_global_attr_as_string("Conventions").as_deref() == Some("CF-1.8")
}

#[test]
fn wake_run_writes_netcdf_pictures_and_the_configuration() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("tiny.toml");
    std::fs::write(&cfg, TINY).unwrap();
    let out = dir.path().join("run");
    let o = wakelab(&[
        "scene",
        "--config",
        cfg.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    for f in ["wake_sections.nc", "wake_surface.nc", "surface_map.nc"] {
        assert!(has_cf_conventions(&out.join(f)), "{f}");
    }
    let mut r = netcdf3::FileReader::open(out.join("wake_sections.nc")).unwrap();
    let time = r.read_var_f32("time").unwrap();
    assert_eq!(time, vec![0.0, 60.0, 120.0]);
    let ds = r.data_set();
    assert_eq!(ds.get_var_attr_as_string("U", "units").as_deref(), Some("m s-1"));
    let mut m = netcdf3::FileReader::open(out.join("surface_map.nc")).unwrap();
    let x = m.read_var_f32("x").unwrap();
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
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
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

#[test]
fn sar_sigma0_and_optics_print_their_json() {
    let o = wakelab(&[
        "sar",
        "sigma0",
        "--json",
        "--wind",
        "10",
        "--band",
        "X",
        "--polarisation",
        "hh",
        "--incidence",
        "40",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
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
    let o = wakelab(&[
        "sar",
        "sigma0",
        "--json",
        "--wind",
        "10",
        "--incidence",
        "40",
        "--look",
        "180",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let (ours, cmod) = (v["sigma0_db"].as_f64().unwrap(), v["cmod5n_db"].as_f64().unwrap());
    assert!((cmod - -12.947).abs() < 1e-3, "CMOD5.N {cmod}");
    assert!((ours - cmod).abs() < 2.0, "wakelab {ours} dB vs CMOD5.N {cmod} dB");

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
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
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
    assert!(!bad.status.success() && stderr(&bad).contains("--band K"));
}

#[test]
fn dataset_refuses_bad_studies_before_work_and_emits_a_slurm_array() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    std::fs::write(
        &bad,
        "[study]\nname = \"b\"\ncombine = \"product\"\nseeds = 1\ntest_fraction = 0.1\ngrouped_split = false\n\
         min_visibility = 0.0\nmixed_layer_depth = 20.0\nbands = [\"C\"]\n[axes]\nwind_speed = [-1.0]\n",
    )
    .unwrap();
    let out = dir.path().join("ds");
    let o = wakelab(&[
        "dataset",
        "--study",
        bad.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("axes.wind_speed"), "{}", stderr(&o));
    assert!(!out.exists());

    let o = wakelab(&[
        "dataset",
        "--study",
        "default",
        "--out",
        out.to_str().unwrap(),
        "--emit-slurm",
        "--tasks",
        "4",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let script = std::fs::read_to_string(out.join("wakelab_dataset.slurm")).unwrap();
    assert!(
        script.contains("--array=0-3") && script.contains("SLURM_ARRAY_TASK_ID/4"),
        "{script}"
    );
    assert!(script.contains("--dependency=afterok") && script.contains("--merge"));

    let o = wakelab(&["dataset", "--out", out.to_str().unwrap(), "--shard", "4/4"]);
    assert!(!o.status.success() && stderr(&o).contains("--shard 4/4"));
}

/// The Slurm script run against a stand-in `sbatch` that executes the array tasks one after the
/// other and then the merge job: the result must equal a single-machine run, byte for byte.
#[test]
fn the_slurm_script_reproduces_a_single_machine_run() {
    let dir = tempfile::tempdir().unwrap();
    let study = dir.path().join("study.toml");
    std::fs::write(
        &study,
        "[study]\nname = \"s\"\ncombine = \"product\"\nseeds = 1\ntest_fraction = 0.5\ngrouped_split = false\n\
         min_visibility = 0.0\nmixed_layer_depth = 20.0\nbands = [\"X\", \"MWIR\"]\n\
         [axes]\nwind_speed = [5.0, 8.0, 11.0]\nimage_size = [32]\npixel_spacing = [10.0]\nalong_track = [2000.0]\n\
         [base]\npreset = \"quick\"\n[base.time]\nduration = 600.0\n",
    )
    .unwrap();
    let bin = dir.path().join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    let sbatch = bin.join("sbatch");
    std::fs::write(
        &sbatch,
        "#!/bin/bash\narray=\"\"; wrap=\"\"\nfor a in \"$@\"; do case \"$a\" in --array=*) array=\"${a#--array=}\";; --wrap=*) wrap=\"${a#--wrap=}\";; esac; done\n\
         if [ -n \"$array\" ]; then for i in $(seq ${array%-*} ${array#*-}); do SLURM_ARRAY_TASK_ID=$i bash -c \"$wrap\" || exit 1; done; echo 42; else bash -c \"$wrap\"; fi\n",
    )
    .unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&sbatch, std::fs::Permissions::from_mode(0o755)).unwrap();
    let (single, array) = (dir.path().join("single"), dir.path().join("array"));
    let o = wakelab(&[
        "dataset",
        "--study",
        study.to_str().unwrap(),
        "--out",
        single.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = wakelab(&[
        "dataset",
        "--study",
        study.to_str().unwrap(),
        "--out",
        array.to_str().unwrap(),
        "--emit-slurm",
        "--tasks",
        "2",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap_or_default());
    let run = Command::new("bash")
        .arg(array.join("wakelab_dataset.slurm"))
        .env("PATH", path)
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    for f in [
        "manifest.json",
        "manifest.csv",
        "splits.json",
        "scenes/000002-w/X.npy",
        "scenes/000001-n/mask_MWIR.npy",
    ] {
        assert_eq!(
            std::fs::read(single.join(f)).unwrap(),
            std::fs::read(array.join(f)).unwrap(),
            "{f}"
        );
    }
}

/// A dataset run killed (SIGKILL) at several moments and resumed each time ends byte-identical to
/// an uninterrupted run.
#[test]
fn a_killed_dataset_run_resumes_to_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let study = dir.path().join("study.toml");
    std::fs::write(
        &study,
        "[study]\nname = \"k\"\ncombine = \"product\"\nseeds = 3\ntest_fraction = 0.25\ngrouped_split = false\n\
         min_visibility = 0.0\nmixed_layer_depth = 20.0\nbands = [\"S\", \"C\", \"X\", \"MWIR\", \"LWIR\"]\n\
         [axes]\nwind_speed = [4.0, 6.0, 9.0]\nimage_size = [96]\npixel_spacing = [10.0]\nalong_track = [2000.0]\n\
         [base]\npreset = \"quick\"\n[base.time]\nduration = 600.0\n",
    )
    .unwrap();
    let (whole, killed) = (dir.path().join("whole"), dir.path().join("killed"));
    let args = |out: &Path| {
        vec![
            "dataset".to_string(),
            "--study".into(),
            study.display().to_string(),
            "--out".into(),
            out.display().to_string(),
            "--quiet".into(),
        ]
    };
    let o = Command::new(env!("CARGO_BIN_EXE_wakelab"))
        .args(args(&whole))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    for delay_ms in [300u64, 700, 1100, 1500] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_wakelab"))
            .args(args(&killed))
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(delay_ms));
        let _ = child.kill();
        let _ = child.wait();
    }
    let o = Command::new(env!("CARGO_BIN_EXE_wakelab"))
        .args(args(&killed))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    for f in ["manifest.json", "manifest.csv", "splits.json"] {
        assert_eq!(
            std::fs::read(whole.join(f)).unwrap(),
            std::fs::read(killed.join(f)).unwrap(),
            "{f}"
        );
    }
    let manifest: Vec<serde_json::Value> =
        serde_json::from_slice(&std::fs::read(whole.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(manifest.len(), 18);
    for r in &manifest {
        for band in ["S", "C", "X", "MWIR", "LWIR"] {
            let p = r["images"][band].as_str().unwrap();
            assert_eq!(
                std::fs::read(whole.join(p)).unwrap(),
                std::fs::read(killed.join(p)).unwrap(),
                "{p}"
            );
        }
    }
    let leftovers = std::fs::read_dir(killed.join("scenes"))
        .unwrap()
        .flat_map(|d| std::fs::read_dir(d.unwrap().path()).unwrap())
        .filter(|e| e.as_ref().unwrap().file_name().to_string_lossy().ends_with(".tmp"))
        .count();
    assert_eq!(leftovers, 0, "temporary files left behind");
}

/// train, eval and detect on a small rendered dataset: files, metrics keys, the saved model used
/// on a plain image, and clear refusals of bad input.
#[test]
fn train_eval_and_detect_on_a_small_dataset() {
    let dir = tempfile::tempdir().unwrap();
    let study = dir.path().join("study.toml");
    std::fs::write(
        &study,
        "[study]\nname = \"l\"\ncombine = \"product\"\nseeds = 2\ntest_fraction = 0.34\ngrouped_split = false\n\
         min_visibility = 0.0\nmixed_layer_depth = 20.0\nbands = [\"X\"]\n\
         [axes]\nwind_speed = [5.0, 8.0, 11.0]\nimage_size = [32]\npixel_spacing = [10.0]\nalong_track = [2000.0]\n\
         [base]\npreset = \"quick\"\n[base.time]\nduration = 600.0\n",
    )
    .unwrap();
    let data = dir.path().join("data");
    let d = data.to_str().unwrap();
    let o = wakelab(&["dataset", "--study", study.to_str().unwrap(), "--out", d, "--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));

    let model = dir.path().join("x_unet.safetensors");
    let o = wakelab(&[
        "train",
        d,
        "--arch",
        "unet",
        "--bands",
        "X",
        "--epochs",
        "2",
        "--unet-epochs",
        "1",
        "--quiet",
        "--model",
        model.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("test split (4 scenes): MCC"), "{}", stdout(&o));
    assert!(model.exists() && dir.path().join("x_unet.pytorch.safetensors").exists());
    assert!(data.join("learn/X_unet_curve.csv").exists());

    let o = wakelab(&[
        "eval",
        d,
        "--arch",
        "base,cls",
        "--bands",
        "X",
        "--epochs",
        "2",
        "--repetitions",
        "2",
        "--quiet",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let metrics: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(metrics.as_array().unwrap().len(), 2);
    for key in [
        "bands",
        "architecture",
        "mcc",
        "mcc_spread",
        "accuracy",
        "accuracy_spread",
        "f1",
        "roc_auc",
        "tp",
        "fn",
    ] {
        assert!(metrics[0].get(key).is_some(), "no {key} in {}", metrics[0]);
    }
    let outputs = std::fs::read_to_string(data.join("learn/outputs.csv")).unwrap();
    assert!(
        outputs.starts_with("bands,architecture,repetition,split,scene,label,output"),
        "{outputs}"
    );
    // the study's test share, 4 of 12 scenes: 2 architectures x 2 repetitions x (2 wake + 2 no-wake)
    assert_eq!(outputs.lines().filter(|l| l.contains(",test,")).count(), 2 * 2 * 4);
    assert_eq!(outputs.lines().filter(|l| l.contains(",train,")).count(), 2 * 2 * 8);
    assert!(data.join("learn/models/X_cls.safetensors").exists());

    // detect on a plain image larger than the model's input: tiles, probability, mask PNG
    let image = data.join("scenes/000000-w/X.npy");
    let mask = dir.path().join("mask.png");
    let o = wakelab(&[
        "detect",
        image.to_str().unwrap(),
        "--model",
        model.to_str().unwrap(),
        "--mask",
        mask.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let det: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let p = det["probability"].as_f64().unwrap();
    assert!((0.0..=1.0).contains(&p));
    assert!(image::open(&mask).unwrap().width() == 32);

    let small = dir.path().join("small.npy");
    std::fs::write(&small, npy_f32_2x2()).unwrap();
    for (args, needle) in [
        (
            vec!["detect", small.to_str().unwrap(), "--model", model.to_str().unwrap()],
            "at least the detector's input, 32 x 32 pixels",
        ),
        (
            vec!["eval", d, "--arch", "resnet"],
            "--arch resnet: must be base, cls or unet",
        ),
        (vec!["eval", d, "--device", "tpu"], "--device"),
        (vec!["eval", d, "--bands", "Q"], "one of the dataset's bands"),
        (vec!["eval", d, "--repetitions", "0"], "repetitions"),
        (
            vec!["detect", image.to_str().unwrap(), "--model", study.to_str().unwrap()],
            "not a safetensors file",
        ),
    ] {
        let o = wakelab(&args);
        assert!(!o.status.success());
        assert!(stderr(&o).contains(needle), "{args:?}: {}", stderr(&o));
    }
}

/// A 2 x 2 float32 .npy file (NumPy format 1.0, header padded to 64 bytes).
fn npy_f32_2x2() -> Vec<u8> {
    let mut header = "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 2), }".to_string();
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend_from_slice(&(header.len() as u16).to_le_bytes());
    bytes.extend_from_slice(header.as_bytes());
    for v in [1.0f32, 2.0, 3.0, 4.0] {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    bytes
}

/// A study small enough for a test: 2 wind speeds x 2 seeds of 32 x 32 pixels in S, X and LWIR,
/// trained a few epochs with a narrow U-Net.
const TINY_STUDY: &str = "[study]\nname = \"tiny\"\ncombine = \"product\"\nseeds = 3\ntest_fraction = 0.34\n\
    grouped_split = false\nmin_visibility = 0.0\nmixed_layer_depth = 20.0\nbands = [\"S\", \"X\", \"LWIR\"]\n\
    [axes]\nwind_speed = [5.0, 8.0]\nimage_size = [32]\npixel_spacing = [20.0]\nalong_track = [2000.0]\n\
    [base]\npreset = \"quick\"\n[base.time]\nduration = 600.0\n\
    [learning]\nrepetitions = 2\nepochs = 2\nlearning_rate = 1e-2\nunet_epochs = 1\nunet_learning_rate = 1e-3\n\
    unet_width = 4\nrotations = [30.0]\nheld_out = \"wind_speed\"\n";

#[test]
fn run_does_the_whole_study_reuses_its_stages_and_repeats_its_tables() {
    let dir = tempfile::tempdir().unwrap();
    let study = dir.path().join("tiny.toml");
    std::fs::write(&study, TINY_STUDY).unwrap();
    let run = |out: &Path| {
        let o = wakelab(&[
            "run",
            "--study",
            study.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        o
    };
    let (first, second) = (dir.path().join("a"), dir.path().join("b"));
    let o = run(&first);
    // the headline table names every input and the decision-level fusions
    for needle in ["S+X", "Bayes classifier (S, X)", "Dempster-Shafer (S, X)", "LWIR"] {
        assert!(stdout(&o).contains(needle), "{needle}: {}", stdout(&o));
    }
    let report = first.join("report");
    let html = std::fs::read_to_string(report.join("report.html")).unwrap();
    for figure in [
        "sigma0_vs_cmod5n_upwind",
        "sigma0_vs_cmod5n_crosswind",
        "across_wake_contrast",
    ] {
        let svg = std::fs::read_to_string(report.join(format!("{figure}.svg"))).unwrap();
        assert!(svg.starts_with("<svg"), "{figure}");
    }
    // self-contained: every picture inline, nothing fetched from the network
    let namespaces = html.matches("xmlns=\"http://www.w3.org/2000/svg\"").count();
    assert_eq!(
        html.matches("http://").count(),
        namespaces,
        "only SVG namespaces, no links"
    );
    assert!(!html.contains("https://") && !html.contains("<script"));
    assert_eq!(
        html.matches("src=\"data:image/png;base64,").count(),
        3 * 3,
        "wake, no wake, mask per band"
    );
    assert_eq!(
        html.matches("<svg").count(),
        3 + 4 + 3,
        "ROC per architecture, training curves per network, sigma0 against CMOD5.N up- and cross-wind, \
         the across-wake contrast"
    );
    assert!(html.contains("CMOD5.N 10<") && html.contains("Across-wake contrast"));
    for needle in [
        "Table 4.4",
        "Table 4.6",
        "Table 5.1",
        "Table 5.3",
        "SAR + IR fusion",
        "Robustness",
        "rotate_30",
        "held-out environment",
        "Wall time per stage",
    ] {
        assert!(html.contains(needle), "report lacks {needle}");
    }
    for t in [
        "table_4_4_base",
        "table_5_2_cls",
        "sar_ir_fusion",
        "confusion",
        "robustness",
        "timing",
    ] {
        assert!(report.join("tables").join(format!("{t}.csv")).exists(), "{t}.csv");
    }
    // robustness: every perturbation and the held-out wind speeds have numbers for "base" on S
    let robustness = std::fs::read_to_string(report.join("tables/robustness.csv")).unwrap();
    let row = robustness.lines().find(|l| l.starts_with("base,S,")).unwrap();
    assert_eq!(
        row.split(',').filter(|c| c.contains('±')).count(),
        1 + 3 + 1,
        "{robustness}"
    );
    let timing: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(first.join("timing.json")).unwrap()).unwrap();
    let stages: Vec<&str> = timing
        .as_array()
        .unwrap()
        .iter()
        .map(|t| t["stage"].as_str().unwrap())
        .collect();
    assert_eq!(
        stages,
        ["dataset", "learning", "held-out environments", "fusion", "report"]
    );
    let markdown = std::fs::read_to_string(report.join("report.md")).unwrap();
    assert!(markdown.contains("| input | MCC | accuracy | AUC | paper MCC | paper accuracy |"));
    // the paper's numbers beside ours: Table 4.4's S row, Table 5.3's Bayes (S, X) row
    assert!(
        markdown.contains("| 0.29 | 61% |") && markdown.contains("| 1.00 | 100% |"),
        "{markdown}"
    );

    // a rerun reuses every stage and gives the same tables
    let tables = |root: &Path| -> Vec<(String, String)> {
        let mut v: Vec<(String, String)> = std::fs::read_dir(root.join("report/tables"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| !p.ends_with("timing.csv"))
            .map(|p| {
                let name = p.file_name().unwrap().to_string_lossy().to_string();
                (name, std::fs::read_to_string(&p).unwrap())
            })
            .collect();
        v.sort();
        v
    };
    let before = tables(&first);
    let o = run(&first);
    assert!(stderr(&o).contains("(reused; computed in"), "{}", stderr(&o));
    assert!(!stderr(&o).contains("done in"), "{}", stderr(&o));
    assert_eq!(before, tables(&first));
    // a run killed during one input's training resumes with that input alone
    std::fs::remove_file(first.join("learn/X/evaluation.json")).unwrap();
    let o = run(&first);
    let err = stderr(&o);
    assert!(
        err.contains("learning: X done in") && !err.contains("learning: S done in"),
        "{err}"
    );
    assert_eq!(before, tables(&first));
    // and a fresh run in another directory computes the same tables from scratch
    run(&second);
    assert_eq!(tables(&first), tables(&second));

    // bad [learning] values are refused before any work, naming the field
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, TINY_STUDY.replace("unet_width = 4", "unet_width = 1000")).unwrap();
    let out = dir.path().join("c");
    let o = wakelab(&[
        "run",
        "--study",
        bad.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("learning.unet_width") && stderr(&o).contains("[4, 256]"),
        "{}",
        stderr(&o)
    );
    assert!(!out.exists());
}

//! `wakelab train`, `eval` and `detect` as a user runs them.

mod common;

use common::*;

/// train, eval and detect on a small rendered dataset: files, metrics keys, the saved model used
/// on a plain image, and clear refusals of bad input.
#[test]
fn train_eval_and_detect_on_a_small_dataset() {
    let dir = tempfile::tempdir().unwrap();
    let study = dir.path().join("study.toml");
    let axes = "wind_speed = [5.0, 8.0, 11.0]\nimage_size = [32]\npixel_spacing = [10.0]\nalong_track = [2000.0]";
    std::fs::write(&study, study_text("l", 2, 0.34, "[\"X\"]", axes)).unwrap();
    let data = dir.path().join("data");
    let d = data.to_str().unwrap();
    let o = dataset(&study, &data, &["--quiet"]);
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
    let export = dir.path().join("x_unet.pytorch.safetensors");
    assert!(model.exists() && export.exists());
    assert!(data.join("learn/X_unet_curve.csv").exists());

    // 2 architectures x 2 repetitions of 2 epochs on X, then `extra`
    let eval_x = |extra: &[&str]| {
        let mut args = vec!["eval", d, "--arch", "base,cls", "--bands", "X", "--epochs", "2"];
        args.extend(["--repetitions", "2", "--quiet"]);
        args.extend_from_slice(extra);
        wakelab(&args)
    };
    let o = eval_x(&["--json"]);
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
    // the repetitions and architectures train in parallel: a second run writes the same bytes,
    // its rows in the sequential order (repetition, then architecture)
    let again = dir.path().join("again");
    let o = eval_x(&["--out", again.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(again.join("outputs.csv")).unwrap(), outputs);
    let order: Vec<(String, String)> = outputs
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[2].to_string(), f[1].to_string())
        })
        .collect();
    let mut blocks = order.clone();
    blocks.dedup();
    let expected: Vec<(String, String)> = [("0", "base"), ("0", "cls"), ("1", "base"), ("1", "cls")]
        .map(|(r, a)| (r.to_string(), a.to_string()))
        .to_vec();
    assert_eq!(blocks, expected);

    // detect on a plain image: windows, probability, the map, overlay, detections and mask
    let image = data.join("scenes/000000-w/X.npy");
    let mask = dir.path().join("mask.png");
    let scan = dir.path().join("scan");
    let o = wakelab(&[
        "detect",
        image.to_str().unwrap(),
        "--model",
        model.to_str().unwrap(),
        "--mask",
        mask.to_str().unwrap(),
        "--stride",
        "8",
        "--out",
        scan.to_str().unwrap(),
        "--json",
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let det: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let p = det["probability"].as_f64().unwrap();
    assert!((0.0..=1.0).contains(&p));
    assert_eq!((det["window"].as_u64(), det["stride"].as_u64()), (Some(32), Some(8)));
    // the verdict and the detections on stdout; every window only with --windows
    assert!(
        det["tiles"].is_null() && det["windows"] == 1 && det["detections"].is_array(),
        "{det}"
    );
    let with_windows = |extra: &[&str]| {
        let mut args = vec!["detect", image.to_str().unwrap(), "--model", model.to_str().unwrap()];
        let again = dir.path().join("scan_again");
        args.extend(["--json", "--quiet", "--out", again.to_str().unwrap()]);
        args.extend_from_slice(extra);
        wakelab(&args)
    };
    let o = with_windows(&["--windows"]);
    let det: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(det["tiles"].as_array().map(Vec::len), Some(1), "{det}");
    // an X-band detector on an image wakelab named LWIR: refused, unless --force
    let lwir = dir.path().join("LWIR.npy");
    std::fs::copy(&image, &lwir).unwrap();
    let o = wakelab(&[
        "detect",
        lwir.to_str().unwrap(),
        "--model",
        model.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("the input is LWIR infrared (from its name") && stderr(&o).contains("X-band SAR"),
        "{}",
        stderr(&o)
    );
    let mut forced = vec!["detect", lwir.to_str().unwrap(), "--model", model.to_str().unwrap()];
    let forced_out = dir.path().join("scan_forced");
    forced.extend(["--force", "--quiet", "--out", forced_out.to_str().unwrap()]);
    let o = wakelab(&forced);
    assert!(
        o.status.success() && stderr(&o).contains("scanned with --force"),
        "{}",
        stderr(&o)
    );
    assert!(image::open(&mask).unwrap().width() == 32);
    // a 32 px image in 8 px cells: a 4 x 4 map, with no georeference (a bare array has none)
    let map = scan.join("probability.tif");
    assert!(wakelab_core::io::geotiff::Georeference::read(&map).unwrap().is_none());
    // read as any TIFF reader does (`detect`'s own reader refuses a constant image, which this
    // map is)
    let mut decoder = tiff::decoder::Decoder::new(std::fs::File::open(&map).unwrap()).unwrap();
    assert_eq!(decoder.dimensions().unwrap(), (4, 4));
    let tiff::decoder::DecodingResult::F32(values) = decoder.read_image().unwrap() else {
        panic!("a float32 map")
    };
    // one window covers the whole image, so every cell holds its probability
    assert!(values.iter().all(|&v| (v as f64 - p).abs() < 1e-6), "{values:?}");
    let written: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(scan.join("detections.json")).unwrap()).unwrap();
    assert_eq!(written["probability"].as_f64(), Some(p));
    assert!(written["detections"].is_array() && written["georeferenced"] == false);
    assert!(scan.join("overlay.png").exists() && scan.join("mask.tif").exists());
    // GeoJSON of a bare array: features without a place on the Earth (RFC 7946's null geometry)
    let geojson: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(scan.join("detections.geojson")).unwrap()).unwrap();
    assert_eq!(geojson["type"], "FeatureCollection");
    for feature in geojson["features"].as_array().unwrap() {
        assert!(feature["geometry"].is_null() && feature["properties"]["kind"] == "window");
    }

    let small = dir.path().join("small.npy");
    std::fs::write(&small, npy_f32_2x2()).unwrap();
    for (args, needle) in [
        (
            vec!["detect", small.to_str().unwrap(), "--model", model.to_str().unwrap()],
            "at least half of the detector's 32 x 32-pixel input in view",
        ),
        (
            vec![
                "detect",
                image.to_str().unwrap(),
                "--model",
                model.to_str().unwrap(),
                "--stride",
                "0",
                "--out",
                scan.to_str().unwrap(),
            ],
            "--stride",
        ),
        (
            vec!["eval", d, "--arch", "resnet"],
            "'resnet' for '--arch <ARCH>': resnet: must be base, cls or unet",
        ),
        (vec!["eval", d, "--device", "tpu"], "--device"),
        (
            vec!["eval", d, "--bands", "Q"],
            "unknown band `Q`: one of S, C, X, MWIR, LWIR",
        ),
        (vec!["eval", d, "--bands", "S"], "one of the dataset's bands [\"X\"]"),
        (vec!["eval", d, "--repetitions", "0"], "repetitions"),
        (
            vec!["eval", d, "--weight-decay", "-1"],
            "`classifier.weight_decay` = -1: in [0, 10]",
        ),
        (
            vec!["eval", d, "--optimiser", "momentum"],
            "\"momentum\" is not an optimiser (allowed: sgd, adam)",
        ),
        (
            vec!["detect", image.to_str().unwrap(), "--model", study.to_str().unwrap()],
            "not a safetensors file",
        ),
        (
            vec!["detect", image.to_str().unwrap(), "--model", export.to_str().unwrap()],
            "the PyTorch-layout export of a detector, for loading into PyTorch; wakelab reads the detector itself (x_unet.safetensors beside it)",
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

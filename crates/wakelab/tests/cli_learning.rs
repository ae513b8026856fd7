//! `wakelab train`, `eval`, `detect` and `run` as a user runs them.

mod common;

use common::*;
use std::path::Path;

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
    assert!(model.exists() && dir.path().join("x_unet.pytorch.safetensors").exists());
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
    assert!(image::open(&mask).unwrap().width() == 32);
    // a 32 px image in 8 px cells: a 4 x 4 map, on the image's pixel grid scaled by the cell
    let map = scan.join("probability.tif");
    let geo = wakelab_core::io::geotiff::Georeference::read(&map).unwrap().unwrap();
    assert_eq!(geo.model_xy(1.0, 1.0), Some((8.0, -8.0)));
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
    assert!(scan.join("probability.json").exists());

    let small = dir.path().join("small.npy");
    std::fs::write(&small, npy_f32_2x2()).unwrap();
    for (args, needle) in [
        (
            vec!["detect", small.to_str().unwrap(), "--model", model.to_str().unwrap()],
            "at least the detector's input, 32 x 32 pixels",
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
            "--arch resnet: must be base, cls or unet",
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
    [draws]\nheading = [0.0, 360.0]\n[base]\npreset = \"quick\"\n[base.time]\nduration = 600.0\n\
    [learning]\nrepetitions = 2\nepochs = 2\nlearning_rate = 1e-2\nunet_epochs = 1\nunet_learning_rate = 1e-3\n\
    unet_width = 4\nrotations = [30.0]\nheld_out = \"wind_speed\"\n";

#[test]
fn run_does_the_whole_study_reuses_its_stages_and_repeats_its_tables() {
    let dir = tempfile::tempdir().unwrap();
    let study = dir.path().join("tiny.toml");
    std::fs::write(&study, TINY_STUDY).unwrap();
    let run = |out: &Path| {
        let o = run_study(&study, out, &["--quiet"]);
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
    // the grid of test scenes: per band and wind, base's highest and lowest wake and no-wake
    // test scene, each with every architecture's verdict; as a table and as thumbnails
    let grid = std::fs::read_to_string(report.join("tables/test_scenes.csv")).unwrap();
    let cells: Vec<Vec<&str>> = grid.lines().skip(1).map(|l| l.split(',').collect()).collect();
    assert!(!cells.is_empty(), "{grid}");
    let score = |c: &Vec<&str>| c[7].split(' ').next().unwrap().parse::<f64>().unwrap();
    for c in &cells {
        assert_eq!(c.len(), 10, "{c:?}");
        assert_eq!(c[3].ends_with("-w"), c[2].starts_with("wake"), "{c:?}");
        assert!(
            c[7..].iter().all(|v| v.ends_with(" right") || v.ends_with(" wrong")),
            "{c:?}"
        );
    }
    for pair in cells.windows(2) {
        let (a, b) = (&pair[0], &pair[1]);
        if a[..2] == b[..2] && a[2].contains("highest") && b[2].contains("lowest") && a[2][..4] == b[2][..4] {
            assert!(score(a) >= score(b), "{a:?} {b:?}");
        }
    }
    // the whole-scene scan: a row per single band (S, X, LWIR), three pictures each
    let whole = std::fs::read_to_string(report.join("tables/whole_scene.csv")).unwrap();
    let scanned: Vec<Vec<&str>> = whole.lines().skip(1).map(|l| l.split(',').collect()).collect();
    assert_eq!(
        scanned.iter().map(|r| r[0]).collect::<Vec<_>>(),
        ["S", "X", "LWIR"],
        "{whole}"
    );
    for r in &scanned {
        let p: f64 = r[1].parse().unwrap();
        assert!((0.0..=1.0).contains(&p) && ["yes", "no"].contains(&r[2]), "{r:?}");
    }
    assert_eq!(
        html.matches("src=\"data:image/png;base64,").count(),
        3 * 3 + cells.len() + 3 * scanned.len(),
        "wake, no wake, mask per band, the test scenes, and the whole scene per band"
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
        "mask_iou",
        "test_scenes",
        "whole_scene",
        "timing",
    ] {
        assert!(report.join("tables").join(format!("{t}.csv")).exists(), "{t}.csv");
    }
    // robustness: every perturbation and the held-out wind speeds have numbers for "base" on S
    let robustness = std::fs::read_to_string(report.join("tables/robustness.csv")).unwrap();
    let row = robustness.lines().find(|l| l.starts_with("base,S,")).unwrap();
    assert_eq!(
        row.split(',').filter(|c| c.contains('±')).count(),
        1 + 4 + 2,
        "clean, rotate_30, drop, noise, shift, held-out environment and heading: {robustness}"
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
        [
            "dataset",
            "learning",
            "held-out environments",
            "held-out geometry",
            "fusion",
            "report"
        ]
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
    // and a fresh run in another directory, as the Slurm jobs of `run --emit-slurm` (dataset
    // shards, merge, one job per input, held-out, report), computes the same outputs and tables
    let o = run_study(&study, &second, &["--emit-slurm", "--tasks", "3", "--device", "cpu"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!second.join("dataset").exists(), "--emit-slurm only writes the script");
    let script = second.join("wakelab_run.slurm");
    let text = std::fs::read_to_string(&script).unwrap();
    assert!(text.contains("for input in S X LWIR S+X; do"), "{text}");
    let jobs = submit_with_stand_in(&script, &stand_in_sbatch(dir.path()));
    assert!(jobs.status.success(), "{}", stderr(&jobs));
    let err = stderr(&jobs);
    for input in ["S", "X", "LWIR", "S+X"] {
        assert!(err.contains(&format!("learning: {input} done in")), "{err}");
        assert_eq!(
            std::fs::read(first.join("learn").join(input).join("outputs.csv")).unwrap(),
            std::fs::read(second.join("learn").join(input).join("outputs.csv")).unwrap(),
            "{input}"
        );
    }
    assert!(stdout(&jobs).contains("submitted: dataset array"), "{}", stdout(&jobs));
    assert_eq!(tables(&first), tables(&second));
    // the stage flags: an input not in the study, and --input without its stage
    let o = run_study(&study, &second, &["--stage", "learning", "--input", "C"]);
    assert!(
        !o.status.success() && stderr(&o).contains("--input C: not an input"),
        "{}",
        stderr(&o)
    );
    let o = run_study(&study, &second, &["--emit-slurm", "--stage", "held-out"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let o = wakelab(&["run", "--study", study.to_str().unwrap(), "--input", "S"]);
    assert!(
        !o.status.success() && stderr(&o).contains("--stage learning"),
        "{}",
        stderr(&o)
    );

    // `eval --study` on the run's dataset reads the study's recipe and reproduces the run's
    // outputs for an input bit for bit; recipe flags beside it are refused
    let eval_dir = dir.path().join("eval");
    let o = wakelab(&[
        "eval",
        first.join("dataset").to_str().unwrap(),
        "--study",
        first.join("study.toml").to_str().unwrap(),
        "--bands",
        "S",
        "--out",
        eval_dir.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read_to_string(eval_dir.join("outputs.csv")).unwrap(),
        std::fs::read_to_string(first.join("learn/S/outputs.csv")).unwrap()
    );
    let o = wakelab(&[
        "eval",
        first.join("dataset").to_str().unwrap(),
        "--study",
        "default",
        "--epochs",
        "3",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--epochs"), "{}", stderr(&o));

    // bad [learning] values are refused before any work, naming the field
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, TINY_STUDY.replace("unet_width = 4", "unet_width = 1000")).unwrap();
    let out = dir.path().join("c");
    let o = run_study(&bad, &out, &["--quiet"]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("learning.unet_width") && stderr(&o).contains("[4, 256]"),
        "{}",
        stderr(&o)
    );
    assert!(!out.exists());
}

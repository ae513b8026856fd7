//! `wakelab run` as a user runs it: the whole study, its stages reused, its tables repeated.

mod common;

use common::*;
use std::path::Path;

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
    let grid = read_table(&report.join("tables/test_scenes.csv"));
    let cells = &grid.rows;
    assert!(!cells.is_empty());
    let score = |c: &Vec<String>| c[grid.column("base")].parse::<f64>().unwrap();
    for c in cells {
        assert_eq!(c.len(), 13, "{c:?}");
        assert_eq!(c[3].ends_with("-w"), c[2].starts_with("wake"), "{c:?}");
        for a in ["base", "cls", "unet"] {
            c[grid.column(a)].parse::<f64>().unwrap();
            assert!(
                ["right", "wrong"].contains(&c[grid.column(&format!("{a} verdict"))].as_str()),
                "{c:?}"
            );
        }
    }
    for pair in cells.windows(2) {
        let (a, b) = (&pair[0], &pair[1]);
        if a[..2] == b[..2] && a[2].contains("highest") && b[2].contains("lowest") && a[2][..4] == b[2][..4] {
            assert!(score(a) >= score(b), "{a:?} {b:?}");
        }
    }
    // the whole-scene scan: a row per single band (S, X, LWIR), three pictures each
    let whole = read_table(&report.join("tables/whole_scene.csv"));
    let scanned = &whole.rows;
    assert_eq!(
        scanned.iter().map(|r| r[0].as_str()).collect::<Vec<_>>(),
        ["S", "X", "LWIR"]
    );
    for r in scanned {
        let p: f64 = r[1].parse().unwrap();
        assert!(
            (0.0..=1.0).contains(&p) && ["yes", "no"].contains(&r[2].as_str()),
            "{r:?}"
        );
        // the threshold calibrated on the detector's no-wake test chips, and the cells above it
        let t: f64 = r[6].parse().unwrap();
        assert!((0.0..=1.0).contains(&t), "{r:?}");
        for share in r[7..11].iter().filter(|v| !v.is_empty()) {
            let v: f64 = share.parse().unwrap();
            assert!((0.0..=1.0).contains(&v), "a share is a fraction: {r:?}");
        }
    }
    assert_eq!(
        html.matches("src=\"data:image/png;base64,").count(),
        cells.len(),
        "a thumbnail per test scene"
    );
    // fields as SVG figures (labels in SVG text, a scale bar, a legend per mask) around their raster
    let fields = html.matches("<svg class=\"field\"").count();
    assert_eq!(
        fields,
        3 * 3 + 3 * scanned.len(),
        "wake, no wake, mask per band, and the whole scene per band"
    );
    assert_eq!(html.matches("href=\"data:image/png;base64,").count(), fields);
    // the scale bar's label is the one text of size 10
    assert_eq!(html.matches("font-size=\"10\">").count(), fields, "a scale bar each");
    assert_eq!(
        html.matches(">no wake</text>").count(),
        3 + scanned.len(),
        "a class legend per mask"
    );
    assert_eq!(html.matches("<h2>Contents</h2>").count(), 1);
    let contents = html
        .split("<h2>Contents</h2>")
        .nth(1)
        .unwrap()
        .split("</ul>")
        .next()
        .unwrap();
    let entries: Vec<&str> = contents.split("</a>").filter_map(|e| e.rsplit('>').next()).collect();
    let unique: std::collections::BTreeSet<&&str> = entries.iter().collect();
    assert_eq!(
        unique.len(),
        entries.len(),
        "one contents entry per section: {entries:?}"
    );
    assert_eq!(
        html.matches("<svg").count() - fields,
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
        "Wall time per step",
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
        "spec_environments",
        "ships_and_wakes",
        "ships_scenes",
        "calibration",
        "timing",
    ] {
        assert!(report.join("tables").join(format!("{t}.csv")).exists(), "{t}.csv");
    }
    // the spec's three environments in the three radar bands, each called bright, dark or none
    let environments = read_table(&report.join("tables/spec_environments.csv"));
    assert_eq!(environments.rows.len(), 3 * 3);
    for row in &environments.rows {
        assert!(["bright", "dark", "none"].contains(&row[4].as_str()), "{row:?}");
    }
    // robustness: every perturbation and the held-out wind speeds have numbers for "base" on S
    let robustness = read_table(&report.join("tables/robustness.csv"));
    let row = robustness.rows.iter().find(|r| r[..2] == ["base", "S"]).unwrap();
    let means: Vec<usize> = (0..robustness.header.len())
        .filter(|&c| robustness.header[c].ends_with(" mean") && !row[c].is_empty())
        .collect();
    assert_eq!(
        means.len(),
        1 + 4 + 2,
        "clean, rotate_30, drop, noise, shift, held-out environment and heading: {:?}",
        robustness.header
    );
    // tidy tables: one number per field, missing values empty (pandas reads numbers, not text)
    for entry in std::fs::read_dir(report.join("tables")).unwrap() {
        let table = read_table(&entry.unwrap().path());
        for field in table.rows.iter().flatten() {
            assert!(
                !field.contains('±') && !field.ends_with('%') && field != "-",
                "{}: {field}",
                table.name
            );
        }
        let mcc: Vec<usize> = (0..table.header.len())
            .filter(|&c| table.header[c] == "MCC mean")
            .collect();
        for row in &table.rows {
            for &c in &mcc {
                assert!(
                    row[c].is_empty() || row[c].parse::<f64>().is_ok(),
                    "{}: {row:?}",
                    table.name
                );
            }
        }
    }
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
            "scan",
            "environments",
            "ships",
            "calibration",
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

/// A report table read back by the `csv` crate, as pandas would.
struct CsvTable {
    name: String,
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl CsvTable {
    fn column(&self, name: &str) -> usize {
        self.header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("{}: no column {name}", self.name))
    }
}

#[test]
fn a_dry_run_measures_every_stage_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let study = dir.path().join("tiny.toml");
    std::fs::write(&study, TINY_STUDY).unwrap();
    let out = dir.path().join("never");
    let o = run_study(&study, &out, &["--dry-run", "--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(!out.exists(), "a dry run wrote {}", out.display());
    assert!(text.contains("6 pairs (12 scenes) of 32 x 32"), "{text}");
    for stage in [
        "dataset: wakes",
        "dataset: scenes",
        "learning",
        "held-out environments",
        "held-out geometry",
        "total",
    ] {
        assert!(text.lines().any(|l| l.starts_with(stage)), "{stage}: {text}");
    }
    // 2 epochs x 8 training scenes x 2 repetitions x 4 inputs (S, X, LWIR, S+X) x 3 classifiers;
    // the U-Net 1 epoch x 8 x 2 x 4
    assert!(text.contains("384 classifier and 64 U-Net image-steps"), "{text}");
    assert!(text.contains("U-Net training step: peak"), "{text}");
    // no GPU is timed here: the GPU column says whose measured rates it carries
    assert!(
        text.contains("NVIDIA H100, wgpu (measured rates)") && text.contains("measured at 256 x 256 on 2026-11-26"),
        "the GPU's figures name the measurement they come from: {text}"
    );
}

fn read_table(path: &std::path::Path) -> CsvTable {
    let mut reader = csv::Reader::from_path(path).unwrap();
    let header = reader.headers().unwrap().iter().map(String::from).collect();
    let rows = reader
        .records()
        .map(|r| r.unwrap().iter().map(String::from).collect())
        .collect();
    CsvTable {
        name: path.display().to_string(),
        header,
        rows,
    }
}

//! `wakelab dataset` as a user runs it: bad studies, Slurm arrays, resuming a killed run.

mod common;

use common::*;
use std::path::Path;
use std::process::Command;

#[test]
fn dataset_refuses_bad_studies_before_work_and_emits_a_slurm_array() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, study_text("b", 1, 0.1, "[\"C\"]", "wind_speed = [-1.0]")).unwrap();
    let out = dir.path().join("ds");
    let o = dataset(&bad, &out, &["--quiet"]);
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
    let axes = "wind_speed = [5.0, 8.0, 11.0]\nimage_size = [32]\npixel_spacing = [10.0]\nalong_track = [2000.0]";
    std::fs::write(&study, study_text("s", 1, 0.5, "[\"X\", \"MWIR\"]", axes)).unwrap();
    let bin = stand_in_sbatch(dir.path());
    let (single, array) = (dir.path().join("single"), dir.path().join("array"));
    let o = dataset(&study, &single, &["--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = dataset(&study, &array, &["--emit-slurm", "--tasks", "2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    // each scene says where its images lie: a local grid of 32 x 32 pixels of 10 m
    let scene: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(single.join("scenes/000002-w/scene.json")).unwrap()).unwrap();
    let georeference = &scene["georeference"];
    assert_eq!(georeference["crs"], "local", "{scene}");
    assert_eq!(
        (georeference["rows"].as_u64(), georeference["pixel_spacing_m"].as_f64()),
        (Some(32), Some(10.0))
    );
    let run = submit_with_stand_in(&array.join("wakelab_dataset.slurm"), &bin);
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
    let bands = "[\"S\", \"C\", \"X\", \"MWIR\", \"LWIR\"]";
    let axes = "wind_speed = [4.0, 6.0, 9.0]\nimage_size = [96]\npixel_spacing = [10.0]\nalong_track = [2000.0]";
    std::fs::write(&study, study_text("k", 3, 0.25, bands, axes)).unwrap();
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
    let o = dataset(&study, &whole, &["--quiet"]);
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
    let o = dataset(&study, &killed, &["--quiet"]);
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

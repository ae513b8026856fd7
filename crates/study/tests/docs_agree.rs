//! The README and the command line's help state what the binary does: the default and paper
//! studies' sizes come from the embedded studies, and the run's time in `run --help` from the
//! latest measured default run in docs/results.md. Each check fails when the two drift apart.

use std::path::{Path, PathBuf};
use wakelab_study::load_study;

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn read(path: &str) -> String {
    std::fs::read_to_string(workspace().join(path)).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// "192 pairs of 32 x 32 pixels at 10 m, 3 repetitions" of an embedded study.
fn shape(name: &str) -> (usize, usize, f64, usize) {
    let study = load_study(name).unwrap();
    let pairs = study.pairs().unwrap();
    let sizes: std::collections::BTreeSet<usize> = pairs.iter().map(|p| p.combination.image_size).collect();
    let spacings: Vec<f64> = pairs.iter().map(|p| p.combination.pixel_spacing).collect();
    assert_eq!(sizes.len(), 1, "{name}: one image size, {sizes:?}");
    assert!(spacings.iter().all(|&d| d == spacings[0]), "{name}: one pixel spacing");
    let size = *sizes.first().unwrap();
    (pairs.len(), size, spacings[0], study.learning.repetitions)
}

#[test]
fn the_readme_describes_the_embedded_studies() {
    let readme = read("README.md").split_whitespace().collect::<Vec<_>>().join(" ");
    let (pairs, size, spacing, repetitions) = shape("default");
    let default = format!("{pairs} pairs of {size} x {size} pixels at {spacing} m, {repetitions} repetitions");
    assert!(readme.contains(&default), "README.md should say \"{default}\"");
    let (pairs, size, _, _) = shape("paper");
    let paper = format!("{pairs} pairs of {size} x {size}");
    assert!(readme.contains(&paper), "README.md should say \"{paper}\"");
}

/// The last "N min M s, peak RSS" of docs/results.md's default study: its latest measured run.
fn latest_default_run_minutes() -> f64 {
    let results = read("docs/results.md");
    let section = results
        .split("\n## ")
        .find(|s| s.starts_with("The default study"))
        .expect("docs/results.md has the default study's section");
    let flat = section.split_whitespace().collect::<Vec<_>>().join(" ");
    let (before, _) = flat
        .rsplit_once(" s, peak RSS")
        .expect("a measured run with its peak RSS");
    let words: Vec<&str> = before.rsplit(' ').take(4).collect();
    // words: [seconds, "min", minutes, ...]
    assert_eq!(words[1], "min", "{before}");
    let minutes: f64 = words[2].trim_start_matches("**").parse().unwrap();
    let seconds: f64 = words[0].parse().unwrap();
    minutes + seconds / 60.0
}

#[test]
fn the_help_states_the_measured_time_of_the_default_run() {
    let cli = read("crates/wakelab/src/cli.rs")
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    let minutes = latest_default_run_minutes().round();
    let said = format!("`default` (embedded, about {minutes} minutes on a 2-core machine)");
    assert!(cli.contains(&said), "run --help should say \"{said}\"");
}

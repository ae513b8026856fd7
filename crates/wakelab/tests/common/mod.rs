//! What the command-line tests share: running `wakelab`, its output, and small inputs.
#![allow(dead_code)] // each test file uses its own part

use std::path::Path;
use std::process::{Command, Output};

pub fn wakelab(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_wakelab"))
        .args(args)
        .output()
        .expect("wakelab runs")
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A study file on the `quick` wake shortened to 600 s: the `[study]` table with these bands
/// (a TOML list) and seeds, the given `[axes]` lines, and the rest as the tests need it.
pub fn study_text(name: &str, seeds: usize, test_fraction: f64, bands: &str, axes: &str) -> String {
    format!(
        "[study]\nname = \"{name}\"\ncombine = \"product\"\nseeds = {seeds}\ntest_fraction = {test_fraction}\n\
         grouped_split = false\nmin_visibility = 0.0\nmixed_layer_depth = 20.0\nbands = {bands}\n\
         [axes]\n{axes}\n[base]\npreset = \"quick\"\n[base.time]\nduration = 600.0\n"
    )
}

/// `wakelab scene --config CONFIG --out OUT` and any further arguments.
pub fn scene(config: &Path, out: &Path, more: &[&str]) -> Output {
    with_input_and_out(&["scene", "--config"], config, out, more)
}

/// `wakelab dataset --study STUDY --out OUT` and any further arguments.
pub fn dataset(study: &Path, out: &Path, more: &[&str]) -> Output {
    with_input_and_out(&["dataset", "--study"], study, out, more)
}

/// `wakelab run --study STUDY --out OUT` and any further arguments.
pub fn run_study(study: &Path, out: &Path, more: &[&str]) -> Output {
    with_input_and_out(&["run", "--study"], study, out, more)
}

fn with_input_and_out(command: &[&str], input: &Path, out: &Path, more: &[&str]) -> Output {
    let mut args = command.to_vec();
    args.extend([input.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    args.extend_from_slice(more);
    wakelab(&args)
}

/// The JSON a successful command printed.
pub fn json_of(o: &Output) -> serde_json::Value {
    assert!(o.status.success(), "{}", stderr(o));
    serde_json::from_str(&stdout(o)).unwrap()
}

/// A grid small enough to simulate in a second.
pub const TINY: &str = r#"
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

/// A stand-in `sbatch` in `dir/bin` (prepend it to PATH): it runs each job's `--wrap` command at
/// once, an array's tasks one after the other with SLURM_ARRAY_TASK_ID set, fails as the job
/// fails, and prints a job id as `sbatch --parsable` does on a cluster ("id;cluster"). Jobs run in
/// the order they are submitted, which every script's dependencies allow.
pub fn stand_in_sbatch(dir: &Path) -> std::path::PathBuf {
    let bin = dir.join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    let sbatch = bin.join("sbatch");
    std::fs::write(
        &sbatch,
        "#!/bin/bash\narray=\"\"; wrap=\"\"\nfor a in \"$@\"; do case \"$a\" in --array=*) array=\"${a#--array=}\";; --wrap=*) wrap=\"${a#--wrap=}\";; esac; done\n\
         if [ -n \"$array\" ]; then for i in $(seq ${array%-*} ${array#*-}); do SLURM_ARRAY_TASK_ID=$i bash -c \"$wrap\" >&2 || exit 1; done;\n\
         else bash -c \"$wrap\" >&2 || exit 1; fi\necho \"$RANDOM;cluster\"\n",
    )
    .unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&sbatch, std::fs::Permissions::from_mode(0o755)).unwrap();
    bin
}

/// `bash SCRIPT` with the stand-in `sbatch` of [`stand_in_sbatch`] first on PATH.
pub fn submit_with_stand_in(script: &Path, bin: &Path) -> Output {
    let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap_or_default());
    Command::new("bash").arg(script).env("PATH", path).output().unwrap()
}

/// GDAL's COG validator (python3-gdal) passes the file.
pub fn assert_valid_cog(path: &Path) {
    let check = Command::new("/usr/bin/python3")
        .args(["-m", "osgeo_utils.samples.validate_cloud_optimized_geotiff"])
        .arg(path)
        .output()
        .expect("python3-gdal's COG validator (apt-get install python3-gdal)");
    let said = String::from_utf8_lossy(&check.stdout).to_string() + &String::from_utf8_lossy(&check.stderr);
    assert!(check.status.success(), "{}: {said}", path.display());
}

//! Every bad input wakelab refuses, one case per class of defect: each must exit with code 1
//! (a refused input) or 2 (a refused command line), never panic, name the field or file at
//! fault in its message, and leave no output behind.

mod common;
use common::*;
use ndarray::Array2;
use std::path::{Path, PathBuf};

/// One bad input: the arguments (with `{dir}` for the case's scratch directory and `{out}` for
/// the output it must not leave), the exit code, and what the message must name.
struct Case {
    name: &'static str,
    args: Vec<String>,
    code: i32,
    needles: &'static [&'static str],
}

fn case(name: &'static str, args: &str, code: i32, needles: &'static [&'static str]) -> Case {
    Case {
        name,
        args: args.split(' ').map(String::from).collect(),
        code,
        needles,
    }
}

const AXES: &str = "wind_speed = [5.0, 8.0]\nimage_size = [32]\npixel_spacing = [20.0]\nalong_track = [2000.0]";

/// `path` as text, for arguments.
fn text(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// A copy of the dataset directory `from` at `to`, every file of every subdirectory.
fn copy_dataset(from: &Path, to: &Path) {
    for entry in walk(from) {
        let target = to.join(entry.strip_prefix(from).unwrap());
        std::fs::create_dir_all(target.parent().unwrap()).unwrap();
        std::fs::copy(&entry, &target).unwrap();
    }
}

fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            files.extend(walk(&p));
        } else {
            files.push(p);
        }
    }
    files
}

/// The safetensors file at `from` with one metadata value changed, written to `to`.
fn with_metadata(from: &Path, to: &Path, key: &str, value: &str) {
    let bytes = std::fs::read(from).unwrap();
    let n = u64::from_le_bytes(bytes[..8].try_into().unwrap()) as usize;
    let mut header: serde_json::Value = serde_json::from_slice(&bytes[8..8 + n]).unwrap();
    header["__metadata__"][key] = value.into();
    let mut h = serde_json::to_vec(&header).unwrap();
    while h.len() % 8 != 0 {
        h.push(b' ');
    }
    let mut out = (h.len() as u64).to_le_bytes().to_vec();
    out.extend(h);
    out.extend(&bytes[8 + n..]);
    std::fs::write(to, out).unwrap();
}

#[test]
fn every_bad_input_is_refused_by_name_without_a_panic_or_leftovers() {
    let root = tempfile::tempdir().unwrap();
    let dir = root.path();
    // fixtures: a small dataset, a detector trained on it, and broken copies of both
    let study = dir.join("ok.toml");
    std::fs::write(&study, study_text("ok", 3, 0.34, "[\"S\"]", AXES)).unwrap();
    let data = dir.join("data");
    let o = dataset(&study, &data, &["--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let models = dir.join("models");
    let o = wakelab(&[
        "train",
        text(&data),
        "--bands",
        "S",
        "--epochs",
        "1",
        "--out",
        text(&models),
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let model = models.join("S_base.safetensors");
    with_metadata(&model, &dir.join("edited.safetensors"), "wakelab.input_size", "64");
    with_metadata(
        &model,
        &dir.join("old.safetensors"),
        "wakelab.format",
        "wakelab-detector-1",
    );
    // a NaN pixel in one image; one image of another shape
    let nan_data = dir.join("nan_data");
    copy_dataset(&data, &nan_data);
    let image = nan_data.join("scenes/000000-w/S.npy");
    let mut pixels: Array2<f32> = ndarray_npy::read_npy(&image).unwrap();
    pixels[[3, 4]] = f32::NAN;
    ndarray_npy::write_npy(&image, &pixels).unwrap();
    let shape_data = dir.join("shape_data");
    copy_dataset(&data, &shape_data);
    ndarray_npy::write_npy(shape_data.join("scenes/000001-n/S.npy"), &Array2::<f32>::ones((24, 24))).unwrap();
    // images for detect
    let mut scene = Array2::<f32>::from_shape_fn((48, 48), |(r, c)| 0.01 + 1e-4 * ((r * 7 + c * 13) % 17) as f32);
    ndarray_npy::write_npy(dir.join("constant.npy"), &Array2::<f32>::from_elem((48, 48), 0.05)).unwrap();
    scene[[10, 10]] = f32::INFINITY;
    ndarray_npy::write_npy(dir.join("inf.npy"), &scene).unwrap();
    image::RgbImage::from_pixel(48, 48, image::Rgb([10, 200, 30]))
        .save(dir.join("rgb.png"))
        .unwrap();
    // silent wrong answers refused: the scene in dB under the default linear scale, a 3-D
    // array, a truncated array, a file that is no image
    let sea = scene.mapv(|v| if v.is_finite() { v } else { 0.01 });
    ndarray_npy::write_npy(dir.join("db.npy"), &sea.mapv(|v| 10.0 * v.log10())).unwrap();
    ndarray_npy::write_npy(dir.join("cube.npy"), &ndarray::Array3::<f32>::zeros((3, 48, 48))).unwrap();
    ndarray_npy::write_npy(dir.join("full.npy"), &sea).unwrap();
    let bytes = std::fs::read(dir.join("full.npy")).unwrap();
    std::fs::write(dir.join("cut.npy"), &bytes[..bytes.len() - 1000]).unwrap();
    std::fs::write(dir.join("text.tif"), "plain text, not a TIFF").unwrap();
    // bad studies
    let study_with = |name: &str, axes: &str| {
        let path = dir.join(name);
        std::fs::write(&path, study_text("bad", 1, 0.34, "[\"S\"]", axes)).unwrap();
    };
    study_with("small.toml", &AXES.replace("[32]", "[16]"));
    study_with("odd.toml", &AXES.replace("[32]", "[36]"));
    study_with("swell.toml", &format!("{AXES}\nswell_direction = [\"opposing\"]"));
    std::fs::write(dir.join("a_file"), "not a directory").unwrap();

    let cases = [
        case(
            "image side below the classifiers'",
            "dataset --study {dir}/small.toml --out {out}",
            1,
            &["axes.image_size", "16", "24, 32"],
        ),
        case(
            "image side the U-Net cannot pool",
            "run --study {dir}/odd.toml --out {out} --quiet",
            1,
            &["axes.image_size", "36", "multiple of 8"],
        ),
        case(
            "unknown swell direction",
            "dataset --study {dir}/swell.toml --out {out}",
            1,
            &["opposing", "calm, following, head, beam"],
        ),
        case(
            "merge with nothing rendered",
            "dataset --study {dir}/ok.toml --out {out} --merge",
            1,
            &["no finished scene", "{out}"],
        ),
        case(
            "NaN pixel in a dataset",
            "train {dir}/nan_data --bands S --epochs 1 --out {out} --quiet",
            1,
            &["000000-w/S.npy", "NaN"],
        ),
        case(
            "images of different shapes",
            "train {dir}/shape_data --bands S --epochs 1 --out {out} --quiet",
            1,
            &["000001-n/S.npy", "24 x 24", "image_size is 32"],
        ),
        case(
            "infinite pixel in detect",
            "detect {dir}/inf.npy --model {dir}/models/S_base.safetensors --out {out}",
            1,
            &["inf.npy", "1 infinite pixel(s)"],
        ),
        case(
            "ship false-alarm probability out of range",
            "detect {dir}/inf.npy --model {dir}/models/S_base.safetensors --out {out} --ship-pfa 0.5",
            1,
            &["--ship-pfa", "0.5", "at most 0.01"],
        ),
        case(
            "unknown peak rule",
            "detect {dir}/inf.npy --model {dir}/models/S_base.safetensors --out {out} --peak strongest",
            2,
            &["--peak", "strongest", "`line` or `network`"],
        ),
        case(
            "constant image in detect",
            "detect {dir}/constant.npy --model {dir}/models/S_base.safetensors --out {out}",
            1,
            &["constant.npy", "constant"],
        ),
        case(
            "colour image in detect",
            "detect {dir}/rgb.png --model {dir}/models/S_base.safetensors --out {out}",
            1,
            &["rgb.png", "has 3 bands"],
        ),
        case(
            "dB image read as linear",
            "detect {dir}/db.npy --model {dir}/models/S_base.safetensors --out {out}",
            1,
            &["--scale", "2304 of 2304 valid pixels are negative", "--scale db"],
        ),
        case(
            "3-D array in detect",
            "detect {dir}/cube.npy --model {dir}/models/S_base.safetensors --out {out}",
            1,
            &["cube.npy", "a 3-D array of shape [3, 48, 48]"],
        ),
        case(
            "truncated array in detect",
            "detect {dir}/cut.npy --model {dir}/models/S_base.safetensors --out {out}",
            1,
            &["cut.npy", "needs 9216 bytes of data, the file holds 8216: truncated"],
        ),
        case(
            "a file that is no image",
            "detect {dir}/text.tif --model {dir}/models/S_base.safetensors --out {out}",
            1,
            &["text.tif", "not an image GDAL reads"],
        ),
        case(
            "a polarisation the input lacks",
            "calibrate {dir}/full.npy --pol VH --out {out}",
            1,
            &["--pol", "VH", "full.npy holds one band"],
        ),
        case(
            "metadata that does not fit the weights",
            "detect {dir}/inf.npy --model {dir}/edited.safetensors --out {out}",
            1,
            &["edited.safetensors", "64 x 64", "classifier.linear1.weight"],
        ),
        case(
            "detector of an older format",
            "detect {dir}/inf.npy --model {dir}/old.safetensors --out {out}",
            1,
            &["old.safetensors", "retrain"],
        ),
        case(
            "negative learning rate",
            "train {dir}/data --learning-rate -1 --out {out} --quiet",
            1,
            &["learning_rate", "-1", "(0, 10]"],
        ),
        case(
            "recipe flags beside --study",
            "eval {dir}/data --study default --epochs 3 --out {out}",
            2,
            &["--epochs", "--study"],
        ),
        case(
            "unknown device",
            "train {dir}/data --device tpu --out {out} --quiet",
            1,
            &["--device", "tpu", "cpu"],
        ),
        case(
            "output path that is a file",
            "dataset --study {dir}/ok.toml --out {dir}/a_file/sub",
            1,
            &["a_file/sub", "Not a directory"],
        ),
        case(
            "real sea for a study without transfer",
            "run --study {dir}/ok.toml --sea-images {dir} --out {out} --quiet",
            1,
            &["--sea-images", "only the transfer study", "--study transfer"],
        ),
        case(
            "a transfer study as Slurm jobs",
            "run --study transfer --emit-slurm --out {out}",
            1,
            &[
                "--emit-slurm applies to a chip study",
                "\"transfer\" is a transfer study",
            ],
        ),
        case(
            "one stage of a transfer study",
            "run --study transfer --stage held-out --out {out} --quiet",
            1,
            &["--stage applies to a chip study", "run it whole"],
        ),
        case(
            "real sea that is no folder",
            "run --study transfer --sea-images {dir}/a_file --out {out} --quiet",
            1,
            &[
                "transfer.sea_images",
                "a_file",
                "a folder of real SAR images without wakes",
            ],
        ),
        case(
            "real wakes for a study without transfer",
            "run --study {dir}/ok.toml --wake-images {dir} --out {out} --quiet",
            1,
            &["--wake-images", "only the transfer study", "--study transfer"],
        ),
        case(
            "real wakes that are no folder",
            "run --study transfer --wake-images {dir}/a_file --out {out} --quiet",
            1,
            &["transfer.wake_images", "a_file", "NAME.geojson drawing its wakes"],
        ),
    ];
    for c in &cases {
        let out = dir.join(format!("out-{}", c.name.replace(' ', "_")));
        let fill = |s: &str| s.replace("{dir}", text(dir)).replace("{out}", text(&out));
        let args: Vec<String> = c.args.iter().map(|a| fill(a)).collect();
        let o = wakelab(&args.iter().map(String::as_str).collect::<Vec<_>>());
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(c.code), "{}: {err}", c.name);
        assert!(!err.contains("panicked"), "{}: {err}", c.name);
        for needle in c.needles {
            assert!(
                err.contains(&fill(needle)),
                "{}: the message lacks {needle:?}: {err}",
                c.name
            );
        }
        // an I/O error is said once, not once per level of its chain
        assert!(err.matches("(os error").count() <= 1, "{}: {err}", c.name);
        assert!(!out.exists(), "{}: left {}", c.name, out.display());
    }
    assert_eq!(std::fs::read_to_string(dir.join("a_file")).unwrap(), "not a directory");
}

/// A study changed under the same dataset directory re-renders what changed instead of reusing
/// the other study's scenes: the manifest says what the new study made.
#[test]
fn a_changed_study_re_renders_its_scenes_instead_of_reusing_them() {
    let root = tempfile::tempdir().unwrap();
    let dir = root.path();
    let (a, b) = (dir.join("a.toml"), dir.join("b.toml"));
    std::fs::write(&a, study_text("a", 1, 0.34, "[\"S\"]", AXES)).unwrap();
    std::fs::write(&b, study_text("b", 1, 0.34, "[\"S\"]", &AXES.replace("[32]", "[24]"))).unwrap();
    let data = dir.join("data");
    let image_sizes = || -> Vec<u64> {
        let m: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(data.join("manifest.json")).unwrap()).unwrap();
        m.as_array()
            .unwrap()
            .iter()
            .map(|r| r["image_size"].as_u64().unwrap())
            .collect()
    };
    assert!(dataset(&a, &data, &["--quiet"]).status.success());
    assert_eq!(image_sizes(), [32; 4]);
    let o = dataset(&b, &data, &["--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("4 re-rendered"), "{}", stderr(&o));
    assert_eq!(image_sizes(), [24; 4]);
    let pixels: Array2<f32> = ndarray_npy::read_npy(data.join("scenes/000000-w/S.npy")).unwrap();
    assert_eq!(pixels.dim(), (24, 24));
    // the same study again reuses every scene
    let o = dataset(&b, &data, &["--quiet"]);
    assert!(
        stderr(&o).contains("rendered 0 scenes (4 already done)"),
        "{}",
        stderr(&o)
    );
}

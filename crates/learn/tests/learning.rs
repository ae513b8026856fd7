//! The learning stage against outside references: finite differences for the gradients, a task
//! with a known answer (a line on noise) and its null (shuffled labels), bit-for-bit
//! reproducibility, and the saved-model round trip.

use burn::module::{Module, ModuleMapper, ModuleVisitor, Param};
use burn::tensor::Gradients;
use burn::tensor::{Device, Int, Tensor, TensorData};
use wakelab_learn::evaluate::{detect, train_detector, EvalOptions};
use wakelab_learn::metrics::Confusion;
use wakelab_learn::models::{init_seeded, Architecture, UNet, WakeClassifier};
use wakelab_learn::store::{load_detector, save_detector, ModelInfo};
use wakelab_learn::synthetic::{examples, line_versus_noise};
use wakelab_learn::train::{bce_with_logits, unet_loss, Recipe};

/// A fixed, parameter-independent direction: element j of parameter k is sin(0.7 j + 1.3 k).
fn direction(dims: &[usize], k: usize, device: &Device) -> Tensor<1> {
    let n: usize = dims.iter().product();
    let v: Vec<f32> = (0..n).map(|j| (0.7 * j as f32 + 1.3 * k as f32).sin()).collect();
    Tensor::from_data(TensorData::new(v, [n]), device)
}

/// Sum over parameters of <gradient, direction>.
struct DirectionalDerivative<'a> {
    grads: &'a Gradients,
    k: usize,
    total: f64,
}

impl ModuleVisitor for DirectionalDerivative<'_> {
    fn visit_float<const D: usize>(&mut self, param: &Param<Tensor<D>>) {
        let value = param.val();
        let dims = value.dims();
        if let Some(g) = value.grad(self.grads) {
            let d = direction(&dims, self.k, &g.device());
            let dot: Tensor<1> = (g.flatten::<1>(0, D - 1) * d).sum();
            self.total += dot.into_data().try_to_vec::<f32>().unwrap()[0] as f64;
        }
        self.k += 1;
    }
}

/// Parameters moved by `step` along the direction.
struct Shift {
    step: f32,
    k: usize,
}

impl ModuleMapper for Shift {
    fn map_float<const D: usize>(&mut self, param: Param<Tensor<D>>) -> Param<Tensor<D>> {
        let k = self.k;
        self.k += 1;
        let step = self.step;
        param.map(|t| {
            let dims = t.dims();
            let d: Tensor<D> = direction(&dims, k, &t.device()).reshape(dims);
            t + d * step
        })
    }
}

/// Central difference of `loss` along the direction against the autodiff directional derivative.
fn check_gradient<M: Module>(model: M, loss: impl Fn(&M) -> Tensor<1>) -> (f64, f64) {
    let grads = loss(&model).backward();
    let mut visitor = DirectionalDerivative {
        grads: &grads,
        k: 0,
        total: 0.0,
    };
    model.visit(&mut visitor);
    let analytic = visitor.total;
    let h = 2e-4;
    let value = |m: &M| loss(m).into_data().try_to_vec::<f32>().unwrap()[0] as f64;
    let plus = value(&model.clone().map(&mut Shift { step: h, k: 0 }));
    let minus = value(&model.map(&mut Shift { step: -h, k: 0 }));
    let numeric = (plus - minus) / (2.0 * h as f64);
    (analytic, numeric)
}

fn assert_close(analytic: f64, numeric: f64, what: &str) {
    let err = (analytic - numeric).abs() / numeric.abs().max(1e-3);
    assert!(
        err < 0.03,
        "{what}: autodiff {analytic} vs finite difference {numeric} ({:.2} %)",
        100.0 * err
    );
    eprintln!(
        "{what}: autodiff {analytic:.6} finite difference {numeric:.6} ({:.3} %)",
        100.0 * err
    );
}

#[test]
fn every_model_loss_gradient_matches_finite_differences() {
    let device = Device::flex().autodiff();
    let samples = examples(&line_versus_noise(4, 24, 3.0, 11));
    // "unet" reads the image and a mask; the others the image once or twice
    let images = |channels: usize, with_mask: bool| {
        let mut v = Vec::new();
        for e in &samples {
            v.extend(e.image.iter().copied());
            if channels == 2 {
                let second = if with_mask {
                    e.mask.as_ref().unwrap()
                } else {
                    &e.image.index_axis(ndarray::Axis(0), 0).to_owned()
                };
                v.extend(second.iter().copied());
            }
        }
        Tensor::<4>::from_data(TensorData::new(v, [4, channels, 24, 24]), &device)
    };
    let labels = Tensor::<1, Int>::from_data(TensorData::new(vec![1i64, 0, 1, 0], [4]), &device);
    for arch in Architecture::ALL {
        let c = arch.classifier_channels(1);
        let model = init_seeded(3, &device, |d| WakeClassifier::new(c, 24, d));
        let x = images(c, arch == Architecture::Unet);
        let (a, n) = check_gradient(model, |m| bce_with_logits(m.forward(x.clone()), labels.clone()));
        assert_close(a, n, &format!("classifier \"{arch}\""));
    }
    let unet = init_seeded(4, &device, |d| UNet::new(1, d));
    let x = images(1, false).slice([0..2, 0..1, 0..16, 0..16]);
    let mut m = Vec::new();
    for e in &samples[..2] {
        m.extend(
            e.mask
                .as_ref()
                .unwrap()
                .slice(ndarray::s![..16, ..16])
                .iter()
                .map(|&v| v as i64),
        );
    }
    let masks = Tensor::<4, Int>::from_data(TensorData::new(m, [2, 1, 16, 16]), &device);
    let (a, n) = check_gradient(unet, |u| unet_loss(u.forward(x.clone()), masks.clone()));
    assert_close(a, n, "U-Net");
}

/// The spec's recipes, shortened, with the classifiers' SGD learning rate raised from 1e-3 to
/// 1e-2: at 1e-3 (and L2 0.1) SGD needs about ten times as many steps as "a few epochs" give.
fn quick_options() -> EvalOptions {
    let mut o = EvalOptions::spec(&[wakelab_schema::band::Band::S]);
    o.classifier = Recipe {
        epochs: 10,
        batch_size: 8,
        learning_rate: 1e-2,
        ..Recipe::classifier()
    };
    o.unet = Recipe {
        epochs: 4,
        ..Recipe::unet()
    };
    o
}

fn mcc_of(outputs: &[f64], labels: &[u8]) -> f64 {
    Confusion::from_outputs(outputs, labels, 0.5).mcc()
}

/// A line of one noise deviation, about one pixel wide, is faint in every pixel, but a line sum
/// holds about one of its pixels per pixel of its length, each at 0.6-0.85 of its peak (as the
/// line falls in the sum's offset bin), so over its 32-45 pixels it sums to 3.4-5.7 deviations,
/// against the noise's largest line sum of about 3.5: the images' largest line sum tells lines
/// from noise, their largest pixel hardly does. And a scan of a detector reading line sums
/// reads its windows as its training and testing did.
#[test]
fn line_sums_show_a_faint_line_and_the_scan_reads_them_alike() {
    use wakelab_learn::detect::{detect_image, ScanOptions};
    use wakelab_learn::evaluate::detect_with_masks;
    use wakelab_learn::line_sums::line_sums;
    use wakelab_schema::architecture::InputForm;
    let test = line_versus_noise(200, 32, 1.0, 12);
    let labels: Vec<u8> = test.iter().map(|s| s.label).collect();
    let largest = |a: &ndarray::Array2<f32>| a.iter().fold(f32::MIN, |m, &v| m.max(v)) as f64;
    let by_sums: Vec<f64> = test.iter().map(|s| largest(&line_sums(&s.image))).collect();
    let by_pixels: Vec<f64> = test.iter().map(|s| largest(&s.image)).collect();
    let (sums_auc, pixels_auc) = (auc(&by_sums, &labels), auc(&by_pixels, &labels));
    eprintln!("largest line sum: AUC {sums_auc:.3}; largest pixel: AUC {pixels_auc:.3}");
    assert!(sums_auc > 0.9, "line sums: AUC {sums_auc}");
    assert!(pixels_auc < 0.75, "pixels: AUC {pixels_auc}");

    let device = Device::flex();
    let train = examples(&line_versus_noise(64, 32, 1.0, 11));
    let mut options = quick_options();
    options.classifier.epochs = 2;
    options.classifier.input = InputForm::LineSums;
    let detector = train_detector(Architecture::Base, &train, &options, 7, &device, &mut |_, _| {}).unwrap();
    let info = scan_info("S", InputForm::LineSums);
    // a window of sigma0 whose dB is a test image (the scan reads radar pixels in dB)
    let image = test[0].image.mapv(|v| 10f32.powf(v / 10.0));
    let scan = detect_image(
        &detector,
        &info,
        &image,
        ScanOptions::default(),
        &device,
        &mut |_, _| {},
    )
    .unwrap();
    let window = wakelab_learn::train::Example {
        image: wakelab_learn::data::detector_input(
            image,
            wakelab_schema::band::Band::S,
            wakelab_learn::data::RadarScale::Linear,
        )
        .insert_axis(ndarray::Axis(0)),
        label: 1,
        mask: None,
    };
    let alone = |form| {
        detect_with_masks(
            &detector,
            Architecture::Base,
            form,
            std::slice::from_ref(&window),
            1,
            &device,
        )
        .0[0]
    };
    // the scan makes the line sums once, for the network and the window's line: the same bits
    assert_eq!(scan.tiles[0].probability, alone(InputForm::LineSums));
    assert!((scan.tiles[0].probability - alone(InputForm::Pixels)).abs() > 1e-4);

    // so does a "cls" detector, whose second channel is a copy of the first
    let cls = train_detector(Architecture::Cls, &train, &options, 7, &device, &mut |_, _| {}).unwrap();
    let info = detector_info(Architecture::Cls, "S", 32, InputForm::LineSums);
    let image = test[0].image.mapv(|v| 10f32.powf(v / 10.0));
    let scan = detect_image(&cls, &info, &image, ScanOptions::default(), &device, &mut |_, _| {}).unwrap();
    let alone = detect_with_masks(
        &cls,
        Architecture::Cls,
        InputForm::LineSums,
        std::slice::from_ref(&window),
        1,
        &device,
    );
    assert_eq!(scan.tiles[0].probability, alone.0[0]);
}

/// A "base" detector of 32-pixel windows of `bands` at threshold 0.5, reading `input_form`.
fn scan_info(bands: &str, input_form: wakelab_schema::architecture::InputForm) -> ModelInfo {
    detector_info(Architecture::Base, bands, 32, input_form)
}

/// A detector's metadata: `architecture` on windows of `input_size` of `bands`, threshold 0.5,
/// no spacing, looks, scale or calibration.
fn detector_info(
    architecture: Architecture,
    bands: &str,
    input_size: usize,
    input_form: wakelab_schema::architecture::InputForm,
) -> ModelInfo {
    ModelInfo {
        architecture,
        bands: bands.parse().unwrap(),
        input_size,
        threshold: 0.5,
        unet_width: wakelab_learn::models::UNET_WIDTH,
        pixel_spacing: None,
        looks: None,
        input_scale: None,
        calibration: None,
        input_form,
        head: Default::default(),
    }
}

/// The area under the ROC curve: the chance that a positive scores above a negative (ties half).
fn auc(scores: &[f64], labels: &[u8]) -> f64 {
    let (mut wins, mut pairs) = (0.0, 0.0);
    for (s, _) in scores.iter().zip(labels).filter(|(_, &l)| l == 1) {
        for (t, _) in scores.iter().zip(labels).filter(|(_, &l)| l == 0) {
            wins += if s > t {
                1.0
            } else if s == t {
                0.5
            } else {
                0.0
            };
            pairs += 1.0;
        }
    }
    wins / pairs
}

#[test]
fn every_architecture_learns_a_line_on_noise_and_not_shuffled_labels() {
    let device = Device::flex();
    let options = quick_options();
    let train = examples(&line_versus_noise(128, 32, 3.0, 1));
    let test = examples(&line_versus_noise(40, 32, 3.0, 2));
    let labels: Vec<u8> = test.iter().map(|e| e.label).collect();
    for arch in Architecture::ALL {
        let detector = train_detector(arch, &train, &options, 7, &device, &mut |_, _| {}).unwrap();
        let mcc = mcc_of(&detect(&detector, arch, &test, &device), &labels);
        eprintln!("{arch}: test MCC {mcc:.3}");
        assert!(mcc > 0.9, "\"{arch}\" reached MCC {mcc} on the line-versus-noise task");
    }
    // the null: labels shuffled at random carry no information about the images
    let mut shuffled = train.clone();
    let mut rng_state = 12345u64;
    for i in (1..shuffled.len()).rev() {
        rng_state = rng_state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let j = (rng_state >> 33) as usize % (i + 1);
        let li = shuffled[i].label;
        shuffled[i].label = shuffled[j].label;
        shuffled[j].label = li;
    }
    let detector = train_detector(Architecture::Base, &shuffled, &options, 7, &device, &mut |_, _| {}).unwrap();
    let mcc = mcc_of(&detect(&detector, Architecture::Base, &test, &device), &labels);
    eprintln!("shuffled labels: test MCC {mcc:.3}");
    assert!(mcc.abs() < 0.4, "trained on shuffled labels yet MCC {mcc}");
}

#[test]
fn same_seed_gives_the_same_weights_and_outputs_bit_for_bit() {
    let device = Device::flex();
    let mut options = quick_options();
    options.classifier.epochs = 2;
    options.unet.epochs = 1;
    // a narrower U-Net than Table 4.2's, which the file must record to be read back
    options.unet.width = 16;
    let train = examples(&line_versus_noise(16, 24, 2.5, 5));
    let test = examples(&line_versus_noise(8, 24, 2.5, 6));
    let run = |seed| {
        let d = train_detector(Architecture::Unet, &train, &options, seed, &device, &mut |_, _| {}).unwrap();
        let o = detect(&d, Architecture::Unet, &test, &device);
        let dir = tempfile::tempdir().unwrap();
        let info = ModelInfo {
            architecture: Architecture::Unet,
            bands: "X".parse().unwrap(),
            input_size: 24,
            threshold: 0.5,
            unet_width: options.unet.width,
            pixel_spacing: Some(10.0),
            looks: Some(4.0),
            input_scale: Some("linear".into()),
            calibration: None,
            input_form: Default::default(),
            head: Default::default(),
        };
        let (path, _) = save_detector(&d, &info, &dir.path().join("m.safetensors")).unwrap();
        let (loaded, loaded_info) = load_detector(&path, Some((Architecture::Unet, 24)), &device).unwrap();
        assert_eq!(loaded_info.unet_width, 16);
        assert_eq!((loaded_info.pixel_spacing, loaded_info.looks), (Some(10.0), Some(4.0)));
        assert_eq!(loaded_info.input_scale.as_deref(), Some("linear"));
        let reloaded = detect(&loaded, Architecture::Unet, &test, &device);
        assert!(o.iter().zip(&reloaded).all(|(a, b)| a.to_bits() == b.to_bits()));
        (o, std::fs::read(path).unwrap())
    };
    let (o1, w1) = run(3);
    let (o2, w2) = run(3);
    let (o3, w3) = run(4);
    assert!(o1.iter().zip(&o2).all(|(a, b)| a.to_bits() == b.to_bits()));
    assert_eq!(w1, w2, "weights differ between two runs with the same seed");
    assert_ne!(w1, w3, "another seed gave the same weights");
    assert_ne!(o1, o3);
}

#[test]
fn saved_detector_reloads_with_the_same_outputs_and_refuses_the_wrong_architecture() {
    let device = Device::flex();
    let mut options = quick_options();
    options.classifier.epochs = 1;
    let train = examples(&line_versus_noise(8, 24, 2.5, 5));
    let detector = train_detector(Architecture::Cls, &train, &options, 1, &device, &mut |_, _| {}).unwrap();
    let before = detect(&detector, Architecture::Cls, &train, &device);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cls.safetensors");
    let info = detector_info(Architecture::Cls, "C", 24, Default::default());
    let (_, export) = save_detector(&detector, &info, &path).unwrap();
    assert!(export.exists());
    let (loaded, loaded_info) = load_detector(&path, Some((Architecture::Cls, 24)), &device).unwrap();
    assert_eq!(loaded_info, info);
    let after = detect(&loaded, Architecture::Cls, &train, &device);
    assert!(
        before.iter().zip(&after).all(|(a, b)| a.to_bits() == b.to_bits()),
        "{before:?} vs {after:?}"
    );
    let wrong_arch = load_detector(&path, Some((Architecture::Base, 24)), &device)
        .err()
        .unwrap()
        .to_string();
    assert!(
        wrong_arch.contains("\"cls\"") && wrong_arch.contains("expected \"base\""),
        "{wrong_arch}"
    );
    let wrong_size = load_detector(&path, Some((Architecture::Cls, 128)), &device)
        .err()
        .unwrap()
        .to_string();
    assert!(
        wrong_size.contains("24 x 24") && wrong_size.contains("128 x 128"),
        "{wrong_size}"
    );
    std::fs::write(dir.path().join("junk.safetensors"), b"not a model").unwrap();
    let junk = load_detector(&dir.path().join("junk.safetensors"), None, &device)
        .err()
        .unwrap()
        .to_string();
    assert!(junk.contains("not a safetensors file"), "{junk}");
}

/// A detector scanned over a scene much larger than its window (the stride's cells averaging
/// the windows over them) puts the map's peak on the one line in the scene, and finds it there.
#[test]
fn a_scan_of_a_large_scene_peaks_on_its_line() {
    use wakelab_learn::detect::{detect_image, Scan, ScanOptions};
    let device = Device::flex();
    let train = examples(&line_versus_noise(128, 32, 3.0, 1));
    let detector = train_detector(Architecture::Base, &train, &quick_options(), 7, &device, &mut |_, _| {}).unwrap();
    // 256 x 256 of unit Gaussian noise (the training images' clutter), a 120 px line of the
    // training contrast (a wake is far longer than a window) through (140, 120) at 30 degrees
    let noise = line_versus_noise(2, 256, 0.0, 9).remove(1).image;
    let mut scene = noise;
    let (r0, c0, angle) = (140.0f64, 120.0f64, 30f64.to_radians());
    let on_line = |r: f64, c: f64| {
        let (dr, dc) = (r - r0, c - c0);
        let along = dc * angle.cos() - dr * angle.sin();
        let across = (dc * angle.sin() + dr * angle.cos()).abs();
        (along.abs() <= 60.0).then_some(across)
    };
    for ((r, c), v) in scene.indexed_iter_mut() {
        if let Some(d) = on_line(r as f64 + 0.5, c as f64 + 0.5) {
            *v += (3.0 * (-d * d / 0.5).exp()) as f32;
        }
    }
    let info = scan_info("LWIR", wakelab_schema::architecture::InputForm::Pixels);
    let options = ScanOptions {
        stride: Some(16),
        batch: 10,
        ..ScanOptions::default()
    };
    let mut calls = Vec::new();
    let scan = detect_image(&detector, &info, &scene, options, &device, &mut |done, total| {
        calls.push((done, total))
    })
    .unwrap();
    // 15 x 15 windows of 32 px every 16 px, scored 10 at a time, two batches side by side
    assert_eq!(scan.tiles.len(), 225);
    assert_eq!(calls.len(), 12);
    assert_eq!(calls.last(), Some(&(225, 225)));
    assert_eq!(scan.map.dim(), (16, 16));
    // the peak: the strongest window (the first of equals), placed on its strongest line
    let strongest = scan
        .tiles
        .iter()
        .fold(&scan.tiles[0], |b, t| if t.probability > b.probability { t } else { b });
    assert_eq!((scan.peak.row, scan.peak.col), strongest.place(32));
    assert_eq!(scan.peak.probability, strongest.probability);
    assert_eq!(scan.peak.probability, scan.probability);
    // placed as the strongest detection is, where that window passes the threshold
    if let Some(first) = scan.detections.first() {
        assert_eq!((first.row, first.col), (scan.peak.row, scan.peak.col));
    }
    let centre = (scan.peak.row, scan.peak.col);
    let near = (0..=120)
        .map(|k| {
            let t = k as f64 - 60.0;
            let (r, c) = (r0 - t * angle.sin(), c0 + t * angle.cos());
            ((r - centre.0).powi(2) + (c - centre.1).powi(2)).sqrt()
        })
        .fold(f64::MAX, f64::min);
    eprintln!(
        "peak {centre:?} ({:.3}, {:?} deg), {near:.1} px from the line; {:?}",
        scan.peak.probability,
        scan.peak.orientation,
        scan.detections.first()
    );
    // on the line (its profile is a pixel wide), in its direction: the window's 32 directions
    // are 5.6 degrees apart, so the nearest is within 2.8 of the line's 30
    assert!(near <= 3.0, "the peak {centre:?} is {near:.1} px from the line");
    let orientation = scan.peak.orientation.expect("a line");
    assert!((orientation - 30.0).abs() <= 3.0, "{orientation}");
    assert!(scan.peak.line_contrast.unwrap() > 0.0, "a bright line");
    // fed in bands of rows (as a whole product is read), each starting at the first window row
    // not yet scored: the same windows, the same map to the bit
    for height in [32, 40, 100] {
        let mut banded = Scan::new(&detector, &info, scene.dim(), options).unwrap();
        while let Some(next) = banded.next_rows() {
            let end = (next.start + height).min(scene.nrows());
            let band = scene.slice(ndarray::s![next.start..end, ..]);
            banded.feed(next.start, band, &device, &mut |_, _| {});
        }
        let banded = banded.finish().unwrap();
        assert_eq!(banded.tiles.len(), 225, "bands of {height} rows");
        assert!(
            banded
                .map
                .iter()
                .zip(scan.map.iter())
                .all(|(a, b)| a.to_bits() == b.to_bits()),
            "bands of {height} rows"
        );
    }
    // the same detector calibrated (T = 2.5): every window's probability is its raw output
    // scaled by the temperature, in the same order
    let calibrated_info = ModelInfo {
        calibration: Some(wakelab_learn::store::Calibration {
            temperature: 2.5,
            false_alarms_per_1000_km2: None,
            open_sea_km2: None,
        }),
        ..info.clone()
    };
    let calibrated = detect_image(&detector, &calibrated_info, &scene, options, &device, &mut |_, _| {}).unwrap();
    let unsaturated = |t: &&(&wakelab_learn::detect::Tile, &wakelab_learn::detect::Tile)| {
        (1e-6..1.0 - 1e-6).contains(&t.0.probability)
    };
    assert_eq!(calibrated.tiles.len(), scan.tiles.len());
    for (raw, cal) in scan
        .tiles
        .iter()
        .zip(&calibrated.tiles)
        .collect::<Vec<_>>()
        .iter()
        .filter(unsaturated)
    {
        let expected = 1.0 / (1.0 + (-(raw.probability / (1.0 - raw.probability)).ln() / 2.5).exp());
        assert!(
            (cal.probability - expected).abs() < 1e-9,
            "{} -> {}",
            raw.probability,
            cal.probability
        );
    }
    // windows scored alone (a ship's, cut where it lies) score as the scan scored them there,
    // calibrated or not; one mostly no data, or not of the detector's side, is not scored
    for (info, scanned) in [(&info, &scan), (&calibrated_info, &calibrated)] {
        let picked: Vec<&wakelab_learn::detect::Tile> = scanned.tiles.iter().step_by(37).collect();
        let mut windows: Vec<ndarray::Array2<f32>> = picked
            .iter()
            .map(|t| {
                scene
                    .slice(ndarray::s![t.row..t.row + 32, t.col..t.col + 32])
                    .to_owned()
            })
            .collect();
        let mut empty = windows[0].clone();
        empty.slice_mut(ndarray::s![..17, ..]).fill(f32::NAN);
        windows.push(empty);
        windows.push(ndarray::Array2::zeros((31, 31)));
        let alone = wakelab_learn::detect::score_windows(&detector, info, &windows, options, &device).unwrap();
        for (t, p) in picked.iter().zip(&alone) {
            let p = p.expect("a full window is scored");
            assert!((p - t.probability).abs() < 1e-6, "{p} against {}", t.probability);
        }
        assert_eq!(alone[picked.len()..], [None, None]);
    }
    let first = scan.detections.first().expect("a detection");
    assert!(first.score > 0.5);
    let d = ((first.row - r0).powi(2) + (first.col - c0).powi(2)).sqrt();
    assert!(
        d < 60.0,
        "strongest detection at ({}, {}), {d:.0} px from the line's centre",
        first.row,
        first.col
    );
    // an image smaller than the window (a chip of 24 x 40 px of the scene, across the line) is
    // scanned as the same chip atop 40 rows of no-data: the same windows (the lower ones more
    // than half no-data, so not scored), the same probabilities and the same map over the
    // chip's cells, to the bit, whole or fed in bands
    let chip = scene.slice(ndarray::s![120..144, 100..140]).to_owned();
    let mut bordered = ndarray::Array2::from_elem((64, 40), f32::NAN);
    bordered.slice_mut(ndarray::s![..24, ..]).assign(&chip);
    let small = detect_image(&detector, &info, &chip, options, &device, &mut |_, _| {}).unwrap();
    let large = detect_image(&detector, &info, &bordered, options, &device, &mut |_, _| {}).unwrap();
    let origins = |d: &wakelab_learn::detect::Detection| d.tiles.iter().map(|t| (t.row, t.col)).collect::<Vec<_>>();
    assert_eq!(origins(&small), [(0, 0), (0, 8)]);
    assert_eq!(origins(&large), origins(&small));
    for (a, b) in small.tiles.iter().zip(&large.tiles) {
        assert_eq!(a.probability.to_bits(), b.probability.to_bits());
    }
    let mut banded = Scan::new(&detector, &info, chip.dim(), options).unwrap();
    assert_eq!(banded.next_rows(), Some(0..24));
    banded.feed(0, chip.view(), &device, &mut |_, _| {});
    assert_eq!(banded.next_rows(), None);
    let banded = banded.finish().unwrap();
    assert_eq!((small.map.dim(), banded.map.dim()), ((2, 3), (2, 3)));
    for ((r, c), v) in small.map.indexed_iter() {
        assert_eq!(v.to_bits(), large.map[[r, c]].to_bits(), "cell ({r}, {c})");
        assert_eq!(v.to_bits(), banded.map[[r, c]].to_bits(), "cell ({r}, {c})");
    }
    assert!(large.map.slice(ndarray::s![2.., ..]).iter().all(|v| v.is_nan()));
    assert_eq!(
        (small.peak.row, small.peak.col, small.peak.probability),
        (large.peak.row, large.peak.col, large.peak.probability)
    );
    // under half the window in view: refused, naming what would do
    let tiny = scene.slice(ndarray::s![..15, ..32]).to_owned();
    let refused = detect_image(&detector, &info, &tiny, options, &device, &mut |_, _| {})
        .err()
        .unwrap()
        .to_string();
    assert!(
        refused.contains("15 x 32 pixels")
            && refused.contains("at least half of the detector's 32 x 32-pixel input in view (16 x 32, 23 x 23"),
        "{refused}"
    );
}

/// A non-finite loss (here from one NaN pixel, which `Dataset::image` refuses but a library
/// caller might pass) stops the training with an error naming the input and architecture,
/// instead of returning a network whose every weight is NaN.
#[test]
fn a_non_finite_loss_stops_the_training_with_an_error() {
    let device = Device::flex();
    let mut train = examples(&line_versus_noise(16, 32, 3.0, 1));
    train[3].image[[0, 5, 5]] = f32::NAN;
    let mut options = quick_options();
    options.classifier.epochs = 2;
    let input: wakelab_schema::band::Input = "S".parse().unwrap();
    let e = train_detector(Architecture::Base, &train, &options, 7, &device, &mut |_, _| {})
        .map_err(|e| wakelab_learn::evaluate::which_training(e, &input, Architecture::Base, 0))
        .expect_err("a NaN loss is an error")
        .to_string();
    assert!(
        e.contains("training stopped") && e.contains("NaN") && e.contains("S \"base\""),
        "{e}"
    );
}

/// The U-Net's class-balanced BCE against its closed form: one wake pixel among four with
/// logits z gives 0.5 ln(1 + e^-z1) + 0.5 mean(ln(1 + e^z)) over the three background ones; a
/// batch of background only gives the plain mean BCE.
#[test]
fn the_balanced_bce_weighs_each_class_half() {
    use wakelab_learn::train::balanced_bce_with_logits;
    let device = Device::flex();
    let z = [2.0f32, -1.0, 0.5, -3.0];
    let logits = Tensor::<1>::from_data(TensorData::new(z.to_vec(), [4]), &device);
    let value = |t: Tensor<1>| t.into_data().try_to_vec::<f32>().unwrap()[0] as f64;
    let softplus = |x: f32| (1.0 + (x as f64).exp()).ln();
    let one_wake = Tensor::<1, Int>::from_data(TensorData::new(vec![1i64, 0, 0, 0], [4]), &device);
    let want = 0.5 * softplus(-z[0]) + 0.5 * (softplus(z[1]) + softplus(z[2]) + softplus(z[3])) / 3.0;
    let got = value(balanced_bce_with_logits(logits.clone(), one_wake));
    assert!((got - want).abs() < 1e-5, "{got} vs {want}");
    let none = Tensor::<1, Int>::from_data(TensorData::new(vec![0i64; 4], [4]), &device);
    let want = z.iter().map(|&x| softplus(x)).sum::<f64>() / 4.0;
    let got = value(balanced_bce_with_logits(logits, none));
    assert!((got - want).abs() < 1e-5, "{got} vs {want}");
}

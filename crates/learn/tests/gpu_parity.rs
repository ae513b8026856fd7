//! The wgpu backend computes what the CPU backend computes: for every network (the classifier of
//! Table 4.1 as "base", "cls" and "unet" read it, and the U-Net of Tables 4.2-4.3 at full width)
//! the forward pass, the loss, every parameter's gradient and one step of its recipe's optimiser
//! agree between `--device cpu` and `--device wgpu` from the same weights; and a detector scanned
//! over a scene gives the same map on both.
//!
//! Built only with `--features wgpu`; `bench/gpu_parity.sh` installs Mesa's software Vulkan
//! driver (lavapipe), fails unless Vulkan lists it, and runs this, so a machine without a GPU
//! executes the GPU path. Where wgpu finds no adapter at all the first operation on the device
//! panics: the test fails, it does not skip.
#![cfg(feature = "wgpu")]

use burn::module::{Module, ModuleVisitor, Param};
use burn::optim::GradientsParams;
use burn::tensor::{Device, Int, Tensor, TensorData};
use ndarray::Array2;
use wakelab_learn::detect::{detect_image, ScanOptions};
use wakelab_learn::device::parse_device;
use wakelab_learn::evaluate::{train_detector, EvalOptions};
use wakelab_learn::models::{init_seeded, Architecture, UNet, WakeClassifier, UNET_WIDTH};
use wakelab_learn::store::{Detector, ModelInfo};
use wakelab_learn::synthetic::{examples, line_versus_noise};
use wakelab_learn::train::{bce_with_logits, unet_loss, Example, Recipe, Trainer};

/// Two backends sum in different orders (a GEMM's tiles against a direct convolution's), so f32
/// results differ by rounding: |wgpu - cpu| <= ATOL x scale + RTOL |cpu| for every value, where
/// the scale is the largest |cpu| of what is compared as one (a tensor; all of a model's
/// gradients, since a gradient that is zero in exact arithmetic, such as a convolution's bias
/// before a BatchNorm, is rounding noise on both backends).
const RTOL: f32 = 1e-3;
const ATOL: f32 = 1e-4;

/// The comparisons of one test: every mismatch is collected and reported together.
#[derive(Default)]
struct Comparison {
    failures: Vec<String>,
}

impl Comparison {
    /// Compares `gpu` with `cpu` against `scale` (None: the largest |cpu|); returns the largest
    /// difference relative to the scale, for the log.
    fn check(&mut self, what: &str, gpu: &[f32], cpu: &[f32], scale: Option<f32>) -> f32 {
        assert_eq!(gpu.len(), cpu.len(), "{what}: lengths");
        let scale = scale.unwrap_or_else(|| largest(cpu)).max(f32::MIN_POSITIVE);
        let mut worst = 0.0f32;
        let mut bad = 0;
        for (i, (g, c)) in gpu.iter().zip(cpu).enumerate() {
            let diff = (g - c).abs();
            if diff.is_nan() || diff > ATOL * scale + RTOL * c.abs() {
                if bad == 0 {
                    self.failures
                        .push(format!("{what}[{i}]: wgpu {g} against cpu {c} (scale {scale})"));
                }
                bad += 1;
            }
            worst = worst.max(diff / scale);
        }
        if bad > 1 {
            self.failures
                .push(format!("{what}: {bad} of {} values differ", cpu.len()));
        }
        worst
    }

    fn finish(self, what: &str) {
        assert!(
            self.failures.is_empty(),
            "{what}: wgpu and cpu differ:\n{}",
            self.failures.join("\n")
        );
    }
}

fn largest(v: &[f32]) -> f32 {
    v.iter().fold(0.0f32, |m, x| m.max(x.abs()))
}

fn cpu() -> Device {
    parse_device("cpu").unwrap()
}

/// `--device wgpu` as a user's build has it: Vulkan wherever Vulkan has a device (lavapipe on a
/// machine without a GPU), else OpenGL, else no device and a panic at the first operation.
fn gpu() -> Device {
    parse_device("wgpu").unwrap()
}

fn values<const D: usize>(t: Tensor<D>) -> Vec<f32> {
    t.into_data().convert::<f32>().try_to_vec::<f32>().unwrap()
}

/// Every float parameter's values, in the module's order.
struct Weights(Vec<Vec<f32>>);

impl ModuleVisitor for Weights {
    fn visit_float<const D: usize>(&mut self, param: &Param<Tensor<D>>) {
        self.0.push(values(param.val()));
    }
}

fn weights<M: Module>(model: &M) -> Vec<Vec<f32>> {
    let mut w = Weights(Vec::new());
    model.visit(&mut w);
    w.0
}

/// Every float parameter's gradient, in the module's order; None for the ones without (the
/// BatchNorm layers' running statistics, which the visitor sees beside the parameters).
struct Gradient<'a>(&'a GradientsParams, Vec<Option<Vec<f32>>>);

impl ModuleVisitor for Gradient<'_> {
    fn visit_float<const D: usize>(&mut self, param: &Param<Tensor<D>>) {
        self.1.push(self.0.get::<D>(param.id).map(values));
    }
}

fn gradients<M: Module>(model: &M, loss: Tensor<1>) -> Vec<Option<Vec<f32>>> {
    let grads = GradientsParams::from_grads(loss.backward(), model);
    let mut g = Gradient(&grads, Vec::new());
    model.visit(&mut g);
    g.1
}

/// Both backends' gradients agree, judged against the largest gradient of the model, and so does
/// which parameters have one; returns the largest difference relative to that scale.
fn same_gradients(c: &mut Comparison, what: &str, gpu: &[Option<Vec<f32>>], cpu: &[Option<Vec<f32>>]) -> f32 {
    let scale = cpu.iter().flatten().map(|g| largest(g)).fold(0.0f32, f32::max);
    assert!(scale > 0.0, "{what}: no gradients at all");
    let mut worst = 0.0f32;
    for (k, pair) in gpu.iter().zip(cpu).enumerate() {
        match pair {
            (Some(g), Some(p)) => {
                worst = worst.max(c.check(&format!("{what} gradient of parameter {k}"), g, p, Some(scale)))
            }
            (None, None) => {}
            _ => c
                .failures
                .push(format!("{what}: parameter {k} has a gradient on one backend only")),
        }
    }
    worst
}

/// Outputs, loss and every gradient of `model` on the CPU and on wgpu (`devices`), each run on a
/// copy on the device's autodiff form, compared; returns the log of the largest differences.
/// The backward pass comes before any read of the graph, as in the trainer.
fn same_forward_backward<M: Module, const D: usize>(
    c: &mut Comparison,
    what: &str,
    model: &M,
    devices: [&Device; 2],
    forward: impl Fn(&M, &Device) -> (Tensor<D>, Tensor<1>),
) -> Vec<(&'static str, f32)> {
    let run = |device: &Device| {
        let ad = device.clone().autodiff();
        let m = model.clone().fork(&ad).train();
        let (outputs, loss) = forward(&m, &ad);
        let grads = gradients(&m, loss.clone());
        (values(outputs), values(loss), grads)
    };
    let (p, g) = (run(devices[0]), run(devices[1]));
    vec![
        ("outputs", c.check(&format!("{what} outputs"), &g.0, &p.0, None)),
        ("loss", c.check(&format!("{what} loss"), &g.1, &p.1, None)),
        ("gradients", same_gradients(c, what, &g.2, &p.2)),
    ]
}

/// `n` line-versus-noise inputs of `size` x `size` as `architecture` reads them (its second
/// channel a copy of the image for "cls", the wake mask for "unet"), their labels and masks.
fn batch(n: usize, size: usize, architecture: Architecture) -> (Vec<f32>, Vec<i64>, Vec<i64>) {
    let samples: Vec<Example> = examples(&line_versus_noise(n, size, 3.0, 21));
    let (mut images, mut labels, mut masks) = (Vec::new(), Vec::new(), Vec::new());
    for e in &samples {
        images.extend(e.image.iter().copied());
        let mask = e.mask.as_ref().expect("synthetic examples carry masks");
        match architecture {
            Architecture::Base => {}
            Architecture::Cls => images.extend(e.image.iter().copied()),
            Architecture::Unet => images.extend(mask.iter().copied()),
        }
        masks.extend(mask.iter().map(|&v| v as i64));
        labels.push(e.label as i64);
    }
    (images, labels, masks)
}

/// How one optimiser step's updates (new weights - old) are compared.
#[derive(Clone, Copy, Debug)]
enum StepCheck {
    /// Every value, against the largest update of the model (SGD: lr (g + decay w), as
    /// well-conditioned as the gradient).
    Values,
    /// Each tensor's relative L2 difference at most ADAM_L2. Adam's first step moves a weight
    /// by lr g / (|g| + 1e-8), which amplifies the rounding of a gradient near 1e-8 to a few per
    /// cent of lr in a handful of weights; a step of the wrong sign, size or decay is off by
    /// 100 % and more in every weight.
    RelativeL2,
}

const ADAM_L2: f32 = 1e-3;

/// The two backends' updates after one optimiser step from the same weights; returns the largest
/// difference (relative to the model's largest update, or the relative L2 difference).
fn same_step<M: Module>(c: &mut Comparison, what: &str, how: StepCheck, before: &[Vec<f32>], cpu: &M, gpu: &M) -> f32 {
    let update = |after: Vec<Vec<f32>>| -> Vec<Vec<f32>> {
        after
            .iter()
            .zip(before)
            .map(|(a, b)| a.iter().zip(b).map(|(a, b)| a - b).collect())
            .collect()
    };
    let (up, ug) = (update(weights(cpu)), update(weights(gpu)));
    let scale = up.iter().map(|u| largest(u)).fold(0.0f32, f32::max);
    assert!(scale > 0.0, "{what}: the step moved nothing");
    let mut worst = 0.0f32;
    for (k, (p, g)) in up.iter().zip(&ug).enumerate() {
        let what = format!("{what} update of parameter {k}");
        worst = worst.max(match how {
            StepCheck::Values => c.check(&what, g, p, Some(scale)),
            StepCheck::RelativeL2 => {
                let norm = |v: &mut dyn Iterator<Item = f32>| v.map(|x| x * x).sum::<f32>().sqrt();
                let d = norm(&mut p.iter().zip(g).map(|(p, g)| p - g))
                    / norm(&mut p.iter().copied()).max(f32::MIN_POSITIVE);
                if d > ADAM_L2 {
                    c.failures
                        .push(format!("{what}: relative L2 difference {d:.2e} over {ADAM_L2}"));
                }
                d
            }
        });
    }
    worst
}

/// A classifier of Table 4.1 (one channel for "base", two for "cls" and "unet") at 64 x 64,
/// batch 8, with the classifiers' recipe (SGD with L2) and with Adam (the shortened studies').
#[test]
fn every_classifier_trains_alike_on_wgpu_and_cpu() {
    let (cpu, gpu) = (cpu(), gpu());
    let (n, size) = (8, 64);
    for arch in Architecture::ALL {
        let channels = arch.classifier_channels(1);
        let (images, labels, _) = batch(n, size, arch);
        let model = init_seeded(31, &cpu, |d| WakeClassifier::new(channels, size, d));
        let before = weights(&model);
        let input = |d: &Device| Tensor::<4>::from_data(TensorData::new(images.clone(), [n, channels, size, size]), d);
        let targets = |d: &Device| Tensor::<1, Int>::from_data(TensorData::new(labels.clone(), [n]), d);

        // forward, loss and gradients from the same weights
        let mut c = Comparison::default();
        let what = format!("classifier \"{arch}\"");
        let mut log = same_forward_backward(&mut c, &what, &model, [&cpu, &gpu], |m, d| {
            let logits = m.forward(input(d));
            (logits.clone(), bce_with_logits(logits, targets(d)))
        });

        // one step of each update rule
        for (rule, how, recipe) in [
            ("SGD", StepCheck::Values, Recipe::classifier()),
            (
                "Adam",
                StepCheck::RelativeL2,
                Recipe {
                    optimiser: wakelab_schema::recipe::Optimiser::Adam,
                    ..Recipe::classifier()
                },
            ),
        ] {
            let step = |d: &Device| {
                let mut t = Trainer::from_model(model.clone(), &recipe, d);
                let (loss, _) = t.step(input(t.device()), &labels);
                (loss, t.finish())
            };
            let ((lp, mp), (lg, mg)) = (step(&cpu), step(&gpu));
            c.check(&format!("{what} {rule} step loss"), &[lg as f32], &[lp as f32], None);
            log.push((
                rule,
                same_step(&mut c, &format!("{what} {rule}"), how, &before, &mp, &mg),
            ));
        }
        eprintln!("{what}: largest difference / scale {log:?}");
        c.finish(&what);
    }
}

/// The U-Net at Table 4.2's full width (64 first-level channels) on 32 x 32 inputs, batch 4:
/// forward, its loss (Eq. (4.1)), gradients, and one Adam step of its recipe.
#[test]
fn the_unet_trains_alike_on_wgpu_and_cpu() {
    let (cpu, gpu) = (cpu(), gpu());
    let (n, size) = (4, 32);
    let (images, _, masks) = batch(n, size, Architecture::Base);
    let model = init_seeded(32, &cpu, |d| UNet::with_width(1, UNET_WIDTH, d));
    let before = weights(&model);
    let input = |d: &Device| Tensor::<4>::from_data(TensorData::new(images.clone(), [n, 1, size, size]), d);
    let target = |d: &Device| Tensor::<4, Int>::from_data(TensorData::new(masks.clone(), [n, 1, size, size]), d);
    let mut c = Comparison::default();
    let mut log = same_forward_backward(&mut c, "U-Net", &model, [&cpu, &gpu], |m, d| {
        let logits = m.forward(input(d));
        (logits.clone(), unet_loss(logits, target(d)))
    });
    let recipe = Recipe::unet();
    let step = |d: &Device| {
        let mut t = Trainer::<UNet>::from_model(model.clone(), &recipe, d);
        let (loss, _) = t.step(input(t.device()), target(t.device()));
        (loss, t.finish())
    };
    let ((lp, mp), (lg, mg)) = (step(&cpu), step(&gpu));
    c.check("U-Net Adam step loss", &[lg as f32], &[lp as f32], None);
    log.push((
        "Adam",
        same_step(&mut c, "U-Net Adam", StepCheck::RelativeL2, &before, &mp, &mg),
    ));
    eprintln!("U-Net: largest difference / scale {log:?}");
    c.finish("U-Net");
}

/// A "unet" detector (classifier and U-Net) trained on the CPU, scanned over a 256 x 256 scene
/// with one line on each backend: the same map within the tolerance, the same peak.
#[test]
fn a_scan_gives_the_same_map_on_wgpu_and_cpu() {
    let (cpu, gpu) = (cpu(), gpu());
    let mut options = EvalOptions::spec(&[wakelab_schema::band::Band::S]);
    options.classifier = Recipe {
        epochs: 4,
        learning_rate: 1e-2,
        ..Recipe::classifier()
    };
    options.unet = Recipe {
        epochs: 2,
        width: 16,
        ..Recipe::unet()
    };
    let train = examples(&line_versus_noise(64, 32, 3.0, 1));
    let detector = train_detector(Architecture::Unet, &train, &options, 7, &cpu, &mut |_, _| {}).unwrap();
    let on_gpu = Detector {
        classifier: detector.classifier.clone().to_device(&gpu),
        segmenter: detector.segmenter.clone().map(|s| s.to_device(&gpu)),
    };
    let mut scene: Array2<f32> = line_versus_noise(2, 256, 0.0, 9).remove(1).image;
    for c in 40..220 {
        scene[[128 + (c - 40) / 4, c]] += 3.0;
    }
    let info = ModelInfo {
        architecture: Architecture::Unet,
        bands: "LWIR".parse().unwrap(),
        input_size: 32,
        threshold: 0.5,
        unet_width: 16,
        pixel_spacing: None,
        looks: None,
        input_scale: None,
        calibration: None,
        input_form: Default::default(),
        head: Default::default(),
    };
    let scan = |d: &Device, detector: &Detector| {
        let options = ScanOptions {
            stride: Some(16),
            batch: 16,
            ..ScanOptions::default()
        };
        detect_image(detector, &info, &scene, options, d, &mut |_, _| {}).unwrap()
    };
    let (p, g) = (scan(&cpu, &detector), scan(&gpu, &on_gpu));
    let mut c = Comparison::default();
    let worst = c.check("scan map", g.map.as_slice().unwrap(), p.map.as_slice().unwrap(), None);
    c.finish("scan");
    assert_eq!((g.peak.row, g.peak.col), (p.peak.row, p.peak.col), "the map's peak");
    assert_eq!(g.tiles.len(), p.tiles.len());
    eprintln!(
        "scan: {} windows, peak at ({}, {}), largest map difference {worst:.2e}",
        p.tiles.len(),
        p.peak.row,
        p.peak.col
    );
}

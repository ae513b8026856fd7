//! Algorithm 2 (spec 4.2): for each repetition, Monte Carlo sample a balanced train/test split,
//! train, evaluate on the test images and keep every output o_i with its scene id; the metrics
//! (Eq. (4.3) and beyond) are computed from the kept outputs, per band set and architecture, as in
//! Tables 4.4-4.6 (and 5.1 for several bands as channels).

use crate::data::{balanced_split, Dataset};
pub use crate::eval_options::{EvalOptions, PAPER_TEST_FRACTION};
use crate::masks::{mask_iou, MaskScore};
use crate::store::{Detector, ModelInfo};
use crate::train::{classify, duplicated, segment, train_classifier, train_unet, with_masks, EpochRecord, Example};
use burn::tensor::Device;
use ndarray::{Array2, Array3, Axis};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::sync::Mutex;
use wakelab_core::{ConfigError, WakelabError};
use wakelab_schema::architecture::InputForm;
use wakelab_schema::band::Input;
use wakelab_schema::results::Architecture;
pub use wakelab_schema::results::{summarise, summarise_split, Output, Summary};
use wakelab_schema::split::{Network, Split};

/// One training curve point.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CurvePoint {
    pub bands: Input,
    pub network: Network,
    pub repetition: usize,
    #[serde(flatten)]
    pub epoch: EpochRecord,
}

/// Progress of an evaluation, for a progress display.
#[derive(Debug, Clone)]
pub struct EvalProgress<'a> {
    pub bands: &'a Input,
    pub network: Network,
    pub repetition: usize,
    pub epoch: &'a EpochRecord,
    pub epochs: usize,
}

impl EvalProgress<'_> {
    /// "S base rep 1/5 epoch 3/60 loss 0.412 118.0 img/s", of `repetitions` in all.
    pub fn describe(&self, repetitions: usize) -> String {
        format!(
            "{} {} rep {}/{repetitions} epoch {}/{} loss {:.3} {:.1} img/s",
            self.bands,
            self.network,
            self.repetition + 1,
            self.epoch.epoch,
            self.epochs,
            self.epoch.loss,
            self.epoch.images_per_second
        )
    }
}

/// Everything Algorithm 2 produced.
pub struct Evaluation {
    pub outputs: Vec<Output>,
    pub curves: Vec<CurvePoint>,
    pub summaries: Vec<Summary>,
    /// The U-Net masks' IoU on every test wake scene ("unet" only).
    pub mask_scores: Vec<MaskScore>,
    /// The detector of the last repetition of each band set and architecture.
    pub detectors: Vec<(Detector, ModelInfo)>,
}

/// Images of `bands` stacked as channels, with the label for that band set and the mask of the
/// first band.
pub fn load_examples(dataset: &Dataset, input: &Input, scenes: &[usize]) -> Result<Vec<Example>, WakelabError> {
    scenes
        .iter()
        .map(|&i| {
            let images = input
                .bands()
                .iter()
                .map(|&b| dataset.image(i, b))
                .collect::<Result<Vec<_>, _>>()?;
            let views: Vec<_> = images.iter().map(|a| a.view().insert_axis(Axis(0))).collect();
            let image: Array3<f32> = ndarray::concatenate(Axis(0), &views).map_err(|e| WakelabError::Image {
                path: dataset.dir.display().to_string(),
                message: format!("bands {input} of scene {} differ in size: {e}", dataset.records[i].id),
            })?;
            Ok(Example {
                image,
                label: dataset.label(i, input),
                mask: Some(dataset.mask(i, input.bands()[0])?),
            })
        })
        .collect()
}

/// Train a detector of `architecture` on `train` (the U-Net first for "unet"); every epoch is
/// reported to `on_epoch` with the network.
pub fn train_detector(
    architecture: Architecture,
    train: &[Example],
    options: &EvalOptions,
    seed: u64,
    device: &Device,
    on_epoch: &mut dyn FnMut(Network, &EpochRecord),
) -> Result<Detector, WakelabError> {
    match architecture {
        Architecture::Base => Ok(Detector {
            classifier: train_classifier(train, &options.classifier, seed, device, &mut |e| {
                on_epoch(Network::Classifier(Architecture::Base), e)
            })?,
            segmenter: None,
        }),
        Architecture::Cls => Ok(Detector {
            classifier: train_classifier(&duplicated(train), &options.classifier, seed, device, &mut |e| {
                on_epoch(Network::Classifier(Architecture::Cls), e)
            })?,
            segmenter: None,
        }),
        Architecture::Unet => {
            let unet = train_unet(train, &options.unet, seed ^ 0x5555, device, &mut |e| {
                on_epoch(Network::Segmenter, e)
            })?;
            let masks = segment(&unet, train, options.unet.batch_size, device);
            let classifier = train_classifier(
                &with_masks(train, &masks),
                &options.classifier,
                seed,
                device,
                &mut |e| on_epoch(Network::Classifier(Architecture::Unet), e),
            )?;
            Ok(Detector {
                classifier,
                segmenter: Some(unet),
            })
        }
    }
}

/// A training's error with the input, architecture and repetition it stopped in.
pub fn which_training(e: WakelabError, input: &Input, architecture: Architecture, repetition: usize) -> WakelabError {
    match e {
        WakelabError::Training(m) => {
            WakelabError::Training(format!("{input} \"{architecture}\" (repetition {repetition}): {m}"))
        }
        other => other,
    }
}

/// Classifier batch of the test scoring (the stored outputs were scored in batches of 8).
const TEST_BATCH: usize = 8;

/// Wake probabilities of a detector on examples (the image channels only; the "cls" copy and the
/// "unet" mask are made here).
pub fn detect(detector: &Detector, architecture: Architecture, examples: &[Example], device: &Device) -> Vec<f64> {
    detect_with_masks(detector, architecture, InputForm::Pixels, examples, TEST_BATCH, device).0
}

/// [`detect`] for a classifier reading its inputs in `form`, and the U-Net's wake masks where
/// the detector has one; the classifier scores `batch` examples at a time (the U-Net at most 4).
pub fn detect_with_masks(
    detector: &Detector,
    architecture: Architecture,
    form: InputForm,
    examples: &[Example],
    batch: usize,
    device: &Device,
) -> (Vec<f64>, Option<Vec<Array2<f32>>>) {
    match (architecture, &detector.segmenter) {
        (Architecture::Base, _) => (classify(&detector.classifier, examples, form, batch, device), None),
        (Architecture::Cls, _) => (
            classify(&detector.classifier, &duplicated(examples), form, batch, device),
            None,
        ),
        (Architecture::Unet, Some(unet)) => {
            let masks = segment(unet, examples, batch.min(4), device);
            let p = classify(&detector.classifier, &with_masks(examples, &masks), form, batch, device);
            (p, Some(masks))
        }
        (Architecture::Unet, None) => panic!("a \"unet\" detector without its U-Net"),
    }
}

/// What one (repetition, architecture) job of Algorithm 2 produced.
struct Job {
    outputs: Vec<Output>,
    curves: Vec<CurvePoint>,
    mask_scores: Vec<MaskScore>,
    detector: Option<(Detector, ModelInfo)>,
}

/// Run Algorithm 2 on a dataset. The (repetition, architecture) trainings of an input are
/// independent, each seeded by its repetition, so they run in parallel (one network's small
/// tensors keep about one core busy); their results are gathered in the sequential order, so
/// outputs, curves and detectors are the same bit for bit as one after another.
pub fn evaluate(
    dataset: &Dataset,
    options: &EvalOptions,
    device: &Device,
    progress: &mut (dyn FnMut(&EvalProgress) + Send),
) -> Result<Evaluation, WakelabError> {
    options.validate()?;
    options.check_dataset(dataset)?;
    let available = dataset.bands();
    let mut outputs = Vec::new();
    let mut curves = Vec::new();
    let mut detectors = Vec::new();
    let mut mask_scores = Vec::new();
    let progress = Mutex::new(progress);
    for input in &options.band_sets {
        if let Some(b) = input.bands().iter().find(|b| !available.contains(b)) {
            let names: Vec<&str> = available.iter().map(|b| b.name()).collect();
            return Err(ConfigError::new("bands", b, format!("one of the dataset's bands {names:?}")).into());
        }
        // split on whether a ship is in the scene, so that every band set of a repetition sees
        // the same scenes (decision-level fusion needs them); metrics use each band's label
        let labels: Vec<u8> = dataset.records.iter().map(|r| r.label).collect();
        let pairs: Vec<usize> = dataset.records.iter().map(|r| r.pair).collect();
        let per_class = labels
            .iter()
            .filter(|&&l| l == 1)
            .count()
            .min(labels.iter().filter(|&&l| l == 0).count());
        let test_per_class = ((per_class as f64 * options.test_fraction).round() as usize).max(1);
        if per_class < test_per_class + 1 {
            return Err(ConfigError::new(
                "dataset",
                format!("{per_class} scenes of the rarer class in bands {input}"),
                "at least 2 of each class (wake and no wake)",
            )
            .into());
        }
        let train_per_class = per_class - test_per_class;
        let mut splits = Vec::with_capacity(options.repetitions);
        for repetition in 0..options.repetitions {
            let seed = options.seed.wrapping_add(1000 * repetition as u64);
            let (train_idx, test_idx) = balanced_split(&labels, &pairs, train_per_class, test_per_class, seed)?;
            let train = load_examples(dataset, input, &train_idx)?;
            let test = load_examples(dataset, input, &test_idx)?;
            splits.push((seed, train_idx, test_idx, train, test));
        }
        let jobs: Vec<(usize, Architecture)> = (0..options.repetitions)
            .flat_map(|r| options.architectures.iter().map(move |&a| (r, a)))
            .collect();
        let done: Vec<Job> = jobs
            .par_iter()
            .map(|&(repetition, architecture)| -> Result<Job, WakelabError> {
                let (seed, train_idx, test_idx, train, test) = &splits[repetition];
                let seed = *seed;
                let mut curves = Vec::new();
                let detector = train_detector(architecture, train, options, seed, device, &mut |network, e| {
                    (progress.lock().expect("progress lock"))(&EvalProgress {
                        bands: input,
                        network,
                        repetition,
                        epoch: e,
                        epochs: options.epochs_of(network),
                    });
                    curves.push(CurvePoint {
                        bands: input.clone(),
                        network,
                        repetition,
                        epoch: e.clone(),
                    });
                })
                .map_err(|e| which_training(e, input, architecture, repetition))?;
                let mut sets = vec![(Split::Train, train.clone()), (Split::Test, test.clone())];
                for (k, p) in options.perturbations.iter().enumerate() {
                    let perturbed = p.apply(test, seed.wrapping_add(k as u64 + 1));
                    sets.push((Split::Perturbed(p.name()), perturbed));
                }
                let mut outputs = Vec::new();
                let mut mask_scores = Vec::new();
                for (split, examples) in &sets {
                    let idx = if *split == Split::Train { train_idx } else { test_idx };
                    let (o, masks) = detect_with_masks(
                        &detector,
                        architecture,
                        options.classifier.input,
                        examples,
                        TEST_BATCH,
                        device,
                    );
                    if *split == Split::Test {
                        for ((&i, e), mask) in idx.iter().zip(examples).zip(masks.iter().flatten()) {
                            let iou = e.mask.as_ref().filter(|_| e.label == 1).and_then(|t| mask_iou(mask, t));
                            mask_scores.extend(iou.map(|iou| MaskScore {
                                bands: input.clone(),
                                repetition,
                                scene: dataset.records[i].id.clone(),
                                iou,
                            }));
                        }
                    }
                    outputs.extend(idx.iter().zip(examples.iter()).zip(o).map(|((&i, e), output)| Output {
                        bands: input.clone(),
                        architecture,
                        repetition,
                        split: split.clone(),
                        scene: dataset.records[i].id.clone(),
                        label: e.label,
                        output,
                    }));
                }
                let last = repetition + 1 == options.repetitions;
                let detector = last.then(|| (detector, options.model_info(architecture, input, dataset)));
                Ok(Job {
                    outputs,
                    curves,
                    mask_scores,
                    detector,
                })
            })
            .collect::<Result<_, _>>()?;
        for job in done {
            outputs.extend(job.outputs);
            curves.extend(job.curves);
            mask_scores.extend(job.mask_scores);
            detectors.extend(job.detector);
        }
    }
    let summaries = summarise(&outputs, options.threshold);
    Ok(Evaluation {
        outputs,
        curves,
        summaries,
        mask_scores,
        detectors,
    })
}

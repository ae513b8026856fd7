//! The mapping from a study's `[learning]` table to Algorithm 2's evaluation options: the
//! recipe, the perturbations of the robustness tests and the inputs trained on.

use crate::Result;
use wakelab_dataset::learning::LearningPlan;
use wakelab_learn::data::Dataset;
use wakelab_learn::evaluate::EvalOptions;
use wakelab_learn::models::Architecture;
use wakelab_learn::robustness::Perturbation;
use wakelab_learn::train::Recipe;
use wakelab_schema::band::Input;

/// The inputs a study's learning stage trains on: every band of the dataset alone, then the
/// plan's feature-level fusions.
pub fn study_inputs(plan: &LearningPlan, dataset: &Dataset) -> Vec<Input> {
    let bands = dataset.bands();
    let mut inputs: Vec<Input> = bands.iter().map(|&b| Input::single(b)).collect();
    inputs.extend(plan.fused_inputs(&bands));
    inputs
}

/// What `wakelab eval --study NAME` runs: the recipe of study `name`'s `[learning]` table, for
/// `architectures` and for `bands` (comma-separated inputs) or else the study's own inputs.
pub fn study_eval_options(
    name: &str,
    dataset: &Dataset,
    architectures: &[wakelab_schema::results::Architecture],
    bands: Option<&str>,
) -> Result<EvalOptions> {
    let study = crate::load_study(name)?;
    let mut options = eval_options(&study.learning, dataset);
    options.architectures = architectures.to_vec();
    options.band_sets = match bands {
        Some(_) => dataset.inputs(bands)?,
        None => study_inputs(&study.learning, dataset),
    };
    Ok(options)
}

/// The evaluation options of a study's `[learning]` table.
pub fn eval_options(plan: &LearningPlan, dataset: &Dataset) -> EvalOptions {
    let mut perturbations: Vec<Perturbation> = plan
        .rotations
        .iter()
        .map(|&degrees| Perturbation::Rotate { degrees })
        .collect();
    if plan.dropped_patches > 0 {
        perturbations.push(Perturbation::DropPatches {
            patches: plan.dropped_patches,
            fraction: plan.patch_fraction,
        });
    }
    if plan.noise > 0.0 {
        perturbations.push(Perturbation::Noise { sigma: plan.noise });
    }
    if plan.shift > 0.0 {
        perturbations.push(Perturbation::Shift { fraction: plan.shift });
    }
    EvalOptions {
        architectures: Architecture::ALL.to_vec(),
        band_sets: Vec::new(),
        repetitions: plan.repetitions,
        test_fraction: dataset.test_fraction(),
        classifier: Recipe {
            epochs: plan.epochs,
            batch_size: plan.batch_size,
            learning_rate: plan.learning_rate,
            optimiser: plan.optimiser,
            weight_decay: plan.weight_decay,
            augmentation: plan.augmentation,
            ..Recipe::classifier()
        },
        unet: Recipe {
            epochs: plan.unet_epochs,
            batch_size: plan.unet_batch_size,
            learning_rate: plan.unet_learning_rate,
            width: plan.unet_width,
            augmentation: plan.augmentation,
            ..Recipe::unet()
        },
        threshold: plan.threshold,
        seed: plan.seed,
        perturbations,
    }
}

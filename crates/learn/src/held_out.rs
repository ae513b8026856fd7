//! Robustness to unseen environments (spec 6.2): detectors trained with one group of scenes held
//! out and tested on it.

use crate::data::Dataset;
use crate::evaluate::{detect, load_examples, train_detector, which_training, EvalOptions, EvalProgress};
use burn::tensor::Device;
use rayon::prelude::*;
use std::sync::Mutex;
use wakelab_core::WakelabError;
use wakelab_schema::results::Architecture;
use wakelab_schema::results::Output;
use wakelab_schema::split::Split;

/// Environments held out of training (robustness, spec 6.2): for each group of scenes, train on
/// every other scene and test on the group. Outputs are kept with split `held_out` and the
/// group's index as `repetition`, so `summarise_split(.., &Split::HeldOut, ..)` averages over groups.
/// The (group, architecture) trainings run in parallel and are gathered in order, as in
/// [`crate::evaluate::evaluate`].
pub fn evaluate_held_out(
    dataset: &Dataset,
    options: &EvalOptions,
    groups: &[Vec<usize>],
    device: &Device,
    progress: &mut (dyn FnMut(&EvalProgress) + Send),
) -> Result<Vec<Output>, WakelabError> {
    options.validate()?;
    options.check_dataset(dataset)?;
    let mut outputs = Vec::new();
    let progress = Mutex::new(progress);
    for input in &options.band_sets {
        let mut sets = Vec::new();
        for (g, test_idx) in groups.iter().enumerate() {
            let train_idx: Vec<usize> = (0..dataset.records.len()).filter(|i| !test_idx.contains(i)).collect();
            if train_idx.is_empty() || test_idx.is_empty() {
                continue;
            }
            let train = load_examples(dataset, input, &train_idx)?;
            let test = load_examples(dataset, input, test_idx)?;
            sets.push((g, test_idx, train, test));
        }
        let jobs: Vec<(usize, Architecture)> = (0..sets.len())
            .flat_map(|k| options.architectures.iter().map(move |&a| (k, a)))
            .collect();
        let done: Vec<Vec<Output>> = jobs
            .par_iter()
            .map(|&(k, architecture)| -> Result<Vec<Output>, WakelabError> {
                let (g, test_idx, train, test) = &sets[k];
                let g = *g;
                let seed = options.seed.wrapping_add(7919 * (g as u64 + 1));
                let detector = train_detector(architecture, train, options, seed, device, &mut |network, e| {
                    (progress.lock().expect("progress lock"))(&EvalProgress {
                        bands: input,
                        network,
                        repetition: g,
                        epoch: e,
                        epochs: options.epochs_of(network),
                    })
                })
                .map_err(|e| which_training(e, input, architecture, g))?;
                let o = detect(&detector, architecture, test, device);
                Ok(test_idx
                    .iter()
                    .zip(test)
                    .zip(o)
                    .map(|((&i, e), output)| Output {
                        bands: input.clone(),
                        architecture,
                        repetition: g,
                        split: Split::HeldOut,
                        scene: dataset.records[i].id.clone(),
                        label: e.label,
                        output,
                    })
                    .collect())
            })
            .collect::<Result<_, _>>()?;
        outputs.extend(done.into_iter().flatten());
    }
    Ok(outputs)
}

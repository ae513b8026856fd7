//! The results' schema: a detector's kept outputs (Algorithm 2's o_i; the architectures of spec
//! 4.1 are in [`crate::architecture`]) and their summaries over repetitions (a row of Tables 4.4-4.6).

use crate::band::Input;
use crate::fusion_row::Source;
use crate::metrics::{mean_and_spread, roc_auc, Confusion};
use crate::split::Split;
use serde::{Deserialize, Serialize};

pub use crate::architecture::{Architecture, MIN_CLASSIFIER_SIZE, UNET_SIZE_MULTIPLE};

/// One kept output o_i.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Output {
    pub bands: Input,
    pub architecture: Architecture,
    pub repetition: usize,
    pub split: Split,
    pub scene: String,
    pub label: u8,
    pub output: f64,
}

/// Metrics of one row (an input, or a fusion of inputs) and architecture over the repetitions
/// (a row of Tables 4.4-4.6 and 5.1-5.3).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    pub bands: Source,
    pub architecture: Architecture,
    pub repetitions: usize,
    pub mcc: f64,
    pub mcc_spread: f64,
    pub accuracy: f64,
    pub accuracy_spread: f64,
    pub f1: f64,
    /// ROC AUC of all kept outputs together (None when one class is missing).
    pub roc_auc: Option<f64>,
    /// Counts summed over the repetitions.
    pub tp: u64,
    pub tn: u64,
    pub fp: u64,
    #[serde(rename = "fn")]
    pub fn_: u64,
}

/// One scored decision, whatever made it: what [`summarise_scores`] groups.
#[derive(Debug, Clone, PartialEq)]
pub struct Scored {
    pub source: Source,
    pub architecture: Architecture,
    pub repetition: usize,
    pub label: u8,
    pub output: f64,
}

impl Scored {
    pub fn new(source: Source, architecture: Architecture, repetition: usize, label: u8, output: f64) -> Self {
        Self {
            source,
            architecture,
            repetition,
            label,
            output,
        }
    }
}

/// Metrics of the kept test outputs of one input and architecture: per repetition, then mean
/// and sample spread.
pub fn summarise(outputs: &[Output], threshold: f64) -> Vec<Summary> {
    summarise_split(outputs, &Split::Test, threshold)
}

/// `summarise` on the outputs of another split: a perturbed test, or the held-out groups
/// (where "repetition" is the held-out group).
pub fn summarise_split(outputs: &[Output], split: &Split, threshold: f64) -> Vec<Summary> {
    let scored: Vec<Scored> = outputs
        .iter()
        .filter(|o| &o.split == split)
        .map(|o| {
            Scored::new(
                Source::Input(o.bands.clone()),
                o.architecture,
                o.repetition,
                o.label,
                o.output,
            )
        })
        .collect();
    summarise_scores(&scored, threshold)
}

/// Metrics of scored decisions per source and architecture, in order of first appearance:
/// confusion counts per repetition, then their mean and sample spread.
pub fn summarise_scores(scored: &[Scored], threshold: f64) -> Vec<Summary> {
    let mut keys: Vec<(&Source, Architecture)> = Vec::new();
    for o in scored {
        if !keys.contains(&(&o.source, o.architecture)) {
            keys.push((&o.source, o.architecture));
        }
    }
    keys.into_iter()
        .map(|(source, architecture)| {
            let group: Vec<&Scored> = scored
                .iter()
                .filter(|o| &o.source == source && o.architecture == architecture)
                .collect();
            let mut reps: Vec<usize> = group.iter().map(|o| o.repetition).collect();
            reps.sort();
            reps.dedup();
            let confusions: Vec<Confusion> = reps
                .iter()
                .map(|&r| {
                    let (o, l): (Vec<f64>, Vec<u8>) = group
                        .iter()
                        .filter(|o| o.repetition == r)
                        .map(|o| (o.output, o.label))
                        .unzip();
                    Confusion::from_outputs(&o, &l, threshold)
                })
                .collect();
            let (mcc, mcc_spread) = mean_and_spread(&confusions.iter().map(Confusion::mcc).collect::<Vec<_>>());
            let (accuracy, accuracy_spread) =
                mean_and_spread(&confusions.iter().map(Confusion::accuracy).collect::<Vec<_>>());
            let (f1, _) = mean_and_spread(&confusions.iter().map(Confusion::f1).collect::<Vec<_>>());
            let (scores, labels): (Vec<f64>, Vec<u8>) = group.iter().map(|o| (o.output, o.label)).unzip();
            Summary {
                bands: source.clone(),
                architecture,
                repetitions: reps.len(),
                mcc,
                mcc_spread,
                accuracy,
                accuracy_spread,
                f1,
                roc_auc: roc_auc(&scores, &labels),
                tp: confusions.iter().map(|c| c.tp).sum(),
                tn: confusions.iter().map(|c| c.tn).sum(),
                fp: confusions.iter().map(|c| c.fp).sum(),
                fn_: confusions.iter().map(|c| c.fn_).sum(),
            }
        })
        .collect()
}

//! The results' schema: the network architectures of spec 4.1, a detector's kept outputs
//! (Algorithm 2's o_i) and their summaries over repetitions (a row of Tables 4.4-4.6).

use crate::band::Input;
use crate::fusion_row::Source;
use crate::metrics::{mean_and_spread, roc_auc, Confusion};
use crate::split::Split;
use serde::{Deserialize, Serialize};

/// Smallest input side of the classifiers of Table 4.1: their three (conv 3x3, pool 2) stages
/// leave one pixel.
pub const MIN_CLASSIFIER_SIZE: usize = 22;
/// The U-Net's input side must be a multiple of this (Table 4.2's three poolings).
pub const UNET_SIZE_MULTIPLE: usize = 8;

/// The classifier architectures of spec 4.1.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Architecture {
    /// One channel per band: the image itself.
    Base,
    /// The control: the bands' images and a copy of the first (4.1, 5.2), so the input is as
    /// wide as "unet"'s.
    Cls,
    /// The bands' images and the mask a U-Net trained on the same bands draws on them.
    Unet,
}

impl Architecture {
    pub const ALL: [Architecture; 3] = [Architecture::Base, Architecture::Cls, Architecture::Unet];

    pub fn name(self) -> &'static str {
        match self {
            Architecture::Base => "base",
            Architecture::Cls => "cls",
            Architecture::Unet => "unet",
        }
    }

    /// Input channels of the classifier for `bands` image channels (Table 4.1's `inChannels`):
    /// one more than the bands for "cls" and "unet" (4.1; 5.2 for several bands).
    pub fn classifier_channels(self, bands: usize) -> usize {
        match self {
            Architecture::Base => bands,
            Architecture::Cls | Architecture::Unet => bands + 1,
        }
    }

    pub fn parse(text: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|a| a.name() == text)
    }

    /// Whether the architecture takes square images of side `size`: Table 4.1's three
    /// (conv 3x3, pool 2) stages need at least [`MIN_CLASSIFIER_SIZE`] pixels, and the U-Net of
    /// Table 4.2 (in "unet") a multiple of [`UNET_SIZE_MULTIPLE`]. The error says what is allowed.
    pub fn accepts_input_size(self, size: usize) -> Result<(), String> {
        let unet = self == Architecture::Unet;
        if size >= MIN_CLASSIFIER_SIZE && (!unet || size % UNET_SIZE_MULTIPLE == 0) {
            return Ok(());
        }
        Err(if unet {
            format!(
                "\"unet\" needs a side that is a multiple of {UNET_SIZE_MULTIPLE} and at least {MIN_CLASSIFIER_SIZE} pixels (24, 32, 40, ...): the U-Net's three poolings and the classifier's three convolution stages"
            )
        } else {
            format!(
                "\"{self}\" needs a side of at least {MIN_CLASSIFIER_SIZE} pixels (three 3 x 3 convolution and pooling stages)"
            )
        })
    }
}

/// A name: `base`, `cls` or `unet`.
impl std::str::FromStr for Architecture {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::parse(s.trim()).ok_or_else(|| format!("{s}: must be base, cls or unet"))
    }
}

impl std::fmt::Display for Architecture {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.name())
    }
}

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

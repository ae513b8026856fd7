//! The network architectures of spec 4.1 and the input sizes they accept.

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

/// What a classifier reads from its window: the window's normalised pixels (the spec's input,
/// 4.2), or its line sums, the window's Radon transform (a line across the window, such as a
/// wake's trough or arm, becomes one bright or dark point; see `wakelab_learn::line_sums`), or
/// the line sums of the window with its ships' returns masked out (the same module), so that a
/// decision rests on the wake and not on a bright ship.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum InputForm {
    #[default]
    Pixels,
    LineSums,
    LineSumsShipsMasked,
}

impl InputForm {
    pub const ALL: [InputForm; 3] = [InputForm::Pixels, InputForm::LineSums, InputForm::LineSumsShipsMasked];

    pub fn name(self) -> &'static str {
        match self {
            InputForm::Pixels => "pixels",
            InputForm::LineSums => "line_sums",
            InputForm::LineSumsShipsMasked => "line_sums_ships_masked",
        }
    }
}

/// A name: `pixels`, `line_sums` or `line_sums_ships_masked`.
impl std::str::FromStr for InputForm {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        crate::recipe::parse_named(s.trim(), &Self::ALL, Self::name, "an input form")
    }
}

impl std::fmt::Display for InputForm {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.name())
    }
}

/// How the classifier of Table 4.1 turns its last feature map into a decision: the table's
/// position-bound linear layers over the flattened map, or each channel's largest response over
/// the map into the same linear layers (global max pooling; Lin et al. 2014, "Network in
/// network", pool the map the same way with its average). A wake's trough is one point in the
/// plane of a window's line sums, anywhere in it; the flattened map must learn each place
/// apart, the pooled one finds it wherever it lies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ClassifierHead {
    #[default]
    Flatten,
    GlobalMax,
}

impl ClassifierHead {
    pub const ALL: [ClassifierHead; 2] = [ClassifierHead::Flatten, ClassifierHead::GlobalMax];

    pub fn name(self) -> &'static str {
        match self {
            ClassifierHead::Flatten => "flatten",
            ClassifierHead::GlobalMax => "global_max",
        }
    }
}

/// A name: `flatten` or `global_max`.
impl std::str::FromStr for ClassifierHead {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        crate::recipe::parse_named(s.trim(), &Self::ALL, Self::name, "a classifier head")
    }
}

impl std::fmt::Display for ClassifierHead {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn input_forms_read_by_name_and_a_wrong_one_lists_the_allowed() {
        for f in InputForm::ALL {
            assert_eq!(f.name().parse::<InputForm>(), Ok(f));
            assert_eq!(f.to_string(), f.name());
        }
        assert_eq!(InputForm::default(), InputForm::Pixels);
        let e = "radon".parse::<InputForm>().unwrap_err();
        assert!(e.contains("pixels, line_sums"), "{e}");
    }

    #[test]
    fn classifier_heads_read_by_name_and_a_wrong_one_lists_the_allowed() {
        for h in ClassifierHead::ALL {
            assert_eq!(h.name().parse::<ClassifierHead>(), Ok(h));
        }
        assert_eq!(ClassifierHead::default(), ClassifierHead::Flatten);
        let e = "mean".parse::<ClassifierHead>().unwrap_err();
        assert!(e.contains("flatten, global_max"), "{e}");
    }
}

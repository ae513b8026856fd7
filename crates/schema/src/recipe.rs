//! The spec's training recipe (4.1-4.2), in one place: the CLI's defaults, the study file's
//! `[learning]` defaults and the learning library's recipes all read these.

/// Repetitions of Algorithm 2 (4.2: 5).
pub const REPETITIONS: usize = 5;
/// Classifier epochs (4.1: 60).
pub const CLASSIFIER_EPOCHS: usize = 60;
/// Classifier batch size (4.1: 8).
pub const CLASSIFIER_BATCH_SIZE: usize = 8;
/// Classifier learning rate, SGD (4.1: 1e-3).
pub const CLASSIFIER_LEARNING_RATE: f64 = 1e-3;
/// Classifier weight decay (4.1: 0.1).
pub const CLASSIFIER_WEIGHT_DECAY: f64 = 0.1;
/// Classifier optimiser (4.1: SGD).
pub const CLASSIFIER_OPTIMISER: Optimiser = Optimiser::Sgd;
/// U-Net epochs (4.1: 60).
pub const UNET_EPOCHS: usize = 60;
/// U-Net batch size (4.1: 4).
pub const UNET_BATCH_SIZE: usize = 4;
/// U-Net learning rate, Adam (4.1: 1e-4).
pub const UNET_LEARNING_RATE: f64 = 1e-4;
/// U-Net weight decay (4.1: 1e-4).
pub const UNET_WEIGHT_DECAY: f64 = 1e-4;
/// First-level channels of the U-Net (Table 4.2: 64).
pub const UNET_WIDTH: usize = 64;
/// Decision threshold on the wake probability (4.2: 0.5; erratum 2).
pub const THRESHOLD: f64 = 0.5;

/// The one of `all` whose `name` is `text` (ASCII case ignored), or an error naming `what` it is
/// not and every allowed name: the `FromStr` of the choices a user types.
pub fn parse_named<T: Copy>(text: &str, all: &[T], name: fn(T) -> &'static str, what: &str) -> Result<T, String> {
    all.iter()
        .copied()
        .find(|&v| name(v).eq_ignore_ascii_case(text))
        .ok_or_else(|| {
            let names: Vec<&str> = all.iter().map(|&v| name(v)).collect();
            format!("\"{text}\" is not {what} (allowed: {})", names.join(", "))
        })
}

/// The rule that turns gradients into weight updates, each with its L2 weight decay added to the
/// gradient (PyTorch's `weight_decay`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Optimiser {
    /// Plain stochastic gradient descent, no momentum (4.1's classifiers).
    #[default]
    Sgd,
    /// Adam (Kingma & Ba 2015) with beta (0.9, 0.999) and epsilon 1e-8 (4.1's U-Net).
    Adam,
}

impl Optimiser {
    pub const ALL: [Optimiser; 2] = [Optimiser::Sgd, Optimiser::Adam];

    pub fn name(self) -> &'static str {
        match self {
            Optimiser::Sgd => "sgd",
            Optimiser::Adam => "adam",
        }
    }
}

impl std::fmt::Display for Optimiser {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Optimiser {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        parse_named(s, &Self::ALL, Self::name, "an optimiser")
    }
}

/// How training inputs are varied from epoch to epoch.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Augmentation {
    /// Random turns by multiples of 90 degrees (4.2).
    #[default]
    QuarterTurns,
    /// Rotations by any angle, mirror flips and shifts by up to an eighth of the image (the wake
    /// anywhere, in any direction).
    Geometric,
}

impl Augmentation {
    pub const ALL: [Augmentation; 2] = [Augmentation::QuarterTurns, Augmentation::Geometric];

    pub fn name(self) -> &'static str {
        match self {
            Augmentation::QuarterTurns => "quarter_turns",
            Augmentation::Geometric => "geometric",
        }
    }
}

impl std::str::FromStr for Augmentation {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        parse_named(s, &Self::ALL, Self::name, "an augmentation")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn choices_parse_by_name_and_a_wrong_one_lists_the_allowed() {
        for o in Optimiser::ALL {
            assert_eq!(o.name().parse::<Optimiser>(), Ok(o));
        }
        for a in Augmentation::ALL {
            assert_eq!(a.name().to_uppercase().parse::<Augmentation>(), Ok(a));
        }
        assert_eq!(
            "momentum".parse::<Optimiser>(),
            Err("\"momentum\" is not an optimiser (allowed: sgd, adam)".to_string())
        );
        assert_eq!(
            "spin".parse::<Augmentation>(),
            Err("\"spin\" is not an augmentation (allowed: quarter_turns, geometric)".to_string())
        );
    }
}

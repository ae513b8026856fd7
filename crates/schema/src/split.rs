//! Which images a kept output was computed on, and which network computed it.

use crate::architecture::Architecture;
use crate::band::serde_by_name;
use std::fmt;
use std::str::FromStr;

/// The images an output was computed on.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Split {
    /// The training images (what decision-level fusion weights sources by; erratum 11).
    Train,
    /// The test images of Algorithm 2.
    Test,
    /// The test images under a named perturbation (robustness, spec 6.2): "test:<name>".
    Perturbed(String),
    /// The scenes of a held-out group (robustness to unseen environments).
    HeldOut,
}

impl fmt::Display for Split {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Split::Train => f.pad("train"),
            Split::Test => f.pad("test"),
            Split::Perturbed(name) => f.pad(&format!("test:{name}")),
            Split::HeldOut => f.pad("held_out"),
        }
    }
}

impl FromStr for Split {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Ok(match s {
            "train" => Split::Train,
            "test" => Split::Test,
            "held_out" => Split::HeldOut,
            _ => match s.strip_prefix("test:") {
                Some(name) if !name.is_empty() => Split::Perturbed(name.to_string()),
                _ => {
                    return Err(format!(
                        "unknown split `{s}`: train, test, test:<perturbation> or held_out"
                    ))
                }
            },
        })
    }
}

serde_by_name!(Split);

/// A network of spec 4.1: one of the classifiers, or the U-Net that draws "unet"'s mask.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Network {
    Classifier(Architecture),
    /// The U-Net itself (Table 4.2), trained on masks before the "unet" classifier.
    Segmenter,
}

impl Network {
    pub fn name(self) -> &'static str {
        match self {
            Network::Classifier(a) => a.name(),
            Network::Segmenter => "segmenter",
        }
    }
}

impl fmt::Display for Network {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.name())
    }
}

impl FromStr for Network {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "segmenter" => Ok(Network::Segmenter),
            _ => Architecture::parse(s)
                .map(Network::Classifier)
                .ok_or_else(|| format!("unknown network `{s}`: base, cls, unet or segmenter")),
        }
    }
}

serde_by_name!(Network);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splits_read_back_as_written() {
        for s in [
            Split::Train,
            Split::Test,
            Split::Perturbed("noise_S".into()),
            Split::HeldOut,
        ] {
            assert_eq!(s.to_string().parse::<Split>(), Ok(s));
        }
        assert!("test:".parse::<Split>().is_err());
        assert!("validation".parse::<Split>().is_err());
    }
}

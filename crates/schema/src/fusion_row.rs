//! What a row of the results tables is about: one input, or a decision-level fusion of inputs
//! by a named method (Tables 5.1-5.3).

use crate::band::{serde_by_name, Input, UnknownBand};
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// The decision-level fusion methods of spec 5.1.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Method {
    /// The Bayes classifier of Eqs. (5.3)-(5.5).
    Bayes,
    /// Dempster's rule of combination, Eq. (5.6).
    DempsterShafer,
}

impl Method {
    pub const ALL: [Method; 2] = [Method::Bayes, Method::DempsterShafer];

    pub fn name(self) -> &'static str {
        match self {
            Method::Bayes => "Bayes classifier",
            Method::DempsterShafer => "Dempster-Shafer",
        }
    }
}

/// A decision-level fusion: a method and the inputs whose decisions it fuses.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct FusionRow {
    pub method: Method,
    pub sources: Vec<Input>,
}

impl fmt::Display for FusionRow {
    /// "Bayes classifier (S, X)", the row name of Tables 5.1-5.3.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let sources: Vec<String> = self.sources.iter().map(Input::name).collect();
        f.pad(&format!("{} ({})", self.method.name(), sources.join(", ")))
    }
}

impl FromStr for FusionRow {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let bad = || format!("not a fusion row `{s}`: e.g. \"Bayes classifier (S, X)\"");
        let (method, rest) = Method::ALL
            .into_iter()
            .find_map(|m| s.strip_prefix(m.name()).map(|rest| (m, rest)))
            .ok_or_else(bad)?;
        let inner = rest
            .strip_prefix(" (")
            .and_then(|r| r.strip_suffix(')'))
            .ok_or_else(bad)?;
        let sources = inner
            .split(", ")
            .map(Input::from_str)
            .collect::<Result<Vec<_>, UnknownBand>>()
            .map_err(|e| e.to_string())?;
        Ok(FusionRow { method, sources })
    }
}

/// What a summary row is about: an input's own detector, or a fusion of detectors' decisions.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Source {
    Input(Input),
    Fusion(FusionRow),
}

impl Source {
    pub fn input(&self) -> Option<&Input> {
        match self {
            Source::Input(i) => Some(i),
            Source::Fusion(_) => None,
        }
    }

    pub fn fusion(&self) -> Option<&FusionRow> {
        match self {
            Source::Fusion(f) => Some(f),
            Source::Input(_) => None,
        }
    }

    /// Whether infrared takes part: an infrared band in the input or in a fused source.
    pub fn has_infrared(&self) -> bool {
        match self {
            Source::Input(i) => i.has_infrared(),
            Source::Fusion(f) => f.sources.iter().any(Input::has_infrared),
        }
    }
}

impl PartialEq<Input> for Source {
    fn eq(&self, other: &Input) -> bool {
        self.input() == Some(other)
    }
}

impl fmt::Display for Source {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Source::Input(i) => i.fmt(f),
            Source::Fusion(r) => r.fmt(f),
        }
    }
}

impl FromStr for Source {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        if s.contains(' ') {
            s.parse().map(Source::Fusion)
        } else {
            s.parse().map(Source::Input).map_err(|e: UnknownBand| e.to_string())
        }
    }
}

serde_by_name!(FusionRow);
serde_by_name!(Source);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_read_back_as_the_tables_name_them() {
        for text in [
            "Bayes classifier (S, X)",
            "Dempster-Shafer (S, C, X, MWIR, LWIR)",
            "C+LWIR",
            "S",
        ] {
            assert_eq!(text.parse::<Source>().unwrap().to_string(), text);
        }
        let row: Source = "Dempster-Shafer (C, LWIR)".parse().unwrap();
        assert!(row.has_infrared() && row.fusion().is_some());
        assert!("Majority (S, X)".parse::<Source>().is_err());
        assert!("Bayes classifier (S, Q)".parse::<Source>().is_err());
    }
}

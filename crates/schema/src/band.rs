//! Bands and inputs: a band wakelab renders (radar, spec 3.2; infrared, spec 3.3), and a
//! detector's input, one band or several as channels (feature-level fusion, spec 5.1), named
//! as the paper's tables and wakelab's files name them ("C", "S+X").

use std::fmt;
use std::str::FromStr;

/// A band every scene can be rendered in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Band {
    S,
    C,
    X,
    Mwir,
    Lwir,
}

/// Whether a band is seen by radar or in the thermal infrared.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BandKind {
    Radar,
    Infrared,
}

impl Band {
    /// Every band, in rendering order.
    pub const ALL: [Band; 5] = [Band::S, Band::C, Band::X, Band::Mwir, Band::Lwir];

    pub fn name(self) -> &'static str {
        match self {
            Band::S => "S",
            Band::C => "C",
            Band::X => "X",
            Band::Mwir => "MWIR",
            Band::Lwir => "LWIR",
        }
    }

    pub fn kind(self) -> BandKind {
        match self {
            Band::S | Band::C | Band::X => BandKind::Radar,
            Band::Mwir | Band::Lwir => BandKind::Infrared,
        }
    }

    pub fn is_radar(self) -> bool {
        self.kind() == BandKind::Radar
    }
}

/// The error of a name that is no band, naming the allowed ones.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UnknownBand(pub String);

impl fmt::Display for UnknownBand {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "unknown band `{}`: one of S, C, X, MWIR, LWIR", self.0)
    }
}

impl std::error::Error for UnknownBand {}

impl FromStr for Band {
    type Err = UnknownBand;
    fn from_str(s: &str) -> Result<Self, UnknownBand> {
        Band::ALL
            .into_iter()
            .find(|b| b.name() == s.trim())
            .ok_or_else(|| UnknownBand(s.to_string()))
    }
}

impl fmt::Display for Band {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.name())
    }
}

/// Bands order by name, so maps keyed by band keep the order of the files written before bands
/// had a type ("C", "LWIR", "MWIR", "S", "X").
impl Ord for Band {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.name().cmp(other.name())
    }
}

impl PartialOrd for Band {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

/// A detector's input: one band, or several bands as channels of one image.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Input {
    bands: Vec<Band>,
}

impl Input {
    /// An input of these bands as channels, in this order; `None` when empty.
    pub fn new(bands: Vec<Band>) -> Option<Self> {
        (!bands.is_empty()).then_some(Self { bands })
    }

    pub fn single(band: Band) -> Self {
        Self { bands: vec![band] }
    }

    pub fn bands(&self) -> &[Band] {
        &self.bands
    }

    /// The band of a one-band input.
    pub fn as_single(&self) -> Option<Band> {
        match self.bands[..] {
            [band] => Some(band),
            _ => None,
        }
    }

    /// Whether the input fuses several bands as channels (feature-level fusion).
    pub fn is_fused(&self) -> bool {
        self.bands.len() > 1
    }

    pub fn has_infrared(&self) -> bool {
        self.bands.iter().any(|b| !b.is_radar())
    }

    /// "C", or "S+X" for several bands as channels.
    pub fn name(&self) -> String {
        self.bands.iter().map(|b| b.name()).collect::<Vec<_>>().join("+")
    }
}

impl From<Band> for Input {
    fn from(band: Band) -> Self {
        Input::single(band)
    }
}

impl fmt::Display for Input {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(&self.name())
    }
}

impl FromStr for Input {
    type Err = UnknownBand;
    /// "C" or "S+X".
    fn from_str(s: &str) -> Result<Self, UnknownBand> {
        let bands = s.split('+').map(Band::from_str).collect::<Result<Vec<_>, _>>()?;
        Input::new(bands).ok_or_else(|| UnknownBand(s.to_string()))
    }
}

/// Serialise a type by its name and read it back by `FromStr`.
macro_rules! serde_by_name {
    ($t:ty) => {
        impl serde::Serialize for $t {
            fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
                serializer.collect_str(self)
            }
        }

        impl<'de> serde::Deserialize<'de> for $t {
            fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
                let text = <String as serde::Deserialize>::deserialize(deserializer)?;
                text.parse().map_err(serde::de::Error::custom)
            }
        }
    };
}
pub(crate) use serde_by_name;

serde_by_name!(Band);
serde_by_name!(Input);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_back_and_order_alphabetically() {
        for b in Band::ALL {
            assert_eq!(b.name().parse::<Band>(), Ok(b));
        }
        let mut sorted = Band::ALL.to_vec();
        sorted.sort();
        assert_eq!(sorted, [Band::C, Band::Lwir, Band::Mwir, Band::S, Band::X]);
        let e = "K".parse::<Band>().unwrap_err().to_string();
        assert!(e.contains("`K`") && e.contains("MWIR"), "{e}");
    }

    #[test]
    fn inputs_are_named_with_plus() {
        let sx: Input = "S+X".parse().unwrap();
        assert_eq!(sx.bands(), [Band::S, Band::X]);
        assert!(sx.is_fused() && !sx.has_infrared());
        assert_eq!(sx.to_string(), "S+X");
        assert_eq!("LWIR".parse::<Input>().unwrap().as_single(), Some(Band::Lwir));
        assert!("S+".parse::<Input>().is_err());
        assert_eq!(serde_json::to_string(&sx).unwrap(), "\"S+X\"");
        assert_eq!(serde_json::from_str::<Input>("\"C+LWIR\"").unwrap().name(), "C+LWIR");
    }
}

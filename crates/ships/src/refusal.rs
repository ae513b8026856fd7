//! Why a ship has no wake: the best line of each signature from it and the test it failed
//! ([`crate::wake::ship_wake`]), so that a user can tell a wake just under a threshold from sea
//! with nothing behind the ship.

use crate::lines::Signature;
use serde::Serialize;

/// The test a ship's best line failed, in the order they are made.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FailedTest {
    /// Its robust z among the directions from its apex is under [`crate::lines::WakeOptions::min_z`].
    Significance,
    /// Its contrast to its sides is under the signature's least.
    Contrast,
    /// A bright line brighter than [`crate::lines::WakeOptions::arm_max_contrast`]: a structure.
    TooBright,
    /// It fades inside the image before its least length.
    Fades,
    /// It leaves the image before [`crate::lines::WakeOptions::min_seen_m`].
    LeavesImage,
}

/// The best line of one signature from a ship that was not taken for its wake, and the test it
/// failed: what a user reads to see whether a wake was near to being seen or not there at all.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Refused {
    pub signature: Signature,
    pub test: FailedTest,
    /// The line's direction from its apex (degrees clockwise from up).
    pub axis_deg: f64,
    /// Its significance among the directions from its apex (robust z) and its contrast to its
    /// sides (the sea's standard deviations), as a wake's.
    pub z: f64,
    pub contrast: f64,
    /// How far it was seen in the image (m), where it passed the tests of z and contrast.
    pub seen_m: Option<f64>,
    pub reason: String,
    /// Where the line lies when significance is the only test it failed; None when it fails
    /// another test too. Its coordinates are the search image's; the outputs give the
    /// product's ([`FaintLine`]).
    #[serde(skip)]
    pub faint_line: Option<FaintLine>,
}

/// A ship's best line that passes every test of a wake but its significance (its contrast, its
/// brightness, its length in the image): where a faint wake would lie, or what chance gives
/// behind a ship. The search takes the best of 360 directions, so chance alone gives such a
/// line behind about one ship in ten (the open-sea points of docs/results.md, "A line along
/// the ship's hull"); it is for an analyst to look at, not a detection.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FaintLine {
    /// Its apex and far end (row, column) and its visible length (m).
    pub start: (f64, f64),
    pub end: (f64, f64),
    pub length_m: f64,
}

/// Why a ship has no wake: its best dark trough and its best bright arm, both refused.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NoWake {
    pub trough: Refused,
    pub bright_arm: Refused,
}

impl Refused {
    /// The failed test and its figure in a few words: "z 3.1", "fades at 600 m".
    pub fn brief(&self) -> String {
        let seen = self.seen_m.unwrap_or(f64::NAN);
        match self.test {
            FailedTest::Significance => format!("z {:.1}", self.z),
            FailedTest::Contrast => format!("contrast {:.2}", self.contrast),
            FailedTest::TooBright => format!("too bright ({:.2})", self.contrast),
            FailedTest::Fades => format!("fades at {seen:.0} m"),
            FailedTest::LeavesImage => format!("leaves at {seen:.0} m"),
        }
    }
}

impl NoWake {
    /// The same refusals with their faint lines moved by `shift` (rows, columns): from a tile's
    /// pixels to the whole image's.
    pub fn shifted(mut self, shift: (f64, f64)) -> Self {
        for refused in [&mut self.trough, &mut self.bright_arm] {
            if let Some(line) = refused.faint_line.as_mut() {
                line.start = (line.start.0 + shift.0, line.start.1 + shift.1);
                line.end = (line.end.0 + shift.0, line.end.1 + shift.1);
            }
        }
        self
    }

    /// "no dark trough: ...; no bright arm: ...".
    pub fn reason(&self) -> String {
        format!(
            "no dark trough: {}; no bright arm: {}",
            self.trough.reason, self.bright_arm.reason
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn refused(signature: Signature, faint_line: Option<FaintLine>) -> Refused {
        Refused {
            signature,
            test: FailedTest::Significance,
            axis_deg: 90.0,
            z: 3.0,
            contrast: 0.5,
            seen_m: None,
            reason: String::new(),
            faint_line,
        }
    }

    /// A tile's faint line moves with the tile's origin; its length and a refusal without one
    /// stay as they were.
    #[test]
    fn a_faint_line_moves_with_its_tile() {
        let line = FaintLine {
            start: (10.0, 20.0),
            end: (10.0, 95.0),
            length_m: 1500.0,
        };
        let n = NoWake {
            trough: refused(Signature::Trough, Some(line)),
            bright_arm: refused(Signature::BrightArm, None),
        }
        .shifted((500.0, 40.0));
        let moved = n.trough.faint_line.unwrap();
        assert_eq!(
            (moved.start, moved.end, moved.length_m),
            ((510.0, 60.0), (510.0, 135.0), 1500.0)
        );
        assert!(n.bright_arm.faint_line.is_none());
    }
}

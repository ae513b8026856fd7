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
    /// "no dark trough: ...; no bright arm: ...".
    pub fn reason(&self) -> String {
        format!(
            "no dark trough: {}; no bright arm: {}",
            self.trough.reason, self.bright_arm.reason
        )
    }
}

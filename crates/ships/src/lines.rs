//! How strongly a line from an apex stands out: its contrast to the bands either side of it,
//! its evidence (the contrast weighed by how much of the line lies in the image), what the way
//! ahead of it takes from a wake's score, and a line's significance among the others (a robust
//! z). The ship's wake search ([`crate::wake`]) and the free one ([`crate::free_wake`]) rank
//! and test their lines by these.

use crate::radon::{median, Normalised};
use crate::wake::{Signature, WakeOptions};

/// How a line stands out from its sides.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Line {
    /// For a trough its darkness under the darker side band, for a bright arm its brightness
    /// over the brighter one (the sea's standard deviations); NaN where the line or both its
    /// sides lie out of the image.
    pub contrast: f64,
    /// The contrast times the square root of the share of the line's samples that lie in the
    /// image, off land and no data. A contrast is a mean over the line's samples, and its noise
    /// falls as one over the square root of their number (the scaling of a t statistic): the
    /// line toward a near edge of the image, or across land, is as noisy as its few samples
    /// make it, and ranked by contrast the directions from a ship near an image's edge were
    /// ranked by their noise (the short lines out of a small chip; docs/results.md). Lines
    /// wholly in the image keep their contrast. The line behind an apex is ranked and tested
    /// by its evidence; the way ahead is taken by its contrast (see `wake::best_ray`).
    pub evidence: f64,
}

/// The line along direction `heading` from `apex`, from `near` to `far` metres, against its
/// side bands.
pub(crate) fn line(
    image: &Normalised,
    apex: (f64, f64),
    heading: f64,
    near: f64,
    o: &WakeOptions,
    far: f64,
    signature: Signature,
) -> Line {
    let (half_width, side_offset, side_half_width, _) = signature.bands(o);
    let (mean, n) = image.ray_mean(apex, heading, (near, far), 0.0, half_width);
    let unseen = Line {
        contrast: f64::NAN,
        evidence: f64::NAN,
    };
    if n < 8 {
        return unseen;
    }
    let left = image
        .ray_mean(apex, heading, (near, far), -side_offset, side_half_width)
        .0;
    let right = image
        .ray_mean(apex, heading, (near, far), side_offset, side_half_width)
        .0;
    // a trough is darker than both its sides, an arm brighter; an edge (a slick's, a coast's)
    // than one only
    let pick = |a: f64, b: f64| match signature {
        Signature::Trough => a.min(b),
        Signature::BrightArm => a.max(b),
    };
    let sides = match (left.is_finite(), right.is_finite()) {
        (true, true) => pick(left, right),
        (true, false) => left,
        (false, true) => right,
        _ => return unseen,
    };
    let contrast = match signature {
        Signature::Trough => sides - mean,
        Signature::BrightArm => mean - sides,
    };
    let capacity = image.ray_capacity((near, far), half_width).max(1);
    Line {
        contrast,
        evidence: contrast * (n as f64 / capacity as f64).min(1.0).sqrt(),
    }
}

/// What the trough's contrast the other way (`ahead`) takes from a wake's score. A wake's score
/// along a heading from an apex is its trough's contrast less the contrast the other way where
/// that is dark too: a wake is a half-line, open sea ahead of its ship; a swell's trough or a
/// slick's edge through the apex is a whole line, dark both ways.
pub(crate) fn ahead_penalty(ahead: f64) -> f64 {
    if ahead.is_finite() {
        ahead.max(0.0)
    } else {
        0.0
    }
}

/// The median of `all` and its robust deviation, 1.4826 MAD (the standard deviation for a
/// Gaussian sample), kept above zero.
pub(crate) fn robust_spread(all: &[f64]) -> (f64, f64) {
    let m = median(all.iter().map(|&v| v as f32)).unwrap_or(0.0);
    let mad = median(all.iter().map(|&v| (v - m).abs() as f32))
        .unwrap_or(0.0)
        .max(1e-6);
    (m, 1.4826 * mad)
}

/// Robust z of `best` among `all`: (best - median) / (1.4826 MAD).
pub(crate) fn robust_z(best: f64, all: &[f64]) -> f64 {
    let (m, sigma) = robust_spread(all);
    (best - m) / sigma
}

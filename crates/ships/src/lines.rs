//! How strongly a line from an apex stands out: its contrast to the bands either side of it,
//! its evidence (the contrast weighed by how much of the line lies in the image), what the way
//! ahead of it takes from a wake's score, and a line's significance among the others (a robust
//! z). The ship's wake search ([`crate::wake`]) and the free one ([`crate::free_wake`]) rank
//! and test their lines by these.

use crate::radon::{median, Normalised};
use crate::wake::{Signature, WakeOptions};

/// The contrast of the line along direction `heading` from `apex` to its side bands: for a
/// trough its darkness under the darker side, for a bright arm its brightness over the
/// brighter side.
pub(crate) fn line_contrast(
    image: &Normalised,
    apex: (f64, f64),
    heading: f64,
    near: f64,
    o: &WakeOptions,
    far: f64,
    signature: Signature,
) -> f64 {
    line_contrast_and_samples(image, apex, heading, near, o, far, signature).0
}

/// The evidence for a line: its contrast times the square root of the share of it that lies
/// in the image. A contrast is a mean over the line's samples, and its noise falls as one over
/// the square root of their number (the scaling of a t statistic): the line toward a near edge
/// of the image, or across land, is as noisy as its few samples make it, and without this
/// weight the directions from a ship near an image's edge are ranked by their noise (the short
/// lines out of a small chip; docs/results.md). Lines wholly in the image keep their contrast.
/// The line behind the apex is ranked and tested by its evidence; the way ahead is taken by
/// its contrast (see `wake::best_ray`).
pub(crate) fn line_evidence(
    image: &Normalised,
    apex: (f64, f64),
    heading: f64,
    near: f64,
    o: &WakeOptions,
    far: f64,
    signature: Signature,
) -> f64 {
    let (contrast, samples) = line_contrast_and_samples(image, apex, heading, near, o, far, signature);
    evidence(image, contrast, samples, near, far, o, signature)
}

/// A line's evidence from its contrast and its samples.
pub(crate) fn evidence(
    image: &Normalised,
    contrast: f64,
    samples: usize,
    near: f64,
    far: f64,
    o: &WakeOptions,
    signature: Signature,
) -> f64 {
    let capacity = image.ray_capacity((near, far), signature.bands(o).0).max(1);
    contrast * (samples as f64 / capacity as f64).min(1.0).sqrt()
}

/// The line's contrast and how many samples its band holds.
pub(crate) fn line_contrast_and_samples(
    image: &Normalised,
    apex: (f64, f64),
    heading: f64,
    near: f64,
    o: &WakeOptions,
    far: f64,
    signature: Signature,
) -> (f64, usize) {
    let (half_width, side_offset, side_half_width, _) = signature.bands(o);
    let (line, n) = image.ray_mean(apex, heading, (near, far), 0.0, half_width);
    if n < 8 {
        return (f64::NAN, n);
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
        _ => return (f64::NAN, n),
    };
    let contrast = match signature {
        Signature::Trough => sides - line,
        Signature::BrightArm => line - sides,
    };
    (contrast, n)
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

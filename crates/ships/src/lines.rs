//! The wake searches' settings and their one measure of a line: how a line from an apex stands
//! out from the bands either side of it (its contrast), and how far that can be trusted from
//! the share of it that lies in the image (its evidence). The ship's wake ([`crate::wake`]) and
//! the free wakes ([`crate::free_wake`]) are both ranked by it.

use crate::radon::Normalised;
use serde::Serialize;

/// The wake searches' settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct WakeOptions {
    /// How far from the apex the trough is searched (m).
    pub length_m: f64,
    /// Half-width of the trough's band and the distance and half-width of the side bands (m).
    pub trough_half_width_m: f64,
    pub side_offset_m: f64,
    pub side_half_width_m: f64,
    /// The largest azimuth offset of a return from its ship searched (m): 130 s x 12 m/s of
    /// range velocity.
    pub max_offset_m: f64,
    /// Significance of a trough among the directions from its apex (robust z).
    pub min_z: f64,
    /// Least contrast of the trough to its sides (in the sea's standard deviations).
    pub min_contrast: f64,
    /// The fastest ship searched (m/s): with R/V known it bounds the return's offset from its
    /// wake for each course.
    pub max_speed: f64,
    /// The free-wake search: its significance among all lines, and the least visible length (m).
    pub free_min_z: f64,
    pub free_min_length_m: f64,
    /// The least visible length of a ship's wake (m) that fades inside the image: a moving
    /// ship's turbulent wake persists for minutes, kilometres behind it (the spec's persistent
    /// wake, Fig. 2.1; the free search's own least length), while the dark patch beside a
    /// bright target (a slick's edge, a shadow, a display's clipped halo) ends within a few
    /// hundred metres. A wake that leaves the image before it fades is kept when it is seen
    /// for `min_seen_m` in it: a kilometre, as for one that fades. At 500 m, short lines from
    /// targets near an image's edge passed as wakes on real images, while every wake found
    /// there was seen for 1.3 km or more (docs/results.md).
    pub min_length_m: f64,
    pub min_seen_m: f64,
    /// The bright arm sought where a ship has no trough: its half-width, the distance and
    /// half-width of its side bands (m), its least brightness over the brighter side (the sea's
    /// standard deviations) and its least visible length (m). At 10 m pixels the narrow V's
    /// arms (half-angles of 1-4 degrees) are a thin bright tail behind the ship, 1-2 pixels
    /// wide; on real C-band display images they ran 500 m to 2 km (docs/results.md).
    pub arm_half_width_m: f64,
    pub arm_side_offset_m: f64,
    pub arm_side_half_width_m: f64,
    pub arm_min_contrast: f64,
    pub arm_min_length_m: f64,
    /// The brightest a bright arm may be (the sea's standard deviations): the narrow V's arms
    /// on real images stood 0.3-1.6 over the brighter side, while lines brighter than that
    /// over a kilometre were structures (a hull at a finer spacing than assumed, a pier, a
    /// sidelobe streak joining ships; docs/results.md).
    pub arm_max_contrast: f64,
    /// A line along the ship's own return needs a robust z of `along_hull_min_z`, not `min_z`:
    /// a moving ship's wake runs straight back along its hull, so a line within
    /// `along_hull_max_deg` of the return's long axis is the wake's expected direction, not one
    /// of 360 directions with nothing to prefer it. The return must be elongated for its axis
    /// to tell: at least `along_hull_min_elongation` times as long as wide and
    /// `along_hull_min_pixels` search pixels long. On the 30 real tuning images, lines at z 4-5
    /// within 15 degrees of such a return's axis lay on a drawn wake 18 times and elsewhere 3
    /// (docs/results.md, "A line along the ship's hull").
    pub along_hull_min_z: f64,
    pub along_hull_max_deg: f64,
    pub along_hull_min_elongation: f64,
    pub along_hull_min_pixels: f64,
    /// Where a search reports no wake at all, the faint line of the largest z (a ship's best
    /// line refused for its significance alone) is reported as its wake when its z is at least
    /// `promote_min_z` ([`crate::promotion::promote_best_faint_line`]); infinite: never. Stated
    /// before a fourth set of real wake images was drawn and scored, and held there: over the
    /// four held-out sets its lines lay on a drawn wake 6 times in 8, as often as the strict
    /// search's own (docs/results.md, "The image's best line").
    pub promote_min_z: f64,
}

impl Default for WakeOptions {
    fn default() -> Self {
        Self {
            length_m: 2500.0,
            trough_half_width_m: 20.0,
            side_offset_m: 190.0,
            side_half_width_m: 100.0,
            max_offset_m: 1500.0,
            min_z: 5.0,
            min_contrast: 0.25,
            max_speed: 15.0,
            free_min_z: 8.0,
            free_min_length_m: 1000.0,
            min_length_m: 1000.0,
            min_seen_m: 1000.0,
            arm_half_width_m: 10.0,
            arm_side_offset_m: 100.0,
            arm_side_half_width_m: 50.0,
            arm_min_contrast: 0.25,
            arm_min_length_m: 500.0,
            arm_max_contrast: 1.6,
            along_hull_min_z: 4.0,
            along_hull_max_deg: 15.0,
            along_hull_min_elongation: 1.5,
            along_hull_min_pixels: 3.0,
            promote_min_z: 4.5,
        }
    }
}

/// What marks a wake in the image.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Signature {
    /// The turbulent wake's dark trough, darker than the sea either side of it.
    #[serde(rename = "dark trough")]
    Trough,
    /// A bright arm of the narrow V (or its two arms merged at the image's resolution), brighter
    /// than the sea either side of it: many real C- and X-band wakes show this alone (the
    /// transfer issue's item 4; the narrow-V wake of Bragg waves, Munk, Scully-Power and
    /// Zachariasen 1987).
    #[serde(rename = "bright arm")]
    BrightArm,
}

impl Signature {
    /// The line's band half-width, the side bands' distance and half-width (m), and the least
    /// contrast of the line to its sides.
    pub(crate) fn bands(self, o: &WakeOptions) -> (f64, f64, f64, f64) {
        match self {
            Signature::Trough => (
                o.trough_half_width_m,
                o.side_offset_m,
                o.side_half_width_m,
                o.min_contrast,
            ),
            Signature::BrightArm => (
                o.arm_half_width_m,
                o.arm_side_offset_m,
                o.arm_side_half_width_m,
                o.arm_min_contrast,
            ),
        }
    }

    /// How far from straight back (degrees, either way) the line's way ahead is measured:
    /// [`ARM_AHEAD_SPREAD_DEG`] for a thin arm, straight back for a trough.
    pub(crate) fn ahead_spread_deg(self) -> f64 {
        match self {
            Signature::Trough => 0.0,
            Signature::BrightArm => ARM_AHEAD_SPREAD_DEG,
        }
    }
}

/// How far from straight back (degrees, either way) a bright arm's way ahead is measured: a
/// sidelobe streak is one or two pixels wide, and a ray tilted under a degree from an apex a
/// pixel off it stays on the streak one way and leaves it the other, making the whole line
/// look like a half-line.
const ARM_AHEAD_SPREAD_DEG: f64 = 1.0;

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
    /// by its evidence; the way ahead is taken by its contrast (see `best_ray`).
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

/// `n` values from `lo` to `hi` inclusive.
pub(crate) fn span(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    let n = ((hi - lo) / step).round() as usize;
    (0..=n).map(|i| lo + step * i as f64).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::radon::SearchImage;
    use crate::Geometry;

    /// Lines from an apex 100 m inside an image's edge over plain speckle: those out of the
    /// image hold a few dozen samples, those into it a full 2.5 km. A mean's noise falls as one
    /// over the square root of its samples, so the short lines' contrasts spread several times
    /// as widely as the long ones'; weighted by the square root of their share in the image
    /// (their evidence) they spread alike, and no short line outranks the long ones by its
    /// noise alone.
    #[test]
    fn a_lines_evidence_is_as_noisy_near_an_edge_as_far_from_it() {
        let g = Geometry::along_rows(10.0, 35.0, None);
        let o = WakeOptions::default();
        let apex = (200.0, 390.0);
        let (mut short, mut long) = ((Vec::new(), Vec::new()), (Vec::new(), Vec::new()));
        for seed in 0..8 {
            let image = crate::speckle(400, 400, 4, 0.01, 100 + seed);
            let search = SearchImage::new(image.view(), &g, 2000.0);
            for h in 0..=60 {
                for (heading, into) in [(60.0 + h as f64, &mut short), (240.0 + h as f64, &mut long)] {
                    let l = line(&search.fine, apex, heading, 60.0, &o, o.length_m, Signature::Trough);
                    let (c, e) = (l.contrast, l.evidence);
                    if c.is_finite() {
                        into.0.push(c);
                        into.1.push(e);
                    }
                }
            }
        }
        let sd = |v: &[f64]| {
            let m = v.iter().sum::<f64>() / v.len() as f64;
            (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (v.len() - 1) as f64).sqrt()
        };
        let contrast_ratio = sd(&short.0) / sd(&long.0);
        let evidence_ratio = sd(&short.1) / sd(&long.1);
        assert!(
            short.0.len() > 300 && long.0.len() == 8 * 61,
            "{} {}",
            short.0.len(),
            long.0.len()
        );
        assert!(contrast_ratio > 3.0, "contrast spread short / long {contrast_ratio:.2}");
        assert!(
            (0.5..2.0).contains(&evidence_ratio),
            "evidence spread short / long {evidence_ratio:.2}"
        );
    }
}

//! The image's best line: where a search finds no wake at all, its faint line of the largest z
//! (a ship's best line refused for its significance alone, [`crate::refusal::FaintLine`]) is
//! promoted to its wake when that z reaches [`WakeOptions::promote_min_z`].

use crate::cfar::Ship;
use crate::lines::WakeOptions;
use crate::radon::SearchImage;
use crate::refusal::NoWake;
use crate::wake::{anchored_wake, Wake};

/// The image's best line: where a search reported no wake at all, the faint line of the
/// largest z among `no_wake` (each ship's index in `ships` with its refusals), measured as a
/// wake (its course, length and speeds) and marked [`Wake::promoted`], when its z is at least
/// [`WakeOptions::promote_min_z`]; None where no faint line reaches it.
///
/// It adds at most one wake to a search, and only to one that reported none, so it cannot take
/// an image past one false wake. A line at z 4.5-5 behind one ship is weaker evidence than the
/// strict search's (`min_z` 5): on the 30 real tuning images that search itself gives a false
/// wake behind 6.5 % of the ships without a drawn one, and 21 of their 155 best lines reach 4.5.
/// The rule was stated with its threshold before a fourth set of real wake images was drawn,
/// and taken on what that set gave (docs/results.md, "The image's best line").
pub fn promote_best_faint_line(
    image: &SearchImage,
    ships: &[Ship],
    no_wake: &[(usize, NoWake)],
    o: &WakeOptions,
) -> Option<Wake> {
    let (index, refused) = no_wake
        .iter()
        .flat_map(|(i, n)| [(*i, &n.trough), (*i, &n.bright_arm)])
        .filter(|(_, r)| r.faint_line.is_some() && r.z >= o.promote_min_z)
        .max_by(|a, b| a.1.z.total_cmp(&b.1.z))?;
    // the same search with the significance lowered to the rule's: it measures the same line,
    // which now passes, with everything a wake is given
    let relaxed = WakeOptions {
        min_z: o.min_z.min(o.promote_min_z),
        along_hull_min_z: o.along_hull_min_z.min(o.promote_min_z),
        ..*o
    };
    let wake = anchored_wake(image, ships.get(index)?, index, &relaxed, refused.signature).ok()?;
    Some(Wake { promoted: true, ..wake })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cfar::CfarOptions;
    use crate::{angle_difference, search, Geometry};
    use ndarray::Array2;

    /// Two ships on 4-look speckle at 10 m, their small returns 2.7 km apart along the azimuth
    /// (beyond the 1.5 km an apex is sought from its return): A (row 150) with a faint trough
    /// (-1 dB, 50 m wide) running west 1.5 km, B (row 420) with a trough of -3 dB where
    /// `b_wake`, else none.
    fn a_faint_trough_beside(b_wake: bool) -> Array2<f32> {
        let mut image = crate::speckle(500, 300, 4, 0.01, 77);
        image
            .slice_mut(ndarray::s![148..153, 40..185])
            .mapv_inplace(|v| v * 0.8);
        image.slice_mut(ndarray::s![140..=159, 199..=200]).fill(3.0);
        if b_wake {
            image
                .slice_mut(ndarray::s![418..423, 40..185])
                .mapv_inplace(|v| v * 0.5);
        }
        image.slice_mut(ndarray::s![419..=421, 198..=200]).fill(3.0);
        image
    }

    /// The image's best line: where a search reports no wake, its faint line of the largest z
    /// is reported as the wake once the rule's threshold is under that z, measured as a wake
    /// (the same wake, field by field, as the search at any significance finds) and marked
    /// promoted, its ship no longer among those without one. Over its z it stays a faint line;
    /// and where the search reports another wake, no line is promoted.
    #[test]
    fn a_search_without_a_wake_promotes_its_best_faint_line() {
        let g = Geometry::along_rows(10.0, 35.0, None);
        let cfar = CfarOptions::default();
        let image = a_faint_trough_beside(false);
        let any = WakeOptions {
            min_z: f64::NEG_INFINITY,
            along_hull_min_z: f64::NEG_INFINITY,
            promote_min_z: f64::INFINITY,
            ..WakeOptions::default()
        };
        let all = search(image.view(), &g, &cfar, &any);
        assert_eq!(all.ships.ships.len(), 2, "{:?}", all.ships.ships);
        let a = all
            .ships
            .ships
            .iter()
            .position(|s| (s.row - 150.0).abs() < 10.0)
            .expect("ship A");
        let faint = all.wakes.iter().find(|w| w.ship == Some(a)).expect("A's line at any z");
        assert!(angle_difference(faint.axis_deg, 270.0).abs() < 2.0, "{faint:?}");
        assert!(!faint.promoted);
        // B's best line, noise (a wake at any z, or refused for another test), stands well
        // under A's: the rule has one line to take
        let b_best = all.wakes.iter().find(|w| w.ship == Some(1 - a)).map_or_else(
            || {
                let (_, n) = &all.no_wake[0];
                n.trough.z.max(n.bright_arm.z)
            },
            |w| w.z,
        );
        assert!(b_best < faint.z - 0.5, "B's {b_best} against {faint:?}");
        let strict = WakeOptions {
            min_z: faint.z + 1.0,
            along_hull_min_z: faint.z + 1.0,
            promote_min_z: faint.z - 0.25,
            ..WakeOptions::default()
        };
        let found = search(image.view(), &g, &cfar, &strict);
        assert_eq!(found.wakes.len(), 1, "{:?}", found.wakes);
        let promoted = &found.wakes[0];
        assert!(promoted.promoted, "{promoted:?}");
        assert_eq!(
            &Wake {
                promoted: false,
                ..promoted.clone()
            },
            faint
        );
        assert!(promoted.course_sigma_deg.is_some() && promoted.speed.is_some());
        assert_eq!(found.no_wake.iter().map(|(k, _)| *k).collect::<Vec<_>>(), vec![1 - a]);
        // the threshold over the line's z: no wake, and the line stays a faint line
        let above = WakeOptions {
            promote_min_z: faint.z + 0.25,
            ..strict
        };
        let found = search(image.view(), &g, &cfar, &above);
        assert!(found.wakes.is_empty(), "{:?}", found.wakes);
        let (_, refused) = found.no_wake.iter().find(|(k, _)| *k == a).expect("A refused");
        assert!(refused.trough.faint_line.is_some() && refused.trough.z >= strict.promote_min_z);
        // B with a wake of its own: A's line, over the rule's threshold, is not promoted
        let image = a_faint_trough_beside(true);
        let found = search(image.view(), &g, &cfar, &strict);
        assert_eq!(found.wakes.len(), 1, "{:?}", found.wakes);
        let b_wake = &found.wakes[0];
        assert!(!b_wake.promoted && (found.ships.ships[b_wake.ship.unwrap()].row - 420.0).abs() < 10.0);
        let (_, refused) = found
            .no_wake
            .iter()
            .find(|(k, _)| *k != b_wake.ship.unwrap())
            .expect("A refused");
        assert!(
            refused.trough.faint_line.is_some() && refused.trough.z >= strict.promote_min_z,
            "{refused:?}"
        );
    }
}

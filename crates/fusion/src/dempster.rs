//! Dempster-Shafer evidence over a finite frame of discernment (spec Eq. (5.6)), sets as bit masks.
//!
//! Dempster's rule: m12(A) = sum_{B cap C = A} m1(B) m2(C) / (1 - k), with the conflict
//! k = sum_{B cap C = empty} m1(B) m2(C). The rule is associative and commutative, so n sources
//! fold pairwise. Belief bel(A) = sum_{B subset of A} m(B) (erratum 10), plausibility
//! pl(A) = sum_{B cap A nonempty} m(B), pignistic probability BetP(x) = sum_{A contains x} m(A) / |A|.

use std::collections::BTreeMap;

/// A mass function: focal sets (bit masks over the frame) and their masses.
pub type Mass = BTreeMap<u32, f64>;

/// Dempster's combination of two mass functions and their conflict k; None when k = 1 (total
/// conflict: the rule is undefined).
pub fn combine(m1: &Mass, m2: &Mass) -> Option<(Mass, f64)> {
    let mut out = Mass::new();
    let mut conflict = 0.0;
    for (&b, &x) in m1 {
        for (&c, &y) in m2 {
            let a = b & c;
            if a == 0 {
                conflict += x * y;
            } else {
                *out.entry(a).or_default() += x * y;
            }
        }
    }
    if conflict >= 1.0 - 1e-15 {
        return None;
    }
    out.values_mut().for_each(|v| *v /= 1.0 - conflict);
    Some((out, conflict))
}

/// Fold n mass functions with Dempster's rule; returns the result and the conflict of each step.
pub fn combine_all(masses: &[Mass]) -> Option<(Mass, Vec<f64>)> {
    let (first, rest) = masses.split_first()?;
    let mut acc = first.clone();
    let mut conflicts = Vec::new();
    for m in rest {
        let (next, k) = combine(&acc, m)?;
        acc = next;
        conflicts.push(k);
    }
    Some((acc, conflicts))
}

/// Belief of set `a`.
pub fn belief(m: &Mass, a: u32) -> f64 {
    m.iter().filter(|(&b, _)| b & !a == 0).map(|(_, v)| v).sum()
}

/// Plausibility of set `a`.
pub fn plausibility(m: &Mass, a: u32) -> f64 {
    m.iter().filter(|(&b, _)| b & a != 0).map(|(_, v)| v).sum()
}

/// Pignistic probability of the singleton with bit index `x`.
pub fn pignistic(m: &Mass, x: u32) -> f64 {
    m.iter()
        .filter(|(&b, _)| b & (1 << x) != 0)
        .map(|(&b, &v)| v / b.count_ones() as f64)
        .sum()
}

/// Frame {wake, no wake}: bit 0 = wake, bit 1 = no wake.
pub const WAKE: u32 = 0b01;
pub const NO_WAKE: u32 = 0b10;
pub const EITHER: u32 = 0b11;

/// Masses from a classifier's output o in [0, 1] and its reliability r in [0, 1] (for example
/// its accuracy on held-out data): m({wake}) = r o, m({no wake}) = r (1 - o), and the doubt
/// m({wake, no wake}) = 1 - r (Shafer's discounting).
pub fn classifier_mass(output: f64, reliability: f64) -> Mass {
    let (o, r) = (output.clamp(0.0, 1.0), reliability.clamp(0.0, 1.0));
    Mass::from([(WAKE, r * o), (NO_WAKE, r * (1.0 - o)), (EITHER, 1.0 - r)])
}

#[cfg(test)]
mod tests {
    use super::*;

    const A: u32 = 1;
    const B: u32 = 2;
    const C: u32 = 4;
    const D: u32 = 8;

    fn issue_masses() -> (Mass, Mass) {
        let m1 = Mass::from([(A, 0.4), (B, 0.2), (A | D, 0.1), (A | B | C | D, 0.3)]);
        let m2 = Mass::from([(B, 0.5), (C, 0.2), (A | C, 0.3)]);
        (m1, m2)
    }

    /// The worked example of the fusion issue (hand-computed from the definitions).
    #[test]
    fn dempsters_rule_on_the_worked_example() {
        let (m1, m2) = issue_masses();
        let (m, k) = combine(&m1, &m2).unwrap();
        assert!((k - 0.45).abs() < 1e-12);
        for (set, want) in [(A, 0.272727), (B, 0.454545), (C, 0.109091), (A | C, 0.163636)] {
            assert!((m[&set] - want).abs() < 1e-6, "{set:#b}: {}", m[&set]);
        }
        assert!((m.values().sum::<f64>() - 1.0).abs() < 1e-12);
        for (x, want) in [(0, 0.525), (1, 0.275), (2, 0.075), (3, 0.125)] {
            assert!((pignistic(&m1, x) - want).abs() < 1e-12);
        }
        assert!((belief(&m1, A) - 0.4).abs() < 1e-12);
        assert!((plausibility(&m1, A) - 0.8).abs() < 1e-12);
    }

    #[test]
    fn the_rule_is_associative_and_commutative() {
        let (m1, m2) = issue_masses();
        let m3 = Mass::from([(A | B, 0.6), (D, 0.1), (A | B | C | D, 0.3)]);
        let left = combine(&combine(&m1, &m2).unwrap().0, &m3).unwrap().0;
        let right = combine(&m1, &combine(&m2, &m3).unwrap().0).unwrap().0;
        let swapped = combine(&combine(&m2, &m1).unwrap().0, &m3).unwrap().0;
        for set in left.keys() {
            assert!((left[set] - right[set]).abs() < 1e-12 && (left[set] - swapped[set]).abs() < 1e-12);
        }
        assert!(combine(&Mass::from([(A, 1.0)]), &Mass::from([(B, 1.0)])).is_none());
    }

    #[test]
    fn classifier_masses_follow_the_reliable_source() {
        let (m, conflicts) = combine_all(&[classifier_mass(0.9, 0.95), classifier_mass(0.2, 0.1)]).unwrap();
        assert!(pignistic(&m, 0) > 0.5);
        assert_eq!(conflicts.len(), 1);
        // a fully unreliable source is vacuous: it changes nothing
        let (alone, _) = combine_all(&[classifier_mass(0.7, 0.8)]).unwrap();
        let (with_vacuous, k) = combine_all(&[classifier_mass(0.7, 0.8), classifier_mass(0.1, 0.0)]).unwrap();
        assert_eq!(k, vec![0.0]);
        for set in alone.keys() {
            assert!((alone[set] - with_vacuous[set]).abs() < 1e-15);
        }
    }
}

//! The Bayes classifier of spec Eqs. (5.1)-(5.5): each source's output o_i is weighted by its
//! precision TP/(TP + FP) and false-omission rate FN/(TN + FN), measured on data the fused
//! images are not part of (erratum 11):
//!   P_wake    = sum_i TP_i/(TP_i + FP_i) o_i + FN_i/(TN_i + FN_i) (1 - o_i)        (5.4)
//!   P_no_wake = sum_i (1 - TP_i/(TP_i + FP_i)) o_i + (1 - FN_i/(TN_i + FN_i)) (1 - o_i) (5.5)
//! and the decision is wake when P_wake > P_no_wake (5.3). A ratio with a zero denominator (a
//! source that never said "wake", or never "no wake") carries no information and is taken as 1/2.

use serde::Serialize;
use wakelab_schema::metrics::Confusion;

/// P[y = 1 | c = 1] and P[y = 1 | c = 0] of one source.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SourceWeights {
    pub precision: f64,
    pub false_omission: f64,
}

impl SourceWeights {
    pub fn from_confusion(c: &Confusion) -> Self {
        let ratio = |num: u64, den: u64| if den == 0 { 0.5 } else { num as f64 / den as f64 };
        Self {
            precision: ratio(c.tp, c.tp + c.fp),
            false_omission: ratio(c.fn_, c.tn + c.fn_),
        }
    }
}

/// The fused evidence and decision for one image.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BayesDecision {
    pub p_wake: f64,
    pub p_no_wake: f64,
    pub wake: bool,
}

/// Fuse the sources' outputs `o_i` (in [0, 1]) with their weights.
pub fn bayes_fuse(outputs: &[f64], weights: &[SourceWeights]) -> BayesDecision {
    assert_eq!(outputs.len(), weights.len(), "one weight per source");
    let (mut wake, mut no) = (0.0, 0.0);
    for (&o, w) in outputs.iter().zip(weights) {
        wake += w.precision * o + w.false_omission * (1.0 - o);
        no += (1.0 - w.precision) * o + (1.0 - w.false_omission) * (1.0 - o);
    }
    BayesDecision {
        p_wake: wake,
        p_no_wake: no,
        wake: wake > no,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_perfect_and_a_useless_classifier_fuse_to_the_perfect_one() {
        let perfect = SourceWeights::from_confusion(&Confusion {
            tp: 50,
            tn: 50,
            fp: 0,
            fn_: 0,
        });
        // a coin: as many right as wrong either way
        let useless = SourceWeights::from_confusion(&Confusion {
            tp: 25,
            tn: 25,
            fp: 25,
            fn_: 25,
        });
        assert_eq!(
            perfect,
            SourceWeights {
                precision: 1.0,
                false_omission: 0.0
            }
        );
        for (o_perfect, o_useless) in [(0.9, 0.1), (0.1, 0.9), (0.8, 0.8), (0.3, 0.0)] {
            let d = bayes_fuse(&[o_perfect, o_useless], &[perfect, useless]);
            assert_eq!(d.wake, o_perfect > 0.5, "{o_perfect} {o_useless}: {d:?}");
        }
    }

    #[test]
    fn equations_5_4_and_5_5_by_hand() {
        let w = SourceWeights::from_confusion(&Confusion {
            tp: 8,
            tn: 6,
            fp: 2,
            fn_: 4,
        });
        // precision 0.8, false omission 0.4; o = 0.7: P_wake = 0.56 + 0.12, P_no = 0.14 + 0.18
        let d = bayes_fuse(&[0.7], &[w]);
        assert!((d.p_wake - 0.68).abs() < 1e-12 && (d.p_no_wake - 0.32).abs() < 1e-12 && d.wake);
    }
}

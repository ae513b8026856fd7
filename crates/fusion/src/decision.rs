//! Decision-level fusion of kept classifier outputs (spec 5.1, 5.2): for each repetition of
//! Algorithm 2, the sources' test outputs on the same scenes are fused by the Bayes classifier
//! (5.3-5.5), each source weighted by its TP/FP/TN/FN on its own training images (erratum 11:
//! never on the images being fused), and by Dempster-Shafer (5.6) with m_i(wake) = o_i,
//! m_i(no wake) = 1 - o_i, decided on the pignistic probability of "wake" and reported with the
//! conflict k of the combination.

use crate::bayes::{bayes_fuse, SourceWeights};
use crate::dempster::{classifier_mass, combine_all, pignistic, Mass};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use wakelab_schema::band::{Band, Input};
pub use wakelab_schema::fusion_row::{FusionRow, Method, Source};
use wakelab_schema::metrics::Confusion;
use wakelab_schema::results::{summarise_scores, Architecture, Output, Scored, Summary};
use wakelab_schema::split::Split;

/// One fused decision on one test scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FusedOutput {
    /// The method and the fused inputs, named "Bayes classifier (S, X)" and the like: the row
    /// name of Tables 5.1-5.3.
    pub fusion: FusionRow,
    pub architecture: Architecture,
    pub repetition: usize,
    pub scene: String,
    pub label: u8,
    /// Bayes: P_wake / (P_wake + P_no_wake); Dempster-Shafer: the pignistic probability of wake.
    pub output: f64,
    /// Dempster-Shafer's total conflict 1 - prod(1 - k_j) over the pairwise folds (0 for Bayes).
    pub conflict: f64,
}

/// Outputs of Dempster-Shafer's rule are undefined at total conflict (one source certain of
/// wake, another certain of no wake); masses are kept this far from 0 and 1.
const CERTAINTY_LIMIT: f64 = 1e-6;

/// Fuse the single-source outputs of `sources` (inputs such as "S" and "X") of one
/// architecture, repetition by repetition, on the test scenes every source saw.
pub fn fuse_decisions(
    outputs: &[Output],
    sources: &[Input],
    architecture: Architecture,
    method: Method,
    threshold: f64,
) -> Vec<FusedOutput> {
    let row = FusionRow {
        method,
        sources: sources.to_vec(),
    };
    let mut repetitions: Vec<usize> = outputs.iter().map(|o| o.repetition).collect();
    repetitions.sort();
    repetitions.dedup();
    let mut fused = Vec::new();
    for r in repetitions {
        let of = |source: &Input, split: Split| -> Vec<&Output> {
            outputs
                .iter()
                .filter(|o| {
                    o.repetition == r && o.architecture == architecture && &o.bands == source && o.split == split
                })
                .collect()
        };
        // each source's weights from its training images
        let weights: Vec<SourceWeights> = sources
            .iter()
            .map(|s| {
                let (o, l): (Vec<f64>, Vec<u8>) = of(s, Split::Train).iter().map(|o| (o.output, o.label)).unzip();
                SourceWeights::from_confusion(&Confusion::from_outputs(&o, &l, threshold))
            })
            .collect();
        let tests: Vec<BTreeMap<&str, &Output>> = sources
            .iter()
            .map(|s| of(s, Split::Test).into_iter().map(|o| (o.scene.as_str(), o)).collect())
            .collect();
        let Some(first) = tests.first() else { continue };
        for (&scene, o0) in first {
            let Some(per_source) = tests
                .iter()
                .map(|t| t.get(scene).map(|o| o.output))
                .collect::<Option<Vec<f64>>>()
            else {
                continue;
            };
            let (output, conflict) = match method {
                Method::Bayes => {
                    let d = bayes_fuse(&per_source, &weights);
                    (d.p_wake / (d.p_wake + d.p_no_wake), 0.0)
                }
                Method::DempsterShafer => {
                    let masses: Vec<Mass> = per_source
                        .iter()
                        .map(|&o| classifier_mass(o.clamp(CERTAINTY_LIMIT, 1.0 - CERTAINTY_LIMIT), 1.0))
                        .collect();
                    let (m, ks) = combine_all(&masses).expect("masses kept off total conflict");
                    let conflict = 1.0 - ks.iter().map(|k| 1.0 - k).product::<f64>();
                    (pignistic(&m, 0), conflict)
                }
            };
            fused.push(FusedOutput {
                fusion: row.clone(),
                architecture,
                repetition: r,
                scene: scene.to_string(),
                label: o0.label,
                output,
                conflict,
            });
        }
    }
    fused
}

/// Source sets fused at decision level from the single bands evaluated: the spec's (S, X) of
/// 5.2, every SAR band together, and SAR with IR (5.4): each set only when all its bands were
/// evaluated alone.
pub fn decision_sets(single_bands: &[Band]) -> Vec<Vec<Input>> {
    use Band::*;
    let pick = |bands: &[Band]| -> Vec<Input> {
        bands
            .iter()
            .filter(|b| single_bands.contains(b))
            .map(|&b| Input::single(b))
            .collect()
    };
    let mut sets = Vec::new();
    for candidate in [
        pick(&[S, X]),
        pick(&[S, C, X]),
        pick(&[C, Lwir]),
        pick(&[S, C, X, Mwir, Lwir]),
    ] {
        if candidate.len() >= 2 && !sets.contains(&candidate) {
            sets.push(candidate);
        }
    }
    sets
}

/// Every decision-level fusion of the kept single-band outputs: for each architecture and source
/// set, Bayes and Dempster-Shafer; returns the fused outputs and their metrics (the fusion rows
/// of Tables 5.1-5.3) with the mean conflict of each Dempster-Shafer row.
pub fn fuse_all(outputs: &[Output], threshold: f64) -> (Vec<FusedOutput>, Vec<(Summary, f64)>) {
    let mut singles: Vec<Band> = outputs.iter().filter_map(|o| o.bands.as_single()).collect();
    singles.sort();
    singles.dedup();
    let mut architectures: Vec<Architecture> = outputs.iter().map(|o| o.architecture).collect();
    architectures.sort();
    architectures.dedup();
    let mut fused = Vec::new();
    for &a in &architectures {
        for set in decision_sets(&singles) {
            for method in Method::ALL {
                fused.extend(fuse_decisions(outputs, &set, a, method, threshold));
            }
        }
    }
    let scored: Vec<Scored> = fused
        .iter()
        .map(|f| {
            Scored::new(
                Source::Fusion(f.fusion.clone()),
                f.architecture,
                f.repetition,
                f.label,
                f.output,
            )
        })
        .collect();
    let summaries = summarise_scores(&scored, threshold)
        .into_iter()
        .map(|s| {
            let ks: Vec<f64> = fused
                .iter()
                .filter(|f| s.bands.fusion() == Some(&f.fusion) && f.architecture == s.architecture)
                .map(|f| f.conflict)
                .collect();
            let mean_conflict = ks.iter().sum::<f64>() / ks.len().max(1) as f64;
            (s, mean_conflict)
        })
        .collect();
    (fused, summaries)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decision_sets_follow_the_bands_evaluated() {
        let b = |v: &[&str]| v.iter().map(|s| s.parse::<Band>().unwrap()).collect::<Vec<_>>();
        let i = |v: &[&str]| v.iter().map(|s| s.parse::<Input>().unwrap()).collect::<Vec<_>>();
        assert_eq!(decision_sets(&b(&["S", "X"])), vec![i(&["S", "X"])]);
        assert_eq!(
            decision_sets(&b(&["C", "LWIR", "MWIR", "S", "X"])),
            vec![
                i(&["S", "X"]),
                i(&["S", "C", "X"]),
                i(&["C", "LWIR"]),
                i(&["S", "C", "X", "MWIR", "LWIR"])
            ]
        );
        assert!(decision_sets(&b(&["C"])).is_empty());
    }

    fn out(bands: &str, split: &str, r: usize, scene: &str, label: u8, output: f64) -> Output {
        Output {
            bands: bands.parse().unwrap(),
            architecture: Architecture::Base,
            repetition: r,
            split: split.parse().unwrap(),
            scene: scene.into(),
            label,
            output,
        }
    }

    #[test]
    fn bayes_follows_the_source_that_was_right_in_training() {
        let mut outputs = Vec::new();
        // training: "S" always right, "X" always says wake
        for (i, label) in [1u8, 0, 1, 0].into_iter().enumerate() {
            let scene = format!("t{i}");
            outputs.push(out("S", "train", 0, &scene, label, if label == 1 { 0.9 } else { 0.1 }));
            outputs.push(out("X", "train", 0, &scene, label, 0.9));
        }
        // test: the two disagree on every scene
        outputs.push(out("S", "test", 0, "a", 0, 0.2));
        outputs.push(out("X", "test", 0, "a", 0, 0.8));
        outputs.push(out("S", "test", 0, "b", 1, 0.8));
        outputs.push(out("X", "test", 0, "b", 1, 0.8));
        let sources = vec![Input::single(Band::S), Input::single(Band::X)];
        let fused = fuse_decisions(&outputs, &sources, Architecture::Base, Method::Bayes, 0.5);
        assert_eq!(fused.len(), 2);
        let a = fused.iter().find(|f| f.scene == "a").unwrap();
        // S: precision 1, false omission 0; X: precision 1/2, false omission 1/2 (no "no wake" ever)
        // P_wake = (1 * 0.2 + 0) + (0.5 * 0.8 + 0.5 * 0.2) = 0.7; P_no = 0.8 + 0.5 = 1.3
        assert!((a.output - 0.7 / 2.0).abs() < 1e-12, "{}", a.output);
        assert_eq!(a.fusion.to_string(), "Bayes classifier (S, X)");
        let ds = fuse_decisions(&outputs, &sources, Architecture::Base, Method::DempsterShafer, 0.5);
        let a = ds.iter().find(|f| f.scene == "a").unwrap();
        // m1 = (0.2, 0.8), m2 = (0.8, 0.2): k = 0.2*0.2 + 0.8*0.8 = 0.68, wake = 0.16 / 0.32
        assert!(
            (a.conflict - 0.68).abs() < 1e-12 && (a.output - 0.5).abs() < 1e-12,
            "{a:?}"
        );
    }
}

//! Probabilities that mean what they say: temperature scaling of a detector's logit (Guo et al.,
//! "On calibration of modern neural networks", ICML 2017; the spec is silent on calibration),
//! its reliability diagram and expected calibration error (ECE), and the decision threshold
//! that holds a stated false-alarm rate on a given area of open sea.

use serde::{Deserialize, Serialize};

/// Scores are clipped this far from 0 and 1 before their logit is taken (a sigmoid in f32
/// saturates at 1 - 6e-8).
const CLIP: f64 = 1e-7;

/// The log-odds of a probability, clipped to [1e-7, 1 - 1e-7].
pub fn logit(p: f64) -> f64 {
    let p = p.clamp(CLIP, 1.0 - CLIP);
    (p / (1.0 - p)).ln()
}

/// The probability a detector of score `p` gives after temperature scaling:
/// sigmoid(logit(p) / T). T > 1 softens an over-confident detector, T < 1 sharpens it.
pub fn scaled(p: f64, temperature: f64) -> f64 {
    1.0 / (1.0 + (-logit(p) / temperature).exp())
}

/// Mean negative log-likelihood (nats) of binary `labels` under the scores scaled by
/// `temperature`.
pub fn mean_nll(scores: &[f64], labels: &[u8], temperature: f64) -> f64 {
    let sum: f64 = scores
        .iter()
        .zip(labels)
        .map(|(&p, &y)| {
            let q = scaled(p, temperature).clamp(1e-12, 1.0 - 1e-12);
            if y == 1 {
                -q.ln()
            } else {
                -(1.0 - q).ln()
            }
        })
        .sum();
    sum / scores.len().max(1) as f64
}

/// Least and largest temperatures searched (a detector whose scores are anti-correlated with
/// its labels gets the largest: its scores then carry almost no information).
pub const TEMPERATURE_RANGE: (f64, f64) = (0.05, 50.0);

/// The temperature that minimises the mean negative log-likelihood of `labels` (Guo et al.
/// 2017, Sec. 4.2), found by golden-section search over ln T in [`TEMPERATURE_RANGE`]; the NLL
/// is convex in 1/T, so unimodal in ln T. 1 when there are no scores.
pub fn fit_temperature(scores: &[f64], labels: &[u8]) -> f64 {
    if scores.is_empty() {
        return 1.0;
    }
    let f = |ln_t: f64| mean_nll(scores, labels, ln_t.exp());
    let (mut a, mut b) = (TEMPERATURE_RANGE.0.ln(), TEMPERATURE_RANGE.1.ln());
    let ratio = (5f64.sqrt() - 1.0) / 2.0;
    let (mut c, mut d) = (b - ratio * (b - a), a + ratio * (b - a));
    let (mut fc, mut fd) = (f(c), f(d));
    while b - a > 1e-6 {
        if fc < fd {
            (b, d, fd) = (d, c, fc);
            c = b - ratio * (b - a);
            fc = f(c);
        } else {
            (a, c, fc) = (c, d, fd);
            d = a + ratio * (b - a);
            fd = f(d);
        }
    }
    (0.5 * (a + b)).exp()
}

/// One bin of a reliability diagram.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ReliabilityBin {
    /// The bin's score interval [lo, hi) (the last bin includes 1).
    pub lo: f64,
    pub hi: f64,
    pub count: usize,
    /// Mean score and share of label 1 of the bin's samples (None in an empty bin).
    pub mean_score: Option<f64>,
    pub observed: Option<f64>,
}

/// The reliability diagram of `scores` against `labels` in `bins` equal-width bins over [0, 1].
pub fn reliability(scores: &[f64], labels: &[u8], bins: usize) -> Vec<ReliabilityBin> {
    let bins = bins.max(1);
    let mut sums = vec![(0usize, 0.0f64, 0usize); bins];
    for (&p, &y) in scores.iter().zip(labels) {
        let k = ((p.clamp(0.0, 1.0) * bins as f64) as usize).min(bins - 1);
        sums[k].0 += 1;
        sums[k].1 += p;
        sums[k].2 += usize::from(y == 1);
    }
    sums.iter()
        .enumerate()
        .map(|(k, &(n, s, ones))| ReliabilityBin {
            lo: k as f64 / bins as f64,
            hi: (k + 1) as f64 / bins as f64,
            count: n,
            mean_score: (n > 0).then(|| s / n as f64),
            observed: (n > 0).then(|| ones as f64 / n as f64),
        })
        .collect()
}

/// Expected calibration error: the bins' |observed - mean score|, weighted by their counts
/// (Naeini et al., AAAI 2015; Guo et al. 2017, Eq. (3) of their paper).
pub fn expected_calibration_error(bins: &[ReliabilityBin]) -> f64 {
    let total: usize = bins.iter().map(|b| b.count).sum();
    if total == 0 {
        return f64::NAN;
    }
    bins.iter()
        .filter_map(|b| Some(b.count as f64 * (b.observed? - b.mean_score?).abs()))
        .sum::<f64>()
        / total as f64
}

/// Brier score: the mean squared difference of score and label.
pub fn brier(scores: &[f64], labels: &[u8]) -> f64 {
    let sum: f64 = scores
        .iter()
        .zip(labels)
        .map(|(&p, &y)| (p - f64::from(y)).powi(2))
        .sum();
    sum / scores.len().max(1) as f64
}

/// Scores calibrated out of sample: two folds, each scaled by the temperature fitted on the
/// other, so that no score is calibrated with its own label. The folds alternate within each
/// label (the 1st, 3rd, ... sample of each label in one, the rest in the other), so that each
/// holds both labels in their proportions whatever the order of the samples (a study's test
/// outputs come in wake / no-wake twins, which alternating positions would split by label).
pub fn cross_fitted(scores: &[f64], labels: &[u8]) -> Vec<f64> {
    let mut seen = [0usize; 2];
    let folds: Vec<usize> = labels
        .iter()
        .map(|&y| {
            let k = usize::from(y == 1);
            seen[k] += 1;
            seen[k] % 2
        })
        .collect();
    let temperatures = [0, 1].map(|fold| {
        let (s, l): (Vec<f64>, Vec<u8>) = scores
            .iter()
            .zip(labels)
            .zip(&folds)
            .filter(|(_, &f)| f == fold)
            .map(|((&p, &y), _)| (p, y))
            .unzip();
        fit_temperature(&s, &l)
    });
    scores
        .iter()
        .zip(&folds)
        .map(|(&p, &fold)| scaled(p, temperatures[1 - fold]))
        .collect()
}

/// The least decision threshold (a detection is a score above it) that leaves at most
/// `per_1000_km2` alarms per 1,000 km^2 among `alarm_scores`, the scores of the separate alarms
/// found on `area_km2` of open sea: the (k+1)-th largest score, k the alarms allowed on that
/// area. With no more alarms than allowed, 0 (every alarm kept).
pub fn threshold_for_alarm_rate(alarm_scores: &[f64], area_km2: f64, per_1000_km2: f64) -> f64 {
    let allowed = (per_1000_km2 * area_km2 / 1000.0).floor().max(0.0) as usize;
    let mut sorted = alarm_scores.to_vec();
    sorted.sort_by(|a, b| b.total_cmp(a));
    match sorted.get(allowed) {
        Some(&s) => s,
        None => 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_distr::{Distribution, Normal};

    /// Samples from a detector whose scores are sigmoid(z) while the truth is drawn with
    /// probability sigmoid(z / T0): the scores are over-confident by the known temperature T0.
    fn overconfident(t0: f64, n: usize, seed: u64) -> (Vec<f64>, Vec<u8>) {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let normal = Normal::new(0.0, 3.0).unwrap();
        (0..n)
            .map(|_| {
                let z: f64 = normal.sample(&mut rng);
                let truth = 1.0 / (1.0 + (-z / t0).exp());
                let y = u8::from(rng.random::<f64>() < truth);
                (1.0 / (1.0 + (-z).exp()), y)
            })
            .unzip()
    }

    /// Temperature scaling recovers the temperature that generated the labels, and the
    /// calibrated scores' ECE falls to sampling noise.
    #[test]
    fn the_fitted_temperature_is_the_generating_one() {
        for t0 in [0.5, 2.0, 4.0] {
            let (scores, labels) = overconfident(t0, 40_000, 7);
            let t = fit_temperature(&scores, &labels);
            assert!((t / t0 - 1.0).abs() < 0.05, "T0 {t0}: fitted {t}");
            let calibrated: Vec<f64> = scores.iter().map(|&p| scaled(p, t)).collect();
            let before = expected_calibration_error(&reliability(&scores, &labels, 10));
            let after = expected_calibration_error(&reliability(&calibrated, &labels, 10));
            assert!(after < 0.01, "T0 {t0}: ECE after {after}");
            assert!(before > 5.0 * after, "T0 {t0}: ECE {before} -> {after}");
        }
    }

    /// Calibrated scores keep their order (the ROC is unchanged), and T = 1 changes nothing.
    #[test]
    fn scaling_keeps_the_order() {
        let ps = [0.01, 0.2, 0.5, 0.7, 0.99];
        for t in [0.3, 1.0, 3.0] {
            let q: Vec<f64> = ps.iter().map(|&p| scaled(p, t)).collect();
            assert!(q.windows(2).all(|w| w[0] < w[1]));
            assert!((scaled(0.5, t) - 0.5).abs() < 1e-12);
        }
        assert!((scaled(0.7, 1.0) - 0.7).abs() < 1e-9);
    }

    /// A perfectly calibrated detector: the reliability bins lie on the diagonal within
    /// binomial noise, and cross-fitting leaves it calibrated (T near 1).
    #[test]
    fn a_calibrated_detector_stays_calibrated() {
        let (scores, labels) = overconfident(1.0, 40_000, 11);
        let t = fit_temperature(&scores, &labels);
        assert!((t - 1.0).abs() < 0.05, "{t}");
        let crossed = cross_fitted(&scores, &labels);
        let ece = expected_calibration_error(&reliability(&crossed, &labels, 10));
        assert!(ece < 0.01, "{ece}");
        // the same samples ordered as a study's twins (wake, no-wake, wake, ...): still calibrated
        let (mut ones, mut zeros): (Vec<usize>, Vec<usize>) = (0..labels.len()).partition(|&i| labels[i] == 1);
        let n = ones.len().min(zeros.len());
        ones.truncate(n);
        zeros.truncate(n);
        let order: Vec<usize> = ones.iter().zip(&zeros).flat_map(|(&a, &b)| [a, b]).collect();
        let (twins, twin_labels): (Vec<f64>, Vec<u8>) = order.iter().map(|&i| (scores[i], labels[i])).unzip();
        let crossed = cross_fitted(&twins, &twin_labels);
        let ece = expected_calibration_error(&reliability(&crossed, &twin_labels, 10));
        let raw = expected_calibration_error(&reliability(&twins, &twin_labels, 10));
        assert!(ece < raw + 0.01, "twins: ECE {raw} -> {ece}");
        let bins = reliability(&scores, &labels, 10);
        assert_eq!(bins.iter().map(|b| b.count).sum::<usize>(), 40_000);
        assert_eq!(brier(&[1.0, 0.0], &[1, 0]), 0.0);
        assert_eq!(brier(&[0.5, 0.5], &[1, 0]), 0.25);
    }

    /// On 2,500 km^2 at one alarm per 1,000 km^2, two alarms are allowed: the threshold is the
    /// third largest score, so that exactly two lie above it.
    #[test]
    fn the_threshold_allows_the_stated_alarms() {
        let scores = [0.2, 0.95, 0.6, 0.9, 0.99, 0.7];
        let t = threshold_for_alarm_rate(&scores, 2500.0, 1.0);
        assert_eq!(t, 0.9);
        assert_eq!(scores.iter().filter(|&&s| s > t).count(), 2);
        // 500 km^2: no alarm allowed, the threshold is the largest score
        assert_eq!(threshold_for_alarm_rate(&scores, 500.0, 1.0), 0.99);
        // more allowed than found: every alarm stays above
        let t = threshold_for_alarm_rate(&scores, 1.0e5, 1.0);
        assert_eq!(scores.iter().filter(|&&s| s > t).count(), scores.len());
        assert_eq!(threshold_for_alarm_rate(&[], 100.0, 1.0), 0.0);
    }
}

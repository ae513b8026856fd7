//! Classification metrics from saved outputs (spec 4.2-4.3, Tables 4.4-4.6).

use serde::Serialize;

/// Confusion counts of binary decisions (1 = wake).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct Confusion {
    pub tp: u64,
    pub tn: u64,
    pub fp: u64,
    pub fn_: u64,
}

impl Confusion {
    /// Count decisions `output >= threshold` against `labels` (the spec's threshold is 0.5;
    /// erratum 2).
    pub fn from_outputs(outputs: &[f64], labels: &[u8], threshold: f64) -> Self {
        assert_eq!(outputs.len(), labels.len(), "one label per output");
        let mut c = Confusion::default();
        for (&o, &l) in outputs.iter().zip(labels) {
            match (o >= threshold, l == 1) {
                (true, true) => c.tp += 1,
                (false, false) => c.tn += 1,
                (true, false) => c.fp += 1,
                (false, true) => c.fn_ += 1,
            }
        }
        c
    }

    pub fn total(&self) -> u64 {
        self.tp + self.tn + self.fp + self.fn_
    }

    /// (TP + TN) / N; zero for no samples.
    pub fn accuracy(&self) -> f64 {
        let n = self.total();
        if n == 0 {
            0.0
        } else {
            (self.tp + self.tn) as f64 / n as f64
        }
    }

    /// Matthews correlation coefficient, Eq. (4.3):
    /// (TP TN - FP FN) / sqrt((TP + FP)(TP + FN)(TN + FP)(TN + FN)), zero when a factor of the
    /// denominator is zero (the convention of Chicco & Jurman 2020).
    pub fn mcc(&self) -> f64 {
        let (tp, tn, fp, fn_) = (self.tp as f64, self.tn as f64, self.fp as f64, self.fn_ as f64);
        let d = (tp + fp) * (tp + fn_) * (tn + fp) * (tn + fn_);
        if d == 0.0 {
            0.0
        } else {
            (tp * tn - fp * fn_) / d.sqrt()
        }
    }

    /// F1 = 2 TP / (2 TP + FP + FN); zero when undefined.
    pub fn f1(&self) -> f64 {
        let d = 2 * self.tp + self.fp + self.fn_;
        if d == 0 {
            0.0
        } else {
            2.0 * self.tp as f64 / d as f64
        }
    }
}

/// "MCC 0.812, accuracy 90.0%, TP/TN/FP/FN 9/9/1/1".
impl std::fmt::Display for Confusion {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "MCC {:.3}, accuracy {:.1}%, TP/TN/FP/FN {}/{}/{}/{}",
            self.mcc(),
            100.0 * self.accuracy(),
            self.tp,
            self.tn,
            self.fp,
            self.fn_
        )
    }
}

/// Area under the ROC curve by the Mann-Whitney statistic, ties counted one half; None when
/// one class is missing.
pub fn roc_auc(scores: &[f64], labels: &[u8]) -> Option<f64> {
    let pos: Vec<f64> = scores
        .iter()
        .zip(labels)
        .filter(|(_, &l)| l == 1)
        .map(|(&s, _)| s)
        .collect();
    let neg: Vec<f64> = scores
        .iter()
        .zip(labels)
        .filter(|(_, &l)| l != 1)
        .map(|(&s, _)| s)
        .collect();
    if pos.is_empty() || neg.is_empty() {
        return None;
    }
    let mut wins = 0.0;
    for p in &pos {
        for n in &neg {
            wins += if p > n {
                1.0
            } else if p == n {
                0.5
            } else {
                0.0
            };
        }
    }
    Some(wins / (pos.len() * neg.len()) as f64)
}

/// Mean and sample standard deviation over repetitions (the spread of Tables 4.4-4.6).
pub fn mean_and_spread(values: &[f64]) -> (f64, f64) {
    let n = values.len();
    if n == 0 {
        return (0.0, 0.0);
    }
    let mean = values.iter().sum::<f64>() / n as f64;
    if n == 1 {
        return (mean, 0.0);
    }
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
    (mean, var.sqrt())
}

/// Spearman's rank correlation (Spearman 1904): Pearson's correlation of the ranks, tied values
/// sharing their mean rank; None for fewer than 3 pairs or a constant variable.
pub fn spearman(x: &[f64], y: &[f64]) -> Option<f64> {
    if x.len() != y.len() || x.len() < 3 {
        return None;
    }
    let (rx, ry) = (ranks(x), ranks(y));
    let n = x.len() as f64;
    let (mx, my) = (rx.iter().sum::<f64>() / n, ry.iter().sum::<f64>() / n);
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (a, b) in rx.iter().zip(&ry) {
        sxy += (a - mx) * (b - my);
        sxx += (a - mx) * (a - mx);
        syy += (b - my) * (b - my);
    }
    (sxx > 0.0 && syy > 0.0).then(|| sxy / (sxx * syy).sqrt())
}

/// Ranks from 1, ties given the mean of the ranks they span.
pub fn ranks(v: &[f64]) -> Vec<f64> {
    let mut order: Vec<usize> = (0..v.len()).collect();
    order.sort_by(|&a, &b| v[a].total_cmp(&v[b]));
    let mut out = vec![0.0; v.len()];
    let mut i = 0;
    while i < order.len() {
        let mut j = i;
        while j + 1 < order.len() && v[order[j + 1]] == v[order[i]] {
            j += 1;
        }
        let mean = (i + j) as f64 / 2.0 + 1.0;
        for &k in &order[i..=j] {
            out[k] = mean;
        }
        i = j + 1;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn c(tp: u64, tn: u64, fp: u64, fn_: u64) -> Confusion {
        Confusion { tp, tn, fp, fn_ }
    }

    #[test]
    fn mcc_and_accuracy_on_hand_made_counts() {
        // (90 * 80 - 20 * 10) / sqrt(110 * 100 * 100 * 90) = 7000 / 9949.874
        let m = c(90, 80, 20, 10);
        assert!((m.mcc() - 0.703_527_4).abs() < 1e-6);
        assert!((m.accuracy() - 170.0 / 200.0).abs() < 1e-15);
        assert!((m.f1() - 180.0 / 210.0).abs() < 1e-15);
        assert_eq!(c(7, 7, 0, 0).mcc(), 1.0);
        assert_eq!(c(0, 0, 7, 7).mcc(), -1.0);
        // a random classifier on a balanced set
        assert_eq!(c(5, 5, 5, 5).mcc(), 0.0);
    }

    #[test]
    fn degenerate_counts_give_zero_not_nan() {
        for m in [
            c(5, 0, 5, 0),
            c(0, 5, 0, 5),
            c(0, 10, 0, 0),
            c(10, 0, 0, 0),
            c(0, 0, 0, 0),
        ] {
            assert_eq!(m.mcc(), 0.0, "{m:?}");
            assert!(m.accuracy().is_finite() && m.f1().is_finite());
        }
        assert_eq!(c(0, 0, 0, 0).accuracy(), 0.0);
    }

    #[test]
    fn confusion_from_outputs_uses_the_threshold() {
        let m = Confusion::from_outputs(&[0.9, 0.5, 0.49, 0.1], &[1, 0, 1, 0], 0.5);
        assert_eq!(m, c(1, 1, 1, 1));
    }

    #[test]
    fn roc_auc_of_the_scikit_learn_example() {
        // scikit-learn's roc_auc_score documentation: y = [0, 0, 1, 1], s = [0.1, 0.4, 0.35, 0.8]
        assert_eq!(roc_auc(&[0.1, 0.4, 0.35, 0.8], &[0, 0, 1, 1]), Some(0.75));
        assert_eq!(roc_auc(&[0.3, 0.3], &[0, 1]), Some(0.5));
        assert_eq!(roc_auc(&[0.3, 0.3], &[1, 1]), None);
    }

    #[test]
    fn spread_is_the_sample_standard_deviation() {
        let (m, s) = mean_and_spread(&[2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0]);
        assert_eq!(m, 5.0);
        assert!((s - (32.0f64 / 7.0).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn spearman_matches_the_textbook_formula_and_handles_ties() {
        // no ties: rho = 1 - 6 sum d^2 / (n (n^2 - 1)) = 1 - 6 * 4 / 120 = 0.8
        let x = [1.0, 2.0, 3.0, 4.0, 5.0];
        let y = [2.0, 1.0, 4.0, 3.0, 5.0];
        assert!((spearman(&x, &y).unwrap() - 0.8).abs() < 1e-12);
        // any monotone map of x ranks the same: +1 increasing, -1 decreasing
        let cubes: Vec<f64> = x.iter().map(|v| v * v * v).collect();
        assert!((spearman(&x, &cubes).unwrap() - 1.0).abs() < 1e-12);
        let falling: Vec<f64> = x.iter().map(|v| -v).collect();
        assert!((spearman(&x, &falling).unwrap() + 1.0).abs() < 1e-12);
        // ties share their mean rank: y's ranks are 1.5, 1.5, 3, 4
        assert_eq!(ranks(&[2.0, 2.0, 5.0, 7.0]), vec![1.5, 1.5, 3.0, 4.0]);
        // Pearson of ranks (1, 2, 3, 4) and (1.5, 1.5, 3, 4): 4.5 / sqrt(5 * 4.5)
        let rho = spearman(&[1.0, 2.0, 3.0, 4.0], &[2.0, 2.0, 5.0, 7.0]).unwrap();
        assert!((rho - 4.5 / (5.0f64 * 4.5).sqrt()).abs() < 1e-12);
        assert_eq!(spearman(&[1.0, 2.0, 3.0], &[4.0, 4.0, 4.0]), None);
        assert_eq!(spearman(&[1.0, 2.0], &[1.0, 2.0]), None);
    }
}

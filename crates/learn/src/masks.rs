//! How well the U-Net's wake masks cover the physics masks: intersection over union on the test
//! wake scenes (the spec reports the U-Net only through its classifier's MCC).

use ndarray::Array2;
use serde::{Deserialize, Serialize};
use wakelab_schema::band::Input;
use wakelab_schema::metrics::mean_and_spread;

/// The level at which a mask's pixel counts as wake, for the U-Net's sigmoid output and the
/// physics mask alike.
pub const MASK_LEVEL: f32 = 0.5;

/// The U-Net mask's IoU on one test wake scene of one repetition.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MaskScore {
    pub bands: Input,
    pub repetition: usize,
    pub scene: String,
    pub iou: f64,
}

/// Intersection over union of the pixels above [`MASK_LEVEL`] in `predicted` and in `truth`;
/// `None` where the truth has no wake pixel (nothing to cover).
pub fn mask_iou(predicted: &Array2<f32>, truth: &Array2<f32>) -> Option<f64> {
    assert_eq!(
        predicted.dim(),
        truth.dim(),
        "a mask and its truth share the image's shape"
    );
    let (mut both, mut either, mut wake) = (0usize, 0usize, 0usize);
    for (&p, &t) in predicted.iter().zip(truth.iter()) {
        let (p, t) = (p > MASK_LEVEL, t > MASK_LEVEL);
        both += usize::from(p && t);
        either += usize::from(p || t);
        wake += usize::from(t);
    }
    (wake > 0).then(|| both as f64 / either as f64)
}

/// Mean IoU of each repetition, then their mean and sample standard deviation (the spread the
/// report gives every metric, [`mean_and_spread`]), and the share of scenes (all repetitions)
/// whose mask reaches IoU 0.5: `(mean, spread, share, scenes)` of one input.
pub fn summarise_masks(scores: &[MaskScore], input: &Input) -> Option<(f64, f64, f64, usize)> {
    let mine: Vec<&MaskScore> = scores.iter().filter(|s| &s.bands == input).collect();
    if mine.is_empty() {
        return None;
    }
    let repetitions = mine.iter().map(|s| s.repetition).max().unwrap_or(0) + 1;
    let means: Vec<f64> = (0..repetitions)
        .filter_map(|r| {
            let v: Vec<f64> = mine.iter().filter(|s| s.repetition == r).map(|s| s.iou).collect();
            (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
        })
        .collect();
    let (mean, spread) = mean_and_spread(&means);
    let share = mine.iter().filter(|s| s.iou >= 0.5).count() as f64 / mine.len() as f64;
    Some((mean, spread, share, mine.len()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two 4 x 4 squares overlapping in a 2 x 4 band: |A n B| = 8, |A u B| = 24, IoU 1/3.
    #[test]
    fn iou_of_overlapping_squares_is_their_shared_share() {
        let square = |r0: usize| Array2::from_shape_fn((8, 8), |(r, c)| f32::from((r0..r0 + 4).contains(&r) && c < 4));
        let wide = Array2::from_shape_fn((8, 8), |(r, _)| f32::from((2..6).contains(&r)));
        assert_eq!(mask_iou(&square(0), &square(0)), Some(1.0));
        assert_eq!(mask_iou(&square(0), &square(4)), Some(0.0));
        assert_eq!(mask_iou(&square(0), &wide), Some(8.0 / 40.0));
        assert_eq!(mask_iou(&wide, &square(0)), Some(8.0 / 40.0));
        let half = Array2::from_shape_fn((8, 8), |(r, c)| f32::from((2..6).contains(&r) && c < 4));
        assert_eq!(mask_iou(&half, &square(0)), Some(8.0 / 24.0));
        assert_eq!(mask_iou(&square(0), &Array2::zeros((8, 8))), None, "no wake to cover");
    }

    #[test]
    fn summaries_average_repetitions_first() {
        let s = |repetition, iou| MaskScore {
            bands: Input::single(wakelab_schema::band::Band::X),
            repetition,
            scene: String::new(),
            iou,
        };
        let scores = [s(0, 0.2), s(0, 0.6), s(1, 0.8)];
        let (mean, spread, share, n) = summarise_masks(&scores, &scores[0].bands).unwrap();
        // repetition means 0.4 and 0.8: sample standard deviation sqrt(2 x 0.2^2 / 1)
        assert!((mean - 0.6).abs() < 1e-12 && (spread - 0.08f64.sqrt()).abs() < 1e-12);
        assert!((share - 2.0 / 3.0).abs() < 1e-12 && n == 3);
        assert!(summarise_masks(&scores, &Input::single(wakelab_schema::band::Band::S)).is_none());
    }
}

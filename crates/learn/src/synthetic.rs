//! The synthetic task models are developed on: a faint straight line on Gaussian noise versus
//! noise alone (a stand-in for a wake on sea clutter), seeded and reproducible.

use ndarray::Array2;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

/// One labelled image.
#[derive(Debug, Clone)]
pub struct Sample {
    pub image: Array2<f32>,
    pub label: u8,
    /// 1 within 1.5 pixels of the line, 0 elsewhere (all 0 without a line).
    pub mask: Array2<f32>,
}

/// Standard normal variate by Box-Muller.
fn gaussian(rng: &mut ChaCha8Rng) -> f64 {
    let u1: f64 = 1.0 - rng.random::<f64>();
    let u2: f64 = rng.random();
    (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos()
}

/// `count` images of `size` x `size`, alternately with (label 1) and without (label 0) a line of
/// amplitude `contrast` (in noise standard deviations) and width about one pixel, through a
/// random point near the centre at a random angle.
pub fn line_versus_noise(count: usize, size: usize, contrast: f64, seed: u64) -> Vec<Sample> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..count)
        .map(|i| {
            let label = (i % 2 == 0) as u8;
            let mut image = Array2::from_shape_fn((size, size), |_| gaussian(&mut rng) as f32);
            let mut mask = Array2::zeros((size, size));
            if label == 1 {
                let angle = rng.random_range(0.0..PI);
                let (cx, cy) = (
                    size as f64 * rng.random_range(0.3..0.7),
                    size as f64 * rng.random_range(0.3..0.7),
                );
                let (s, c) = angle.sin_cos();
                for ((r, col), v) in image.indexed_iter_mut() {
                    // distance of the pixel centre from the line
                    let d = ((col as f64 + 0.5 - cx) * s - (r as f64 + 0.5 - cy) * c).abs();
                    *v += (contrast * (-d * d / 0.5).exp()) as f32;
                    mask[[r, col]] = (d < 1.5) as u8 as f32;
                }
            }
            Sample { image, label, mask }
        })
        .collect()
}

/// The samples as single-channel training examples.
pub fn examples(samples: &[Sample]) -> Vec<crate::train::Example> {
    samples
        .iter()
        .map(|s| crate::train::Example {
            image: s.image.clone().insert_axis(ndarray::Axis(0)),
            label: s.label,
            mask: Some(s.mask.clone()),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_are_balanced_seeded_and_carry_the_line() {
        let a = line_versus_noise(10, 32, 3.0, 1);
        let b = line_versus_noise(10, 32, 3.0, 1);
        assert_eq!(a.iter().map(|s| s.label as usize).sum::<usize>(), 5);
        assert!(a.iter().zip(&b).all(|(x, y)| x.image == y.image));
        // noise images have unit variance; line images carry extra energy
        let energy = |s: &Sample| s.image.iter().map(|v| (*v as f64).powi(2)).sum::<f64>() / s.image.len() as f64;
        let noise: f64 = a.iter().filter(|s| s.label == 0).map(energy).sum::<f64>() / 5.0;
        let line: f64 = a.iter().filter(|s| s.label == 1).map(energy).sum::<f64>() / 5.0;
        assert!((noise - 1.0).abs() < 0.1, "{noise}");
        assert!(line > noise + 0.05, "{line} vs {noise}");
    }
}

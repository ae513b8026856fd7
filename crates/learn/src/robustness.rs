//! Perturbed test images for the robustness study the spec leaves to future work (6.2): rotations
//! by angles that are not multiples of 90 degrees (what quarter-turn training never saw), dropped
//! patches (occlusion, missing data) and added noise. Images are normalised robustly when loaded
//! ([`crate::data::detector_input`]), so "the image mean" is near 0 and noise is in units of the
//! image's robust spread.

use crate::augment::Pose;
use crate::train::Example;
use ndarray::{Array2, Array3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use serde::{Deserialize, Serialize};

/// One way of perturbing a test image.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Perturbation {
    /// Rotation about the centre by this angle (degrees, counter-clockwise), bilinear; pixels
    /// from outside the image take the mean (0).
    Rotate { degrees: f64 },
    /// `patches` squares of side `fraction` x the image side, at seeded positions, set to the
    /// mean (0) in every channel.
    DropPatches { patches: usize, fraction: f64 },
    /// Independent Gaussian noise of this standard deviation added to every pixel.
    Noise { sigma: f64 },
}

impl Perturbation {
    /// A short name for tables and the `split` column: `rotate_30`, `drop_4x12.5%`, `noise_0.5`.
    pub fn name(&self) -> String {
        match self {
            Self::Rotate { degrees } => format!("rotate_{degrees}"),
            Self::DropPatches { patches, fraction } => format!("drop_{patches}x{}%", fraction * 100.0),
            Self::Noise { sigma } => format!("noise_{sigma}"),
        }
    }

    /// The perturbed copy of every example; `seed` fixes patch positions and noise.
    pub fn apply(&self, examples: &[Example], seed: u64) -> Vec<Example> {
        examples
            .iter()
            .enumerate()
            .map(|(i, e)| {
                let mut rng = ChaCha8Rng::seed_from_u64(seed.wrapping_mul(0x9E37_79B9).wrapping_add(i as u64));
                Example {
                    image: self.perturb(&e.image, &mut rng),
                    label: e.label,
                    mask: e.mask.as_ref().map(|m| match self {
                        Self::Rotate { degrees } => rotate(m, *degrees),
                        _ => m.clone(),
                    }),
                }
            })
            .collect()
    }

    fn perturb(&self, image: &Array3<f32>, rng: &mut ChaCha8Rng) -> Array3<f32> {
        let (channels, h, w) = image.dim();
        match *self {
            Self::Rotate { degrees } => {
                let mut out = Array3::zeros((channels, h, w));
                for c in 0..channels {
                    let plane = image.index_axis(ndarray::Axis(0), c).to_owned();
                    out.index_axis_mut(ndarray::Axis(0), c).assign(&rotate(&plane, degrees));
                }
                out
            }
            Self::DropPatches { patches, fraction } => {
                let mut out = image.clone();
                let side = ((fraction * h.min(w) as f64).round() as usize).clamp(1, h.min(w));
                for _ in 0..patches {
                    let (r0, c0) = (rng.random_range(0..=h - side), rng.random_range(0..=w - side));
                    out.slice_mut(ndarray::s![.., r0..r0 + side, c0..c0 + side]).fill(0.0);
                }
                out
            }
            Self::Noise { sigma } => {
                let normal = Normal::new(0.0, sigma as f32).expect("sigma validated finite, >= 0");
                image.mapv(|v| v + normal.sample(rng))
            }
        }
    }
}

/// Rotate a plane about its centre by `degrees` (counter-clockwise), bilinear; 0 outside: the
/// training augmentation's resampling ([`crate::augment::Pose`]).
pub fn rotate(plane: &Array2<f32>, degrees: f64) -> Array2<f32> {
    Pose {
        degrees,
        ..Pose::IDENTITY
    }
    .apply(plane, false)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quarter_turn_by_interpolation_equals_the_exact_quarter_turn() {
        let plane = Array2::from_shape_fn((6, 6), |(r, c)| (r * 7 + c * c) as f32);
        let turned = rotate(&plane, 90.0);
        // counter-clockwise on screen: the top row becomes the left column, read upwards
        let mut exact = plane.t().to_owned();
        exact.invert_axis(ndarray::Axis(0));
        for (a, b) in turned.iter().zip(exact.iter()) {
            assert!((a - b).abs() < 1e-4, "{turned:?}\n{exact:?}");
        }
        let full = rotate(&plane, 360.0);
        assert!(full.iter().zip(plane.iter()).all(|(a, b)| (a - b).abs() < 1e-3));
    }

    #[test]
    fn a_rotation_keeps_a_constant_inside_and_fills_corners_with_the_mean() {
        let plane = Array2::from_elem((33, 33), 2.0f32);
        let turned = rotate(&plane, 45.0);
        assert!((turned[[16, 16]] - 2.0).abs() < 1e-6);
        assert_eq!(turned[[0, 0]], 0.0);
    }

    #[test]
    fn dropped_patches_and_noise_change_what_they_say_and_are_seeded() {
        let e = Example {
            image: Array3::from_elem((2, 32, 32), 1.0f32),
            label: 1,
            mask: None,
        };
        let drop = Perturbation::DropPatches {
            patches: 1,
            fraction: 0.25,
        };
        let dropped = drop.apply(std::slice::from_ref(&e), 3);
        let zeros = dropped[0].image.iter().filter(|&&v| v == 0.0).count();
        assert_eq!(zeros, 2 * 8 * 8, "one 8 x 8 patch in both channels");
        let noise = Perturbation::Noise { sigma: 0.5 };
        let a = noise.apply(std::slice::from_ref(&e), 3);
        let b = noise.apply(std::slice::from_ref(&e), 3);
        assert_eq!(a[0].image, b[0].image);
        let n = a[0].image.len() as f32;
        let mean = a[0].image.iter().sum::<f32>() / n;
        let var = a[0].image.iter().map(|v| (v - mean).powi(2)).sum::<f32>() / n;
        assert!(
            (mean - 1.0).abs() < 0.05 && (var.sqrt() - 0.5).abs() < 0.05,
            "{mean} {var}"
        );
    }
}

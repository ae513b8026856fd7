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
    /// Rotation about the centre by this angle (degrees, counter-clockwise), each pixel the
    /// nearest source pixel (the texture kept; see [`crate::augment`]); pixels from outside the
    /// image take the mean (0).
    Rotate { degrees: f64 },
    /// `patches` squares of side `fraction` x the image side, at seeded positions, set to the
    /// mean (0) in every channel.
    DropPatches { patches: usize, fraction: f64 },
    /// Independent Gaussian noise of this standard deviation added to every pixel.
    Noise { sigma: f64 },
    /// The image (and its mask) moved by `fraction` x its side in a seeded direction, whole
    /// pixels; pixels from outside take the mean (0): the wake elsewhere in the window.
    Shift { fraction: f64 },
}

impl Perturbation {
    /// A short name for tables and the `split` column: `rotate_30`, `drop_4x12.5%`, `noise_0.5`.
    pub fn name(&self) -> String {
        match self {
            Self::Rotate { degrees } => format!("rotate_{degrees}"),
            Self::DropPatches { patches, fraction } => format!("drop_{patches}x{}%", fraction * 100.0),
            Self::Noise { sigma } => format!("noise_{sigma}"),
            Self::Shift { fraction } => format!("shift_{}%", fraction * 100.0),
        }
    }

    /// The perturbed copy of every example; `seed` fixes patch positions and noise.
    pub fn apply(&self, examples: &[Example], seed: u64) -> Vec<Example> {
        examples
            .iter()
            .enumerate()
            .map(|(i, e)| {
                let mut rng = ChaCha8Rng::seed_from_u64(seed.wrapping_mul(0x9E37_79B9).wrapping_add(i as u64));
                if let Self::Shift { fraction } = *self {
                    let pose = shift_pose(fraction, e.image.dim().1, &mut rng);
                    return Example {
                        image: each_channel(&e.image, |plane| pose.apply(plane)),
                        label: e.label,
                        mask: e.mask.as_ref().map(|m| pose.apply(m)),
                    };
                }
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
        let (_, h, w) = image.dim();
        match *self {
            Self::Rotate { degrees } => each_channel(image, |plane| rotate(plane, degrees)),
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
            Self::Shift { .. } => unreachable!("a shift moves image and mask together in apply"),
        }
    }
}

/// A move by `fraction` x `side` pixels (rounded) in a direction drawn uniformly from the circle.
fn shift_pose(fraction: f64, side: usize, rng: &mut ChaCha8Rng) -> Pose {
    let reach = fraction * side as f64;
    let (sin, cos) = rng.random_range(0.0..std::f64::consts::TAU).sin_cos();
    Pose {
        shift: ((reach * sin).round() as i32, (reach * cos).round() as i32),
        ..Pose::IDENTITY
    }
}

/// `image` with `plane_map` applied to every channel.
fn each_channel(image: &Array3<f32>, plane_map: impl Fn(&Array2<f32>) -> Array2<f32>) -> Array3<f32> {
    let mut out = Array3::zeros(image.dim());
    for c in 0..image.dim().0 {
        let plane = image.index_axis(ndarray::Axis(0), c).to_owned();
        out.index_axis_mut(ndarray::Axis(0), c).assign(&plane_map(&plane));
    }
    out
}

/// Rotate a plane about its centre by `degrees` (counter-clockwise), by nearest pixel; 0
/// outside: the training augmentation's resampling ([`crate::augment::Pose`]).
pub fn rotate(plane: &Array2<f32>, degrees: f64) -> Array2<f32> {
    Pose {
        degrees,
        ..Pose::IDENTITY
    }
    .apply(plane)
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

    /// A shift moves every pixel of image and mask by the same whole offset of the stated
    /// length, fills the uncovered band with the mean (0) and is seeded.
    #[test]
    fn a_shift_moves_image_and_mask_together_by_the_stated_distance() {
        let image = Array3::from_shape_fn((2, 32, 32), |(c, r, k)| 1.0 + (c * 1000 + r * 32 + k) as f32);
        let mask = Array2::from_shape_fn((32, 32), |(r, k)| (r * 32 + k) as f32);
        let e = Example {
            image,
            label: 1,
            mask: Some(mask),
        };
        let shift = Perturbation::Shift { fraction: 0.25 };
        assert_eq!(shift.name(), "shift_25%");
        let a = shift.apply(std::slice::from_ref(&e), 5);
        assert_eq!(a[0].image, shift.apply(std::slice::from_ref(&e), 5)[0].image);
        // recover the offset from one moved pixel, then check every pixel against it
        let (mut dr, mut dc) = (0i64, 0i64);
        'find: for r in 0..32 {
            for k in 0..32 {
                let v = a[0].image[[0, r, k]];
                if v != 0.0 {
                    let source = (v - 1.0) as i64;
                    (dr, dc) = (r as i64 - source / 32, k as i64 - source % 32);
                    break 'find;
                }
            }
        }
        let length = ((dr * dr + dc * dc) as f64).sqrt();
        assert!((length - 8.0).abs() <= 0.75, "moved by ({dr}, {dc})");
        for c in 0..2 {
            for r in 0..32i64 {
                for k in 0..32i64 {
                    let (sr, sk) = (r - dr, k - dc);
                    let inside = (0..32).contains(&sr) && (0..32).contains(&sk);
                    let want = if inside {
                        e.image[[c, sr as usize, sk as usize]]
                    } else {
                        0.0
                    };
                    assert_eq!(a[0].image[[c, r as usize, k as usize]], want);
                    if c == 0 && inside {
                        let m = a[0].mask.as_ref().unwrap();
                        assert_eq!(m[[r as usize, k as usize]], (sr * 32 + sk) as f32);
                    }
                }
            }
        }
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

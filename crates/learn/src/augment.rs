//! Training inputs varied from epoch to epoch ([`Augmentation`]): the spec's quarter turns (4.2),
//! or rotations by any angle, mirror flips and shifts, so that a detector meets the wake in any
//! direction and anywhere in the image. Each input's [`Pose`] is drawn from the recipe's seed;
//! images are resampled bilinearly and masks by their nearest pixel, both reading 0 (the
//! normalised image's median; no wake) from outside the image.

use ndarray::Array2;
use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use wakelab_schema::recipe::Augmentation;

/// One input's variation in one epoch: mirrored (columns reversed) if `flip`, then turned
/// `degrees` counter-clockwise about the centre, then moved by `shift` (rows, columns).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    pub degrees: f64,
    pub flip: bool,
    pub shift: (i32, i32),
}

impl Pose {
    /// The input as it is.
    pub const IDENTITY: Pose = Pose {
        degrees: 0.0,
        flip: false,
        shift: (0, 0),
    };

    /// Draw a pose for an input of side `size`: a quarter turn (the same draws as the spec's
    /// recipe always made), or any angle, a flip and a shift of up to size / 8.
    pub fn draw(augmentation: Augmentation, size: usize, rng: &mut ChaCha8Rng) -> Pose {
        match augmentation {
            Augmentation::QuarterTurns => Pose {
                degrees: 90.0 * rng.random_range(0..4u8) as f64,
                ..Pose::IDENTITY
            },
            Augmentation::Geometric => {
                let reach = (size / 8) as i32;
                Pose {
                    degrees: rng.random_range(0.0..360.0),
                    flip: rng.random_bool(0.5),
                    shift: (rng.random_range(-reach..=reach), rng.random_range(-reach..=reach)),
                }
            }
        }
    }

    /// Whole quarter turns, if that is all the pose is.
    fn quarter_turns(&self) -> Option<u8> {
        let turns = self.degrees / 90.0;
        (!self.flip && self.shift == (0, 0) && turns.fract() == 0.0).then(|| turns.rem_euclid(4.0) as u8)
    }

    /// `plane` in this pose: bilinear, or the nearest pixel for a mask (`nearest`); 0 from
    /// outside. Quarter turns alone move pixels exactly.
    pub fn apply(&self, plane: &Array2<f32>, nearest: bool) -> Array2<f32> {
        if let Some(k) = self.quarter_turns() {
            return crate::data::rotate_quarter(plane, k);
        }
        let (rows, cols) = plane.dim();
        let (cr, cc) = ((rows as f64 - 1.0) / 2.0, (cols as f64 - 1.0) / 2.0);
        let (sin, cos) = self.degrees.to_radians().sin_cos();
        let read = |r: isize, c: isize| -> f32 {
            if r < 0 || c < 0 || r >= rows as isize || c >= cols as isize {
                0.0
            } else {
                plane[[r as usize, c as usize]]
            }
        };
        let bilinear = |y: f64, x: f64| -> f32 {
            // positions a rounding error outside the edge are on it
            let (y, x) = (snap(y, rows), snap(x, cols));
            if y < 0.0 || x < 0.0 || y > (rows - 1) as f64 || x > (cols - 1) as f64 {
                return 0.0;
            }
            let (y0, x0) = (y.floor() as usize, x.floor() as usize);
            let (y1, x1) = ((y0 + 1).min(rows - 1), (x0 + 1).min(cols - 1));
            let (fy, fx) = ((y - y0 as f64) as f32, (x - x0 as f64) as f32);
            let top = plane[[y0, x0]] * (1.0 - fx) + plane[[y0, x1]] * fx;
            let bottom = plane[[y1, x0]] * (1.0 - fx) + plane[[y1, x1]] * fx;
            top * (1.0 - fy) + bottom * fy
        };
        Array2::from_shape_fn((rows, cols), |(r, c)| {
            // to centred axes (x right, y up), undo the shift and the turn, then the flip
            let x1 = c as f64 - self.shift.1 as f64 - cc;
            let y1 = -(r as f64 - self.shift.0 as f64 - cr);
            let (x, y) = (cos * x1 + sin * y1, -sin * x1 + cos * y1);
            let x = if self.flip { -x } else { x };
            let (ri, ci) = (cr - y, cc + x);
            if nearest {
                read(ri.round() as isize, ci.round() as isize)
            } else {
                bilinear(ri, ci)
            }
        })
    }
}

/// `v` on the edge 0 or n - 1 when within a rounding error of it.
fn snap(v: f64, n: usize) -> f64 {
    if v.abs() < 1e-9 {
        0.0
    } else if (v - (n - 1) as f64).abs() < 1e-9 {
        (n - 1) as f64
    } else {
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    fn ramp(n: usize) -> Array2<f32> {
        Array2::from_shape_fn((n, n), |(r, c)| (r * n + c) as f32)
    }

    /// A turn by a hair over 90 degrees, which takes the bilinear path, moves pixels as the
    /// exact quarter turn does.
    #[test]
    fn a_general_right_angle_is_the_quarter_turn() {
        let img = ramp(9);
        let exact = crate::data::rotate_quarter(&img, 1);
        let general = Pose {
            degrees: 90.000_000_001,
            ..Pose::IDENTITY
        }
        .apply(&img, false);
        let worst = (&general - &exact).mapv(f32::abs).fold(0.0f32, |m, &v| m.max(v));
        assert!(worst < 1e-3, "{worst}");
    }

    /// A line through the centre turned by 30 degrees lies on the turned line, in the image and
    /// in its mask alike; a flip mirrors the columns; a shift moves the pixels.
    #[test]
    fn images_and_masks_move_together() {
        let n = 65;
        let c = 32.0;
        let line = Array2::from_shape_fn((n, n), |(r, _)| if r == 32 { 1.0f32 } else { 0.0 });
        let pose = Pose {
            degrees: 30.0,
            ..Pose::IDENTITY
        };
        let (image, mask) = (pose.apply(&line, false), pose.apply(&line, true));
        // the turned line: rows = c - tan(30) (col - c), counter-clockwise in the picture
        let t = 30f64.to_radians().tan();
        for col in [10usize, 20, 44, 54] {
            let row = (c - t * (col as f64 - c)).round() as usize;
            assert!(mask[[row, col]] == 1.0, "mask at ({row}, {col})");
            assert!(
                image[[row, col]] > 0.3,
                "image at ({row}, {col}): {}",
                image[[row, col]]
            );
            assert!(image[[row + 3, col]] == 0.0 && mask[[row + 3, col]] == 0.0);
        }
        let img = ramp(8);
        let flipped = Pose {
            flip: true,
            ..Pose::IDENTITY
        }
        .apply(&img, true);
        assert_eq!(flipped[[2, 0]], img[[2, 7]]);
        let moved = Pose {
            shift: (1, -2),
            ..Pose::IDENTITY
        }
        .apply(&img, true);
        assert_eq!((moved[[3, 3]], moved[[0, 0]], moved[[7, 7]]), (img[[2, 5]], 0.0, 0.0));
    }

    /// Quarter-turn draws are the spec recipe's draws; geometric ones cover the circle, both
    /// flips and shifts within an eighth, from the seed alone.
    #[test]
    fn poses_come_from_the_seed() {
        let mut a = ChaCha8Rng::seed_from_u64(3);
        let mut b = ChaCha8Rng::seed_from_u64(3);
        for _ in 0..50 {
            let p = Pose::draw(Augmentation::QuarterTurns, 64, &mut a);
            assert_eq!(p.degrees, 90.0 * b.random_range(0..4u8) as f64);
        }
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let poses: Vec<Pose> = (0..400)
            .map(|_| Pose::draw(Augmentation::Geometric, 64, &mut rng))
            .collect();
        assert!(poses.iter().all(|p| p.shift.0.abs() <= 8 && p.shift.1.abs() <= 8));
        assert!(poses.iter().any(|p| p.flip) && poses.iter().any(|p| !p.flip));
        assert!(poses.iter().any(|p| p.degrees < 30.0) && poses.iter().any(|p| p.degrees > 330.0));
        let mut again = ChaCha8Rng::seed_from_u64(3);
        assert_eq!(poses[0], Pose::draw(Augmentation::Geometric, 64, &mut again));
    }
}

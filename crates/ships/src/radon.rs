//! The image as the wake searches read it, and its line integrals (the Radon transform taken
//! along rays and lines of the ground).
//!
//! The image is normalised as the field's Radon wake detectors normalise it (Rey et al. 1990;
//! Karakus et al. 2020): in dB, less a local mean over `background_m` (so that the wind's and
//! the incidence's gradients and the slicks' large patches do not make lines), over the sea's
//! robust standard deviation (1.4826 MAD), clipped at +-3 so that a ship's bright return does
//! not outweigh a kilometre of wake. NaN stays NaN and is left out of every integral.

use crate::Geometry;
use ndarray::{Array2, ArrayView2};
use rayon::prelude::*;

/// The normalised image at its own spacing and at a coarser one (at least `COARSE_M`) for the
/// searches' first passes.
pub struct SearchImage {
    pub fine: Normalised,
    pub coarse: Normalised,
    pub factor: usize,
    /// The directions of the scene's sidelobe streaks (degrees, in [0, 180);
    /// [`crate::sidelobes`]), along which no bright arm is sought: none until measured.
    pub sidelobe_axes: Vec<f64>,
}

/// The coarse image's least spacing (m).
pub const COARSE_M: f64 = 20.0;

impl SearchImage {
    /// `image` (linear sigma0, NaN for no data) normalised, at both spacings.
    pub fn new(image: ArrayView2<f32>, geometry: &Geometry, background_m: f64) -> Self {
        let fine = normalise(image, geometry, background_m);
        let factor = (COARSE_M / geometry.spacing.0.max(geometry.spacing.1)).ceil().max(1.0) as usize;
        let coarse = fine.coarsened(factor);
        Self {
            fine,
            coarse,
            factor,
            sidelobe_axes: Vec::new(),
        }
    }

    /// A fine pixel position on the coarse grid.
    pub fn to_coarse(&self, (r, c): (f64, f64)) -> (f64, f64) {
        let f = self.factor as f64;
        ((r + 0.5) / f - 0.5, (c + 0.5) / f - 0.5)
    }
}

/// A normalised image with its geometry.
pub struct Normalised {
    pub values: Array2<f32>,
    pub geometry: Geometry,
}

/// Box mean of the finite values of `a` over windows of (2 half.0 + 1) x (2 half.1 + 1), NaN
/// where the window holds none (summed-area table).
pub fn box_mean(a: &Array2<f32>, half: (usize, usize)) -> Array2<f32> {
    let (h, w) = a.dim();
    let sw = w + 1;
    let mut table = vec![[0f64; 2]; (h + 1) * sw];
    for r in 0..h {
        let mut row = [0f64; 2];
        for c in 0..w {
            let v = a[[r, c]];
            if v.is_finite() {
                row[0] += 1.0;
                row[1] += v as f64;
            }
            let above = table[r * sw + c + 1];
            table[(r + 1) * sw + c + 1] = [above[0] + row[0], above[1] + row[1]];
        }
    }
    let mut out = Array2::from_elem((h, w), f32::NAN);
    out.axis_iter_mut(ndarray::Axis(0))
        .into_par_iter()
        .enumerate()
        .for_each(|(r, mut row)| {
            let (ra, rb) = (r.saturating_sub(half.0), (r + half.0 + 1).min(h));
            for c in 0..w {
                let (ca, cb) = (c.saturating_sub(half.1), (c + half.1 + 1).min(w));
                let at = |r: usize, c: usize| table[r * sw + c];
                let (a, b, cc, d) = (at(rb, cb), at(ra, cb), at(rb, ca), at(ra, ca));
                let n = a[0] - b[0] - cc[0] + d[0];
                if n > 0.0 {
                    row[c] = ((a[1] - b[1] - cc[1] + d[1]) / n) as f32;
                }
            }
        });
    out
}

/// The median of the finite values (None without any).
pub fn median(values: impl Iterator<Item = f32>) -> Option<f64> {
    let mut v: Vec<f32> = values.filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return None;
    }
    let mid = v.len() / 2;
    let (_, m, _) = v.select_nth_unstable_by(mid, f32::total_cmp);
    Some(*m as f64)
}

/// The median of `all` and its robust deviation, 1.4826 MAD (the standard deviation for a
/// Gaussian sample), kept above zero.
pub fn robust_spread(all: &[f64]) -> (f64, f64) {
    let m = median(all.iter().map(|&v| v as f32)).unwrap_or(0.0);
    let mad = median(all.iter().map(|&v| (v - m).abs() as f32))
        .unwrap_or(0.0)
        .max(1e-6);
    (m, 1.4826 * mad)
}

/// `image` (linear sigma0, NaN for no data) normalised for the wake searches.
pub fn normalise(image: ArrayView2<f32>, geometry: &Geometry, background_m: f64) -> Normalised {
    let db = image.mapv(|v| {
        if v > 0.0 && v.is_finite() {
            10.0 * v.log10()
        } else {
            f32::NAN
        }
    });
    let half = (
        (0.5 * background_m / geometry.spacing.0).round().max(1.0) as usize,
        (0.5 * background_m / geometry.spacing.1).round().max(1.0) as usize,
    );
    let local = box_mean(&db, half);
    let mut values = &db - &local;
    // the sea's spread: the MAD of a sample of the pixels (every 7th: enough for a median)
    let sample = || values.iter().step_by(7).copied();
    let centre = median(sample()).unwrap_or(0.0) as f32;
    let mad = median(sample().map(|v| (v - centre).abs())).unwrap_or(1.0).max(1e-6);
    let scale = (1.4826 * mad) as f32;
    values.mapv_inplace(|v| {
        if v.is_finite() {
            ((v - centre) / scale).clamp(-3.0, 3.0)
        } else {
            v
        }
    });
    Normalised {
        values,
        geometry: *geometry,
    }
}

impl Normalised {
    /// Block means (NaN-aware) of `factor` x `factor` pixels: the same image at a coarser
    /// spacing, for the searches' first passes. Its pixel (i, j) is centred on the fine pixel
    /// ((i + 0.5) factor - 0.5, (j + 0.5) factor - 0.5).
    pub fn coarsened(&self, factor: usize) -> Normalised {
        let (h, w) = self.values.dim();
        let (ch, cw) = (h.div_ceil(factor), w.div_ceil(factor));
        let mut values = Array2::from_elem((ch, cw), f32::NAN);
        values
            .axis_iter_mut(ndarray::Axis(0))
            .into_par_iter()
            .enumerate()
            .for_each(|(i, mut row)| {
                for j in 0..cw {
                    let (mut sum, mut n) = (0f32, 0);
                    for r in i * factor..((i + 1) * factor).min(h) {
                        for c in j * factor..((j + 1) * factor).min(w) {
                            let v = self.values[[r, c]];
                            if v.is_finite() {
                                sum += v;
                                n += 1;
                            }
                        }
                    }
                    if n > 0 {
                        row[j] = sum / n as f32;
                    }
                }
            });
        let g = self.geometry;
        Normalised {
            values,
            geometry: Geometry {
                spacing: (g.spacing.0 * factor as f64, g.spacing.1 * factor as f64),
                ..g
            },
        }
    }

    /// The value at a fractional pixel, bilinear over the finite neighbours (NaN outside).
    pub fn at(&self, row: f64, col: f64) -> f32 {
        let (h, w) = self.values.dim();
        if !(row >= 0.0 && col >= 0.0 && row <= (h - 1) as f64 && col <= (w - 1) as f64) {
            return f32::NAN;
        }
        let (r0, c0) = (row.floor() as usize, col.floor() as usize);
        let (fr, fc) = ((row - r0 as f64) as f32, (col - c0 as f64) as f32);
        let (mut sum, mut weight) = (0f32, 0f32);
        for (dr, wr) in [(0, 1.0 - fr), (1, fr)] {
            for (dc, wc) in [(0, 1.0 - fc), (1, fc)] {
                let (r, c) = ((r0 + dr).min(h - 1), (c0 + dc).min(w - 1));
                let v = self.values[[r, c]];
                if v.is_finite() && wr * wc > 0.0 {
                    sum += v * wr * wc;
                    weight += wr * wc;
                }
            }
        }
        if weight > 0.0 {
            sum / weight
        } else {
            f32::NAN
        }
    }

    /// The mean along a ray from `start` (fractional pixel) in direction `heading_deg`, from
    /// `near` to `far` metres, over a band `half_width` metres to either side of it at
    /// `across` metres off the ray (0: on it), and how many samples it holds.
    pub fn ray_mean(
        &self,
        start: (f64, f64),
        heading_deg: f64,
        (near, far): (f64, f64),
        across: f64,
        half_width: f64,
    ) -> (f64, usize) {
        let g = &self.geometry;
        let (ur, uc) = g.step(heading_deg);
        let (vr, vc) = g.step(heading_deg + 90.0);
        let step = g.spacing.0.min(g.spacing.1);
        // across a wide band every third of its half-width is enough (the mean of a band)
        let across_step = step.max(half_width / 3.0);
        let (mut sum, mut n) = (0f64, 0usize);
        let mut d = near;
        while d <= far {
            let mut x = across - half_width;
            loop {
                let v = self.at(start.0 + ur * d + vr * x, start.1 + uc * d + vc * x);
                if v.is_finite() {
                    sum += v as f64;
                    n += 1;
                }
                x += across_step;
                if x > across + half_width + 1e-9 {
                    break;
                }
            }
            d += step;
        }
        (if n > 0 { sum / n as f64 } else { f64::NAN }, n)
    }

    /// How many samples [`Self::ray_mean`] takes over the same ray and band where all of it
    /// lies in the image: the count its own would reach without edges, land or no data.
    pub fn ray_capacity(&self, (near, far): (f64, f64), half_width: f64) -> usize {
        let step = self.geometry.spacing.0.min(self.geometry.spacing.1);
        let across_step = step.max(half_width / 3.0);
        let along = if far >= near {
            ((far - near) / step + 1e-9).floor() as usize + 1
        } else {
            0
        };
        let across = (2.0 * half_width / across_step + 1e-9).floor() as usize + 1;
        along * across
    }

    /// The profile along a ray: the band's mean at every `step` metres from `near` to `far`.
    pub fn ray_profile(
        &self,
        start: (f64, f64),
        heading_deg: f64,
        (near, far): (f64, f64),
        half_width: f64,
    ) -> Vec<f32> {
        let g = &self.geometry;
        let (ur, uc) = g.step(heading_deg);
        let (vr, vc) = g.step(heading_deg + 90.0);
        let step = g.spacing.0.min(g.spacing.1);
        let mut out = Vec::new();
        let mut d = near;
        while d <= far {
            let (mut sum, mut n) = (0f32, 0);
            let mut x = -half_width;
            while x <= half_width + 1e-9 {
                let v = self.at(start.0 + ur * d + vr * x, start.1 + uc * d + vc * x);
                if v.is_finite() {
                    sum += v;
                    n += 1;
                }
                x += step;
            }
            out.push(if n > 0 { sum / n as f32 } else { f32::NAN });
            d += step;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn geometry() -> Geometry {
        Geometry::along_rows(10.0, 35.0, None)
    }

    #[test]
    fn box_means_skip_no_data() {
        let mut a = Array2::from_elem((5, 5), 2.0f32);
        a[[2, 2]] = f32::NAN;
        a[[0, 0]] = 7.0;
        let m = box_mean(&a, (1, 1));
        assert_eq!(m[[2, 2]], 2.0);
        assert_eq!(m[[0, 0]], (7.0 + 3.0 * 2.0) / 4.0);
    }

    /// On a plane of 1 with a line of 0 running up from the centre, the ray along it means 0,
    /// the band 100 m to its right 1, and the ray the other way 1.
    #[test]
    fn rays_follow_their_heading() {
        let g = geometry();
        let mut values = Array2::from_elem((101, 101), 1.0f32);
        for r in 0..=50 {
            values[[r, 50]] = 0.0;
        }
        let image = Normalised { values, geometry: g };
        let on = image.ray_mean((50.0, 50.0), 0.0, (0.0, 400.0), 0.0, 0.0);
        let beside = image.ray_mean((50.0, 50.0), 0.0, (0.0, 400.0), 100.0, 20.0);
        let behind = image.ray_mean((50.0, 50.0), 180.0, (10.0, 400.0), 0.0, 0.0);
        assert!((behind.0 - 1.0).abs() < 1e-6, "{behind:?}");
        assert!(on.0.abs() < 1e-6 && on.1 == 41, "{on:?}");
        assert!((beside.0 - 1.0).abs() < 1e-6, "{beside:?}");
    }

    /// `ray_capacity` counts what `ray_mean` samples when the whole ray lies in the image, for
    /// bands narrower and wider than a pixel and rays along and across the grid; a ray half
    /// out of the image samples fewer.
    #[test]
    fn a_rays_capacity_is_what_it_samples_inside_the_image() {
        let g = crate::Geometry::along_rows(10.0, 35.0, None);
        let image = normalise(crate::speckle(400, 400, 4, 0.01, 5).view(), &g, 2000.0);
        for (heading, half_width) in [(0.0, 5.0), (90.0, 20.0), (37.0, 100.0), (210.0, 10.0)] {
            let (_, n) = image.ray_mean((200.0, 200.0), heading, (60.0, 1500.0), 0.0, half_width);
            assert_eq!(
                n,
                image.ray_capacity((60.0, 1500.0), half_width),
                "{heading} {half_width}"
            );
            let (_, cut) = image.ray_mean((200.0, 380.0), 90.0, (60.0, 1500.0), 0.0, half_width);
            assert!(cut < n / 4, "{cut} of {n}");
        }
    }
}

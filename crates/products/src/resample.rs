//! Area averaging to a coarser pixel spacing: each output pixel is the mean of the input pixels
//! it covers, weighted by the area they share with it (fractional at its edges), so that a
//! factor of 2.5 is as exact as a factor of 2. Averaging sigma0 in linear power is what a SAR
//! processor's multilooking does. No-data (NaN) pixels are left out of the mean, and an output
//! pixel less than half covered by data is no-data itself.

use ndarray::{Array2, Axis};
use rayon::prelude::*;

/// For each output index along an axis of `len` input pixels shrunk by `factor`, the input
/// pixels it covers and their weights (the overlap of [i f, (i + 1) f) with [k, k + 1)).
fn weights(len: usize, factor: f64) -> Vec<Vec<(usize, f64)>> {
    let out = ((len as f64) / factor).floor().max(1.0) as usize;
    (0..out)
        .map(|i| {
            let (lo, hi) = (i as f64 * factor, ((i + 1) as f64 * factor).min(len as f64));
            (lo.floor() as usize..(hi.ceil() as usize).min(len))
                .map(|k| (k, (hi.min(k as f64 + 1.0) - lo.max(k as f64)).max(0.0)))
                .filter(|&(_, w)| w > 0.0)
                .collect()
        })
        .collect()
}

/// `image` averaged over blocks of `row_factor` x `col_factor` input pixels (both >= 1).
pub fn area_average(image: &Array2<f32>, row_factor: f64, col_factor: f64) -> Array2<f32> {
    let (h, w) = image.dim();
    let (rw, cw) = (weights(h, row_factor), weights(w, col_factor));
    let mut out = Array2::<f32>::zeros((rw.len(), cw.len()));
    out.axis_iter_mut(Axis(0))
        .into_par_iter()
        .zip(rw.par_iter())
        .for_each(|(mut row, rows)| {
            // the rows' weighted sums and valid weights across the full width, then the columns
            let mut sum = vec![0.0f64; w];
            let mut weight = vec![0.0f64; w];
            let mut area = 0.0;
            for &(r, a) in rows {
                area += a;
                for (c, &v) in image.row(r).iter().enumerate() {
                    if !v.is_nan() {
                        sum[c] += a * v as f64;
                        weight[c] += a;
                    }
                }
            }
            for (o, cols) in row.iter_mut().zip(&cw) {
                let (mut s, mut valid, mut total) = (0.0, 0.0, 0.0);
                for &(c, b) in cols {
                    s += b * sum[c];
                    valid += b * weight[c];
                    total += b * area;
                }
                *o = if valid >= 0.5 * total && valid > 0.0 {
                    (s / valid) as f32
                } else {
                    f32::NAN
                };
            }
        });
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::array;

    #[test]
    fn blocks_average_with_fractional_edges() {
        let image = Array2::from_shape_fn((4, 5), |(r, c)| (r * 5 + c) as f32);
        let half = area_average(&image, 2.0, 2.5);
        assert_eq!(half.dim(), (2, 2));
        // rows 0-1, columns 0, 1 and half of 2: (0 + 1 + 0.5*2 + 5 + 6 + 0.5*7) / 5
        assert!((half[[0, 0]] - (0.0 + 1.0 + 1.0 + 5.0 + 6.0 + 3.5) / 5.0).abs() < 1e-6);
        // the mean is conserved where the factors divide the image
        let even = area_average(&image.slice(ndarray::s![.., ..4]).to_owned(), 2.0, 2.0);
        let mean = |a: &Array2<f32>| a.iter().map(|&v| v as f64).sum::<f64>() / a.len() as f64;
        assert!((mean(&even) - mean(&image.slice(ndarray::s![.., ..4]).to_owned())).abs() < 1e-9);
    }

    #[test]
    fn no_data_is_left_out_and_mostly_empty_blocks_are_no_data() {
        let nan = f32::NAN;
        let image = array![[1.0f32, 3.0, nan, nan], [nan, 5.0, nan, 7.0]];
        let out = area_average(&image, 2.0, 2.0);
        assert_eq!(out[[0, 0]], 3.0);
        // one valid pixel of four: less than half
        assert!(out[[0, 1]].is_nan());
    }
}

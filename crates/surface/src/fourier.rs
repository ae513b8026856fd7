//! Two-dimensional discrete Fourier transforms of square arrays by rows then columns (rustfft).

use rayon::prelude::*;
use rustfft::num_complex::Complex64;
use rustfft::{Fft, FftPlanner};

/// The signed frequency index (cycles per transform length) of DFT bin `i` of `n`: 0, 1, ..,
/// n/2, then -(n/2 - 1), .., -1.
pub fn signed_frequency(i: usize, n: usize) -> f64 {
    if i <= n / 2 {
        i as f64
    } else {
        i as f64 - n as f64
    }
}

/// Unnormalised 2D DFT in place of the n x n row-major `data` with a planned 1D transform of
/// length n, on one thread: every row in one batched call, a transpose, the rows again, and the
/// transpose back (rows are contiguous; columns are not).
pub fn fft_2d_with(data: &mut [Complex64], n: usize, fft: &dyn Fft<f64>, scratch: &mut [Complex64]) {
    fft.process_with_scratch(data, scratch);
    transpose_in_place(data, n);
    fft.process_with_scratch(data, scratch);
    transpose_in_place(data, n);
}

/// Unnormalised forward (e^{-ikx}) or inverse (e^{+ikx}) 2D DFT in place, rows and the
/// transposes shared out over the threads (the same values on any number of threads: every row's
/// transform is computed alone).
pub fn fft_2d(data: &mut [Complex64], n: usize, inverse: bool) {
    let mut planner = FftPlanner::new();
    let fft = if inverse {
        planner.plan_fft_inverse(n)
    } else {
        planner.plan_fft_forward(n)
    };
    let rows = |data: &mut [Complex64]| {
        data.par_chunks_mut(n * ROWS_PER_TASK.min(n)).for_each(|chunk| {
            let mut scratch = vec![Complex64::new(0.0, 0.0); fft.get_inplace_scratch_len()];
            fft.process_with_scratch(chunk, &mut scratch);
        })
    };
    let mut transposed = vec![Complex64::new(0.0, 0.0); n * n];
    rows(data);
    transpose_into(data, &mut transposed, n);
    rows(&mut transposed);
    transpose_into(&transposed, data, n);
}

/// Rows of a parallel transform handed to a thread at once.
const ROWS_PER_TASK: usize = 16;

/// Side of the square tiles a transpose moves at once (two tiles fit in the L1 cache).
const TILE: usize = 16;

/// `to` = the transpose of the n x n `from`, in tiles, output row bands in parallel.
fn transpose_into(from: &[Complex64], to: &mut [Complex64], n: usize) {
    to.par_chunks_mut(n * TILE).enumerate().for_each(|(band, out)| {
        let c0 = band * TILE;
        let width = out.len() / n;
        for r0 in (0..n).step_by(TILE) {
            for r in r0..(r0 + TILE).min(n) {
                for dc in 0..width {
                    out[dc * n + r] = from[r * n + c0 + dc];
                }
            }
        }
    });
}

/// Transpose the n x n `data` in place, tile by tile.
fn transpose_in_place(data: &mut [Complex64], n: usize) {
    for r0 in (0..n).step_by(TILE) {
        for c0 in (r0..n).step_by(TILE) {
            for r in r0..(r0 + TILE).min(n) {
                let first = if c0 == r0 { r + 1 } else { c0 };
                for c in first..(c0 + TILE).min(n) {
                    data.swap(r * n + c, c * n + r);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forward_then_inverse_is_n_squared_times_the_identity() {
        let n = 12;
        let orig: Vec<Complex64> = (0..n * n)
            .map(|i| Complex64::new((i as f64).sin(), (i as f64 * 0.3).cos()))
            .collect();
        let mut d = orig.clone();
        fft_2d(&mut d, n, false);
        // DC term is the sum
        let sum: Complex64 = orig.iter().sum();
        assert!((d[0] - sum).norm() < 1e-9);
        fft_2d(&mut d, n, true);
        for (a, b) in d.iter().zip(&orig) {
            assert!((a / (n * n) as f64 - b).norm() < 1e-12);
        }
    }

    /// The batched, transposing transforms equal the 2D DFT's definition, on a size that is not
    /// a multiple of the tile, for the serial and the parallel path.
    #[test]
    fn both_paths_equal_the_definition() {
        let n = 21;
        let orig: Vec<Complex64> = (0..n * n)
            .map(|i| Complex64::new((i as f64 * 0.7).sin(), (i as f64 * 0.11).cos()))
            .collect();
        let mut want = vec![Complex64::new(0.0, 0.0); n * n];
        for (p, w) in want.iter_mut().enumerate() {
            let (a, b) = (p / n, p % n);
            for (q, v) in orig.iter().enumerate() {
                let (r, c) = (q / n, q % n);
                let phase = -2.0 * std::f64::consts::PI * ((a * r + b * c) % n) as f64 / n as f64;
                *w += v * Complex64::from_polar(1.0, phase);
            }
        }
        let mut parallel = orig.clone();
        fft_2d(&mut parallel, n, false);
        let fft = FftPlanner::new().plan_fft_forward(n);
        let mut serial = orig.clone();
        let mut scratch = vec![Complex64::new(0.0, 0.0); fft.get_inplace_scratch_len()];
        fft_2d_with(&mut serial, n, fft.as_ref(), &mut scratch);
        for ((p, s), w) in parallel.iter().zip(&serial).zip(&want) {
            assert!((p - w).norm() < 1e-9 && (s - w).norm() < 1e-9);
        }
    }
}

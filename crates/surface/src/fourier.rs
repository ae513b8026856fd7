//! Two-dimensional discrete Fourier transforms of square arrays by rows then columns (rustfft).

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

/// Unnormalised 2D DFT in place of the n x n row-major `data` with a planned 1D transform.
pub fn fft_2d_with(data: &mut [Complex64], n: usize, fft: &dyn Fft<f64>, scratch: &mut [Complex64]) {
    for row in data.chunks_mut(n) {
        fft.process_with_scratch(row, scratch);
    }
    let mut column = vec![Complex64::new(0.0, 0.0); n];
    for c in 0..n {
        for r in 0..n {
            column[r] = data[r * n + c];
        }
        fft.process_with_scratch(&mut column, scratch);
        for r in 0..n {
            data[r * n + c] = column[r];
        }
    }
}

/// Unnormalised forward (e^{-ikx}) or inverse (e^{+ikx}) 2D DFT in place.
pub fn fft_2d(data: &mut [Complex64], n: usize, inverse: bool) {
    let mut planner = FftPlanner::new();
    let fft = if inverse {
        planner.plan_fft_inverse(n)
    } else {
        planner.plan_fft_forward(n)
    };
    let mut scratch = vec![Complex64::new(0.0, 0.0); fft.get_inplace_scratch_len()];
    fft_2d_with(data, n, fft.as_ref(), &mut scratch);
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
}

//! The random sea surface by windowed spectral synthesis, spec Eqs. (2.72)-(2.76) after
//! Lyzenga (1986).
//!
//! The scene is covered by square windows of M x M pixels placed every M/2 pixels in both
//! directions. In each window a random field is synthesised from the spectrum on the window's
//! wavenumber grid k_m = 2 pi (m - M/2) / L (Eqs. (2.72)-(2.73)), with amplitudes
//! sqrt(6 F(k) dk_x dk_y) r e^{i psi}, r uniform in [-1, 1] and psi in [0, 2 pi) (Eq. (2.76)), and
//! weighted by the square-root Hann windows of Eqs. (2.74)-(2.75); the windows are summed. The
//! squares of square-root Hann windows half a window apart sum to one, and E[r^2] = 1/3 with
//! Re(.) halving the variance, so the factor sqrt(6) (over the spec's 2 pi sqrt(S / (L_x L_y)) =
//! sqrt(F dk_x dk_y)) makes the surface's variance equal the spectrum's m0 over the resolved band.
//! Slopes come from the same amplitudes times i k (the window's own gradient is neglected).
//! Each window draws from a ChaCha8 stream seeded by (seed, window index): the same seed gives the
//! same surface, bit for bit, in any thread order.

use crate::fourier::fft_2d_with;
use crate::scene::heading_frame_wavenumber;
use crate::spectrum::SeaSpectrum;
use ndarray::Array2;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use rustfft::num_complex::Complex64;
use rustfft::FftPlanner;
use std::f64::consts::PI;

/// Elevation and slopes of a realised sea surface, row-major (rows, cols), pixel spacing `dx`;
/// slopes in the scene frame (east, north).
#[derive(Debug, Clone)]
pub struct RandomSurface {
    pub elevation: Array2<f64>,
    /// d zeta / d x along the columns, eastward (m/m).
    pub slope_x: Array2<f64>,
    /// d zeta / d y along the rows, northward: to decreasing row index (m/m).
    pub slope_y: Array2<f64>,
    pub dx: f64,
}

/// Square-root Hann weight of Eqs. (2.74)-(2.75) for index m of M.
pub fn root_hann(m: usize, window: usize) -> f64 {
    (0.5 - 0.5 * (2.0 * PI * m as f64 / window as f64).cos())
        .max(0.0)
        .sqrt()
}

/// Synthesise a `size` x `size` surface with pixel spacing `dx` from `spectrum`.
/// `heading` is the ship's course in the image (radians clockwise from up), which turns the
/// spectrum's heading-frame directions into the image's.
pub fn synthesise_surface(
    spectrum: &SeaSpectrum,
    size: usize,
    dx: f64,
    heading: f64,
    window: usize,
    seed: u64,
) -> RandomSurface {
    let m = window;
    let hop = m / 2;
    let starts: Vec<isize> = (-(hop as isize)..size as isize).step_by(hop).collect();
    let dk = 2.0 * PI / (m as f64 * dx);
    // amplitude scale per wavenumber bin, shared by every window
    let mut scale = vec![0.0; m * m];
    for a in 0..m {
        for b in 0..m {
            let k_row = (a as f64 - (m / 2) as f64) * dk;
            let k_col = (b as f64 - (m / 2) as f64) * dk;
            let (kx, ky) = heading_frame_wavenumber(k_col, k_row, heading);
            if a == 0 || b == 0 {
                continue; // Eqs. (2.72)-(2.73) use m in [1, M - 1]
            }
            scale[a * m + b] = (6.0 * spectrum.directional(kx, ky) * dk * dk).sqrt();
        }
    }
    let fft = FftPlanner::new().plan_fft_inverse(m);
    let windows: Vec<(usize, isize, isize)> = starts
        .iter()
        .flat_map(|&r0| starts.iter().map(move |&c0| (r0, c0)))
        .enumerate()
        .map(|(i, (r0, c0))| (i, r0, c0))
        .collect();
    let window_weight: Vec<f64> = (0..m).map(|i| root_hann(i, m)).collect();
    // each window's three fields, computed in parallel, then added in a fixed order
    let patches: Vec<[Vec<f64>; 3]> = windows
        .par_iter()
        .map(|&(index, _, _)| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed ^ (index as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
            let mut fields = [
                vec![Complex64::new(0.0, 0.0); m * m],
                vec![Complex64::new(0.0, 0.0); m * m],
                vec![Complex64::new(0.0, 0.0); m * m],
            ];
            for a in 0..m {
                for b in 0..m {
                    let r: f64 = rng.random_range(-1.0..=1.0);
                    let psi: f64 = rng.random_range(0.0..2.0 * PI);
                    let amp = Complex64::from_polar(scale[a * m + b] * r, psi);
                    // place wavenumber (a - M/2, b - M/2) at FFT index (shifted)
                    let (fa, fb) = ((a + m / 2) % m, (b + m / 2) % m);
                    let k_row = (a as f64 - (m / 2) as f64) * dk;
                    let k_col = (b as f64 - (m / 2) as f64) * dk;
                    fields[0][fa * m + fb] = amp;
                    fields[1][fa * m + fb] = amp * Complex64::new(0.0, k_col);
                    fields[2][fa * m + fb] = amp * Complex64::new(0.0, -k_row);
                }
            }
            let mut scratch = vec![Complex64::new(0.0, 0.0); fft.get_inplace_scratch_len()];
            fields.map(|mut f| {
                fft_2d_with(&mut f, m, fft.as_ref(), &mut scratch);
                f.iter()
                    .enumerate()
                    .map(|(i, z)| z.re * window_weight[i / m] * window_weight[i % m])
                    .collect()
            })
        })
        .collect();
    let mut out = [
        Array2::<f64>::zeros((size, size)),
        Array2::<f64>::zeros((size, size)),
        Array2::<f64>::zeros((size, size)),
    ];
    for (&(_, r0, c0), patch) in windows.iter().zip(&patches) {
        for (field, values) in out.iter_mut().zip(patch) {
            for a in 0..m {
                let row = r0 + a as isize;
                if row < 0 || row >= size as isize {
                    continue;
                }
                for b in 0..m {
                    let col = c0 + b as isize;
                    if col < 0 || col >= size as isize {
                        continue;
                    }
                    field[[row as usize, col as usize]] += values[a * m + b];
                }
            }
        }
    }
    let [elevation, slope_x, slope_y] = out;
    RandomSurface {
        elevation,
        slope_x,
        slope_y,
        dx,
    }
}

/// The variance the synthesis reproduces: the spectrum summed over the window's wavenumber grid.
pub fn resolved_variance(spectrum: &SeaSpectrum, dx: f64, heading: f64, window: usize) -> f64 {
    let m = window;
    let dk = 2.0 * PI / (m as f64 * dx);
    let mut v = 0.0;
    for a in 1..m {
        for b in 1..m {
            let k_row = (a as f64 - (m / 2) as f64) * dk;
            let k_col = (b as f64 - (m / 2) as f64) * dk;
            let (kx, ky) = heading_frame_wavenumber(k_col, k_row, heading);
            v += spectrum.directional(kx, ky) * dk * dk;
        }
    }
    v
}

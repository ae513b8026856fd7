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
//! Taking the real part equals transforming the amplitudes' Hermitian part, whose transform is
//! real: so two real fields share one complex transform (elevation and east slope), and each
//! window needs two transforms for its three fields.
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
    let window_weight: Vec<f64> = (0..m).map(|i| root_hann(i, m)).collect();
    // per FFT index: its wavenumber and the index of minus it; per centred index, the FFT index
    let wavenumber: Vec<f64> = (0..m)
        .map(|i| (((i + m / 2) % m) as f64 - (m / 2) as f64) * dk)
        .collect();
    let negative: Vec<usize> = (0..m).map(|i| (m - i) % m).collect();
    let fft_index: Vec<usize> = (0..m).map(|a| (a + m / 2) % m).collect();
    let mut out = [
        Array2::<f64>::zeros((size, size)),
        Array2::<f64>::zeros((size, size)),
        Array2::<f64>::zeros((size, size)),
    ];
    // one row of windows at a time: its windows in parallel (each thread reusing its buffers),
    // then added in a fixed order
    let mut patches: Vec<[Vec<f64>; 3]> = starts
        .iter()
        .map(|_| [vec![0.0; m * m], vec![0.0; m * m], vec![0.0; m * m]])
        .collect();
    for (window_row, &r0) in starts.iter().enumerate() {
        patches.par_iter_mut().enumerate().for_each_init(
            || {
                let zero = Complex64::new(0.0, 0.0);
                [
                    vec![zero; m * m],
                    vec![zero; m * m],
                    vec![zero; m * m],
                    vec![zero; fft.get_inplace_scratch_len()],
                ]
            },
            |[amplitude, first, second, scratch], (window_col, patch)| {
                let index = (window_row * starts.len() + window_col) as u64;
                let mut rng = ChaCha8Rng::seed_from_u64(seed ^ index.wrapping_mul(0x9E37_79B9_7F4A_7C15));
                // amplitudes in FFT order (index i holds wavenumber index i - M/2 shifted by M/2)
                for a in 0..m {
                    for b in 0..m {
                        amplitude[fft_index[a] * m + fft_index[b]] = scale[a * m + b] * random_phasor(&mut rng);
                    }
                }
                // Re(sum A e^{ikx}) is the transform of A's Hermitian part H(k) = (A(k) +
                // conj A(-k)) / 2, a real field, and so are its slopes i k H: one complex
                // transform carries the elevation (real part) and the east slope (imaginary
                // part), a second the north slope
                for fa in 0..m {
                    for fb in 0..m {
                        let mirror = negative[fa] * m + negative[fb];
                        let h = 0.5 * (amplitude[fa * m + fb] + amplitude[mirror].conj());
                        let (k_row, k_col) = (wavenumber[fa], wavenumber[fb]);
                        first[fa * m + fb] = h * (1.0 - k_col); // H + i (i k_col H)
                        second[fa * m + fb] = h * Complex64::new(0.0, -k_row);
                    }
                }
                fft_2d_with(first, m, fft.as_ref(), scratch);
                fft_2d_with(second, m, fft.as_ref(), scratch);
                let [elevation, east, north] = patch;
                for (i, (z1, z2)) in first.iter().zip(second.iter()).enumerate() {
                    let w = window_weight[i / m] * window_weight[i % m];
                    (elevation[i], east[i], north[i]) = (z1.re * w, z1.im * w, z2.re * w);
                }
            },
        );
        for (f, field) in out.iter_mut().enumerate() {
            let rows = (r0.max(0) as usize)..((r0 + m as isize).min(size as isize) as usize);
            field
                .slice_mut(ndarray::s![rows.clone(), ..])
                .axis_iter_mut(ndarray::Axis(0))
                .into_par_iter()
                .zip(rows)
                .for_each(|(mut line, row)| {
                    let a = (row as isize - r0) as usize;
                    for (&c0, patch) in starts.iter().zip(&patches) {
                        let values = &patch[f][a * m..(a + 1) * m];
                        for (b, v) in values.iter().enumerate() {
                            let col = c0 + b as isize;
                            if (0..size as isize).contains(&col) {
                                line[col as usize] += v;
                            }
                        }
                    }
                });
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

/// r e^{i psi} with r uniform in [-1, 1] and psi uniform in [0, 2 pi) (Eq. (2.76)), drawn as
/// sqrt(s) (u, v) for (u, v) uniform in the unit disc and s = u^2 + v^2: the angle of (u, v) is
/// uniform and independent of s, which is uniform in [0, 1] like |r| (a sign of r is a half
/// turn of psi, so r e^{i psi} and |r| e^{i psi} have one distribution); no sine or cosine.
fn random_phasor(rng: &mut ChaCha8Rng) -> Complex64 {
    loop {
        let u: f64 = rng.random_range(-1.0..1.0);
        let v: f64 = rng.random_range(-1.0..1.0);
        let s = u * u + v * v;
        if s <= 1.0 {
            let root = s.sqrt();
            return Complex64::new(root * u, root * v);
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The phasors have the moments of r e^{i psi} with r uniform in [-1, 1] and psi uniform
    /// (Eq. (2.76)): E|z| = 1/2, E|z|^2 = 1/3, and a uniform phase, E z = E z^2 = 0; and
    /// |z| is uniform: a quarter of the draws below 1/4.
    #[test]
    fn phasors_have_the_moments_of_eq_2_76() {
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let n = 200_000;
        let draws: Vec<Complex64> = (0..n).map(|_| random_phasor(&mut rng)).collect();
        let mean = |f: &dyn Fn(&Complex64) -> Complex64| draws.iter().map(f).sum::<Complex64>() / n as f64;
        // standard errors at n = 2e5 are about 1e-3
        assert!((mean(&|z| z.norm().into()).re - 0.5).abs() < 4e-3);
        assert!((mean(&|z| z.norm_sqr().into()).re - 1.0 / 3.0).abs() < 4e-3);
        assert!(mean(&|z| *z).norm() < 4e-3);
        assert!(mean(&|z| z * z).norm() < 4e-3);
        let below = draws.iter().filter(|z| z.norm() < 0.25).count() as f64 / n as f64;
        assert!((below - 0.25).abs() < 4e-3, "{below}");
    }
}

//! Linear filters of the scene's elevation by 2D FFT.

use ndarray::Array2;
use rustfft::num_complex::Complex64;
use wakelab_surface::fourier::{fft_2d, signed_frequency};
use wakelab_surface::scene::heading_frame_wavenumber;

/// Line-of-sight orbital velocity (m/s, away from the sensor) of the long waves in `elevation`
/// (an image of spacing `dx` whose ship runs at `heading`, radians clockwise from up; see
/// `wakelab_surface::scene`), by linear deep-water theory:
/// for a wave travelling along k, v_r = Re[A omega ((k.l) sin(theta) + i cos(theta)) e^{i k x}],
/// l the horizontal look direction `look`, theta the incidence. A snapshot cannot tell which of
/// k and -k a component travels along: the one running with the wind (direction `wind`) is taken.
pub fn line_of_sight_velocity(
    elevation: &Array2<f64>,
    dx: f64,
    heading: f64,
    theta: f64,
    look: f64,
    wind: f64,
    omega: impl Fn(f64) -> f64,
) -> Array2<f64> {
    let n = elevation.nrows();
    let mut data: Vec<Complex64> = elevation.iter().map(|&z| Complex64::new(z, 0.0)).collect();
    fft_2d(&mut data, n, false);
    let dk = 2.0 * std::f64::consts::PI / (n as f64 * dx);
    let freq = |i: usize| signed_frequency(i, n);
    let (lx, ly) = (look.cos(), look.sin());
    let (wx, wy) = (wind.cos(), wind.sin());
    let (st, ct) = theta.sin_cos();
    for a in 0..n {
        for b in 0..n {
            let (k_row, k_col) = (freq(a) * dk, freq(b) * dk);
            let (kx, ky) = heading_frame_wavenumber(k_col, k_row, heading);
            let k = kx.hypot(ky);
            let h = if k == 0.0 {
                Complex64::new(0.0, 0.0)
            } else {
                let w = omega(k);
                let along = (kx * lx + ky * ly) / k;
                if kx * wx + ky * wy >= 0.0 {
                    Complex64::new(w * along * st, w * ct)
                } else {
                    Complex64::new(w * along * st, -w * ct)
                }
            };
            data[a * n + b] *= h;
        }
    }
    fft_2d(&mut data, n, true);
    let scale = 1.0 / (n * n) as f64;
    Array2::from_shape_fn((n, n), |(r, c)| data[r * n + c].re * scale)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A single down-wind wave zeta = a cos(k x_h) seen from above (theta = 0): the vertical
    /// velocity is a omega sin(k x_h - omega t) at t = 0, i.e. a omega sin(k x_h), positive up,
    /// so away from a nadir-looking sensor it is -a omega sin(k x_h).
    #[test]
    fn nadir_velocity_of_a_single_wave() {
        let (n, dx) = (64usize, 2.0);
        let k = 2.0 * std::f64::consts::PI * 4.0 / (n as f64 * dx);
        let a = 0.5;
        let omega = (9.81 * k).sqrt();
        // a ship running left (heading 270 degrees): x_h = -col dx
        let z = Array2::from_shape_fn((n, n), |(_, c)| a * (k * -(c as f64) * dx).cos());
        let heading = 270f64.to_radians();
        let v = line_of_sight_velocity(&z, dx, heading, 0.0, 0.0, 0.0, |kk| (9.81 * kk).sqrt());
        for c in 0..n {
            let xh = -(c as f64) * dx;
            let want = -a * omega * (k * xh).sin();
            assert!((v[[3, c]] - want).abs() < 1e-9, "col {c}: {} vs {want}", v[[3, c]]);
        }
    }
}

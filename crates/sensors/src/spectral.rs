//! Linear filters of the scene's elevation by 2D FFT.

use ndarray::Array2;
use rayon::prelude::*;
use rustfft::num_complex::Complex64;
use wakelab_surface::fourier::{fft_2d, signed_frequency};
use wakelab_surface::scene::SceneGrid;

/// Line-of-sight orbital velocity (m/s, away from the sensor) of the long waves in `elevation`
/// (an image on `grid`), by linear deep-water theory: a component zeta = Re[A e^{i k x}]
/// travelling along s k (s = +-1) has horizontal velocity s omega zeta k/|k| and vertical
/// velocity -i s omega zeta, so with l the horizontal look direction `look` (heading frame) and
/// theta the incidence, v_r = u.l sin(theta) - w cos(theta) =
/// Re[s A omega ((k.l)/|k| sin(theta) + i cos(theta)) e^{i k x}]. A snapshot cannot tell which
/// of k and -k a component travels along: the one running with the wind (direction `wind`) is
/// taken, so of each pair k and -k one has s = 1 and the other s = -1, and the filter keeps a
/// real field real.
pub fn line_of_sight_velocity(
    elevation: &Array2<f64>,
    grid: &SceneGrid,
    theta: f64,
    look: f64,
    wind: f64,
    omega: impl Fn(f64) -> f64 + Sync,
) -> Array2<f64> {
    let n = elevation.nrows();
    let mut data: Vec<Complex64> = elevation.iter().map(|&z| Complex64::new(z, 0.0)).collect();
    fft_2d(&mut data, n, false);
    let dk = 2.0 * std::f64::consts::PI / (n as f64 * grid.pixel_spacing);
    let freq = |i: usize| signed_frequency(i, n);
    let (lx, ly) = (look.cos(), look.sin());
    let (wx, wy) = (wind.cos(), wind.sin());
    let (st, ct) = theta.sin_cos();
    data.par_chunks_mut(n).enumerate().for_each(|(a, row)| {
        for (b, value) in row.iter_mut().enumerate() {
            let (kx, ky) = grid.heading_frame_wavenumber(freq(b) * dk, freq(a) * dk);
            let k = kx.hypot(ky);
            if k == 0.0 {
                *value = Complex64::new(0.0, 0.0);
                continue;
            }
            let w = omega(k);
            let along = (kx * lx + ky * ly) / k;
            // downwind; a wave across the wind is taken to run to the wind's left
            let dot = kx * wx + ky * wy;
            let downwind = dot > 0.0 || (dot == 0.0 && kx * wy - ky * wx < 0.0);
            let s = if downwind { 1.0 } else { -1.0 };
            *value *= Complex64::new(s * w * along * st, s * w * ct);
        }
    });
    fft_2d(&mut data, n, true);
    let scale = 1.0 / (n * n) as f64;
    Array2::from_shape_fn((n, n), |(r, c)| data[r * n + c].re * scale)
}

#[cfg(test)]
mod tests {
    use super::*;
    use wakelab_core::config::SceneConfig;

    /// A scene of a ship running left (heading 270 degrees): forward x_h = -col dx.
    fn grid(n: usize, dx: f64) -> SceneGrid {
        SceneGrid::new(&SceneConfig {
            pixel_spacing: dx,
            size: n,
            along_track: 0.0,
            cross_track: 0.0,
            heading: 270.0,
            other_wakes: Vec::new(),
            centre: None,
        })
    }

    /// The same wave seen at 40 degrees incidence, looking along it: the horizontal orbital
    /// velocity a omega cos(k x_h) (along the travel) adds sin(theta) of itself to the vertical
    /// part's -cos(theta) a omega sin(k x_h); against the wind the wave is taken to run the
    /// other way, and both parts change sign.
    #[test]
    fn oblique_velocity_has_the_horizontal_orbital_part() {
        let (n, dx) = (64usize, 2.0);
        let k = 2.0 * std::f64::consts::PI * 4.0 / (n as f64 * dx);
        let (a, theta) = (0.5, 40f64.to_radians());
        let omega = (9.81 * k).sqrt();
        let z = Array2::from_shape_fn((n, n), |(_, c)| a * (k * -(c as f64) * dx).cos());
        for (wind, travel) in [(0.0, 1.0), (std::f64::consts::PI, -1.0)] {
            let v = line_of_sight_velocity(&z, &grid(n, dx), theta, 0.0, wind, |kk| (9.81 * kk).sqrt());
            for c in 0..n {
                let xh = -(c as f64) * dx;
                let want = travel * a * omega * (theta.sin() * (k * xh).cos() - theta.cos() * (k * xh).sin());
                assert!((v[[5, c]] - want).abs() < 1e-9, "col {c}: {} vs {want}", v[[5, c]]);
            }
        }
    }

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
        let v = line_of_sight_velocity(&z, &grid(n, dx), 0.0, 0.0, 0.0, |kk| (9.81 * kk).sqrt());
        for c in 0..n {
            let xh = -(c as f64) * dx;
            let want = -a * omega * (k * xh).sin();
            assert!((v[[3, c]] - want).abs() < 1e-9, "col {c}: {} vs {want}", v[[3, c]]);
        }
    }
}

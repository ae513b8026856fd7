//! The narrow-V: the divergent waves' stationary-phase amplitude against the thin-ship field's own
//! sum, and the arms' half-angle against the published relation of Munk, Scully-Power &
//! Zachariasen (1987), sqrt(g lambda_B / (8 pi)) / U, across bands and ship speeds.

use rustfft::num_complex::Complex64;
use std::f64::consts::PI;
use wakelab_core::config::HullForm;
use wakelab_core::units::RadarBand;
use wakelab_surface::kelvin::{KelvinWaves, ThinShip};
use wakelab_surface::narrow_v::divergent_ray;

const GRAVITY: f64 = 9.81;
/// Sea water's kinematic viscosity (m^2/s), spec Table 2.1.
const VISCOSITY: f64 = 1.05e-6;

fn ship(speed: f64) -> ThinShip {
    ThinShip {
        form: HullForm::Wigley,
        length: 50.0,
        beam: 8.0,
        draft: 3.0,
        speed,
        gravity: GRAVITY,
    }
}

/// A smooth step from 0 below `lo` to 1 above `hi`.
fn step(q: f64, lo: f64, hi: f64) -> f64 {
    let t = ((q - lo) / (hi - lo)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Far behind the ship (x = 60 L) the divergent waves' energy over the rays from 3 to 8 deg is
/// the stationary-phase amplitude's (a^2, no viscosity) within 10 %: the field's envelope is
/// taken from the thin-ship sum itself, the divergent branch (|q_y| above a split the
/// transverse waves never reach there) and its Hilbert transform across the track.
#[test]
fn the_divergent_amplitude_is_the_thin_ship_fields() {
    let waves = KelvinWaves::new(ship(8.0));
    let x = 3000.0;
    let (h, n) = (0.125, 1 << 16);
    // the divergent wavenumber on the 8 deg ray, and the transverse one at 19 deg, far below
    let k0 = waves.ship.kelvin_wavenumber();
    let split = 0.3 * k0 * 3.0;
    let divergent = move |_: f64, qy: f64| Complex64::new(step(qy.abs(), split, 2.0 * split), 0.0);
    let quadrature = move |_: f64, qy: f64| Complex64::new(0.0, -qy.signum() * step(qy.abs(), split, 2.0 * split));
    let fields = waves.track_fields(&[x], n, h, 0.8 * PI / h, &[&divergent, &quadrature]);
    let (field, hilbert) = (fields.field(0), fields.field(1));
    let (mut energy, mut theory, mut count) = (0.0, 0.0, 0);
    for j in n / 2..n {
        let y = (j as f64 - n as f64 / 2.0) * h;
        let angle = (y / x).atan().to_degrees();
        if !(3.0..=8.0).contains(&angle) {
            continue;
        }
        let (f, q) = (field[[0, j]] as f64, hilbert[[0, j]] as f64);
        energy += f * f + q * q;
        theory += divergent_ray(&waves, x, y)
            .unwrap()
            .linear_amplitude(&waves, x, 0.0)
            .powi(2);
        count += 1;
    }
    let ratio = energy / theory;
    eprintln!("divergent energy / stationary phase = {ratio:.4} over {count} points");
    assert!((ratio - 1.0).abs() < 0.10, "ratio {ratio}");
}

/// The half-angle of the brightest ray of each band's narrow-V, looking across the track
/// (30 deg incidence, 300 m behind the stern, sea water's viscosity, a 10 % spread), against
/// sqrt(g lambda_B / (8 pi)) / U for S, C and X band at 6 and 12 m/s: within 20 %.
#[test]
fn the_half_angle_follows_the_bragg_wavelength_and_the_ship_speed() {
    let x = 300.0;
    let mut worst: f64 = 0.0;
    for speed in [6.0, 12.0] {
        let waves = KelvinWaves::new(ship(speed));
        for band in RadarBand::ALL {
            let kb = band.bragg_wavenumber(30.0);
            let bragg = (0.0, kb);
            // the brightest point across the track, on 0.01 m steps out to 10 deg
            let (mut best, mut best_y) = (0.0, 0.0);
            let steps = (x * 10f64.to_radians().tan() / 0.01) as usize;
            for i in 1..steps {
                let y = i as f64 * 0.01;
                let d = divergent_ray(&waves, x, y).map_or(0.0, |r| {
                    0.5 * r.amplitude(&waves, x, VISCOSITY).powi(2) * r.bragg_weight(bragg, 0.1 * kb)
                });
                if d > best {
                    (best, best_y) = (d, y);
                }
            }
            let angle = (best_y / x).atan();
            let lambda = 2.0 * PI / kb;
            let published = (GRAVITY * lambda / (8.0 * PI)).sqrt() / speed;
            let error = angle / published - 1.0;
            eprintln!(
                "{} band, U = {speed} m/s: half-angle {:.3} deg vs {:.3} deg published ({:+.1} %)",
                band.name(),
                angle.to_degrees(),
                published.to_degrees(),
                100.0 * error
            );
            worst = worst.max(error.abs());
        }
    }
    assert!(worst < 0.20, "worst error {worst}");
}

//! The Kelvin wave pattern against thin-ship theory's outside numbers: Kelvin's cusp angle
//! asin(1/3), the transverse wavelength 2 pi U^2 / g, the cusp amplitude's x^(-1/3) decay and the
//! Michell wave resistance of Wigley's hull as published.

use rustfft::num_complex::Complex64;
use std::f64::consts::PI;
use wakelab_core::config::HullForm;
use wakelab_surface::kelvin::{KelvinWaves, ThinShip};

/// Wigley's standard hull (L/B = 10, L/T = 16) at Froude number `froude`.
fn wigley(length: f64, froude: f64) -> KelvinWaves {
    KelvinWaves::new(ThinShip {
        form: HullForm::Wigley,
        length,
        beam: length / 10.0,
        draft: length / 16.0,
        speed: froude * (9.81 * length).sqrt(),
        gravity: 9.81,
    })
}

/// The elevation's envelope (|analytic signal|) on the row `x` behind the stern, on 1-m points
/// across the track, port side: (y, envelope).
fn envelope(waves: &KelvinWaves, x: f64) -> Vec<(f64, f64)> {
    let h = 1.0;
    let n = ((0.9 * x / h) as usize).next_power_of_two().max(1024);
    let elevation = |_: f64, _: f64| Complex64::new(1.0, 0.0);
    // the quadrature field: every wave's phase advanced by a quarter period
    let quadrature = |qx: f64, _: f64| Complex64::new(0.0, qx.signum());
    let t = waves.track_fields(&[x], n, h, PI / h, &[&elevation, &quadrature]);
    let f = [t.field(0), t.field(1)];
    (n / 2..n)
        .map(|j| ((j - n / 2) as f64 * h, (f[0][[0, j]] as f64).hypot(f[1][[0, j]] as f64)))
        .collect()
}

/// Where (y) the envelope peaks on row x, and its value there.
fn cusp(waves: &KelvinWaves, x: f64) -> (f64, f64) {
    envelope(waves, x)
        .into_iter()
        .fold((0.0, 0.0), |best, (y, e)| if e > best.1 { (y, e) } else { best })
}

/// Michell's wave resistance of Wigley's hull at Fr = 0.35 is 10^3 C_w = 1.2486 (Doctors & Beck
/// 1987, J. Ship Res. 31(1), Table 1), on the wetted area of the hull's two sides; the amplitudes
/// the wave field is built from give it (Havelock's energy flux) within 10 %.
#[test]
fn wigley_wave_resistance_is_the_published_michell_value() {
    let waves = wigley(100.0, 0.35);
    let ship = waves.ship;
    // the wetted area, 2 int int sqrt(1 + f_x^2 + f_z^2) dx dz, by the midpoint rule
    let (nx, nz) = (2000, 400);
    let (dx, dz) = (ship.length / nx as f64, ship.draft / nz as f64);
    let mut area = 0.0;
    for i in 0..nx {
        for j in 0..nz {
            let (x, z) = (-ship.length + (i as f64 + 0.5) * dx, -(j as f64 + 0.5) * dz);
            let fx = (ship.half_breadth(x + 1e-4, z) - ship.half_breadth(x - 1e-4, z)) / 2e-4;
            let fz = (ship.half_breadth(x, z + 1e-4) - ship.half_breadth(x, z - 1e-4)) / 2e-4;
            area += 2.0 * (1.0 + fx * fx + fz * fz).sqrt() * dx * dz;
        }
    }
    let rho = 1000.0;
    let cw = waves.wave_resistance(rho) / (0.5 * rho * ship.speed.powi(2) * area);
    eprintln!("10^3 Cw = {:.4} (published 1.2486)", 1e3 * cw);
    assert!((1e3 * cw / 1.2486 - 1.0).abs() < 0.1, "10^3 Cw = {}", 1e3 * cw);
}

/// At low Froude number the envelope's crest lies on Kelvin's cusp line, asin(1/3) = 19.47
/// degrees off the track, within 1 degree.
#[test]
fn cusp_lines_lie_at_the_kelvin_angle() {
    let waves = wigley(100.0, 0.2);
    for x in [3000.0, 10_000.0] {
        let (y, _) = cusp(&waves, x);
        let angle = (y / x).atan().to_degrees();
        let kelvin = (1.0f64 / 3.0).asin().to_degrees();
        eprintln!("cusp at x = {x} m: {angle:.2} degrees");
        assert!((angle - kelvin).abs() < 1.0, "x = {x}: {angle:.2} degrees");
    }
}

/// On the track the transverse waves' wavelength is 2 pi U^2 / g within 2 %: measured between
/// the first and last upward zero crossings of 8 waves.
#[test]
fn transverse_wavelength_is_two_pi_u_squared_over_g() {
    let waves = wigley(100.0, 0.2);
    let u = waves.ship.speed;
    let want = 2.0 * PI * u * u / 9.81;
    let n = 8192;
    let rows: Vec<f64> = (0..(9.0 * want / 0.25) as usize)
        .map(|i| 2000.0 + 0.25 * i as f64)
        .collect();
    let elevation = |_: f64, _: f64| Complex64::new(1.0, 0.0);
    let f = waves.track_fields(&rows, n, 1.0, PI, &[&elevation]).field(0);
    let centre = f.column(n / 2);
    let up: Vec<f64> = (1..rows.len())
        .filter(|&i| centre[i - 1] < 0.0 && centre[i] >= 0.0)
        .map(|i| {
            let t = (centre[i - 1] / (centre[i - 1] - centre[i])) as f64;
            rows[i - 1] + t * 0.25
        })
        .collect();
    assert!(up.len() >= 8, "{} crossings", up.len());
    let measured = (up[up.len() - 1] - up[0]) / (up.len() - 1) as f64;
    eprintln!("transverse wavelength {measured:.3} m vs 2 pi U^2 / g = {want:.3} m");
    assert!((measured / want - 1.0).abs() < 0.02, "{measured} m vs {want} m");
}

/// The cusp's amplitude decays as x^(-1/3) (stationary phase at coalescing points): over the
/// decade 1-10 km the fitted exponent is -1/3 within 10 %, where the hull's amplitude function is
/// smooth over the cusp's Airy width (Fr = 0.5; at lower Froude numbers the bow and stern waves'
/// interference still varies across that width at 10 km).
#[test]
fn cusp_amplitude_decays_as_x_to_the_minus_one_third() {
    let waves = wigley(100.0, 0.5);
    let xs: [f64; 4] = [1000.0, 2000.0, 5000.0, 10_000.0];
    let points: Vec<(f64, f64)> = xs.iter().map(|&x| (x.ln(), cusp(&waves, x).1.ln())).collect();
    let n = points.len() as f64;
    let (mx, my) = (
        points.iter().map(|p| p.0).sum::<f64>() / n,
        points.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let slope = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum::<f64>()
        / points.iter().map(|p| (p.0 - mx).powi(2)).sum::<f64>();
    eprintln!("cusp decay exponent {slope:.4}");
    assert!((slope / (-1.0 / 3.0) - 1.0).abs() < 0.1, "exponent {slope:.3}");
}

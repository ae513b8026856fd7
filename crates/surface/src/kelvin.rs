//! The ship's Kelvin wave pattern by linear thin-ship theory (Michell 1898), in deep water.
//!
//! The spec models the turbulent wake only (spec 2.1); real SAR images of moving ships also show
//! the Kelvin arms. wakelab follows the Fourier form of the thin-ship problem (as in Zilman,
//! Zapolski & Marom 2004): the hull y = +-f(x, z) is replaced by sources of density
//! sigma = 2 U df/dx on its centre plane, in a uniform stream U along +x (the track frame: x
//! behind the stern, y to port, z up; the hull spans -L <= x <= 0, -T <= z <= 0). Linearised,
//! with Rayleigh's radiation condition, a source of volume flux m at depth d raises the surface
//!   zeta^(q) = i U q_x m e^{-|q| d} / (g |q| - U^2 q_x^2 + i mu U q_x),   mu -> 0+,
//! (2D transform e^{-i q.x}). Behind the hull (x > 0) the q_x integral closes on the two poles
//! q_x = +-K(q_y) of the steady dispersion relation U^2 K^2 = g |q|, leaving the free waves
//!   zeta(x, y) = (1 / 2 pi) int dq_y e^{i q_y y} [Z(q_y) e^{i K x} + c.c.],
//!   Z(q_y) = M(K, |q|) / (U (1 + sin^2 theta)),  sin theta = q_y / |q|,
//! with M(q_x, kappa) = int int sigma e^{kappa z} e^{-i q_x x} dx dz the source transform.
//! The local (non-wave) disturbance beside the hull is left out. For each row x the q_y integral
//! is one inverse FFT across the track, so the field costs a transform per row and never wraps
//! along the track; across it the transform covers the whole Kelvin wedge.
//!
//! The same amplitudes give Havelock's wave resistance R = (pi rho U^2 / 2) int |A|^2 cos^3
//! theta d theta, here R = (rho g / 2 pi) int |Z|^2 (1 + sin^2 theta) dq_y, which is Michell's
//! integral (tested against the published Wigley hull value).

use crate::fourier::signed_frequency;
use ndarray::Array2;
use rayon::prelude::*;
use rustfft::num_complex::Complex64;
use rustfft::FftPlanner;
use std::f64::consts::PI;
use wakelab_core::config::{HullForm, ShipConfig};

/// A thin ship: its hull's form and main dimensions, and its speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThinShip {
    pub form: HullForm,
    pub length: f64,
    pub beam: f64,
    pub draft: f64,
    pub speed: f64,
    pub gravity: f64,
}

impl ThinShip {
    pub fn new(ship: &ShipConfig, form: HullForm, gravity: f64) -> Self {
        Self {
            form,
            length: ship.length,
            beam: ship.beam,
            draft: ship.draft,
            speed: ship.speed,
            gravity,
        }
    }

    /// The Kelvin wavenumber k0 = g / U^2 (rad/m): the transverse waves' wavenumber.
    pub fn kelvin_wavenumber(&self) -> f64 {
        self.gravity / (self.speed * self.speed)
    }

    /// Froude number U / sqrt(g L).
    pub fn froude_number(&self) -> f64 {
        self.speed / (self.gravity * self.length).sqrt()
    }

    /// Half-breadth f(x, z) of the hull at x behind the stern (-L..0) and z up (-T..0); 0 outside.
    pub fn half_breadth(&self, x: f64, z: f64) -> f64 {
        let (xi, zeta) = (self.station(x), z / self.draft);
        if xi.abs() > 1.0 || !(-1.0..=0.0).contains(&zeta) {
            return 0.0;
        }
        match self.form {
            HullForm::Wigley => 0.5 * self.beam * (1.0 - xi * xi) * (1.0 - zeta * zeta),
        }
    }

    /// Position along the hull, -1 at the bow (x = -L) to 1 at the stern (x = 0).
    fn station(&self, x: f64) -> f64 {
        (2.0 * x + self.length) / self.length
    }

    /// Displaced volume (m^3): 4/9 L B T for Wigley's hull.
    pub fn displacement_volume(&self) -> f64 {
        match self.form {
            HullForm::Wigley => 4.0 / 9.0 * self.length * self.beam * self.draft,
        }
    }

    /// Area of the waterplane (m^2): 2/3 L B for Wigley's hull.
    pub fn waterplane_area(&self) -> f64 {
        match self.form {
            HullForm::Wigley => 2.0 / 3.0 * self.length * self.beam,
        }
    }

    /// The source transform M(q_x, kappa) = int int 2 U f_x e^{kappa z} e^{-i q_x x} dx dz over
    /// the centre plane. For Wigley's hull f_x = -(2 B xi / L)(1 - z^2/T^2) and both integrals
    /// close: int xi e^{-i q_x x} dx = -i L e^{i q_x L/2} j1(q_x L/2) (j1 the spherical Bessel
    /// function) and int (1 - z^2/T^2) e^{kappa z} dz = T D(kappa T), see [`depth_factor`].
    pub fn source_transform(&self, qx: f64, kappa: f64) -> Complex64 {
        match self.form {
            HullForm::Wigley => {
                let half = 0.5 * self.length;
                let along = Complex64::from_polar(1.0, qx * half) * spherical_j1(qx * half);
                Complex64::new(0.0, 4.0 * self.speed * self.beam)
                    * self.draft
                    * depth_factor(kappa * self.draft)
                    * along
            }
        }
    }
}

/// D(s) = int_{-1}^{0} (1 - t^2) e^{s t} dt: by its series sum_n (-s)^n / n! 2 / ((n+1)(n+3))
/// below s = 4, where the closed form (1/s)(1 - 2/s^2 + 2 e^{-s}(1/s + 1/s^2)) cancels.
pub fn depth_factor(s: f64) -> f64 {
    if s < 4.0 {
        let mut term = 1.0; // (-s)^n / n!
        let mut sum = 0.0;
        for n in 0..40 {
            let nf = n as f64;
            sum += term * 2.0 / ((nf + 1.0) * (nf + 3.0));
            term *= -s / (nf + 1.0);
        }
        sum
    } else {
        (1.0 - 2.0 / (s * s) + 2.0 * (-s).exp() * (1.0 / s + 1.0 / (s * s))) / s
    }
}

/// The spherical Bessel function j1(a) = sin a / a^2 - cos a / a (its series near 0).
pub fn spherical_j1(a: f64) -> f64 {
    if a.abs() < 1e-2 {
        let a2 = a * a;
        a / 3.0 * (1.0 - a2 / 10.0 + a2 * a2 / 280.0)
    } else {
        (a.sin() / a - a.cos()) / a
    }
}

/// A linear operator on the wave field, by its multiplier m(q_x, q_y) of the elevation's
/// transform at wave vector q (track frame); m(-q) must be conj(m(q)) for a real field.
pub type Multiplier<'a> = &'a (dyn Fn(f64, f64) -> Complex64 + Sync);

/// The free Kelvin waves of a thin ship (module doc).
#[derive(Debug, Clone, Copy)]
pub struct KelvinWaves {
    pub ship: ThinShip,
}

impl KelvinWaves {
    pub fn new(ship: ThinShip) -> Self {
        Self { ship }
    }

    /// The along-track wavenumber K of the steady wave of cross-track wavenumber q_y:
    /// U^2 K^2 = g sqrt(K^2 + q_y^2), K^2 = (k0^2 / 2)(1 + sqrt(1 + 4 q_y^2 / k0^2)).
    pub fn along_track_wavenumber(&self, qy: f64) -> f64 {
        let k0 = self.ship.kelvin_wavenumber();
        (0.5 * k0 * k0 * (1.0 + (1.0 + 4.0 * (qy / k0).powi(2)).sqrt())).sqrt()
    }

    /// The wave of cross-track wavenumber q_y: (K, |q|, Z) of the module doc.
    pub fn wave(&self, qy: f64) -> (f64, f64, Complex64) {
        let k0 = self.ship.kelvin_wavenumber();
        let kx = self.along_track_wavenumber(qy);
        let kappa = kx * kx / k0;
        let sin2 = (qy / kappa).powi(2);
        let z = self.ship.source_transform(kx, kappa) / (self.ship.speed * (1.0 + sin2));
        (kx, kappa, z)
    }

    /// Havelock's wave resistance (N) in water of density `density`: (rho g / 2 pi) int |Z|^2
    /// (1 + sin^2 theta) dq_y, integrated over theta (q_y = k0 sec^2 theta sin theta) by the
    /// midpoint rule in t = tan(theta) / (1 + |tan(theta)|), which spreads the oscillating
    /// amplitude evenly.
    pub fn wave_resistance(&self, density: f64) -> f64 {
        let k0 = self.ship.kelvin_wavenumber();
        let n = 400_000;
        let mut sum = 0.0;
        for i in 0..n {
            let t = (i as f64 + 0.5) / n as f64; // theta in [0, pi/2): tan = t / (1 - t)
            let tan = t / (1.0 - t);
            let dtan_dt = 1.0 / (1.0 - t).powi(2);
            let sec2 = 1.0 + tan * tan;
            let qy = k0 * sec2 * tan / sec2.sqrt();
            // dq_y / d tan = k0 (1 + sin^2) / cos^3 * cos^2 = k0 (1 + 2 tan^2) / sqrt(1 + tan^2)
            let dqy = k0 * (1.0 + 2.0 * tan * tan) / sec2.sqrt() * dtan_dt / n as f64;
            let (_, kappa, z) = self.wave(qy);
            sum += z.norm_sqr() * (1.0 + (qy / kappa).powi(2)) * dqy;
        }
        // both signs of q_y
        2.0 * density * self.ship.gravity / (2.0 * PI) * sum
    }

    /// Real fields on a track-frame grid: rows at `rows` (m behind the stern), `columns`
    /// points `spacing` apart centred on the track (y_j = (j - columns/2) spacing); field i is
    /// `operators[i]` applied to the elevation. Waves with |q| above `cutoff` (rad/m) are left
    /// out, by a cos^2 taper from 0.6 `cutoff`, so that the grid (and any interpolation from it)
    /// resolves what remains. Rows in parallel, in blocks that step each wave's phase e^{i K x}
    /// from row to row; one inverse FFT per two fields.
    pub fn track_fields(
        &self,
        rows: &[f64],
        columns: usize,
        spacing: f64,
        cutoff: f64,
        operators: &[Multiplier],
    ) -> TrackFields {
        let n = columns;
        let dq = 2.0 * PI / (n as f64 * spacing);
        // the columns of the spectrum the taper keeps: index, K, the amplitude tapered and
        // turned by the phase of y_0 = -n/2 h, and each operator's multipliers at (+-K, q_y)
        let active: Vec<ActiveWave> = (0..n)
            .filter_map(|j| {
                let m = signed_frequency(j, n);
                let qy = m * dq;
                let (kx, kappa, z) = self.wave(qy);
                let taper = cutoff_taper(kappa, cutoff);
                (taper > 0.0).then(|| {
                    let sign = if (m as i64).rem_euclid(2) == 0 { 1.0 } else { -1.0 };
                    let ops = operators.iter().map(|op| (op(kx, qy), op(-kx, qy))).collect();
                    ActiveWave {
                        column: j,
                        kx,
                        amplitude: z * taper * sign,
                        multipliers: ops,
                    }
                })
            })
            .collect();
        let fields = operators.len();
        assert!(fields <= FIELDS, "at most {FIELDS} fields");
        let transforms = fields.div_ceil(2);
        let fft = FftPlanner::new().plan_fft_inverse(n);
        let scale = 1.0 / (n as f64 * spacing);
        let mut values = vec![[0f32; FIELDS]; rows.len() * n];
        let block = 16;
        values
            .par_chunks_mut(block * n)
            .zip(rows.par_chunks(block))
            .for_each(|(out, xs)| {
                let zero = Complex64::new(0.0, 0.0);
                let mut buffer = vec![zero; n * transforms];
                let mut scratch = vec![zero; fft.get_inplace_scratch_len()];
                // each wave's e^{i K x} at the block's first row, and its step to the next
                let mut phase: Vec<Complex64> = active
                    .iter()
                    .map(|w| Complex64::from_polar(1.0, w.kx * xs[0]))
                    .collect();
                for (r, &x) in xs.iter().enumerate() {
                    if r > 0 {
                        let dx = x - xs[r - 1];
                        for (p, w) in phase.iter_mut().zip(&active) {
                            *p *= Complex64::from_polar(1.0, w.kx * dx);
                        }
                    }
                    buffer.fill(zero);
                    for (wave, p) in active.iter().zip(&phase) {
                        let (j, ops) = (wave.column, &wave.multipliers);
                        let forward = wave.amplitude * p;
                        // the s = -1 pole's term conj(Z) e^{-i K x}
                        let backward = forward.conj();
                        for (f, (plus, minus)) in ops.iter().enumerate() {
                            let v = plus * forward + minus * backward;
                            buffer[(f / 2) * n + j] += if f % 2 == 0 { v } else { Complex64::new(-v.im, v.re) };
                        }
                    }
                    fft.process_with_scratch(&mut buffer, &mut scratch);
                    let row = &mut out[r * n..(r + 1) * n];
                    for (c, node) in row.iter_mut().enumerate() {
                        for (f, v) in node.iter_mut().enumerate().take(fields) {
                            let z = buffer[(f / 2) * n + c];
                            *v = ((if f % 2 == 0 { z.re } else { z.im }) * scale) as f32;
                        }
                    }
                }
            });
        TrackFields {
            rows: rows.len(),
            columns: n,
            fields,
            values,
        }
    }
}

/// One column of the cross-track spectrum that the taper keeps: its index, K, the amplitude
/// (tapered, turned by the phase of the first column), and each operator's multipliers at
/// (+K, q_y) and (-K, q_y).
struct ActiveWave {
    column: usize,
    kx: f64,
    amplitude: Complex64,
    multipliers: Vec<(Complex64, Complex64)>,
}

/// The most fields [`KelvinWaves::track_fields`] computes at once.
pub const FIELDS: usize = 8;

/// Fields on a track-frame grid, interleaved: field f at (row r, column c) is
/// `values[r * columns + c][f]`, so that an interpolation reads every field of a node at once.
#[derive(Debug, Clone)]
pub struct TrackFields {
    pub rows: usize,
    pub columns: usize,
    pub fields: usize,
    pub values: Vec<[f32; FIELDS]>,
}

impl TrackFields {
    /// One field as a (rows, columns) array.
    pub fn field(&self, f: usize) -> Array2<f32> {
        Array2::from_shape_fn((self.rows, self.columns), |(r, c)| self.values[r * self.columns + c][f])
    }
}

/// 1 below 0.6 `cutoff`, falling as cos^2 to 0 at `cutoff`.
fn cutoff_taper(kappa: f64, cutoff: f64) -> f64 {
    let start = 0.6 * cutoff;
    if kappa <= start {
        1.0
    } else if kappa >= cutoff {
        0.0
    } else {
        (0.5 * PI * (kappa - start) / (cutoff - start)).cos().powi(2)
    }
}

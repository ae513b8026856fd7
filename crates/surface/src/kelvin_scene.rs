//! The Kelvin waves on a scene ([`crate::kelvin`]): elevation and slopes for the radar's tilt and
//! the infrared facets, the line-of-sight orbital velocity for velocity bunching, each band's
//! hydrodynamic modulation of its Bragg waves, the Kelvin-arm mask and the hull's footprint.
//!
//! The fields are computed on a track-frame grid of the scene's pixel spacing that covers the
//! scene's footprint (rows) and the whole Kelvin wedge (columns), then interpolated to the pixels
//! by Keys' cubic convolution. Waves shorter than 2.5 pixels are left out (a cos^2 taper from
//! 4 pixels), which the interpolation could not carry. Ahead of the stern the field is zero: the
//! waves beside the hull are not modelled.
//!
//! Hydrodynamic modulation: the Kelvin currents strain the Bragg waves through the same
//! relaxation balance as the turbulent wake ([`crate::action`], the relaxation form of Eq.
//! (2.67)), linearised: with r = 1 + delta, (mu + d/dt) delta = R, R = (d ln N0 / dk_j) k_i
//! dU_i/dx_j, d/dt = (U + c_g) . grad in the ship's frame. For a steady component e^{i q.x} this
//! is the relaxation MTF of Alpers, Ross & Rufenach (1981), delta = i (g.q)(k.m) zeta /
//! (mu + i q.(U + c_g)), with m the orbital velocity per unit elevation. Towards and away Bragg
//! waves are weighted by their background densities, as the wake's modulation is.

use crate::action::Relaxation;
use crate::kelvin::{KelvinWaves, Multiplier, ThinShip, TrackFields, FIELDS};
use crate::narrow_v::{divergent_ray, BREAKING_STEEPNESS, SPREAD_END};
use crate::scene::SceneGrid;
use ndarray::Array2;
use rayon::prelude::*;
use rustfft::num_complex::Complex64;
use std::f64::consts::PI;
use wakelab_core::units::RadarBand;

/// The narrow-V's nu below which a pixel's is left at 0 (0.0004 dB).
pub const NARROW_V_FLOOR: f64 = 1e-4;

/// Threshold of the Kelvin waves' local rms slope for the Kelvin-arm mask.
pub const MASK_KELVIN_SLOPE: f64 = 0.01;

/// One band's Bragg waves as the hydrodynamic modulation needs them: both Bragg wave vectors'
/// relaxation and their background spectral densities.
#[derive(Debug, Clone, Copy)]
pub struct BraggWaves {
    pub band: RadarBand,
    pub towards: Relaxation,
    pub away: Relaxation,
    /// Background spectral densities (towards, away), m^4.
    pub density: (f64, f64),
    /// Spread (rad/m) of the Kelvin pattern's own Bragg waves' spectrum ([`crate::narrow_v`]):
    /// k_B times the rms slope of the longer waves.
    pub spread: f64,
}

/// The radar's view: incidence and horizontal look direction (heading frame, radians).
#[derive(Debug, Clone, Copy)]
pub struct RadarView {
    pub incidence: f64,
    pub look: f64,
}

/// The Kelvin waves and the hull on a scene.
#[derive(Debug, Clone)]
pub struct KelvinScene {
    /// Elevation of the Kelvin waves alone (m); the scene's surface holds it added to the sea's.
    pub elevation: Array2<f64>,
    /// Their slopes (east, north), which the scene's surface also holds added.
    pub slope_x: Array2<f64>,
    pub slope_y: Array2<f64>,
    /// Line-of-sight orbital velocity (m/s, away from the radar).
    pub line_of_sight_velocity: Array2<f64>,
    /// Relative change delta of each band's Bragg spectral density (N/N0 = 1 + delta).
    pub bragg_change: Vec<(RadarBand, Array2<f64>)>,
    /// The narrow-V: each band's Bragg spectral density added by the Kelvin pattern's own
    /// short waves, relative to the background's (N/N0 = 1 + delta + nu; [`crate::narrow_v`]).
    pub narrow_v: Vec<(RadarBand, Array2<f64>)>,
    /// 1 where the Kelvin waves' rms slope over a transverse wavelength exceeds
    /// [`MASK_KELVIN_SLOPE`].
    pub mask: Array2<u8>,
    /// Fraction of each pixel under the hull's waterplane; None when the ship is not in the scene.
    pub hull_cover: Option<Array2<f64>>,
}

/// A heading-frame vector (forward, port) in the track frame (behind, port).
fn to_track((x, y): (f64, f64)) -> (f64, f64) {
    (-x, y)
}

/// The Kelvin waves of `ship` on `grid`, seen by a radar `view`, with each band's Bragg waves.
/// `viscosity` (m^2/s) damps the short waves of the narrow-V.
pub fn kelvin_scene(
    ship: ThinShip,
    grid: &SceneGrid,
    view: RadarView,
    bands: &[BraggWaves],
    viscosity: f64,
) -> KelvinScene {
    let waves = KelvinWaves::new(ship);
    let (g, u) = (ship.gravity, ship.speed);
    let h = grid.pixel_spacing;
    let n = grid.size();
    // the scene's footprint in the track frame
    let corners: Vec<(f64, f64)> = [(0, 0), (0, n - 1), (n - 1, 0), (n - 1, n - 1)]
        .iter()
        .map(|&(r, c)| grid.track_position(r, c))
        .collect();
    let (x_lo, x_hi) = corners
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.0), b.max(p.0)));
    let y_reach = corners.iter().fold(0.0f64, |m, p| m.max(p.1.abs()));
    let x_first = x_lo.max(0.0) - 2.0 * h;
    let rows: Vec<f64> = (0..(((x_hi - x_first) / h).ceil() as usize + 4))
        .map(|i| x_first + i as f64 * h)
        .collect();
    // across the track: the scene and the whole wedge (with its Airy fringe), which must not wrap
    let wedge = 0.4 * x_hi.max(0.0) + ship.length + 20.0 * h;
    let columns = ((2.0 * y_reach.max(wedge) / h) as usize + 8).next_power_of_two();
    let cutoff = 0.8 * PI / h;
    let look = to_track((view.look.cos(), view.look.sin()));
    let (st, ct) = view.incidence.sin_cos();
    let elevation = |_: f64, _: f64| Complex64::new(1.0, 0.0);
    let slope_along = |qx: f64, _: f64| Complex64::new(0.0, qx);
    let slope_across = |_: f64, qy: f64| Complex64::new(0.0, qy);
    let line_of_sight = |qx: f64, qy: f64| {
        let [mx, my, mw] = orbital_velocity(qx, qy, u, g);
        (mx * look.0 + my * look.1) * st - mw * ct
    };
    let modulations: Vec<_> = bands
        .iter()
        .map(|b| {
            let (ft, fa) = b.density;
            move |qx: f64, qy: f64| {
                (ft * bragg_straining(qx, qy, &b.towards, u, g) + fa * bragg_straining(qx, qy, &b.away, u, g))
                    / (ft + fa)
            }
        })
        .collect();
    let mut operators: Vec<Multiplier> = vec![&elevation, &slope_along, &slope_across, &line_of_sight];
    for m in &modulations {
        operators.push(m);
    }
    let track = waves.track_fields(&rows, columns, h, cutoff, &operators);
    let mut fields = interpolate(grid, &track, rows[0], h);

    let bragg_change: Vec<(RadarBand, Array2<f64>)> = bands.iter().map(|b| b.band).zip(fields.drain(4..)).collect();
    let [elevation, along, across, line_of_sight]: [Array2<f64>; 4] = fields.try_into().expect("four fields");
    // slopes from the track frame (behind, port) to the image's (east, north)
    let mut slope_x = Array2::zeros((n, n));
    let mut slope_y = Array2::zeros((n, n));
    ndarray::Zip::from(&mut slope_x)
        .and(&mut slope_y)
        .and(&along)
        .and(&across)
        .par_for_each(|sx, sy, &a, &c| (*sx, *sy) = grid.scene_frame(-a, c));
    let wavelength = 2.0 * PI / ship.kelvin_wavenumber();
    let mask = slope_mask(&slope_x, &slope_y, (0.5 * wavelength / h).round().max(1.0) as usize);
    KelvinScene {
        elevation,
        slope_x,
        slope_y,
        line_of_sight_velocity: line_of_sight,
        bragg_change,
        narrow_v: narrow_v(&waves, grid, bands, viscosity),
        mask,
        hull_cover: hull_cover(&ship, grid),
    }
}

/// Each band's narrow-V, nu = (F(k_B) + F(-k_B)) of the divergent waves over the background's.
/// The amplitude, the costly part, is worked out only where some band's nu could reach
/// [`NARROW_V_FLOOR`] at the breaking cap, within 6 standard deviations of the spread.
fn narrow_v(
    waves: &KelvinWaves,
    grid: &SceneGrid,
    bands: &[BraggWaves],
    viscosity: f64,
) -> Vec<(RadarBand, Array2<f64>)> {
    let n = grid.size();
    let braggs: Vec<((f64, f64), f64, f64)> = bands
        .iter()
        .map(|b| {
            (
                to_track((b.towards.k.kx, b.towards.k.ky)),
                b.spread,
                b.density.0 + b.density.1,
            )
        })
        .collect();
    let mut nu = vec![0.0; n * n * bands.len()];
    nu.par_chunks_mut(bands.len()).enumerate().for_each(|(i, out)| {
        let (x, y) = grid.track_position(i / n, i % n);
        let Some(ray) = divergent_ray(waves, x, y) else { return };
        let cap = 0.5 * (BREAKING_STEEPNESS / ray.wavenumber).powi(2);
        let mut amplitude = None;
        for (v, &(bragg, spread, background)) in out.iter_mut().zip(&braggs) {
            // |k_B -+ k| >= ||k_B| - |k||: the weight is at most 2 G(|k_B| - |k|)
            let miss = (bragg.0.hypot(bragg.1) - ray.wavenumber) / spread;
            let exponent = 0.5 * miss * miss;
            if exponent > SPREAD_END || exponent > (cap / (PI * spread * spread * background * NARROW_V_FLOOR)).ln() {
                continue;
            }
            let weight = ray.bragg_weight(bragg, spread) / background;
            if cap * weight >= NARROW_V_FLOOR {
                let a: f64 = *amplitude.get_or_insert_with(|| ray.amplitude(waves, x, viscosity));
                *v = 0.5 * a * a * weight;
            }
        }
    });
    bands
        .iter()
        .enumerate()
        .map(|(j, b)| {
            let field = Array2::from_shape_fn((n, n), |(r, c)| nu[(r * n + c) * bands.len() + j]);
            (b.band, field)
        })
        .collect()
}

/// Orbital velocity (u_x, u_y, w) at the surface per unit elevation of the steady wave
/// e^{i q.x} (track frame): from zeta = -(U/g) phi_x, u = grad phi = -(g / (U q_x)) q zeta, and
/// w = U zeta_x (the surface is steady in the ship's frame).
pub fn orbital_velocity(qx: f64, qy: f64, speed: f64, gravity: f64) -> [Complex64; 3] {
    let horizontal = -gravity / (speed * qx);
    [
        Complex64::new(horizontal * qx, 0.0),
        Complex64::new(horizontal * qy, 0.0),
        Complex64::new(0.0, speed * qx),
    ]
}

/// delta per unit elevation for the steady wave e^{i q.x} (track frame) of a ship of `speed`:
/// i (g.q)(k.m) / (mu + i q.(U + c_g)) (module doc), with k, g = d ln N0 / dk, c_g and mu those
/// of `bragg` (heading frame).
pub fn bragg_straining(qx: f64, qy: f64, bragg: &Relaxation, speed: f64, gravity: f64) -> Complex64 {
    let [mx, my, _] = orbital_velocity(qx, qy, speed, gravity);
    let k = to_track((bragg.k.kx, bragg.k.ky));
    let grad = to_track(bragg.dln_action_dk);
    let cg = to_track(bragg.group_velocity);
    let advection = qx * (speed + cg.0) + qy * cg.1;
    Complex64::new(0.0, grad.0 * qx + grad.1 * qy) * (mx * k.0 + my * k.1) / Complex64::new(bragg.rate, advection)
}

/// Keys' cubic convolution weights (a = -1/2) of the four nodes around fraction t.
fn keys(t: f64) -> [f64; 4] {
    let (t2, t3) = (t * t, t * t * t);
    [
        -0.5 * t3 + t2 - 0.5 * t,
        1.5 * t3 - 2.5 * t2 + 1.0,
        -1.5 * t3 + 2.0 * t2 + 0.5 * t,
        0.5 * t3 - 0.5 * t2,
    ]
}

/// Every track field at every pixel, by cubic convolution; 0 ahead of the stern and off the grid.
fn interpolate(grid: &SceneGrid, track: &TrackFields, x0: f64, h: f64) -> Vec<Array2<f64>> {
    let n = grid.size();
    let (rows, cols, fields) = (track.rows, track.columns, track.fields);
    // per scene row, its fields one after another
    let lines: Vec<Vec<f64>> = (0..n)
        .into_par_iter()
        .map(|r| {
            let mut line = vec![0.0; n * fields];
            for c in 0..n {
                let (x, y) = grid.track_position(r, c);
                if x < 0.0 {
                    continue;
                }
                let (fr, fc) = ((x - x0) / h, y / h + (cols / 2) as f64);
                let (i, j) = (fr.floor() as isize - 1, fc.floor() as isize - 1);
                if i < 0 || j < 0 || i as usize + 4 > rows || j as usize + 4 > cols {
                    continue;
                }
                let (wr, wc) = (keys(fr - fr.floor()), keys(fc - fc.floor()));
                let mut sum = [0f32; FIELDS];
                for (a, wa) in wr.iter().enumerate() {
                    let start = (i as usize + a) * cols + j as usize;
                    for (node, wb) in track.values[start..start + 4].iter().zip(&wc) {
                        let w = (wa * wb) as f32;
                        for (s, v) in sum.iter_mut().zip(node) {
                            *s += w * v;
                        }
                    }
                }
                for (f, s) in sum.iter().take(fields).enumerate() {
                    line[f * n + c] = *s as f64;
                }
            }
            line
        })
        .collect();
    (0..fields)
        .into_par_iter()
        .map(|f| {
            let mut field = Array2::zeros((n, n));
            for (mut row, line) in field.axis_iter_mut(ndarray::Axis(0)).zip(&lines) {
                row.as_slice_mut()
                    .expect("standard layout")
                    .copy_from_slice(&line[f * n..(f + 1) * n]);
            }
            field
        })
        .collect()
}

/// 1 where the rms slope over a (2 radius + 1)^2 box exceeds [`MASK_KELVIN_SLOPE`].
fn slope_mask(sx: &Array2<f64>, sy: &Array2<f64>, radius: usize) -> Array2<u8> {
    let squared = ndarray::Zip::from(sx).and(sy).par_map_collect(|a, b| a * a + b * b);
    box_mean(&squared, radius).mapv(|m| u8::from(m.sqrt() > MASK_KELVIN_SLOPE))
}

/// Mean over the (2 radius + 1)^2 box around each point (fewer points at the edges): along the
/// rows by prefix sums, rows in parallel, then across them by a running sum of whole rows.
fn box_mean(a: &Array2<f64>, radius: usize) -> Array2<f64> {
    let (rows, cols) = a.dim();
    let mut along = Array2::zeros((rows, cols));
    along
        .axis_iter_mut(ndarray::Axis(0))
        .into_par_iter()
        .zip(a.axis_iter(ndarray::Axis(0)))
        .for_each(|(mut o, line)| {
            let mut prefix = vec![0.0; cols + 1];
            for (i, v) in line.iter().enumerate() {
                prefix[i + 1] = prefix[i] + v;
            }
            for (c, o) in o.iter_mut().enumerate() {
                let (lo, hi) = (c.saturating_sub(radius), (c + radius + 1).min(cols));
                *o = (prefix[hi] - prefix[lo]) / (hi - lo) as f64;
            }
        });
    let mut prefix = Array2::<f64>::zeros((rows + 1, cols));
    for r in 0..rows {
        let next = &prefix.row(r) + &along.row(r);
        prefix.row_mut(r + 1).assign(&next);
    }
    Array2::from_shape_fn((rows, cols), |(r, c)| {
        let (lo, hi) = (r.saturating_sub(radius), (r + radius + 1).min(rows));
        (prefix[[hi, c]] - prefix[[lo, c]]) / (hi - lo) as f64
    })
}

/// Fraction of each pixel inside the hull's waterline (4 x 4 samples per pixel); None when no
/// pixel is.
pub fn hull_cover(ship: &ThinShip, grid: &SceneGrid) -> Option<Array2<f64>> {
    let n = grid.size();
    // the hull's bounding box in pixels, from its four corners
    let corners = [
        (-ship.length, -ship.beam),
        (-ship.length, ship.beam),
        (0.0, -ship.beam),
        (0.0, ship.beam),
    ];
    let pixels: Vec<(f64, f64)> = corners.iter().map(|&(x, y)| grid.pixel_of(x, 0.5 * y)).collect();
    let (r_lo, r_hi) = pixels
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.0), b.max(p.0)));
    let (c_lo, c_hi) = pixels
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.1), b.max(p.1)));
    let last = n as f64 - 1.0;
    if r_hi < -1.0 || c_hi < -1.0 || r_lo > last + 1.0 || c_lo > last + 1.0 {
        return None;
    }
    let clamp = |v: f64| v.clamp(0.0, last) as usize;
    let mut cover = Array2::zeros((n, n));
    let d = grid.pixel_spacing;
    let samples = 4;
    for r in clamp(r_lo.floor())..=clamp(r_hi.ceil()) {
        for c in clamp(c_lo.floor())..=clamp(c_hi.ceil()) {
            let mut inside = 0;
            for a in 0..samples {
                for b in 0..samples {
                    let east = grid.x[c] + ((b as f64 + 0.5) / samples as f64 - 0.5) * d;
                    let north = grid.y[r] - ((a as f64 + 0.5) / samples as f64 - 0.5) * d;
                    let (forward, port) = grid.heading_frame(east, north);
                    if port.abs() <= ship.half_breadth(-forward, 0.0) {
                        inside += 1;
                    }
                }
            }
            cover[[r, c]] = inside as f64 / (samples * samples) as f64;
        }
    }
    cover.iter().any(|&v| v > 0.0).then_some(cover)
}

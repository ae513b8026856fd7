//! A ship's speed from its Kelvin waves, read where they lie in the image's spectrum.
//!
//! Behind a ship in deep water its waves are steady in the ship's frame: a wave whose crests
//! run at angle theta to the track keeps pace with the ship when its phase speed is U cos theta,
//! so its wavenumber is k = g / (U^2 cos^2 theta) (Lamb 1932, section 256). Every Kelvin wave,
//! transverse (theta near 0: lambda = 2 pi U^2 / g) and divergent, lies on this one curve of the
//! wavenumber plane (the Kelvin wake is their superposition, Havelock 1908), and the curve is
//! set by U alone. So the speed is read as the curve along which the spectrum of the region
//! behind the ship holds most power: the transverse waves, which along the track alone are
//! often too weak to read (docs/results.md), and the divergent waves on the arms, which SAR
//! images show best, are read together.
//!
//! The region's power is taken over its own level (its smoothed spectrum over the median of
//! the bins around it), so that the sea's smooth spectrum and the trough's long wavelengths do
//! not count; and the curve's power is held against the same curve in the sea either side of
//! the wake, outside the Kelvin wedge (half-angle 19.47 degrees): a swell or wind sea on the
//! curve is there too, and a speed is read only where the sea beside the wake has no power on
//! it. A wavelength must span at least two resolution cells: the transverse waves of a ship
//! slower than sqrt(2 g dx / (2 pi)) are not resolved, nor the parts of the curve beyond the
//! image's Nyquist wavenumber.

use crate::radon::Normalised;
use rustfft::{num_complex::Complex, FftPlanner};
use serde::Serialize;

/// A speed and its standard uncertainty (m/s).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Speed {
    pub value: f64,
    pub sigma: f64,
}

/// A Kelvin speed with its transverse wavelength (m), the mean log power of the region behind
/// the ship over its own level along the speed's curve, and the same of the sea beside the wake
/// (the larger side's).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct KelvinReading {
    pub speed: Speed,
    pub wavelength_m: f64,
    pub locus_power: f64,
    pub sides_power: f64,
}

/// The region read behind the ship: from `near` metres behind the apex, `REGION_LENGTH_M` along
/// the track and `REGION_WIDTH_M` across it; the sides' regions are as large, their centre lines
/// `SIDE_OFFSET_M` to either side (at 1 km behind the ship the Kelvin wedge is 354 m wide each
/// way, so a side 650 m off holds none of the ship's waves but the sea of the same place).
const REGION_LENGTH_M: f64 = 1000.0;
const REGION_WIDTH_M: f64 = 500.0;
const SIDE_OFFSET_M: f64 = 650.0;
/// The least share of a region that must lie in the image with data.
const MIN_IN_IMAGE: f64 = 0.7;
/// Spectral bins: the smoothing of the periodogram (3 x 3) and the square whose median is its
/// own level (15 x 15 bins; a bin is 2 pi / 1 km along the track).
const SMOOTH_HALF: isize = 1;
const LEVEL_HALF: isize = 7;
/// The curve's directions (degrees off the track, every degree): past 70 degrees the
/// divergent waves are shorter than any image resolves.
const MAX_THETA_DEG: i32 = 70;
/// The least number of the curve's distinct bins within the Nyquist wavenumber for a speed to
/// be read.
const MIN_POINTS: usize = 20;
/// The least mean log power of the curve behind the ship over the sides' (`MIN_MARGIN`) and the
/// most the sides may hold on it (`MAX_SIDES_POWER`). Chosen on 66 simulated X-band scenes at
/// 2.5 m (30 without swell, 36 with) and their twins without the ship, read with their true
/// stern and course: 9 speeds read, all within 7 % (median error 1.1 %), none in a twin, none
/// under the swell. Held on 48 other scenes: 4 read, within 2.2 % (median 1.1 %), none in a
/// twin or under the swell (docs/results.md).
pub const MIN_MARGIN: f64 = 0.5;
/// The curve's distinct bins for which `MIN_MARGIN` holds (a 9 m/s ship's curve at 2.5 m); a
/// curve of n bins must pass MIN_MARGIN sqrt(REFERENCE_BINS / n), as a mean's noise falls with
/// the square root of its count: on coarser pixels the curve crosses fewer bins (at 10 m 20-50
/// against 60-100 at 2.5 m), and with a fixed margin 8 of 100 speckle images at 10 m read a
/// speed.
const REFERENCE_BINS: f64 = 90.0;
pub const MAX_SIDES_POWER: f64 = 0.3;
/// The speeds tried (m/s): every 0.1 from the slowest whose transverse waves are resolved.
const SPEED_STEP: f64 = 0.1;
const SLOWEST: f64 = 3.0;

/// A region's samples along the track (rows) and across it (columns), NaN where off the
/// image or without data.
fn region(image: &Normalised, apex: (f64, f64), axis_deg: f64, near: f64, lateral: f64, step: f64) -> Vec<Vec<f64>> {
    let g = &image.geometry;
    let (ar, ac) = g.step(axis_deg);
    let (cr, cc) = g.step(axis_deg + 90.0);
    let (ns, nt) = (
        (REGION_LENGTH_M / step).round() as usize,
        (REGION_WIDTH_M / step).round() as usize,
    );
    (0..ns)
        .map(|i| {
            let s = near + i as f64 * step;
            (0..nt)
                .map(|j| {
                    let t = lateral - 0.5 * REGION_WIDTH_M + j as f64 * step;
                    image.at(apex.0 + ar * s + cr * t, apex.1 + ac * s + cc * t) as f64
                })
                .collect()
        })
        .collect()
}

/// The periodogram of a region (its mean taken out, no data as the mean, Hann-tapered both
/// ways), or None where less than `MIN_IN_IMAGE` of it holds data.
fn periodogram(samples: &[Vec<f64>]) -> Option<Vec<Vec<f64>>> {
    let (ns, nt) = (samples.len(), samples.first().map_or(0, Vec::len));
    let finite: Vec<f64> = samples.iter().flatten().copied().filter(|v| v.is_finite()).collect();
    if ns < 8 || nt < 8 || (finite.len() as f64) < MIN_IN_IMAGE * (ns * nt) as f64 {
        return None;
    }
    let mean = finite.iter().sum::<f64>() / finite.len() as f64;
    let hann = |i: usize, n: usize| 0.5 - 0.5 * (2.0 * std::f64::consts::PI * i as f64 / (n - 1) as f64).cos();
    let mut data: Vec<Vec<Complex<f64>>> = samples
        .iter()
        .enumerate()
        .map(|(i, row)| {
            row.iter()
                .enumerate()
                .map(|(j, &v)| {
                    let x = if v.is_finite() { v - mean } else { 0.0 };
                    Complex::new(x * hann(i, ns) * hann(j, nt), 0.0)
                })
                .collect()
        })
        .collect();
    let mut planner = FftPlanner::new();
    let across = planner.plan_fft_forward(nt);
    for row in data.iter_mut() {
        across.process(row);
    }
    let along = planner.plan_fft_forward(ns);
    let mut column = vec![Complex::new(0.0, 0.0); ns];
    for j in 0..nt {
        for (c, row) in column.iter_mut().zip(&data) {
            *c = row[j];
        }
        along.process(&mut column);
        for (c, row) in column.iter().zip(data.iter_mut()) {
            row[j] = *c;
        }
    }
    Some(
        data.iter()
            .map(|row| row.iter().map(|c| c.norm_sqr()).collect())
            .collect(),
    )
}

/// The power over its own level at each bin asked for: the periodogram's 3 x 3 mean over the
/// median of those means in the 15 x 15 bins around it (both periodic, as a spectrum is).
struct OwnLevel {
    smooth: Vec<Vec<f64>>,
    level: std::collections::HashMap<(usize, usize), f64>,
}

impl OwnLevel {
    fn new(power: &[Vec<f64>]) -> Self {
        let (ns, nt) = (power.len() as isize, power[0].len() as isize);
        let at = |i: isize, j: isize| power[i.rem_euclid(ns) as usize][j.rem_euclid(nt) as usize];
        let smooth = (0..ns)
            .map(|i| {
                (0..nt)
                    .map(|j| {
                        let mut sum = 0.0;
                        for di in -SMOOTH_HALF..=SMOOTH_HALF {
                            for dj in -SMOOTH_HALF..=SMOOTH_HALF {
                                sum += at(i + di, j + dj);
                            }
                        }
                        sum / ((2 * SMOOTH_HALF + 1) * (2 * SMOOTH_HALF + 1)) as f64
                    })
                    .collect()
            })
            .collect();
        Self {
            smooth,
            level: Default::default(),
        }
    }

    /// ln(power / level) at bin (i, j).
    fn log_over_level(&mut self, i: usize, j: usize) -> f64 {
        let smooth = &self.smooth;
        let (ns, nt) = (smooth.len() as isize, smooth[0].len() as isize);
        let level = *self.level.entry((i, j)).or_insert_with(|| {
            let mut around: Vec<f64> = (-LEVEL_HALF..=LEVEL_HALF)
                .flat_map(|di| {
                    (-LEVEL_HALF..=LEVEL_HALF).map(move |dj| {
                        smooth[(i as isize + di).rem_euclid(ns) as usize][(j as isize + dj).rem_euclid(nt) as usize]
                    })
                })
                .collect();
            let mid = around.len() / 2;
            *around.select_nth_unstable_by(mid, f64::total_cmp).1
        });
        (smooth[i][j].max(1e-300) / level.max(1e-300)).ln()
    }
}

/// The mean of ln(power / level) along the Kelvin curve of each of `speeds` (a point every
/// degree) and the number of distinct bins it crosses (the mean NaN where fewer than
/// `MIN_POINTS` of them lie within the Nyquist wavenumber), for a region of `ns` x `nt` samples
/// `step` metres apart.
fn curve_power(power: &[Vec<f64>], speeds: &[f64], step: f64) -> Vec<(f64, usize)> {
    let (ns, nt) = (power.len(), power[0].len());
    let (dks, dkt) = (
        2.0 * std::f64::consts::PI / (ns as f64 * step),
        2.0 * std::f64::consts::PI / (nt as f64 * step),
    );
    // within the Nyquist wavenumber, with a tenth to spare for the taper's spread
    let k_max = 0.9 * std::f64::consts::PI / step;
    let mut own = OwnLevel::new(power);
    speeds
        .iter()
        .map(|&u| {
            // the curve's bins, a degree apart: near the track neighbouring directions share a
            // bin, so the transverse waves weigh as the degrees they span
            let bins: Vec<(usize, usize)> = (-MAX_THETA_DEG..=MAX_THETA_DEG)
                .filter_map(|deg| {
                    let theta = (deg as f64).to_radians();
                    let k = crate::GRAVITY / (u * u * theta.cos().powi(2));
                    (k < k_max).then(|| {
                        let i = ((k * theta.cos() / dks).round() as isize).rem_euclid(ns as isize) as usize;
                        let j = ((k * theta.sin() / dkt).round() as isize).rem_euclid(nt as isize) as usize;
                        (i, j)
                    })
                })
                .collect();
            let mut distinct = bins.clone();
            distinct.sort_unstable();
            distinct.dedup();
            let values: Vec<f64> = bins.into_iter().map(|(i, j)| own.log_over_level(i, j)).collect();
            let mean = if distinct.len() < MIN_POINTS {
                f64::NAN
            } else {
                values.iter().sum::<f64>() / values.len() as f64
            };
            (mean, distinct.len())
        })
        .collect()
}

/// The Kelvin speed of the ship whose wake starts at `apex` (fractional pixels of `image`) and
/// runs along `axis_deg` (clockwise from up, away from the ship), read from the region from
/// `near` metres behind the apex, for ships up to `max_speed`; an error says why none (the
/// region leaves the image, no sea beside it, the waves unresolved, none over the sea beside
/// the wake, or the sea beside the wake holding waves on the same curve).
pub fn kelvin_speed(
    image: &Normalised,
    apex: (f64, f64),
    axis_deg: f64,
    near: f64,
    max_speed: f64,
) -> Result<KelvinReading, String> {
    let g = &image.geometry;
    let step = g.spacing.0.min(g.spacing.1);
    let pixel = g.spacing.0.max(g.spacing.1);
    // the transverse wavelength must span two resolution cells
    let slowest = (crate::GRAVITY * 2.0 * pixel / (2.0 * std::f64::consts::PI))
        .sqrt()
        .max(SLOWEST);
    if slowest >= max_speed {
        return Err(format!(
            "Kelvin waves of ships up to {max_speed:.0} m/s are not resolved at {pixel:.0} m pixels"
        ));
    }
    // a fifth past the fastest ship sought, so that a faster ship's curve peaks at the range's
    // end and is refused rather than read as the fastest
    let speeds: Vec<f64> = (0..)
        .map(|i| slowest + SPEED_STEP * i as f64)
        .take_while(|&u| u <= 1.2 * max_speed + 1e-9)
        .collect();
    let behind = periodogram(&region(image, apex, axis_deg, near, 0.0, step))
        .ok_or("the kilometre behind the ship leaves the image")?;
    let sides: Vec<Vec<(f64, usize)>> = [-SIDE_OFFSET_M, SIDE_OFFSET_M]
        .iter()
        .filter_map(|&lateral| periodogram(&region(image, apex, axis_deg, near, lateral, step)))
        .map(|p| curve_power(&p, &speeds, step))
        .collect();
    if sides.is_empty() {
        return Err("no sea beside the wake in the image to hold its waves against".into());
    }
    let own = curve_power(&behind, &speeds, step);
    let Some((best, &(power, bins))) = own
        .iter()
        .enumerate()
        .filter(|(_, p)| p.0.is_finite())
        .max_by(|a, b| a.1 .0.total_cmp(&b.1 .0))
    else {
        return Err("the Kelvin curves leave the image's resolved wavenumbers".into());
    };
    let sides_power = sides
        .iter()
        .map(|s| s[best].0)
        .filter(|p| p.is_finite())
        .fold(f64::NEG_INFINITY, f64::max);
    let u = speeds[best];
    if best + 1 == speeds.len() {
        return Err(format!(
            "the best Kelvin curve is the fastest tried ({u:.1} m/s): a ship faster than that, or no waves"
        ));
    }
    // the margin's noise falls as the square root of the curve's bins: MIN_MARGIN holds for
    // REFERENCE_BINS, as on the 2.5 m scenes it was chosen on
    let least = MIN_MARGIN * (REFERENCE_BINS / bins as f64).sqrt();
    if !sides_power.is_finite() || power - sides_power < least {
        return Err(format!(
            "no Kelvin waves stand over the sea beside the wake (the best curve, {u:.1} m/s, {:.2} over the sides, under {least:.2} for its {bins} bins)",
            power - sides_power
        ));
    }
    if sides_power > MAX_SIDES_POWER {
        return Err(format!(
            "the sea beside the wake holds waves on the Kelvin curve of {u:.1} m/s (a swell or wind sea: {sides_power:.2} over its level), so the ship's cannot be told from them"
        ));
    }
    // half a bin of the transverse wavenumber k0 = g / U^2 along the track: dU / U = dk / (2 k0)
    let dk = 2.0 * std::f64::consts::PI / REGION_LENGTH_M;
    let k0 = crate::GRAVITY / (u * u);
    Ok(KelvinReading {
        speed: Speed {
            value: u,
            sigma: (u * 0.5 * dk / (2.0 * k0)).hypot(0.5 * SPEED_STEP),
        },
        wavelength_m: 2.0 * std::f64::consts::PI * u * u / crate::GRAVITY,
        locus_power: power,
        sides_power,
    })
}

/// A Kelvin wake's surface elevation (unit amplitude per direction) at `along` metres behind
/// the ship and `across` to its side, for a ship of `speed`: Havelock's superposition of the
/// waves on the curve k = g / (U^2 cos^2 theta), theta every 2 degrees within 60 of the track,
/// inside the wedge of half-angle 19.47 degrees. For the tests of this reader and of the wake
/// search.
#[cfg(test)]
pub(crate) fn kelvin_pattern(along: f64, across: f64, speed: f64) -> f64 {
    if along <= 0.0 || across.abs() > along * 19.47f64.to_radians().tan() {
        return 0.0;
    }
    let terms = (-30..=30).map(|k| (2 * k) as f64);
    let n = terms.clone().count() as f64;
    terms
        .map(|deg| {
            let theta = f64::to_radians(deg);
            let k = crate::GRAVITY / (speed * speed * theta.cos().powi(2));
            (k * (along * theta.cos() + across * theta.sin())).cos()
        })
        .sum::<f64>()
        / n.sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::radon::normalise;
    use crate::Geometry;

    /// 4-look speckle over `n` x `n` pixels of `spacing` metres, its dB raised by `db(north,
    /// east)` (metres from the image's centre).
    fn image(n: usize, spacing: f64, seed: u64, db: impl Fn(f64, f64) -> f64) -> ndarray::Array2<f32> {
        let centre = 0.5 * n as f64;
        let mut scene = crate::speckle(n, n, 4, 0.01, seed);
        scene.indexed_iter_mut().for_each(|((r, c), v)| {
            let (north, east) = ((centre - r as f64) * spacing, (c as f64 - centre) * spacing);
            *v *= 10f64.powf(db(north, east) / 10.0) as f32;
        });
        scene
    }

    /// The ship at the image's centre sailing along `course`: the metres behind it and to its
    /// side of a point `north`, `east` of it.
    fn wake_frame(course: f64, north: f64, east: f64) -> (f64, f64) {
        let axis = (course + 180.0).to_radians();
        let (sa, ca) = axis.sin_cos();
        (east * sa + north * ca, east * ca - north * sa)
    }

    /// Havelock's Kelvin wake, 1 dB per direction, over 4-look speckle at 5 m: ships of 6-12
    /// m/s on four courses read their speed within 3 % and within two of its uncertainties.
    #[test]
    fn the_kelvin_curve_gives_the_speed() {
        for (k, &(course, speed)) in [(20.0, 6.0), (110.0, 8.0), (235.0, 10.0), (300.0, 12.0)]
            .iter()
            .enumerate()
        {
            let spacing = 5.0;
            let scene = image(500, spacing, 40 + k as u64, |north, east| {
                let (along, across) = wake_frame(course, north, east);
                kelvin_pattern(along, across, speed)
            });
            let g = Geometry::along_rows(spacing, 35.0, None);
            let normalised = normalise(scene.view(), &g, 2000.0);
            let axis = (course + 180.0f64).rem_euclid(360.0);
            let reading = kelvin_speed(&normalised, (250.0, 250.0), axis, 60.0, 15.0)
                .unwrap_or_else(|e| panic!("course {course}, {speed} m/s: {e}"));
            let error = (reading.speed.value - speed).abs();
            assert!(error < 0.03 * speed, "{speed} m/s: {reading:?}");
            assert!(error < 2.0 * reading.speed.sigma + 0.05, "{speed} m/s: {reading:?}");
        }
    }

    /// A swell of 100 m along the track (its crests on the curve of about 12.5 m/s), on the
    /// wake and beside it: behind the ship its curve stands well over the spectrum's own level,
    /// more than a read needs over the sides, yet it is refused, for the sides hold it too.
    #[test]
    fn a_swell_on_the_curve_is_no_ship() {
        let (spacing, course) = (5.0, 60.0);
        let scene = image(500, spacing, 5, |north, east| {
            let (along, _) = wake_frame(course, north, east);
            3.0 * (2.0 * std::f64::consts::PI * along / 100.0).cos()
        });
        let g = Geometry::along_rows(spacing, 35.0, None);
        let normalised = normalise(scene.view(), &g, 2000.0);
        let axis = course + 180.0;
        let behind = periodogram(&region(&normalised, (250.0, 250.0), axis, 60.0, 0.0, spacing)).unwrap();
        let speeds: Vec<f64> = (0..100).map(|i| 8.0 + 0.1 * i as f64).collect();
        let (best, power) = curve_power(&behind, &speeds, spacing)
            .iter()
            .enumerate()
            .map(|(i, p)| (speeds[i], p.0))
            .fold((0.0, f64::NEG_INFINITY), |a, b| if b.1 > a.1 { b } else { a });
        assert!(
            power > 2.0 * MIN_MARGIN,
            "the swell's curve ({best} m/s) stands {power:.2}"
        );
        assert!((best - 12.5).abs() < 1.5, "the swell's curve is {best} m/s");
        let e = kelvin_speed(&normalised, (250.0, 250.0), axis, 60.0, 15.0).unwrap_err();
        assert!(
            e.contains("over the sides") || e.contains("beside the wake holds"),
            "{e}"
        );
    }

    /// Speckle alone, white (4 looks) and correlated as an oversampled product's (a 3 x 3 box
    /// mean: lag-1 correlation 0.67), 100 draws each at 10 m: no speed is read from more than
    /// 2 of them.
    #[test]
    fn speckle_reads_no_speed() {
        let g = Geometry::along_rows(10.0, 35.0, None);
        for correlated in [false, true] {
            let read = (0..100u64)
                .filter(|&seed| {
                    let mut scene = image(260, 10.0, 1000 + seed, |_, _| 0.0);
                    if correlated {
                        scene = crate::radon::box_mean(&scene, (1, 1));
                    }
                    let normalised = normalise(scene.view(), &g, 2000.0);
                    kelvin_speed(&normalised, (130.0, 130.0), 90.0 + 3.6 * seed as f64, 60.0, 15.0).is_ok()
                })
                .count();
            assert!(read <= 2, "correlated {correlated}: {read} of 100 read a speed");
        }
    }

    /// At 150 m pixels no ship's transverse waves span two cells: unresolved.
    #[test]
    fn coarse_pixels_resolve_no_speed() {
        let g = Geometry::along_rows(150.0, 35.0, None);
        let scene = image(40, 150.0, 3, |_, _| 0.0);
        let normalised = normalise(scene.view(), &g, 2000.0);
        let e = kelvin_speed(&normalised, (20.0, 20.0), 90.0, 60.0, 15.0).unwrap_err();
        assert!(e.contains("not resolved"), "{e}");
    }
}

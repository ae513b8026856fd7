//! Image formation: what an instrument records of the scene's sigma0 and brightness temperature.
//!
//! SAR (Goodman 1976; Oliver & Quegan 1998, ch. 4): each of L independent looks is the
//! amplitude sqrt(sigma0 + NESZ) times a circular complex Gaussian field passed through the
//! impulse response h; the image is the mean of the looks' intensities. (Signal and thermal
//! noise are independent complex Gaussians, so their sum is one of power sigma0 + NESZ wherever
//! sigma0 is uniform over the resolution cell; one field instead of two halves the cost and
//! leaves out only sigma0's variation inside a cell.) h is Gaussian with |h|^2 of full width at
//! half maximum equal to the resolution and sum |h|^2 = 1, so every look's mean intensity is
//! sigma0 + NESZ, the L-look coefficient of variation over a uniform sea is 1/sqrt(L), and the
//! intensity's autocorrelation coefficient at a lag of d pixels is |rho_z(d)|^2 =
//! exp(-d^2 / (2 s^2)), s = resolution / (2 sqrt(ln 2)) in pixels (the Siegert relation).
//!
//! Infrared: the imager's point-spread function, a Gaussian of the resolution as full width at
//! half maximum, blurs the brightness temperature, and white noise of standard deviation NETD is
//! added per pixel.
//!
//! Fields are periodic over the scene (the convolutions wrap), so statistics do not change at
//! the edges.

use ndarray::{Array2, Axis};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use rayon::prelude::*;

/// Full width at half maximum over the standard deviation of a Gaussian: 2 sqrt(2 ln 2).
const FWHM_PER_SIGMA: f64 = 2.354_820_045_030_949;

/// A Gaussian's taps at integer offsets out to 4 standard deviations, scaled so that the sum
/// of their `power`-th powers is 1 (power 2: an amplitude response of unit energy; power 1: a
/// point-spread function that keeps the mean).
fn gaussian_taps(sigma: f64, power: i32) -> Vec<f64> {
    let reach = (4.0 * sigma).ceil().max(1.0) as i64;
    let taps: Vec<f64> = (-reach..=reach)
        .map(|i| (-(i as f64).powi(2) / (2.0 * sigma * sigma)).exp())
        .collect();
    let norm = taps.iter().map(|t| t.powi(power)).sum::<f64>().powf(1.0 / power as f64);
    taps.into_iter().map(|t| t / norm).collect()
}

/// Periodic convolution of every row, then every column, with the same odd-length taps, into
/// `out`, through `rows_done` (both the field's shape; reused, so large scenes allocate once).
/// Both passes run over contiguous rows: a row is padded with its wrapped ends, and the column
/// pass adds whole shifted rows.
fn convolve_separable_into(field: &Array2<f64>, taps: &[f64], rows_done: &mut Array2<f64>, out: &mut Array2<f64>) {
    let field = field.as_standard_layout();
    let rows = field.nrows();
    let half = taps.len() / 2;
    rows_done
        .axis_iter_mut(Axis(0))
        .into_par_iter()
        .zip(field.axis_iter(Axis(0)).into_par_iter())
        .for_each_init(Vec::new, |padded, (o, line)| {
            let line = line.to_slice().expect("standard layout");
            filter_row(line, taps, padded, o.into_slice().expect("standard layout"));
        });
    let rows_done = &*rows_done;
    out.axis_iter_mut(Axis(0))
        .into_par_iter()
        .enumerate()
        .for_each(|(r, o)| {
            let source = |t: usize| {
                let row = rows_done.row((r + t + rows * (half / rows + 1) - half) % rows);
                row.to_slice().expect("standard layout")
            };
            add_rows(taps, source, o.into_slice().expect("standard layout"));
        });
}

/// `out` = the periodic convolution of `line` with odd-length `taps` (centred), through the
/// buffer `padded` (the line with its wrapped ends); tap by tap over the whole row, so it
/// vectorises, each output summed in tap order.
fn filter_row(line: &[f64], taps: &[f64], padded: &mut Vec<f64>, out: &mut [f64]) {
    let cols = line.len();
    let half = taps.len() / 2;
    padded.clear();
    if half < cols {
        padded.extend_from_slice(&line[cols - half..]);
        padded.extend_from_slice(line);
        padded.extend_from_slice(&line[..half]);
    } else {
        padded.extend((0..cols + 2 * half).map(|j| line[(j + cols - half % cols) % cols]));
    }
    add_rows(taps, |t| &padded[t..t + cols], out);
}

/// `out` = sum over t of taps[t] times row `source(t)`, in tap order.
fn add_rows<'a>(taps: &[f64], source: impl Fn(usize) -> &'a [f64], out: &mut [f64]) {
    out.fill(0.0);
    for (t, w) in taps.iter().enumerate() {
        for (o, &v) in out.iter_mut().zip(source(t)) {
            *o += w * v;
        }
    }
}

fn convolve_separable(field: &Array2<f64>, taps: &[f64]) -> Array2<f64> {
    let (mut rows_done, mut out) = (Array2::zeros(field.raw_dim()), Array2::zeros(field.raw_dim()));
    convolve_separable_into(field, taps, &mut rows_done, &mut out);
    out
}

/// Fill `out` with independent standard normal values, each row from its own stream of `seed`,
/// so the field is the same however the rows are shared out.
fn fill_white(out: &mut Array2<f64>, seed: u64) {
    out.axis_iter_mut(Axis(0))
        .into_par_iter()
        .enumerate()
        .for_each(|(r, mut row)| white_row(row.as_slice_mut().expect("standard layout"), seed, r));
}

/// What the SAR instrument adds to the scene's sigma0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SarFormation {
    /// Independent looks averaged; 0 for the perfect SAR of spec Eq. (3.3) (no speckle).
    pub looks: u32,
    /// Resolution over pixel spacing (the impulse response's |h|^2 full width at half maximum,
    /// in pixels).
    pub resolution_pixels: f64,
    /// Thermal noise power, linear sigma0 units; 0 for none.
    pub nesz: f64,
}

/// The intensity the SAR records of `sigma0` (module docs); with 0 looks, sigma0 + NESZ.
///
/// Every look's real and imaginary fields are made, filtered and squared a block of rows at a
/// time, with the rows the filter reaches beyond the block made again from their own streams,
/// so the work stays in the cache and the image is the same for any number of threads.
pub fn form_sar_image(sigma0: &Array2<f64>, formation: SarFormation, seed: u64) -> Array2<f64> {
    let SarFormation {
        looks,
        resolution_pixels,
        nesz,
    } = formation;
    if looks == 0 {
        return sigma0.mapv(|v| v + nesz);
    }
    let taps = gaussian_taps(resolution_pixels / FWHM_PER_SIGMA * std::f64::consts::SQRT_2, 2);
    let half = taps.len() / 2;
    let sigma0 = sigma0.as_standard_layout();
    let (rows, cols) = sigma0.dim();
    // each look's real and imaginary parts, each of variance 1/2, from their own seeds
    let field_seeds: Vec<u64> = (0..looks as u64)
        .flat_map(|look| {
            (1..=2u64).map(move |k| {
                (seed ^ (look << 32))
                    .wrapping_mul(0x9E37_79B9_7F4A_7C15)
                    .wrapping_add(k)
            })
        })
        .collect();
    let mut sum = Array2::<f64>::zeros((rows, cols));
    sum.axis_chunks_iter_mut(Axis(0), BLOCK_ROWS)
        .into_par_iter()
        .enumerate()
        .for_each(|(block, mut out)| {
            let r0 = block * BLOCK_ROWS;
            let height = out.nrows();
            // the block's source rows r0 - half .. r0 + height + half (wrapped), filtered along
            let mut filtered = Array2::<f64>::zeros((height + 2 * half, cols));
            let (mut white, mut padded, mut part) = (vec![0.0; cols], Vec::new(), vec![0.0; cols]);
            for &field_seed in &field_seeds {
                for (i, line) in filtered.axis_iter_mut(Axis(0)).enumerate() {
                    let source = (r0 + i + rows * (half / rows + 1) - half) % rows;
                    white_row(&mut white, field_seed, source);
                    filter_row(&white, &taps, &mut padded, line.into_slice().expect("standard layout"));
                }
                let filtered = filtered.as_slice().expect("standard layout");
                for (i, line) in out.axis_iter_mut(Axis(0)).enumerate() {
                    add_rows(&taps, |t| &filtered[(i + t) * cols..(i + t + 1) * cols], &mut part);
                    let line = line.into_slice().expect("standard layout");
                    let power = sigma0.row(r0 + i);
                    let power = power.as_slice().expect("standard layout");
                    for ((s, &z), &v) in line.iter_mut().zip(&part).zip(power) {
                        let p = v.max(0.0) + nesz.max(0.0);
                        *s += 0.5 * p * z * z;
                    }
                }
            }
        });
    sum.mapv_inplace(|v| v / looks as f64);
    sum
}

/// Rows of the SAR image a thread forms at once.
const BLOCK_ROWS: usize = 64;

/// Row `row` of the white field of `seed`: independent standard normal values from the row's
/// own stream (see [`fill_white`]).
fn white_row(out: &mut [f64], seed: u64, row: usize) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(row as u64);
    for v in out.iter_mut() {
        *v = StandardNormal.sample(&mut rng);
    }
}

/// What the infrared imager adds to the scene's brightness temperature.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IrFormation {
    /// Full width at half maximum of the point-spread function over the pixel spacing; at or
    /// below 1 no blur beyond the pixel.
    pub resolution_pixels: f64,
    /// Noise-equivalent temperature difference (K); 0 for none.
    pub netd: f64,
}

/// The brightness temperature the imager records: blurred by its point-spread function, plus
/// white noise of standard deviation NETD.
pub fn form_ir_image(brightness: &Array2<f64>, formation: IrFormation, seed: u64) -> Array2<f64> {
    let mut out = if formation.resolution_pixels > 1.0 {
        convolve_separable_mean(brightness, formation.resolution_pixels / FWHM_PER_SIGMA)
    } else {
        brightness.clone()
    };
    if formation.netd > 0.0 {
        let mut noise = Array2::zeros(out.raw_dim());
        fill_white(&mut noise, seed);
        out.zip_mut_with(&noise, |v, n| *v += formation.netd * n);
    }
    out
}

/// A Gaussian blur of standard deviation `sigma` pixels that keeps the mean.
fn convolve_separable_mean(field: &Array2<f64>, sigma: f64) -> Array2<f64> {
    // taps summing to 1 along each axis keep the mean
    convolve_separable(field, &gaussian_taps(sigma, 1))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mean(a: &Array2<f64>) -> f64 {
        a.mean().unwrap()
    }

    fn std_dev(a: &Array2<f64>) -> f64 {
        let m = mean(a);
        (a.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (a.len() - 1) as f64).sqrt()
    }

    /// Autocorrelation coefficient of `a` at a lag of `d` pixels along rows (periodic).
    fn autocorrelation(a: &Array2<f64>, d: usize) -> f64 {
        let (m, v) = (mean(a), std_dev(a).powi(2));
        let cols = a.ncols();
        let mut s = 0.0;
        for r in 0..a.nrows() {
            for c in 0..cols {
                s += (a[[r, c]] - m) * (a[[r, (c + d) % cols]] - m);
            }
        }
        s / a.len() as f64 / v
    }

    /// The image formed a block of rows at a time (each block making its filter's reach again)
    /// equals the definition computed whole: every look's real and imaginary white fields
    /// filtered over the full scene, 0.5 p z^2 summed and divided by L. Rows span several
    /// blocks and a sigma0 that varies; one thread and two give the same bytes.
    #[test]
    fn blocked_speckle_equals_the_whole_field_definition() {
        let (rows, cols) = (150, 40);
        let sigma0 = Array2::from_shape_fn((rows, cols), |(r, c)| 0.01 + 1e-4 * ((r * 7 + c * 3) % 50) as f64);
        let formation = SarFormation {
            looks: 3,
            resolution_pixels: 2.5,
            nesz: 1e-3,
        };
        let seed = 42;
        let image = form_sar_image(&sigma0, formation, seed);
        let taps = gaussian_taps(2.5 / FWHM_PER_SIGMA * std::f64::consts::SQRT_2, 2);
        let mut want = Array2::<f64>::zeros((rows, cols));
        for look in 0..3u64 {
            for k in 1..=2u64 {
                let mut white = Array2::zeros((rows, cols));
                fill_white(
                    &mut white,
                    (seed ^ (look << 32))
                        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
                        .wrapping_add(k),
                );
                let z = convolve_separable(&white, &taps);
                ndarray::Zip::from(&mut want)
                    .and(&z)
                    .and(&sigma0)
                    .for_each(|w, &z, &s| *w += 0.5 * (s + 1e-3) * z * z);
            }
        }
        want.mapv_inplace(|v| v / 3.0);
        for (a, b) in image.iter().zip(&want) {
            assert!((a - b).abs() <= 1e-12 * b.abs(), "{a} vs {b}");
        }
        let one_thread = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        assert_eq!(one_thread.install(|| form_sar_image(&sigma0, formation, seed)), image);
    }

    #[test]
    fn speckle_keeps_the_mean_and_has_the_looks_coefficient_of_variation() {
        let sigma0 = Array2::from_elem((256, 256), 0.05);
        for looks in [1u32, 4] {
            let formation = SarFormation {
                looks,
                resolution_pixels: 1.0,
                nesz: 0.0,
            };
            let image = form_sar_image(&sigma0, formation, 7);
            // 65536 pixels, nearly independent at one pixel's resolution: relative standard
            // error of the mean 1/sqrt(L N) < 0.4 %, of the CV about 0.5 %
            let m = mean(&image);
            assert!((m / 0.05 - 1.0).abs() < 0.015, "L = {looks}: mean {m}");
            let cv = std_dev(&image) / m;
            let want = 1.0 / (looks as f64).sqrt();
            assert!((cv / want - 1.0).abs() < 0.03, "L = {looks}: cv {cv}, want {want}");
        }
    }

    #[test]
    fn speckle_is_correlated_over_the_resolution_cell() {
        let sigma0 = Array2::from_elem((512, 512), 1.0);
        let resolution_pixels = 3.0;
        let formation = SarFormation {
            looks: 1,
            resolution_pixels,
            nesz: 0.0,
        };
        let image = form_sar_image(&sigma0, formation, 11);
        // the Siegert relation for a Gaussian |h|^2 of FWHM 3 px: rho_I(d) = exp(-d^2 / (2 s^2))
        let s = resolution_pixels / (2.0 * 2f64.ln().sqrt());
        for d in [1usize, 2, 4] {
            let want = (-(d as f64).powi(2) / (2.0 * s * s)).exp();
            let got = autocorrelation(&image, d);
            assert!((got - want).abs() < 0.04, "lag {d}: {got}, closed form {want}");
        }
        // and the mean still holds, with the coefficient of variation of one look
        assert!((mean(&image) - 1.0).abs() < 0.04);
        assert!((std_dev(&image) - 1.0).abs() < 0.08);
    }

    #[test]
    fn a_dark_sea_reads_at_the_noise_equivalent_sigma_zero() {
        let nesz = 10f64.powf(-22.0 / 10.0);
        let sigma0 = Array2::zeros((256, 256));
        let formation = SarFormation {
            looks: 4,
            resolution_pixels: 1.5,
            nesz,
        };
        let image = form_sar_image(&sigma0, formation, 3);
        let m = mean(&image);
        assert!((m / nesz - 1.0).abs() < 0.03, "mean {m} vs NESZ {nesz}");
        // the perfect SAR adds the noise's mean
        let perfect = form_sar_image(&sigma0, SarFormation { looks: 0, ..formation }, 3);
        assert!(perfect.iter().all(|&v| (v - nesz).abs() < 1e-18));
    }

    #[test]
    fn a_uniform_infrared_scene_shows_the_netd() {
        let scene = Array2::from_elem((256, 256), 290.0);
        let formation = IrFormation {
            resolution_pixels: 2.0,
            netd: 0.05,
        };
        let image = form_ir_image(&scene, formation, 5);
        assert!((mean(&image) - 290.0).abs() < 0.001);
        let sd = std_dev(&image);
        assert!((sd / 0.05 - 1.0).abs() < 0.02, "sd {sd}");
    }

    #[test]
    fn the_point_spread_function_has_the_resolution_as_its_width() {
        let mut scene = Array2::zeros((64, 64));
        scene[[32, 32]] = 1.0;
        let resolution_pixels = 4.0;
        let blurred = form_ir_image(
            &scene,
            IrFormation {
                resolution_pixels,
                netd: 0.0,
            },
            0,
        );
        assert!((blurred.sum() - 1.0).abs() < 1e-12, "the blur keeps the total");
        // second moment along a row: the Gaussian's variance (FWHM / 2.3548)^2
        let variance: f64 = blurred
            .indexed_iter()
            .map(|((_, c), v)| v * (c as f64 - 32.0).powi(2))
            .sum();
        let want = (resolution_pixels / 2.354_820_045).powi(2);
        assert!((variance / want - 1.0).abs() < 0.01, "{variance} vs {want}");
    }

    #[test]
    fn the_same_seed_gives_the_same_image_and_another_seed_another() {
        let sigma0 = Array2::from_shape_fn((32, 32), |(r, c)| 0.01 + 0.001 * (r + c) as f64);
        let f = SarFormation {
            looks: 2,
            resolution_pixels: 2.0,
            nesz: 1e-3,
        };
        let a = form_sar_image(&sigma0, f, 1);
        assert_eq!(a, form_sar_image(&sigma0, f, 1));
        assert_ne!(a, form_sar_image(&sigma0, f, 2));
    }
}

//! Natural dark features of the open sea, in wake and no-wake scenes alike: biogenic slicks and
//! wind variability (low-wind patches). Both are seeded random fields on the scene; they act on
//! the image only through the surface and radar physics that the wake's fields go through (film
//! damping of the Bragg waves, the local wind's spectrum), never by editing an image.
//!
//! A field is a stationary Gaussian random field of unit variance with a Gaussian covariance
//! exp(-(s_a^2 / L_a^2 + s_c^2 / L_c^2) / 2) (s_a, s_c the separation along and across a given
//! direction), made by filtering white noise in the Fourier domain with the square root of its
//! power spectrum exp(-(k_a^2 L_a^2 + k_c^2 L_c^2) / 2) (e.g. Liu et al. 2019, "Advances in
//! Gaussian random field generation", Math. Geosci. 51, 639). The field is periodic over the
//! scene, and normalised by its expected (not its sample) variance, so the sample statistics of
//! one realisation scatter as they should.
//!
//! Slicks: where the field exceeds its (1 - coverage) quantile z_c = Phi^-1(1 - coverage), the
//! surface film is the slick's, of reference elasticity `slicks.elasticity` instead of the open
//! sea's `sea.film_elasticity`, over a smooth edge a quarter of a standard deviation wide inside
//! the slick; elongated along the wind, the patches form the
//! filaments that wind-aligned convergence makes of real slicks (Espedal et al. 1996, Int. J.
//! Remote Sens. 17, 1255). The coverage is the expected fraction of the scene with g > z_c.
//!
//! Wind: U(x) = max(U (1 + sigma g(x)), 0.5 m/s), sigma = `environment.wind.variability`, an
//! isotropic field of correlation length `environment.wind.gust_length`.

use crate::fourier::{fft_2d, signed_frequency};
use crate::scene::SceneGrid;
use ndarray::Array2;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use rustfft::num_complex::Complex64;
use wakelab_core::config::{SlickConfig, WindConfig};

/// Seed offsets of the natural fields, apart from the sea surface's and the sensors' draws.
const SLICK_SEED: u64 = 0x511C_0000_0000;
const WIND_SEED: u64 = 0x57_1ED0_0000;

/// The slowest wind the variable wind field takes (m/s).
pub const MIN_LOCAL_WIND: f64 = 0.5;

/// A unit-variance Gaussian random field on the scene with correlation lengths `along` and
/// `across` a direction (heading-frame angle `direction`, radians from the heading).
///
/// The transform of white noise is white noise: the field is the real part of one inverse
/// transform of circular complex Gaussian noise W (E|W|^2 = 1) times the filter, whose
/// real part has half the filtered power. Noise is drawn, in a fixed order, only in the bins
/// where the filter exceeds e^-20 of its peak (those beyond add less than 1e-9 of the field).
pub fn gaussian_field(grid: &SceneGrid, along: f64, across: f64, direction: f64, seed: u64) -> Array2<f64> {
    let n = grid.size();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (we, wn) = grid.scene_frame(direction.cos(), direction.sin());
    let dk = 2.0 * std::f64::consts::PI / (n as f64 * grid.pixel_spacing);
    let freq = |i: usize| signed_frequency(i, n);
    let mut data = vec![Complex64::new(0.0, 0.0); n * n];
    let mut power = 0.0;
    for a in 0..n {
        for b in 0..n {
            let (k_east, k_north) = (freq(b) * dk, -freq(a) * dk);
            let k_along = k_east * we + k_north * wn;
            let k_across = -k_east * wn + k_north * we;
            // the power spectrum exp(-q / 2); its square root filters the noise
            let q = (k_along * along).powi(2) + (k_across * across).powi(2);
            if q < 80.0 {
                let spectrum = (-0.5 * q).exp();
                power += spectrum;
                let (re, im): (f64, f64) = (StandardNormal.sample(&mut rng), StandardNormal.sample(&mut rng));
                data[a * n + b] = Complex64::new(re, im) * (0.5 * spectrum).sqrt();
            }
        }
    }
    fft_2d(&mut data, n, true);
    // Re of sum W s_k e^{ikx} has variance sum s_k^2 / 2 = power / 2
    let scale = 1.0 / (0.5 * power).sqrt();
    Array2::from_shape_fn((n, n), |(r, c)| data[r * n + c].re * scale)
}

/// The standard normal quantile Phi^-1(p), by Newton's method on libm's erfc.
pub fn normal_quantile(p: f64) -> f64 {
    let p = p.clamp(1e-12, 1.0 - 1e-12);
    let mut x = 0.0;
    for _ in 0..60 {
        let cdf = 0.5 * libm::erfc(-x / std::f64::consts::SQRT_2);
        let pdf = (-0.5 * x * x).exp() / (2.0 * std::f64::consts::PI).sqrt();
        let step = (cdf - p) / pdf.max(1e-300);
        x -= step.clamp(-1.0, 1.0);
        if step.abs() < 1e-14 {
            break;
        }
    }
    x
}

/// The slicks of a scene.
#[derive(Debug, Clone)]
pub struct Slicks {
    /// The local film's reference elasticity (N/m): the open sea's outside the slicks.
    pub elasticity: Array2<f64>,
    /// Whether each pixel lies in a slick (the field above its threshold).
    pub mask: Array2<u8>,
}

/// Slicks of the configured coverage on a sea whose own film has reference elasticity `ambient`
/// (N/m), their filaments along the wind (heading-frame direction `wind_direction`, degrees);
/// None when the coverage is zero.
pub fn natural_slicks(
    grid: &SceneGrid,
    config: &SlickConfig,
    ambient: f64,
    wind_direction: f64,
    seed: u64,
) -> Option<Slicks> {
    if config.coverage <= 0.0 {
        return None;
    }
    let across = config.length;
    let field = gaussian_field(
        grid,
        across * config.elongation,
        across,
        wind_direction.to_radians(),
        seed ^ SLICK_SEED,
    );
    let threshold = normal_quantile(1.0 - config.coverage);
    const EDGE: f64 = 0.25;
    let elasticity = field.mapv(|g| {
        let s = ((g - threshold) / EDGE).clamp(0.0, 1.0);
        ambient + (config.elasticity - ambient) * s * s * (3.0 - 2.0 * s)
    });
    let mask = field.mapv(|g| u8::from(g > threshold));
    Some(Slicks { elasticity, mask })
}

/// The local 10-m wind speed over the scene; None when the wind is uniform.
pub fn local_wind(grid: &SceneGrid, wind: &WindConfig, seed: u64) -> Option<Array2<f64>> {
    if wind.variability <= 0.0 {
        return None;
    }
    let g = gaussian_field(grid, wind.gust_length, wind.gust_length, 0.0, seed ^ WIND_SEED);
    Some(g.mapv(|v| (wind.speed * (1.0 + wind.variability * v)).max(MIN_LOCAL_WIND)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use wakelab_core::config::SceneConfig;

    fn grid(size: usize, heading: f64) -> SceneGrid {
        SceneGrid::new(&SceneConfig {
            pixel_spacing: 10.0,
            size,
            along_track: 5000.0,
            cross_track: 0.0,
            heading,
            other_wakes: Vec::new(),
            centre: None,
        })
    }

    #[test]
    fn the_quantile_inverts_the_normal_distribution() {
        // tabulated: Phi(1.959964) = 0.975, Phi(-1.281552) = 0.1
        assert!((normal_quantile(0.975) - 1.959964).abs() < 1e-6);
        assert!((normal_quantile(0.1) + 1.281552).abs() < 1e-6);
        assert_eq!(normal_quantile(0.5), 0.0);
    }

    /// Unit variance, and the correlation at one correlation length is exp(-1/2) along the
    /// field's direction and across it (lengths 5 and 20 px here, along the image's rows).
    #[test]
    fn the_field_has_the_covariance_it_was_made_with() {
        // heading 270: the heading frame's port direction (90 degrees) points down the image
        let g = grid(512, 270.0);
        let f = gaussian_field(&g, 200.0, 50.0, std::f64::consts::FRAC_PI_2, 3);
        let n = 512;
        let var = f.iter().map(|v| v * v).sum::<f64>() / (n * n) as f64;
        let corr = |dr: usize, dc: usize| {
            let mut s = 0.0;
            for r in 0..n {
                for c in 0..n {
                    s += f[[r, c]] * f[[(r + dr) % n, (c + dc) % n]];
                }
            }
            s / (n * n) as f64 / var
        };
        eprintln!("variance {var:.3}, along {:.3}, across {:.3}", corr(20, 0), corr(0, 5));
        assert!((var - 1.0).abs() < 0.1, "variance {var}");
        let want = (-0.5f64).exp();
        assert!((corr(20, 0) - want).abs() < 0.06, "along {}", corr(20, 0));
        assert!((corr(0, 5) - want).abs() < 0.06, "across {}", corr(0, 5));
    }

    /// The covered fraction scatters around the configured coverage by its sampling error: the
    /// mean over 16 seeds lies within three standard errors of the configured fraction.
    #[test]
    fn slick_coverage_is_the_configured_fraction() {
        let g = grid(256, 30.0);
        for coverage in [0.1, 0.3] {
            let config = SlickConfig {
                coverage,
                length: 100.0,
                elongation: 3.0,
                elasticity: 0.01,
            };
            let fractions: Vec<f64> = (0..16)
                .map(|seed| {
                    let s = natural_slicks(&g, &config, 0.003, 0.0, seed).unwrap();
                    s.mask.iter().map(|&m| m as f64).sum::<f64>() / s.mask.len() as f64
                })
                .collect();
            let m = fractions.iter().sum::<f64>() / 16.0;
            let sd = (fractions.iter().map(|f| (f - m).powi(2)).sum::<f64>() / 15.0).sqrt();
            eprintln!("coverage {coverage}: mean {m:.4}, sd over seeds {sd:.4}");
            assert!((m - coverage).abs() < 3.0 * sd / 4.0, "{m} vs {coverage} (sd {sd})");
            assert!(
                sd > 0.0 && sd < 0.5 * coverage,
                "a sampling spread, not a fixed fraction"
            );
        }
    }
}

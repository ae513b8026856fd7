//! Rendering one wake/no-wake pair: images in every band, physics-based wake masks and the
//! wake's visibility.
//!
//! Mask rule (reproducible, unlike the spec's hand-drawn masks): a pixel belongs to the wake in
//! a SAR band where the wake changes that band's Bragg spectral density by more than
//! [`MASK_MODULATION`] against the paired no-wake scene (|N_wake/N_no_wake - 1| > 5 %), and in
//! an IR band where the wake changes the surface temperature by more than [`MASK_TEMPERATURE`]
//! (0.02 K, a good thermal imager's NETD). Visibility is the contrast-to-clutter ratio
//! |mean(wake) - mean(sea)| / sd(sea) of the image over that mask; for the no-wake scene the
//! pair's mask is applied to it, which measures how much "wake" chance alone shows.

use crate::study::ScenePair;
use ndarray::Array2;
use rayon::prelude::*;
use wakelab_core::units::RadarBand;
use wakelab_hydro::SurfaceMap;
use wakelab_schema::band::Band;
use wakelab_sensors::{IrBand, IrScene, SarScene};
use wakelab_surface::{simulate_surface, SurfaceScene};

/// Threshold of |N_wake/N_no_wake - 1| for the SAR wake masks.
pub const MASK_MODULATION: f64 = 0.05;
/// Threshold of |dT| (K) for the IR wake masks.
pub const MASK_TEMPERATURE: f64 = 0.02;

/// One band of a rendered pair.
pub struct BandPair {
    pub band: Band,
    pub wake: Array2<f32>,
    pub no_wake: Array2<f32>,
    pub mask: Array2<u8>,
    /// (wake scene, no-wake scene) contrast-to-clutter ratios.
    pub visibility: (f64, f64),
    /// What the images hold.
    pub quantity: &'static str,
}

/// The sensor that renders a band: a radar band of the SAR or an infrared band of the imager.
enum Sensor {
    Radar(RadarBand),
    Infrared(IrBand),
}

fn sensor(band: Band) -> Sensor {
    match band {
        Band::S => Sensor::Radar(RadarBand::S),
        Band::C => Sensor::Radar(RadarBand::C),
        Band::X => Sensor::Radar(RadarBand::X),
        Band::Mwir => Sensor::Infrared(IrBand::Mwir),
        Band::Lwir => Sensor::Infrared(IrBand::Lwir),
    }
}

/// The radar band of a band; None for an infrared band.
pub fn radar_band(band: Band) -> Option<RadarBand> {
    match sensor(band) {
        Sensor::Radar(b) => Some(b),
        Sensor::Infrared(_) => None,
    }
}

/// Contrast-to-clutter ratio of `image` over `mask`.
pub fn visibility(image: &Array2<f32>, mask: &Array2<u8>) -> f64 {
    let (mut sw, mut nw, mut ss, mut ns) = (0.0, 0usize, 0.0, 0usize);
    for (&v, &m) in image.iter().zip(mask.iter()) {
        if m > 0 {
            sw += v as f64;
            nw += 1;
        } else {
            ss += v as f64;
            ns += 1;
        }
    }
    if nw == 0 || ns < 2 {
        return 0.0;
    }
    let (mw, ms) = (sw / nw as f64, ss / ns as f64);
    let var = image
        .iter()
        .zip(mask.iter())
        .filter(|(_, &m)| m == 0)
        .map(|(&v, _)| (v as f64 - ms).powi(2))
        .sum::<f64>()
        / (ns - 1) as f64;
    if var <= 0.0 {
        return if (mw - ms).abs() > 0.0 { f64::INFINITY } else { 0.0 };
    }
    (mw - ms).abs() / var.sqrt()
}

/// The SAR wake mask of band `b`: where the wake changes the Bragg spectral density by more
/// than [`MASK_MODULATION`] against the paired no-wake scene, N_wake / N_no_wake. The ratio, not
/// N_wake / N0: natural slicks and low-wind patches lie in both scenes of a pair and are not the
/// wake (measured against N0 they filled up to a fifth of a mask).
fn radar_wake_mask(with: &SurfaceScene, without: &SurfaceScene, b: RadarBand) -> Array2<u8> {
    let (w, n) = (bragg_modulation(with, b), bragg_modulation(without, b));
    ndarray::Zip::from(w)
        .and(n)
        .map_collect(|&w, &n| u8::from((w / n - 1.0).abs() > MASK_MODULATION))
}

fn bragg_modulation(scene: &SurfaceScene, b: RadarBand) -> &Array2<f64> {
    &scene.bragg.iter().find(|x| x.band == b).expect("every band").modulation
}

/// A rendered pair: every band, the Kelvin-arm mask of the wake scene when it has Kelvin waves,
/// and the natural slicks' mask.
pub struct RenderedPair {
    pub bands: Vec<BandPair>,
    pub kelvin_mask: Option<Array2<u8>>,
    /// The natural slicks' pixels (1), the same in both scenes; None without slicks.
    pub slick_mask: Option<Array2<u8>>,
}

/// Render a pair in `bands` from the wake's surface map; also returns the seconds spent in the
/// surface stage and in the sensors.
pub fn render_pair(pair: &ScenePair, map: &SurfaceMap, bands: &[Band]) -> (RenderedPair, f64, f64) {
    let cfg = &pair.config;
    let t = std::time::Instant::now();
    let with: SurfaceScene = simulate_surface(cfg, Some(map));
    let without: SurfaceScene = simulate_surface(cfg, None);
    let surface = t.elapsed().as_secs_f64();
    let t = std::time::Instant::now();
    let (radar_with, radar_without) = (SarScene::new(cfg, &with), SarScene::new(cfg, &without));
    let (infrared_with, infrared_without) = (IrScene::new(cfg, &with), IrScene::new(cfg, &without));
    // the bands are independent images: side by side
    let out = bands
        .par_iter()
        .map(|&band| match sensor(band) {
            Sensor::Radar(b) => {
                let mask = radar_wake_mask(&with, &without, b);
                let wake = radar_with.render(b).sigma0.mapv(|v| v as f32);
                let no_wake = radar_without.render(b).sigma0.mapv(|v| v as f32);
                finish(band, wake, no_wake, mask, "sigma0 (linear)")
            }
            Sensor::Infrared(b) => {
                let mask = with.temperature_anomaly.mapv(|v| u8::from(v.abs() > MASK_TEMPERATURE));
                let wake = infrared_with.render(b).brightness_temperature.mapv(|v| v as f32);
                let no_wake = infrared_without.render(b).brightness_temperature.mapv(|v| v as f32);
                finish(band, wake, no_wake, mask, "brightness temperature (K)")
            }
        })
        .collect();
    let rendered = RenderedPair {
        bands: out,
        kelvin_mask: with.kelvin.map(|k| k.mask),
        slick_mask: with.slick_mask,
    };
    (rendered, surface, t.elapsed().as_secs_f64())
}

/// Every band's image of one scene without a wake (the sea, its slicks and the sensors; what
/// `wakelab run --dry-run` times).
pub fn render_sea_scene(cfg: &wakelab_core::WakelabConfig, bands: &[Band]) -> Vec<Array2<f32>> {
    let sea: SurfaceScene = simulate_surface(cfg, None);
    let (radar, infrared) = (SarScene::new(cfg, &sea), IrScene::new(cfg, &sea));
    bands
        .par_iter()
        .map(|&band| match sensor(band) {
            Sensor::Radar(b) => radar.render(b).sigma0.mapv(|v| v as f32),
            Sensor::Infrared(b) => infrared.render(b).brightness_temperature.mapv(|v| v as f32),
        })
        .collect()
}

fn finish(band: Band, wake: Array2<f32>, no_wake: Array2<f32>, mask: Array2<u8>, quantity: &'static str) -> BandPair {
    let visibility = (visibility(&wake, &mask), visibility(&no_wake, &mask));
    BandPair {
        band,
        wake,
        no_wake,
        mask,
        visibility,
        quantity,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn visibility_is_the_contrast_to_clutter_ratio() {
        // sea alternating 1, 3 (mean 2, sample sd of 4 values = 1.1547); wake at 5
        let image = Array2::from_shape_vec((1, 6), vec![1.0f32, 3.0, 1.0, 3.0, 5.0, 5.0]).unwrap();
        let mask = Array2::from_shape_vec((1, 6), vec![0u8, 0, 0, 0, 1, 1]).unwrap();
        let sd = (4.0f64 / 3.0).sqrt();
        assert!((visibility(&image, &mask) - 3.0 / sd).abs() < 1e-12);
        assert_eq!(visibility(&image, &Array2::zeros((1, 6))), 0.0);
    }
}

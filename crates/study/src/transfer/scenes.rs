//! The transfer study's training scenes (issue 38, item 1): the ships step's 5.12 km C-band
//! scenes, each drawing its acquisition and sea from the plan's ranges, and the way its image
//! reaches a user (calibrated sigma0, or an 8-bit display stretch).

use super::look_alikes::LookAlikes;
use crate::steps::open_sea::SeaPair;
use crate::steps::ships::{scene_config, SPACING, SPEEDS};
use ndarray::Array2;
use rand::{RngExt, SeedableRng};
use wakelab_core::WakelabConfig;
use wakelab_dataset::transfer::TransferPlan;

/// Scene indices of the training scenes (the ships step's are 0..27, the calibration step's
/// open sea 1000 and on, the transfer study's unseen open sea 2000 and on).
pub const FIRST_TRAINING_SCENE: usize = 5000;
pub const FIRST_UNSEEN_SCENE: usize = 2000;

/// How an 8-bit display image is made from sigma0: the amplitude (or its dB, `log`) clipped at
/// two percentiles, raised to `gamma`, spread over `span` grey levels from `offset` (a sea shown
/// in a narrow band of grey, as beside bright ships or land) and quantised; then, where
/// `jpeg_quality` is set, JPEG-compressed at that quality.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DisplayStretch {
    pub log: bool,
    pub low_percentile: f64,
    pub high_percentile: f64,
    pub gamma: f64,
    pub span: f64,
    pub offset: f64,
    pub jpeg_quality: Option<u8>,
}

impl DisplayStretch {
    /// The grey levels of `sigma0`.
    pub fn grey(&self, sigma0: &Array2<f32>) -> Array2<u8> {
        let value = |s: f32| -> f64 {
            let s = (s as f64).max(1e-12);
            if self.log {
                10.0 * s.log10()
            } else {
                s.sqrt()
            }
        };
        let mut sorted: Vec<f64> = sigma0.iter().map(|&s| value(s)).collect();
        sorted.sort_by(f64::total_cmp);
        let at = |p: f64| sorted[((p / 100.0) * (sorted.len() - 1) as f64).round() as usize];
        let (lo, hi) = (at(self.low_percentile), at(self.high_percentile));
        let range = (hi - lo).max(1e-12);
        let grey = sigma0.mapv(|s| {
            let x = ((value(s) - lo) / range).clamp(0.0, 1.0).powf(self.gamma);
            (self.offset + self.span * x).round().clamp(0.0, 255.0) as u8
        });
        match self.jpeg_quality {
            Some(quality) => jpeg_round_trip(&grey, quality),
            None => grey,
        }
    }

    /// `sigma0` as a display image read back the way `wakelab detect --scale display` reads an
    /// 8-bit image (grey level g as 10^(g/10)), so that the product path's averaging and the
    /// detector's dB see what they see on a user's PNG or JPEG.
    pub fn apply(&self, sigma0: &Array2<f32>) -> Array2<f32> {
        self.grey(sigma0).mapv(|g| 10f64.powf(g as f64 / 10.0) as f32)
    }
}

/// `grey` compressed as a JPEG of `quality` and decoded.
fn jpeg_round_trip(grey: &Array2<u8>, quality: u8) -> Array2<u8> {
    let (rows, cols) = grey.dim();
    let pixels: Vec<u8> = grey.iter().copied().collect();
    let mut bytes = Vec::new();
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut bytes, quality)
        .encode(&pixels, cols as u32, rows as u32, image::ExtendedColorType::L8)
        .expect("an in-memory grey image encodes");
    let decoded = image::load_from_memory_with_format(&bytes, image::ImageFormat::Jpeg)
        .expect("a JPEG just written decodes")
        .into_luma8();
    Array2::from_shape_vec((rows, cols), decoded.into_raw()).expect("the JPEG keeps the image's size")
}

/// How a training scene reaches the detector: a brightness trend across the scene (dB per km,
/// towards a direction in the image, the same in both twins: the incidence and antenna-pattern
/// trends of real products, and the shading of screenshots), then calibrated sigma0 or an 8-bit
/// display image.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Delivery {
    pub trend_db_per_km: f64,
    pub trend_direction: f64,
    pub display: Option<DisplayStretch>,
}

impl Delivery {
    /// `sigma0` (pixels of `spacing` m) as delivered.
    pub fn apply(&self, sigma0: &Array2<f32>, spacing: f64) -> Array2<f32> {
        let (sin, cos) = self.trend_direction.to_radians().sin_cos();
        let (rows, cols) = sigma0.dim();
        let (r0, c0) = (0.5 * rows as f64, 0.5 * cols as f64);
        let trended = Array2::from_shape_fn((rows, cols), |(r, c)| {
            let km = ((c as f64 - c0) * sin - (r as f64 - r0) * cos) * spacing / 1000.0;
            sigma0[[r, c]] * 10f64.powf(self.trend_db_per_km * km / 10.0) as f32
        });
        match &self.display {
            Some(d) => d.apply(&trended),
            None => trended,
        }
    }
}

/// Training scene `j`: its configuration and its delivery (None: calibrated sigma0), or None
/// when the scene cannot be drawn (the study's wake too short for it).
pub fn training_scene(base: &WakelabConfig, plan: &TransferPlan, j: usize) -> Option<(WakelabConfig, Delivery)> {
    let k = FIRST_TRAINING_SCENE + j;
    let mut rng =
        rand_chacha::ChaCha8Rng::seed_from_u64(base.seed ^ plan.seed.rotate_left(32) ^ (0x7AA5_0000 + k as u64));
    let in_view = !rng.random_bool(plan.free_wake_fraction);
    let mut c = scene_config(base, k, SPEEDS[j % SPEEDS.len()], in_view, SPACING)?;
    let draw =
        |rng: &mut rand_chacha::ChaCha8Rng, [lo, hi]: [f64; 2]| if hi > lo { rng.random_range(lo..hi) } else { lo };
    c.environment.wind.speed = draw(&mut rng, plan.wind_speed);
    c.environment.wind.variability = draw(&mut rng, plan.wind_variability);
    c.platform.incidence = draw(&mut rng, plan.incidence);
    c.sar.looks = rng.random_range(plan.looks[0]..=plan.looks[1]);
    c.sar.resolution = draw(&mut rng, plan.resolution) * c.scene.pixel_spacing;
    c.sar.nesz = Some(draw(&mut rng, plan.nesz));
    c.slicks.coverage = draw(&mut rng, plan.slick_coverage);
    c.slicks.elongation = draw(&mut rng, plan.slick_elongation);
    if !rng.random_bool(plan.swell_fraction) {
        c.environment.swell.amplitude = 0.0;
    }
    let display = rng.random_bool(plan.display_fraction).then(|| {
        let span = rng.random_range(30.0..255.0);
        DisplayStretch {
            log: rng.random_bool(0.5),
            low_percentile: rng.random_range(0.0..2.0),
            high_percentile: rng.random_range(98.0..100.0),
            gamma: rng.random_range(0.6..1.6),
            span,
            offset: rng.random_range(0.0..=255.0 - span),
            jpeg_quality: rng.random_bool(0.7).then(|| rng.random_range(50..=95)),
        }
    });
    let delivery = Delivery {
        trend_db_per_km: rng.random_range(-plan.trend_db_per_km..=plan.trend_db_per_km),
        trend_direction: rng.random_range(0.0..360.0),
        display,
    };
    c.validate().ok()?;
    Some((c, delivery))
}

/// The look-alikes of scene `c` (drawn from its seed and the plan's ranges) drawn onto both
/// twins of `pair` alike, so that they still differ by the ship and its wake alone.
pub(crate) fn add_look_alikes(pair: &mut SeaPair, c: &WakelabConfig, plan: &TransferPlan) -> LookAlikes {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(c.seed ^ 0x100C_A11E);
    let [few, many] = plan.wakeless_ships;
    let ships = rng.random_range(few..=many);
    let side = pair.with.nrows().min(pair.with.ncols());
    // drawn only when the plan asks for some: a study without them keeps its draws, and bytes
    let strong = match plan.strong_targets {
        [0, 0] => 0,
        [few, many] => rng.random_range(few..=many),
    };
    let look_alikes = LookAlikes::draw(&mut rng, side, pair.spacing, ships, plan.look_alike_fraction, strong);
    // the twin without the wake's mean: both twins get the same targets
    let sea = pair.without.iter().map(|&v| v as f64).sum::<f64>() / pair.without.len().max(1) as f64;
    for image in [&mut pair.with, &mut pair.without] {
        let mut speckle = rng.clone();
        look_alikes.apply(image, pair.spacing, c.sar.looks, sea, &mut speckle);
    }
    look_alikes
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A display stretch maps the clipped range onto 0-255 grey levels, read back as 10^(g/10).
    #[test]
    fn a_display_stretch_gives_grey_levels_read_back_as_decibels() {
        let sigma0 = Array2::from_shape_fn((10, 10), |(r, c)| 1e-3 * (1 + r * 10 + c) as f32);
        let stretch = DisplayStretch {
            log: true,
            low_percentile: 0.0,
            high_percentile: 100.0,
            gamma: 1.0,
            span: 255.0,
            offset: 0.0,
            jpeg_quality: None,
        };
        let grey = stretch.apply(&sigma0).mapv(|v| 10.0 * (v as f64).log10());
        assert!((grey[[0, 0]] - 0.0).abs() < 1e-3, "{}", grey[[0, 0]]);
        assert!((grey[[9, 9]] - 255.0).abs() < 1e-3, "{}", grey[[9, 9]]);
        assert!(grey.iter().all(|g| (g - g.round()).abs() < 1e-3));
        // sigma0 x 10 is 10 dB more: (10 - 0) / (20 - 0) of the span
        let middle = 255.0 * (10.0 * (10e-3f64).log10() + 30.0) / 20.0;
        assert!(
            (grey[[0, 9]] - middle.round()).abs() < 1e-3,
            "{} {middle}",
            grey[[0, 9]]
        );
    }

    /// A JPEG of quality 90 keeps a smooth grey ramp within a few levels, and a trend of 1 dB
    /// per km towards the image's right makes the right edge of a 1 km image 1 dB brighter than
    /// its left.
    #[test]
    fn a_jpeg_keeps_a_ramp_and_a_trend_brightens_its_direction() {
        let ramp = Array2::from_shape_fn((64, 64), |(r, c)| (50 + r + c) as u8);
        let back = jpeg_round_trip(&ramp, 90);
        let worst = ramp
            .iter()
            .zip(back.iter())
            .map(|(&a, &b)| (a as i32 - b as i32).abs())
            .max()
            .unwrap();
        assert!(worst <= 3, "{worst}");
        let flat = Array2::from_elem((3, 101), 0.01f32);
        let trend = Delivery {
            trend_db_per_km: 1.0,
            trend_direction: 90.0,
            display: None,
        };
        let out = trend.apply(&flat, 10.0);
        let db = |v: f32| 10.0 * (v as f64).log10();
        assert!((db(out[[1, 100]]) - db(out[[1, 0]]) - 1.0).abs() < 1e-4);
        // the trend is 0 dB at the scene's centre, column 50.5: half a pixel (5 m) right of column 50
        assert!((db(out[[1, 50]]) + 20.0 + 0.005).abs() < 1e-4, "{}", db(out[[1, 50]]));
    }

    /// The look-alikes go onto both twins alike: a pair whose twins differ by a dark line keeps
    /// exactly that ratio everywhere (the ships' own speckle drawn the same in both), the ships
    /// brighten the sea by their cross section, the strong targets peak their stated decibels
    /// over the sea's mean, and their counts are the plan's.
    #[test]
    fn look_alikes_leave_the_twins_differing_by_the_wake_alone() {
        let (base, mut plan) = (WakelabConfig::default(), TransferPlan::default());
        plan.wakeless_ships = [3, 3];
        plan.strong_targets = [2, 2];
        plan.look_alike_fraction = 1.0;
        let side = 256;
        let without = Array2::from_elem((side, side), 0.01f32);
        let mut with = without.clone();
        with.row_mut(100).fill(0.005);
        let mut pair = SeaPair {
            with,
            without,
            track: ((100.0, 0.0), (100.0, 255.0)),
            spacing: 10.0,
            km2: 6.5536,
        };
        let before = (pair.with.sum() as f64, pair.without.sum() as f64);
        let drawn = add_look_alikes(&mut pair, &base, &plan);
        assert_eq!((drawn.ships.len(), drawn.strong_targets.len()), (3, 2));
        for t in &drawn.strong_targets {
            let peak = pair.without[[t.centre.0 as usize, t.centre.1 as usize]] as f64;
            let db = 10.0 * (peak / 0.01).log10();
            assert!((db - t.peak_db).abs() < 0.1, "{db} against {}", t.peak_db);
        }
        for ((r, c), &w) in pair.with.indexed_iter() {
            let o = pair.without[[r, c]];
            if r != 100 {
                assert_eq!(w, o, "({r}, {c})");
            }
        }
        // the two twins gain the same cross section (m^2 over 100 m^2 pixels) beyond the factors
        let gained = (pair.with.sum() as f64 - before.0, pair.without.sum() as f64 - before.1);
        assert!(
            gained.1 > 0.0 && (gained.0 - gained.1).abs() < 0.05 * gained.1.abs() + 1.0,
            "{gained:?}"
        );
    }

    #[test]
    fn the_training_scenes_span_the_plan_and_are_valid() {
        let study =
            wakelab_dataset::study::Study::from_toml_str(wakelab_dataset::study::TRANSFER_STUDY, "transfer").unwrap();
        let (base, plan) = (study.base_config().unwrap(), study.transfer.clone().unwrap());
        let scenes: Vec<_> = (0..plan.scenes)
            .filter_map(|j| training_scene(&base, &plan, j))
            .collect();
        assert!(
            scenes.len() >= plan.scenes * 9 / 10,
            "{} of {}",
            scenes.len(),
            plan.scenes
        );
        let winds: Vec<f64> = scenes.iter().map(|s| s.0.environment.wind.speed).collect();
        // the plan's winds (the embedded 2-6 m/s), both ends of the range reached
        let [low, high] = plan.wind_speed;
        assert!(winds.iter().all(|w| (low..high).contains(w)), "{winds:?}");
        let near = 0.15 * (high - low);
        assert!(winds.iter().any(|&w| w < low + near) && winds.iter().any(|&w| w > high - near));
        let looks: Vec<u32> = scenes.iter().map(|s| s.0.sar.looks).collect();
        assert!(looks.contains(&1) && looks.contains(&10));
        let shown = scenes.iter().filter(|s| s.1.display.is_some()).count();
        assert!(shown > 0 && shown < scenes.len());
    }
}

//! The `[transfer]` table of a study file (issue 38): detectors for real images, trained on
//! windows of kilometres cut from simulated C-band scenes whose every acquisition and sea is
//! drawn from wide ranges (domain randomisation), with look-alikes as negatives.
//!
//! ```toml
//! [transfer]
//! scenes = 192                     # training scenes, each rendered with its wake and without
//! footprints = [1280.0, 2560.0]    # window sides on the ground (m), each a detector
//! window = 64                      # window side (pixels): spacing = footprint / window
//! wind_speed = [2.0, 15.0]         # m/s
//! input = "line_sums"              # what the classifier reads: pixels (default) or line_sums
//! head = "global_max"              # how it decides: flatten (Table 4.1, default) or global_max
//! ```

use serde::{Deserialize, Serialize};
use wakelab_core::{ConfigError, WakelabError};
use wakelab_schema::architecture::{ClassifierHead, InputForm};
use wakelab_schema::results::{Architecture, MIN_CLASSIFIER_SIZE};

/// What a transfer study trains and on what scenes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TransferPlan {
    /// Training scenes of 5.12 km at 10 m, each rendered with its ship and wake and without.
    pub scenes: usize,
    /// Ground footprints of the detectors' windows (m); one detector each.
    pub footprints: Vec<f64>,
    /// Window side (pixels).
    pub window: usize,
    pub architecture: Architecture,
    /// What the classifier reads of a window: `pixels` (the spec's input), `line_sums` (the
    /// window's Radon transform; a wake's line becomes a point) or `line_sums_ships_masked` (the
    /// same with the ships' returns masked out first).
    pub input: InputForm,
    /// How the classifier decides from its last feature map: `flatten` (Table 4.1) or
    /// `global_max` (each channel's largest response, wherever in the window it lies).
    pub head: ClassifierHead,
    pub epochs: usize,
    pub batch_size: usize,
    pub learning_rate: f64,
    pub weight_decay: f64,
    /// Open-sea scenes (5.12 km) that set each detector's threshold, and as many other ones,
    /// never seen, on which its false-alarm rate is then counted.
    pub open_sea_scenes: usize,
    /// Alarms per 1,000 km^2 of open sea the threshold holds.
    pub alarms_per_1000_km2: f64,
    /// The ranges each training scene draws from (uniformly).
    pub wind_speed: [f64; 2],
    pub incidence: [f64; 2],
    pub looks: [u32; 2],
    /// Impulse-response width over pixel spacing: 1 gives uncorrelated speckle, 2.5 a lag-1
    /// autocorrelation near that of oversampled products.
    pub resolution: [f64; 2],
    /// Noise-equivalent sigma zero (dB).
    pub nesz: [f64; 2],
    pub slick_coverage: [f64; 2],
    pub slick_elongation: [f64; 2],
    pub wind_variability: [f64; 2],
    /// Share of the scenes with swell (the study's base swell; the rest calm).
    pub swell_fraction: f64,
    /// Share of the scenes whose ship has sailed out of view, leaving its wake alone.
    pub free_wake_fraction: f64,
    /// Share of the scenes delivered as display-stretched 8-bit images (percentile clip, gamma,
    /// the sea in 30-255 grey levels, 70 % of them JPEG-compressed at quality 50-95), the way
    /// screenshots and JPEGs reach users.
    pub display_fraction: f64,
    /// Largest brightness trend across a scene (dB per km, any direction).
    pub trend_db_per_km: f64,
    /// Ships without a visible wake (anchored, or too slow to leave one) in each scene of the
    /// look-alike test set (and of training, with `look_alike_training`), drawn uniformly
    /// from this range.
    pub wakeless_ships: [usize; 2],
    /// Targets so bright that their sidelobes draw a line along the image's row and column
    /// through them (the cross of a large ship or a platform), in each such scene, drawn
    /// uniformly from this range.
    pub strong_targets: [usize; 2],
    /// Chance of each of an internal-wave packet, a rain cell and a current front in such a
    /// scene.
    pub look_alike_fraction: f64,
    /// Whether training draws those look-alikes too (windows on them as negatives), keeps only
    /// the wake windows where the wake shows, and repeats them to balance the classes. On in
    /// the embedded study, which reads line sums; reading pixels, the Table 4.1 classifier
    /// learnt nothing with it (see docs/results.md).
    pub look_alike_training: bool,
    /// A folder of real SAR images without wakes (each with its `NAME.geojson`, as `--real`
    /// reads them), onto whose windows training also draws each simulated wake that shows, each
    /// beside the same window without it: the detectors learn the wake on a real sensor's
    /// clutter, not only on the simulator's (`wakelab run --sea-images DIR`). None: simulated
    /// sea only.
    pub sea_images: Option<std::path::PathBuf>,
    /// A folder of real SAR images with their wakes drawn (each with its `NAME.geojson` in
    /// pixel coordinates, as `--real` reads them), from which training also takes windows along
    /// each drawn wake (wakes) and windows clear of every drawn wake (no wake): the detectors
    /// learn real wakes and the real clutter around them (`wakelab run --wake-images DIR`).
    /// None: no real wake.
    pub wake_images: Option<std::path::PathBuf>,
    pub seed: u64,
}

impl Default for TransferPlan {
    fn default() -> Self {
        Self {
            scenes: 192,
            footprints: vec![1280.0, 2560.0],
            window: 64,
            architecture: Architecture::Base,
            input: InputForm::Pixels,
            head: ClassifierHead::Flatten,
            epochs: 40,
            batch_size: 16,
            learning_rate: 1e-3,
            weight_decay: 1e-4,
            open_sea_scenes: 40,
            alarms_per_1000_km2: 1.0,
            wind_speed: [2.0, 15.0],
            incidence: [15.0, 50.0],
            looks: [1, 10],
            resolution: [1.0, 2.5],
            nesz: [-35.0, -18.0],
            slick_coverage: [0.0, 0.3],
            slick_elongation: [1.0, 16.0],
            wind_variability: [0.0, 0.3],
            swell_fraction: 0.5,
            free_wake_fraction: 0.25,
            display_fraction: 0.3,
            trend_db_per_km: 0.3,
            wakeless_ships: [0, 6],
            strong_targets: [0, 0],
            look_alike_fraction: 0.3,
            look_alike_training: false,
            sea_images: None,
            wake_images: None,
            seed: 0,
        }
    }
}

fn plan_error(field: &str, value: impl ToString, allowed: &str) -> WakelabError {
    ConfigError::new(format!("transfer.{field}"), value, allowed).into()
}

impl TransferPlan {
    /// Every value against its allowed range; the error names the field.
    pub fn validate(&self) -> Result<(), WakelabError> {
        for (name, v, lo, hi) in [
            ("scenes", self.scenes, 2, 10_000),
            ("window", self.window, MIN_CLASSIFIER_SIZE, 512),
            ("epochs", self.epochs, 1, 10_000),
            ("batch_size", self.batch_size, 1, 4096),
            ("open_sea_scenes", self.open_sea_scenes, 1, 10_000),
        ] {
            if !(lo..=hi).contains(&v) {
                return Err(plan_error(name, v, &format!("an integer in [{lo}, {hi}]")));
            }
        }
        if self.architecture == Architecture::Unet {
            return Err(plan_error("architecture", "unet", "\"base\" or \"cls\" (a classifier)"));
        }
        if self.footprints.is_empty() {
            return Err(plan_error(
                "footprints",
                "[]",
                "a non-empty list of sides in [320, 5120] m",
            ));
        }
        for &f in &self.footprints {
            let spacing = f / self.window as f64;
            // the scenes are 5.12 km at 10 m, averaged by a whole factor to the window's spacing
            let whole = (spacing / 10.0 - (spacing / 10.0).round()).abs() < 1e-9;
            if !(320.0..=5120.0).contains(&f) || !whole || spacing < 10.0 {
                return Err(plan_error(
                    "footprints",
                    f,
                    &format!(
                        "sides in [320, 5120] m that make the window's spacing (side / {}) a whole multiple of 10 m",
                        self.window
                    ),
                ));
            }
        }
        let ranges: [(&str, [f64; 2], f64, f64); 9] = [
            ("wind_speed", self.wind_speed, 0.5, 30.0),
            ("incidence", self.incidence, 15.0, 60.0),
            ("resolution", self.resolution, 1.0, 4.0),
            ("nesz", self.nesz, -60.0, 0.0),
            ("slick_coverage", self.slick_coverage, 0.0, 0.9),
            ("slick_elongation", self.slick_elongation, 1.0, 50.0),
            ("wind_variability", self.wind_variability, 0.0, 0.5),
            ("looks", [self.looks[0] as f64, self.looks[1] as f64], 1.0, 100.0),
            ("learning_rate", [self.learning_rate; 2], 1e-6, 1.0),
        ];
        for (name, [lo, hi], min, max) in ranges {
            if !(lo >= min && hi <= max && lo <= hi) {
                return Err(plan_error(
                    name,
                    format!("[{lo}, {hi}]"),
                    &format!("low <= high, both in [{min}, {max}]"),
                ));
            }
        }
        for (name, v) in [
            ("swell_fraction", self.swell_fraction),
            ("free_wake_fraction", self.free_wake_fraction),
            ("display_fraction", self.display_fraction),
            ("look_alike_fraction", self.look_alike_fraction),
        ] {
            if !(0.0..=1.0).contains(&v) {
                return Err(plan_error(name, v, "in [0, 1]"));
            }
        }
        for (name, [few, many]) in [
            ("wakeless_ships", self.wakeless_ships),
            ("strong_targets", self.strong_targets),
        ] {
            if few > many || many > 50 {
                return Err(plan_error(
                    name,
                    format!("[{few}, {many}]"),
                    "low <= high, both in [0, 50]",
                ));
            }
        }
        if !(0.0..=3.0).contains(&self.trend_db_per_km) {
            return Err(plan_error(
                "trend_db_per_km",
                self.trend_db_per_km,
                "in [0, 3] dB per km",
            ));
        }
        if !(0.0..=10.0).contains(&self.weight_decay) {
            return Err(plan_error("weight_decay", self.weight_decay, "in [0, 10]"));
        }
        if !(self.alarms_per_1000_km2 > 0.0 && self.alarms_per_1000_km2 <= 1000.0) {
            return Err(plan_error(
                "alarms_per_1000_km2",
                self.alarms_per_1000_km2,
                "in (0, 1000]",
            ));
        }
        if let Some(dir) = self.sea_images.as_ref().filter(|d| !d.is_dir()) {
            return Err(plan_error(
                "sea_images",
                dir.display(),
                "a folder of real SAR images without wakes, each with its NAME.geojson",
            ));
        }
        if let Some(dir) = self.wake_images.as_ref().filter(|d| !d.is_dir()) {
            return Err(plan_error(
                "wake_images",
                dir.display(),
                "a folder of real SAR images, each with its NAME.geojson drawing its wakes",
            ));
        }
        Ok(())
    }

    /// The window's pixel spacing (m) of `footprint`.
    pub fn spacing(&self, footprint: f64) -> f64 {
        footprint / self.window as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_plan_is_valid_and_bad_values_name_their_field() {
        TransferPlan::default().validate().unwrap();
        let bad = |f: fn(&mut TransferPlan), field: &str| {
            let mut p = TransferPlan::default();
            f(&mut p);
            let e = p.validate().unwrap_err().to_string();
            assert!(e.contains(&format!("transfer.{field}")), "{e}");
        };
        bad(|p| p.footprints = vec![1000.0], "footprints");
        bad(|p| p.footprints.clear(), "footprints");
        bad(|p| p.wind_speed = [8.0, 3.0], "wind_speed");
        bad(|p| p.looks = [0, 4], "looks");
        bad(|p| p.display_fraction = 1.5, "display_fraction");
        bad(|p| p.architecture = Architecture::Unet, "architecture");
        bad(|p| p.scenes = 1, "scenes");
        bad(|p| p.wakeless_ships = [4, 2], "wakeless_ships");
        bad(|p| p.strong_targets = [0, 51], "strong_targets");
        bad(|p| p.look_alike_fraction = -0.1, "look_alike_fraction");
    }

    /// `input` reads by name; a wrong name lists the allowed ones.
    #[test]
    fn the_input_form_reads_by_name() {
        let plan: TransferPlan = toml::from_str("input = \"line_sums\"").unwrap();
        assert_eq!(plan.input, InputForm::LineSums);
        assert_eq!(toml::from_str::<TransferPlan>("").unwrap().input, InputForm::Pixels);
        let e = toml::from_str::<TransferPlan>("input = \"radon\"")
            .unwrap_err()
            .to_string();
        assert!(e.contains("pixels") && e.contains("line_sums"), "{e}");
    }
}

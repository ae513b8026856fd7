//! What the transfer study found (`transfer/transfer.json`): per footprint, its training and
//! what it does on simulated open sea.

use serde::{Deserialize, Serialize};
use std::path::PathBuf;
use wakelab_dataset::transfer::TransferPlan;
use wakelab_learn::calibration::ReliabilityBin;

/// What one detector of a footprint learnt and does on simulated open sea.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct TransferDetector {
    /// The window's side on the ground (m), its pixels and their spacing (m).
    pub footprint: f64,
    pub window: usize,
    pub spacing: f64,
    pub training_windows: usize,
    pub wake_windows: usize,
    /// The windows cut on wakes' tracks, and those in which the wake shows against the sea at
    /// this spacing (`windows::wake_shows`: a strip along the track whose change exceeds 3
    /// times the sea profile's deviation): how much of the training can be learnt from the
    /// wake rather than from the ship at its apex.
    pub track_windows: usize,
    pub track_windows_shown: usize,
    /// The wake's visibility in those windows as delivered (`visibility::visibility`: its
    /// strongest strip along the track against the sea's strip-to-strip deviation).
    pub track_visibility: Option<super::visibility::Spread>,
    /// The same measure on the same windows of the sea without the ship: its floor.
    pub sea_visibility: Option<super::visibility::Spread>,
    pub training_seconds: f64,
    /// The last epoch's loss and accuracy on the training windows.
    pub final_loss: f64,
    pub final_accuracy: f64,
    /// The open sea the threshold was set on: its area, the alarms per 1,000 km^2 at 0.5 and
    /// at the threshold, and the wakes found in the same seas at either (of `scenes`).
    pub scenes: usize,
    pub km2: f64,
    pub alarms_at_half: f64,
    pub threshold: f64,
    pub alarms_at_threshold: f64,
    pub wakes_found_at_half: usize,
    pub wakes_found: usize,
    pub off_wake_alarms: f64,
    /// ROC AUC of the windows on a wake against the open sea's windows.
    pub window_auc: Option<f64>,
    /// Open sea it never saw: area, alarms per 1,000 km^2 at the threshold, wakes found (of
    /// `unseen_scenes`) and alarms off the wake per 1,000 km^2.
    pub unseen_scenes: usize,
    pub unseen_km2: f64,
    pub unseen_alarms: f64,
    pub unseen_wakes_found: usize,
    pub unseen_off_wake_alarms: f64,
    /// The look-alike test set: the unseen seas with ships without a wake, internal waves,
    /// rain cells and fronts drawn on them.
    pub look_alikes: LookAlikeScore,
    /// Reliability of the probabilities on the unseen seas' windows (those within half a
    /// window of a wake's track against every open-sea window), 10 bins, and its expected
    /// calibration error.
    pub reliability: Vec<ReliabilityBin>,
    pub calibration_error: f64,
    /// The real wake-free sea of `--sea-images`, where given, on which the threshold also holds
    /// the alarm rate.
    #[serde(default)]
    pub real_sea: Option<RealSeaThreshold>,
    pub file: PathBuf,
}

/// The threshold that holds the alarm rate on the real sea of `--sea-images`: the images
/// scanned, their area, that threshold alone, and the alarms per 1,000 km^2 there at the
/// detector's threshold (the larger of it and the simulated open sea's).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RealSeaThreshold {
    pub images: usize,
    pub km2: f64,
    pub threshold: f64,
    pub alarms_at_threshold: f64,
    /// The separate alarms' probabilities, for the rate at any threshold.
    #[serde(skip)]
    pub alarms: Vec<f64>,
    /// The strongest of them with their images ([`super::real_sea::STRONGEST`]), strongest
    /// first: where a wake left undrawn in the "wake-free" sea would raise the threshold.
    #[serde(default)]
    pub strongest: Vec<SeaAlarm>,
}

/// One alarm on the real sea: its image's file name, its cell's centre in that image's own
/// pixels (row down, column right) and its probability.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SeaAlarm {
    pub image: String,
    pub row: f64,
    pub col: f64,
    pub probability: f64,
}

impl RealSeaThreshold {
    /// The same with the alarms per 1,000 km^2 at `threshold`.
    pub fn at(mut self, threshold: f64) -> Self {
        let above = self.alarms.iter().filter(|&&p| p > threshold).count();
        self.alarms_at_threshold = above as f64 * 1000.0 / self.km2.max(f64::MIN_POSITIVE);
        self
    }
}

/// What a detector does on the look-alike test set (issue 38, item 3).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct LookAlikeScore {
    pub km2: f64,
    /// Alarms per 1,000 km^2 at the threshold on the sea without a ship and its wake.
    pub alarms: f64,
    /// Ships without a wake drawn there, and the alarms within 500 m of one.
    pub ships: usize,
    pub ship_alarms: usize,
    /// The same seas with a ship and its wake: wakes found, and alarms off the wake per 1,000
    /// km^2.
    pub wakes_found: usize,
    pub off_wake_alarms: f64,
}

/// `transfer/transfer.json`.
#[derive(Serialize, Deserialize)]
pub struct TransferResults {
    pub(super) key: String,
    pub seconds: f64,
    pub plan: TransferPlan,
    /// Training scenes rendered (with and without the ship), of which delivered as 8-bit.
    pub training_scenes: usize,
    pub display_scenes: usize,
    pub render_seconds: f64,
    pub alarms_target: f64,
    pub detectors: Vec<TransferDetector>,
}

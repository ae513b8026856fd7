//! What the learning steps share: their context, and the cache that lets a rerun reuse a step
//! whose inputs have not changed.

use crate::{Display, StepTime};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::time::Instant;
use wakelab_learn::data::Dataset;
use wakelab_learn::evaluate::{CurvePoint, EvalOptions, Output};
use wakelab_learn::masks::MaskScore;
use wakelab_learn::models::Architecture;

/// A learning step's results as cached beside its files.
#[derive(Serialize, Deserialize)]
pub(crate) struct CachedStep {
    pub key: String,
    pub seconds: f64,
    pub outputs: Vec<Output>,
    pub curves: Vec<CurvePoint>,
    /// Required: the key does not hash wakelab's code, so a cache written before mask scores
    /// existed must fail to read (and be recomputed) rather than give an empty IoU table.
    pub mask_scores: Vec<MaskScore>,
}

pub(crate) fn read_cache(path: &Path, key: &str) -> Option<CachedStep> {
    let text = std::fs::read_to_string(path).ok()?;
    let cached: CachedStep = serde_json::from_str(&text).ok()?;
    (cached.key == key).then_some(cached)
}

/// Relative cost of one U-Net image pass against one classifier image pass (measured at 64 x 64
/// on the CPU backend: width 16 about 40x), for the progress display's time left.
pub(crate) fn unet_cost(width: usize) -> u64 {
    (40 * width / 16).max(1) as u64
}

/// Work units of training `options` on `images` training images (for the progress display).
pub(crate) fn training_units(options: &EvalOptions, images: usize, runs: usize) -> u64 {
    let per_run: u64 = options
        .architectures
        .iter()
        .map(|a| {
            options.classifier.epochs as u64
                + match a {
                    Architecture::Unet => options.unet.epochs as u64 * unet_cost(options.unet.width),
                    _ => 0,
                }
        })
        .sum();
    per_run * (images * runs * options.band_sets.len()) as u64
}

/// The wall time of `step` begun at `start`; `computed`: the seconds it took when it was computed
/// (a reused step).
pub(crate) fn step_time(step: &str, start: Instant, computed: Option<f64>) -> StepTime {
    let seconds = start.elapsed().as_secs_f64();
    StepTime {
        step: step.to_string(),
        seconds,
        computed_seconds: computed.unwrap_or(seconds),
        reused: computed.is_some(),
    }
}

/// What the learning steps share.
pub(crate) struct Context<'a> {
    pub dataset: &'a Dataset,
    options: &'a EvalOptions,
    /// Hash of the dataset's manifest (part of every step key).
    manifest_hash: &'a str,
    device: &'a wakelab_learn::device::Device,
    display: &'a Display,
}

type ContextParts<'a> = (
    &'a Dataset,
    &'a EvalOptions,
    &'a str,
    &'a wakelab_learn::device::Device,
    &'a Display,
);

impl<'a> Context<'a> {
    pub(crate) fn new(
        dataset: &'a Dataset,
        options: &'a EvalOptions,
        manifest_hash: &'a str,
        device: &'a wakelab_learn::device::Device,
        display: &'a Display,
    ) -> Self {
        Self {
            dataset,
            options,
            manifest_hash,
            device,
            display,
        }
    }

    pub(crate) fn parts(&self) -> ContextParts<'a> {
        (
            self.dataset,
            self.options,
            self.manifest_hash,
            self.device,
            self.display,
        )
    }
}

/// Write a step's results as pretty JSON at `file` (its folder made first).
pub(crate) fn write_results<T: Serialize>(file: &Path, results: &T) -> crate::Result<()> {
    let dir = file.parent().expect("a folder");
    std::fs::create_dir_all(dir).map_err(|e| wakelab_core::WakelabError::io(dir, e))?;
    wakelab_core::io::write_atomically(file, serde_json::to_string_pretty(results)?.as_bytes())?;
    Ok(())
}

/// Scene pixels per detector pixel: the detector's training spacing over the scenes' `spacing`
/// (m), None unless a whole number of at least 1.
pub(crate) fn whole_factor(info: &wakelab_learn::store::ModelInfo, spacing: f64) -> Option<usize> {
    let ratio = info.pixel_spacing.unwrap_or(spacing) / spacing;
    (ratio >= 1.0 && (ratio - ratio.round()).abs() <= 1e-6).then(|| ratio.round() as usize)
}

/// `image` averaged over `factor` x `factor` pixels (itself when `factor` is 1).
pub(crate) fn at_factor(image: &ndarray::Array2<f32>, factor: usize) -> std::borrow::Cow<'_, ndarray::Array2<f32>> {
    if factor == 1 {
        std::borrow::Cow::Borrowed(image)
    } else {
        let f = factor as f64;
        std::borrow::Cow::Owned(wakelab_products::resample::area_average(image, f, f))
    }
}

pub(crate) fn fnv_hex(text: &str) -> String {
    format!("{:016x}", wakelab_dataset::fnv(text))
}

/// What a learning step's results depend on: the dataset's manifest, the options and wakelab.
pub(crate) fn step_key(manifest_hash: &str, options: &EvalOptions) -> String {
    fnv_hex(&format!("{manifest_hash} {options:?} {}", env!("CARGO_PKG_VERSION")))
}

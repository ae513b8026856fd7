//! The files a learning stage writes: outputs, metrics and curves as CSV and JSON, and the
//! trained detectors (safetensors).

use crate::Result;
use std::path::{Path, PathBuf};
use wakelab_core::io::write_atomically;
use wakelab_core::WakelabError;
use wakelab_learn::evaluate::{CurvePoint, Evaluation, Output, Summary};
use wakelab_learn::masks::MaskScore;
use wakelab_learn::models::Architecture;
use wakelab_learn::store::save_detector;
use wakelab_schema::band::Input;

/// Rows as CSV (RFC 4180), one column per field of the first row.
pub fn csv<T: serde::Serialize>(rows: &[T]) -> Result<Vec<u8>> {
    Ok(wakelab_core::io::csv_of_rows(rows)?.into_bytes())
}

/// Where [`write_evaluation`] saves the detector of `input` and `architecture` in an
/// evaluation's directory `dir` (`models/<input>_<architecture>.safetensors`).
pub fn detector_path(dir: &Path, input: &Input, architecture: Architecture) -> PathBuf {
    dir.join("models").join(format!("{input}_{architecture}.safetensors"))
}

/// Write an evaluation's files: outputs, metrics (CSV, JSON), curves, the U-Net masks' IoU and
/// the detectors.
pub fn write_evaluation(dir: &Path, evaluation: &Evaluation) -> Result<()> {
    let models = dir.join("models");
    std::fs::create_dir_all(&models).map_err(|e| WakelabError::io(&models, e))?;
    write_atomically(dir.join("outputs.csv"), &csv::<Output>(&evaluation.outputs)?)?;
    write_atomically(dir.join("metrics.csv"), &csv::<Summary>(&evaluation.summaries)?)?;
    write_atomically(
        dir.join("metrics.json"),
        serde_json::to_string_pretty(&evaluation.summaries)?.as_bytes(),
    )?;
    write_atomically(dir.join("curves.csv"), &csv::<CurvePoint>(&evaluation.curves)?)?;
    if !evaluation.mask_scores.is_empty() {
        write_atomically(dir.join("mask_iou.csv"), &csv::<MaskScore>(&evaluation.mask_scores)?)?;
    }
    for (detector, info) in &evaluation.detectors {
        save_detector(detector, info, &detector_path(dir, &info.bands, info.architecture))?;
    }
    Ok(())
}

//! The files a learning stage writes: outputs, metrics and curves as CSV and JSON, and the
//! trained detectors (safetensors).

use crate::Result;
use std::io::Write;
use std::path::Path;
use wakelab_core::io::write_atomically;
use wakelab_learn::evaluate::{band_set_name, CurvePoint, Evaluation, Output, Summary};
use wakelab_learn::store::save_detector;

/// Rows as CSV, one column per field of the first row (strings unquoted, null empty).
pub fn csv<T: serde::Serialize>(rows: &[T]) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    let values: Vec<serde_json::Value> = rows
        .iter()
        .map(serde_json::to_value)
        .collect::<std::result::Result<_, _>>()?;
    let Some(first) = values.first().and_then(|v| v.as_object()) else {
        return Ok(out);
    };
    let keys: Vec<String> = first.keys().cloned().collect();
    writeln!(out, "{}", keys.join(","))?;
    for v in &values {
        let cells: Vec<String> = keys
            .iter()
            .map(|k| match &v[k] {
                serde_json::Value::String(s) => s.clone(),
                serde_json::Value::Null => String::new(),
                other => other.to_string(),
            })
            .collect();
        writeln!(out, "{}", cells.join(","))?;
    }
    Ok(out)
}

/// Write an evaluation's files: outputs, metrics (CSV, JSON), curves and the detectors.
pub fn write_evaluation(dir: &Path, evaluation: &Evaluation) -> Result<()> {
    std::fs::create_dir_all(dir.join("models"))?;
    write_atomically(dir.join("outputs.csv"), &csv::<Output>(&evaluation.outputs)?)?;
    write_atomically(dir.join("metrics.csv"), &csv::<Summary>(&evaluation.summaries)?)?;
    write_atomically(
        dir.join("metrics.json"),
        serde_json::to_string_pretty(&evaluation.summaries)?.as_bytes(),
    )?;
    write_atomically(dir.join("curves.csv"), &csv::<CurvePoint>(&evaluation.curves)?)?;
    for (detector, info) in &evaluation.detectors {
        let name = format!("{}_{}.safetensors", band_set_name(&info.bands), info.architecture);
        save_detector(detector, info, &dir.join("models").join(name))?;
    }
    Ok(())
}

//! The range checks every section's `validate` uses: each error names the field as written in
//! TOML, its value and the allowed range.

use crate::error::ConfigError;

pub(super) fn range(field: &str, v: f64, lo: f64, hi: f64, unit: &str) -> Result<(), ConfigError> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(())
    } else {
        Err(ConfigError::new(
            field,
            v,
            format!("must be in [{lo}, {hi}] {unit}").trim_end().to_string(),
        ))
    }
}

pub(super) fn positive(field: &str, v: f64, lo: f64, hi: f64, unit: &str) -> Result<(), ConfigError> {
    range(field, v, lo, hi, unit)
}

pub(super) fn count(field: &str, v: usize, lo: usize, hi: usize) -> Result<(), ConfigError> {
    if (lo..=hi).contains(&v) {
        Ok(())
    } else {
        Err(ConfigError::new(
            field,
            v,
            format!("must be an integer in [{lo}, {hi}]"),
        ))
    }
}

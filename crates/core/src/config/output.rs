//! `[output]`: which files a run writes, with each value's allowed range.

use super::checks::positive;
use crate::error::ConfigError;
use serde::{Deserialize, Serialize};

/// Where and what the run writes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputConfig {
    /// Run directory.
    pub dir: String,
    /// Along-track spacing of the surface (x, y) map (m).
    pub map_dx: f64,
    /// Write NetCDF files.
    pub netcdf: bool,
    /// Write PNG pictures.
    pub pictures: bool,
}

impl OutputConfig {
    /// Check every value of `[output]` against its allowed range; the error names the field.
    pub(super) fn validate(&self) -> Result<(), ConfigError> {
        let o = self;
        if o.dir.trim().is_empty() {
            return Err(ConfigError::new("output.dir", "\"\"", "a non-empty path"));
        }
        positive("output.map_dx", o.map_dx, 0.1, 10_000.0, "m")?;
        Ok(())
    }
}

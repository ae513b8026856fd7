//! Errors shared by every stage.

use thiserror::Error;

/// A configuration value outside its allowed range, or a key that does not exist.
#[derive(Debug, Error, Clone, PartialEq)]
#[error("invalid configuration: `{field}` = {value}: {allowed}")]
pub struct ConfigError {
    /// Dotted path of the field, as written in the TOML file (`ship.speed`).
    pub field: String,
    /// The offending value as the user wrote it.
    pub value: String,
    /// What would have been accepted.
    pub allowed: String,
}

impl ConfigError {
    pub fn new(field: impl Into<String>, value: impl ToString, allowed: impl Into<String>) -> Self {
        Self {
            field: field.into(),
            value: value.to_string(),
            allowed: allowed.into(),
        }
    }
}

/// Every error a wakelab stage can return.
#[derive(Debug, Error)]
pub enum WakelabError {
    #[error(transparent)]
    Config(#[from] ConfigError),
    #[error("could not parse configuration {path}: {message}")]
    Parse { path: String, message: String },
    #[error("simulation blew up at step {step} (t = {time:.2} s): {detail}")]
    BlowUp { step: usize, time: f64, detail: String },
    /// The I/O error is part of the message, not a `source`: a `{:#}` chain would say it twice.
    #[error("I/O error on {path}: {error}")]
    Io { path: String, error: std::io::Error },
    #[error("NetCDF error on {path}: {message}")]
    NetCdf { path: String, message: String },
    #[error("image error on {path}: {message}")]
    Image { path: String, message: String },
    #[error("model file {path}: {message}")]
    Model { path: String, message: String },
    #[error("dataset {path}: {message}")]
    Dataset { path: String, message: String },
    #[error("training stopped: {0}")]
    Training(String),
}

impl WakelabError {
    pub fn io(path: impl AsRef<std::path::Path>, source: std::io::Error) -> Self {
        Self::Io {
            path: path.as_ref().display().to_string(),
            error: source,
        }
    }
}

//! wakelab-core: the types every stage of the pipeline (spec Fig. 2.1) shares.
//!
//! - [`config`]: the TOML configuration with an embedded default for every value, presets and
//!   validation that names the field, its value and the allowed range.
//! - [`grid`]: the cross-wake (y, z) grid of the 2D+t domain (spec 2.1.2).
//! - [`io`]: atomic file output, NetCDF (CF) writing and PNG pictures with a colour bar.

pub mod config;
pub mod error;
pub mod grid;
pub mod io;
pub mod memory;
pub mod units;

pub use config::WakelabConfig;
pub use error::{ConfigError, WakelabError};
pub use grid::CrossGrid;

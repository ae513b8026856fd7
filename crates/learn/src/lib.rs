//! wakelab-learn: stage 5 of the pipeline (spec 4.1-4.3, Algorithm 2): the CNN classifiers
//! "base", "cls" and "unet" (Table 4.1) and the U-Net (Tables 4.2-4.3) in burn, their training
//! recipes, Algorithm 2's repeated Monte Carlo evaluation with the metrics of Eq. (4.3) and
//! beyond, trained detectors on disk (safetensors), and detection on a user's own image.
//!
//! The backend is a run-time choice ([`device::parse_device`]): burn's pure-Rust `flex` CPU
//! backend by default, `wgpu` and `cuda` behind the cargo features of the same names.

pub mod augment;
pub mod calibration;
pub mod cost;
pub mod data;
pub mod detect;
pub mod device;
pub mod eval_options;
pub mod evaluate;
pub mod held_out;
pub mod image_file;
pub mod kernels;
pub mod line_sums;
pub mod loss;
pub mod masks;
pub mod models;
pub mod peak;
pub mod peak_chance;
pub mod robustness;
pub mod store;
pub mod synthetic;
pub mod tile;
pub mod train;
pub mod upsample;
pub mod window_line;

/// Confusion counts and metrics live in the schema crate (fusion reads them without burn).
pub use wakelab_schema::metrics;

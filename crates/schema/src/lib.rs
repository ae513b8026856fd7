//! wakelab-schema: what the stages after the physics exchange, and nothing that computes it.
//!
//! - [`axes`]: the study axes, declared once, and a scene's combination of their values;
//! - [`band`]: bands and inputs (one band, or bands as channels), with their names;
//! - [`dataset`]: a scene record of the manifest and the study combination it was made from
//!   (what `wakelab-dataset` writes and `wakelab-learn` reads);
//! - [`results`]: the network architectures, a detector's kept outputs and their summaries (what
//!   `wakelab-learn` writes and `wakelab-fusion` and the report read);
//! - [`split`], [`fusion_row`]: what a kept output was computed on and by, and what a table
//!   row is about;
//! - [`metrics`]: confusion counts, MCC, accuracy, F1 and ROC AUC (spec 4.2-4.3, Eq. (4.3));
//! - [`recipe`]: the spec's training recipe, read by every default.
//!
//! It depends on the core only, so learning builds without the physics and fusion without burn.

pub mod architecture;
pub mod axes;
pub mod band;
pub mod dataset;
pub mod fusion_row;
pub mod metrics;
pub mod recipe;
pub mod results;
pub mod split;

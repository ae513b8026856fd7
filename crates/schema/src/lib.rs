//! wakelab-schema: what the stages after the physics exchange, and nothing that computes it.
//!
//! - [`dataset`]: a scene record of the manifest and the study combination it was made from
//!   (what `wakelab-data` writes and `wakelab-learn` reads);
//! - [`results`]: the network architectures, a detector's kept outputs and their summaries (what
//!   `wakelab-learn` writes and `wakelab-fusion` and the report read);
//! - [`metrics`]: confusion counts, MCC, accuracy, F1 and ROC AUC (spec 4.2-4.3, Eq. (4.3));
//! - [`recipe`]: the spec's training recipe, read by every default.
//!
//! It depends on the core only, so learning builds without the physics and fusion without burn.

pub mod dataset;
pub mod metrics;
pub mod recipe;
pub mod results;

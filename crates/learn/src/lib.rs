//! wakelab-learn: stage 5 of the pipeline (spec 4.1-4.3, Algorithm 2). This first part holds
//! what every classifier shares: the evaluation metrics (Eq. 4.3 and beyond), the dataset
//! reader with the spec's normalisation and augmentation, the Monte Carlo train/test sampling of
//! Algorithm 2, and a synthetic line-versus-noise task to develop models on. The models and
//! their training (burn) build on it.

pub mod data;
pub mod metrics;
pub mod synthetic;

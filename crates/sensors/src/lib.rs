//! wakelab-sensors: stage 3 of the pipeline (spec chapter 3): SAR images in S, C and X band
//! (Eqs. 3.1-3.3) from the surface stage's scene.

pub mod output;
pub mod permittivity;
pub mod sar;
pub mod sar_image;
pub mod spectral;

pub use sar_image::{render_sar, SarImage};

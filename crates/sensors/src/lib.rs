//! wakelab-sensors: stage 3 of the pipeline (spec chapter 3): SAR images in S, C and X band
//! (Eqs. (3.1)-(3.3)) and infrared images in a mid-wave and a long-wave band (Eqs. (3.4)-(3.21),
//! Algorithm 1) from the surface stage's scene. Every image of a scene shares its surface and
//! footprint, pixel for pixel.

pub mod breaking;
pub mod gmf;
pub mod image_formation;
pub mod ir;
pub mod ir_image;
pub mod optics;
pub mod optics_report;
pub mod output;
pub mod permittivity;
pub mod planck;
pub mod sar;
pub mod sar_image;
pub mod sigma0_report;
pub mod slopes;
pub mod spectral;

/// A scene as one sensor sees it in all its bands: `T`, what the bands share, is made once,
/// when the first band needs it ([`SarScene`], [`IrScene`]).
pub struct SensorScene<'a, T> {
    config: &'a wakelab_core::WakelabConfig,
    scene: &'a wakelab_surface::SurfaceScene,
    shared: std::sync::OnceLock<T>,
}

impl<'a, T> SensorScene<'a, T> {
    pub fn new(config: &'a wakelab_core::WakelabConfig, scene: &'a wakelab_surface::SurfaceScene) -> Self {
        Self {
            config,
            scene,
            shared: std::sync::OnceLock::new(),
        }
    }
}

pub use ir::IrBand;
pub use ir_image::{render_ir, IrImage, IrScene};
pub use sar_image::{render_sar, SarImage, SarScene};

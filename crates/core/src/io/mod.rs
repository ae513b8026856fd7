//! File output shared by every stage: atomic writes, NetCDF (CF) and PNG pictures.

pub mod atomic;
pub mod geotiff;
pub mod netcdf;
pub mod picture;
pub mod text;

pub use atomic::{write_atomically, AtomicFile};

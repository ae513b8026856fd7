//! File output shared by every stage: atomic writes, CSV, NetCDF (CF) and PNG pictures.

pub mod atomic;
pub mod csv;
pub mod geotiff;
pub mod netcdf;
pub mod picture;
pub mod text;

pub use atomic::{write_atomically, AtomicFile};
pub use csv::{csv_of_rows, csv_record};

//! NetCDF-3 (64-bit offset) files with CF-1.8 metadata, written in pure Rust by `netcdf3`.
//!
//! xarray, netCDF4-python, ncview and Panoply read these files. Writers define the layout with
//! [`CfLayout`], then stream records (one time slice at a time, so memory stays bounded) through a
//! `netcdf3::FileWriter` opened on an [`AtomicFile`](super::AtomicFile)'s temporary path.

use crate::error::WakelabError;
use netcdf3::DataSet;

/// One variable of a CF file.
#[derive(Debug, Clone)]
pub struct CfVariable {
    pub name: String,
    pub dims: Vec<String>,
    pub units: String,
    pub long_name: String,
    pub standard_name: Option<String>,
    /// `X`, `Y`, `Z` or `T` for coordinate variables.
    pub axis: Option<String>,
    /// `up` or `down` for vertical coordinates.
    pub positive: Option<String>,
}

impl CfVariable {
    pub fn new(name: &str, dims: &[&str], units: &str, long_name: &str) -> Self {
        Self {
            name: name.into(),
            dims: dims.iter().map(|d| d.to_string()).collect(),
            units: units.into(),
            long_name: long_name.into(),
            standard_name: None,
            axis: None,
            positive: None,
        }
    }

    pub fn standard_name(mut self, s: &str) -> Self {
        self.standard_name = Some(s.into());
        self
    }

    pub fn axis(mut self, a: &str) -> Self {
        self.axis = Some(a.into());
        self
    }

    pub fn positive(mut self, p: &str) -> Self {
        self.positive = Some(p.into());
        self
    }
}

/// Dimensions, variables (all float32) and global attributes of a CF file.
#[derive(Debug, Clone, Default)]
pub struct CfLayout {
    pub dims: Vec<(String, usize)>,
    /// The record dimension and its number of records.
    pub record_dim: Option<(String, usize)>,
    pub variables: Vec<CfVariable>,
    pub global: Vec<(String, String)>,
}

impl CfLayout {
    /// Build the `netcdf3::DataSet` of this layout, with `Conventions = CF-1.8`.
    pub fn data_set(&self, path: &str) -> Result<DataSet, WakelabError> {
        let err = |e: netcdf3::InvalidDataSet| WakelabError::NetCdf {
            path: path.to_string(),
            message: format!("{e:?}"),
        };
        let mut ds = DataSet::new();
        if let Some((name, n)) = &self.record_dim {
            ds.set_unlimited_dim(name, *n).map_err(err)?;
        }
        for (name, n) in &self.dims {
            ds.add_fixed_dim(name, *n).map_err(err)?;
        }
        for v in &self.variables {
            ds.add_var_f32(&v.name, &v.dims).map_err(err)?;
            ds.add_var_attr_string(&v.name, "units", &v.units).map_err(err)?;
            ds.add_var_attr_string(&v.name, "long_name", &v.long_name)
                .map_err(err)?;
            for (attr, value) in [
                ("standard_name", &v.standard_name),
                ("axis", &v.axis),
                ("positive", &v.positive),
            ] {
                if let Some(value) = value {
                    ds.add_var_attr_string(&v.name, attr, value).map_err(err)?;
                }
            }
        }
        ds.add_global_attr_string("Conventions", "CF-1.8").map_err(err)?;
        for (k, v) in &self.global {
            ds.add_global_attr_string(k, v).map_err(err)?;
        }
        // CF's `source` (Sec. 2.6.2) on every file, whichever stage wrote it
        if !self.global.iter().any(|(k, _)| k == "source") {
            ds.add_global_attr_string("source", format!("wakelab {}", env!("CARGO_PKG_VERSION")))
                .map_err(err)?;
        }
        Ok(ds)
    }
}

/// A `netcdf3` writer on `path` through a 1 MiB buffer (the crate writes value by value; unbuffered
/// that is one system call per number). The buffer is flushed when the writer is closed.
pub fn buffered_writer<'a>(path: &std::path::Path) -> Result<netcdf3::FileWriter<'a>, WakelabError> {
    let file = std::fs::File::create(path).map_err(|e| WakelabError::io(path, e))?;
    let out = std::io::BufWriter::with_capacity(1 << 20, file);
    netcdf3::FileWriter::open_seek_write(&path.display().to_string(), Box::new(out)).map_err(|e| write_error(path, e))
}

/// Write a file of fixed-size variables atomically: `data` gives every variable's values.
pub fn write_netcdf(
    path: &std::path::Path,
    layout: &CfLayout,
    data: &[(&str, &[f32])],
) -> Result<std::path::PathBuf, WakelabError> {
    let file = crate::io::AtomicFile::new(path)?;
    let name = path.file_name().unwrap_or_default().to_string_lossy().into_owned();
    let ds = layout.data_set(&name)?;
    let tmp = file.temporary_path().to_path_buf();
    let mut w = buffered_writer(&tmp)?;
    w.set_def(&ds, netcdf3::Version::Offset64Bit, 0)
        .map_err(|e| write_error(&tmp, e))?;
    for (var, values) in data {
        w.write_var_f32(var, values).map_err(|e| write_error(&tmp, e))?;
    }
    w.close().map_err(|e| write_error(&tmp, e))?;
    file.commit()
}

/// Map a `netcdf3` write error to a [`WakelabError`].
pub fn write_error(path: &std::path::Path, e: netcdf3::WriteError) -> WakelabError {
    WakelabError::NetCdf {
        path: path.display().to_string(),
        message: format!("{e:?}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use netcdf3::{FileReader, Version};

    #[test]
    fn written_file_reads_back_with_cf_attributes() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.nc");
        let layout = CfLayout {
            dims: vec![("y".into(), 3)],
            record_dim: Some(("time".into(), 2)),
            variables: vec![
                CfVariable::new("y", &["y"], "m", "cross-track distance").axis("Y"),
                CfVariable::new("u", &["time", "y"], "m s-1", "velocity"),
            ],
            global: vec![("title".into(), "test".into())],
        };
        let ds = layout.data_set("t.nc").unwrap();
        let mut w = buffered_writer(&path).unwrap();
        w.set_def(&ds, Version::Offset64Bit, 0).unwrap();
        w.write_var_f32("y", &[0.0, 1.0, 2.0]).unwrap();
        w.write_record_f32("u", 0, &[1.0, 2.0, 3.0]).unwrap();
        w.write_record_f32("u", 1, &[4.0, 5.0, 6.0]).unwrap();
        w.close().unwrap();
        let mut r = FileReader::open(&path).unwrap();
        let u = r.read_var_f32("u").unwrap();
        assert_eq!(u, vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        let ds = r.data_set();
        assert_eq!(ds.get_global_attr_as_string("Conventions").unwrap(), "CF-1.8");
        assert!(ds.get_global_attr_as_string("source").unwrap().starts_with("wakelab "));
        assert_eq!(ds.get_var_attr_as_string("u", "units").unwrap(), "m s-1");
    }
}

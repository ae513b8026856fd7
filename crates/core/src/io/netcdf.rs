//! NetCDF-4 files with CF-1.8 metadata, written through Unidata's libnetcdf (the `netcdf` crate):
//! every field deflate-compressed with the shuffle filter, time as a CF duration that xarray
//! decodes to `timedelta64`.
//!
//! Writers define the layout with [`CfLayout`], then stream records (one time slice at a time, so
//! memory stays bounded) through a [`CfWriter`], which writes to a temporary path and renames on
//! [`CfWriter::commit`]: a failed run leaves no half-written file.

use crate::error::WakelabError;
use std::path::{Path, PathBuf};

/// Deflate level of every variable (1-9): 4 keeps most of the gain of 9 at a fraction of the time.
const DEFLATE_LEVEL: i32 = 4;

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
    /// A duration in seconds (float64, `dtype = "timedelta64[s]"`) rather than a float32 field.
    pub duration: bool,
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
            duration: false,
        }
    }

    /// A time coordinate that is a duration (CF-1.8 Sec. 4.4 allows units without "since"; xarray
    /// decodes `units = "seconds"` as `timedelta64`, and its coming default asks for the `dtype`
    /// attribute that says so).
    pub fn duration(name: &str, dims: &[&str], long_name: &str) -> Self {
        Self {
            duration: true,
            ..Self::new(name, dims, "seconds", long_name)
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

/// Dimensions, variables and global attributes of a CF file.
#[derive(Debug, Clone, Default)]
pub struct CfLayout {
    pub dims: Vec<(String, usize)>,
    /// The record (unlimited) dimension.
    pub record_dim: Option<String>,
    pub variables: Vec<CfVariable>,
    pub global: Vec<(String, String)>,
}

/// Switch off HDF5's printing of its error stack on this thread: libnetcdf (4.9) asks HDF5 for
/// attributes a file may lack (the quantize attributes of every variable it opens), and HDF5
/// prints each miss to stderr ("HDF5-DIAG: Error detected ..."), though libnetcdf handles it.
/// A thread-safe HDF5 (Debian's) keeps that setting per thread. Errors still reach wakelab as
/// return codes.
fn quiet_hdf5() {
    thread_local!(static QUIET: std::cell::Cell<bool> = const { std::cell::Cell::new(false) });
    QUIET.with(|quiet| {
        if !quiet.replace(true) {
            // SAFETY: H5Eset_auto2 on this thread's default error stack with no handler only
            // turns printing off
            unsafe {
                hdf5_metno_sys::h5e::H5Eset_auto2(hdf5_metno_sys::h5e::H5E_DEFAULT, None, std::ptr::null_mut());
            }
        }
    });
}

fn nc_error(path: &Path, e: netcdf::Error) -> WakelabError {
    WakelabError::NetCdf {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

/// A NetCDF-4 file being written: created at a temporary path, renamed into place on commit.
pub struct CfWriter {
    file: netcdf::FileMut,
    atomic: crate::io::AtomicFile,
    path: PathBuf,
}

impl CfWriter {
    /// Create the file of `layout` (its dimensions, variables and attributes, with
    /// `Conventions = CF-1.8` and a `source`) to be committed at `path`.
    pub fn create(path: &Path, layout: &CfLayout) -> Result<Self, WakelabError> {
        quiet_hdf5();
        let atomic = crate::io::AtomicFile::new(path)?;
        let err = |e| nc_error(path, e);
        let mut file = netcdf::create(atomic.temporary_path()).map_err(err)?;
        if let Some(name) = &layout.record_dim {
            file.add_unlimited_dimension(name).map_err(err)?;
        }
        for (name, n) in &layout.dims {
            file.add_dimension(name, *n).map_err(err)?;
        }
        for v in &layout.variables {
            let dims: Vec<&str> = v.dims.iter().map(String::as_str).collect();
            let mut var = if v.duration {
                file.add_variable::<f64>(&v.name, &dims).map_err(err)?
            } else {
                file.add_variable::<f32>(&v.name, &dims).map_err(err)?
            };
            // coordinates stay plain; the fields are what is large
            if v.dims.len() > 1 {
                var.set_compression(DEFLATE_LEVEL, true).map_err(err)?;
            }
            var.put_attribute("units", v.units.as_str()).map_err(err)?;
            var.put_attribute("long_name", v.long_name.as_str()).map_err(err)?;
            if v.duration {
                var.put_attribute("dtype", "timedelta64[s]").map_err(err)?;
            }
            for (attr, value) in [
                ("standard_name", &v.standard_name),
                ("axis", &v.axis),
                ("positive", &v.positive),
            ] {
                if let Some(value) = value {
                    var.put_attribute(attr, value.as_str()).map_err(err)?;
                }
            }
        }
        file.add_attribute("Conventions", "CF-1.8").map_err(err)?;
        for (k, v) in &layout.global {
            file.add_attribute(k, v.as_str()).map_err(err)?;
        }
        // CF's `source` (Sec. 2.6.2) on every file, whichever stage wrote it
        if !layout.global.iter().any(|(k, _)| k == "source") {
            let source = format!("wakelab {}", env!("CARGO_PKG_VERSION"));
            file.add_attribute("source", source.as_str()).map_err(err)?;
        }
        Ok(Self {
            file,
            atomic,
            path: path.to_path_buf(),
        })
    }

    fn variable(&mut self, name: &str) -> Result<netcdf::VariableMut<'_>, WakelabError> {
        let path = self.path.display().to_string();
        self.file.variable_mut(name).ok_or_else(|| WakelabError::NetCdf {
            path,
            message: format!("no variable `{name}`"),
        })
    }

    /// Every value of a float32 variable.
    pub fn put(&mut self, name: &str, values: &[f32]) -> Result<(), WakelabError> {
        let path = self.path.clone();
        self.variable(name)?
            .put_values(values, ..)
            .map_err(|e| nc_error(&path, e))
    }

    /// Record `i` of a float32 variable whose first dimension is the record dimension.
    pub fn put_record(&mut self, name: &str, i: usize, values: &[f32]) -> Result<(), WakelabError> {
        let path = self.path.clone();
        let mut var = self.variable(name)?;
        let extents: Vec<netcdf::Extent> = std::iter::once(netcdf::Extent::from(i..i + 1))
            .chain(var.dimensions()[1..].iter().map(|d| netcdf::Extent::from(0..d.len())))
            .collect();
        var.put_values(values, extents).map_err(|e| nc_error(&path, e))
    }

    /// Record `i` of a duration variable (seconds).
    pub fn put_duration(&mut self, name: &str, i: usize, seconds: f64) -> Result<(), WakelabError> {
        let path = self.path.clone();
        self.variable(name)?
            .put_value(seconds, [i])
            .map_err(|e| nc_error(&path, e))
    }

    /// Close the file and move it into place; returns its path.
    pub fn commit(self) -> Result<PathBuf, WakelabError> {
        self.file.close().map_err(|e| nc_error(&self.path, e))?;
        self.atomic.commit()
    }
}

/// Write a file of fixed-size float32 variables atomically: `data` gives every variable's values.
pub fn write_netcdf(path: &Path, layout: &CfLayout, data: &[(&str, &[f32])]) -> Result<PathBuf, WakelabError> {
    let mut writer = CfWriter::create(path, layout)?;
    for (var, values) in data {
        writer.put(var, values)?;
    }
    writer.commit()
}

/// Every value of a float32 variable of the file at `path`.
pub fn read_f32(path: &Path, name: &str) -> Result<Vec<f32>, WakelabError> {
    quiet_hdf5();
    let file = netcdf::open(path).map_err(|e| nc_error(path, e))?;
    let var = file.variable(name).ok_or_else(|| WakelabError::NetCdf {
        path: path.display().to_string(),
        message: format!("no variable `{name}`"),
    })?;
    var.get_values::<f32, _>(..).map_err(|e| nc_error(path, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn written_file_reads_back_compressed_with_cf_attributes() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.nc");
        let layout = CfLayout {
            dims: vec![("y".into(), 3)],
            record_dim: Some("time".into()),
            variables: vec![
                CfVariable::duration("time", &["time"], "time since the start").axis("T"),
                CfVariable::new("y", &["y"], "m", "cross-track distance").axis("Y"),
                CfVariable::new("u", &["time", "y"], "m s-1", "velocity"),
            ],
            global: vec![("title".into(), "test".into())],
        };
        let mut w = CfWriter::create(&path, &layout).unwrap();
        w.put("y", &[0.0, 1.0, 2.0]).unwrap();
        for (i, (t, u)) in [(0.0, [1.0, 2.0, 3.0]), (60.0, [4.0, 5.0, 6.0])].iter().enumerate() {
            w.put_duration("time", i, *t).unwrap();
            w.put_record("u", i, u).unwrap();
        }
        assert!(!path.exists(), "nothing in place before the commit");
        w.commit().unwrap();
        assert_eq!(read_f32(&path, "u").unwrap(), vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        let file = netcdf::open(&path).unwrap();
        let text = |a: Option<netcdf::Attribute>| match a.unwrap().value().unwrap() {
            netcdf::AttributeValue::Str(s) => s,
            other => panic!("{other:?}"),
        };
        assert_eq!(text(file.attribute("Conventions")), "CF-1.8");
        assert!(text(file.attribute("source")).starts_with("wakelab "));
        let u = file.variable("u").unwrap();
        assert_eq!(text(u.attribute("units")), "m s-1");
        let time = file.variable("time").unwrap();
        assert_eq!(text(time.attribute("units")), "seconds");
        assert_eq!(text(time.attribute("dtype")), "timedelta64[s]");
        assert_eq!(time.get_values::<f64, _>(..).unwrap(), vec![0.0, 60.0]);
    }
}

//! Where a SAFE product's files are (a directory, its manifest, or a folder inside a zip read
//! through GDAL's `/vsizip/`), reading them as text, and choosing a polarisation's files by
//! ESA's naming (`s1a-iw-grd-vv-<start>-<stop>-<orbit>-<take>-<image>`).

use std::ffi::CString;
use std::path::{Path, PathBuf};
use wakelab_core::WakelabError;

/// Where a SAFE product's files are: a directory, or a folder inside a zip (GDAL's VSI path).
#[derive(Debug, Clone)]
pub struct SafeLocation {
    /// What the user passed.
    pub input: PathBuf,
    /// The SAFE folder as GDAL opens it (`/vsizip/...` inside a zip).
    pub root: String,
    /// Its name without `.SAFE` (the product identifier).
    pub name: String,
}

pub(super) fn safe_error(path: &Path, message: impl ToString) -> WakelabError {
    WakelabError::Image {
        path: path.display().to_string(),
        message: message.to_string(),
    }
}

impl SafeLocation {
    /// The SAFE product at `path` (a `.SAFE` directory, its `manifest.safe` or a `.zip` holding
    /// one), or None when `path` is none of these.
    pub fn find(path: &Path) -> Result<Option<Self>, WakelabError> {
        let root = if path.is_dir() && path.join("manifest.safe").is_file() {
            path.to_string_lossy().into_owned()
        } else if path.file_name().is_some_and(|n| n == "manifest.safe") {
            path.parent().unwrap_or(Path::new(".")).to_string_lossy().into_owned()
        } else if crate::extension(path) == "zip" {
            let zip = format!("/vsizip/{}", path.display());
            let entries = gdal::vsi::read_dir(&zip, true)
                .map_err(|e| safe_error(path, format!("not a zip GDAL can read: {e}")))?;
            let manifest = entries
                .iter()
                .find(|e| e.file_name().is_some_and(|n| n == "manifest.safe"))
                .ok_or_else(|| safe_error(path, "a zip without a manifest.safe: not a Sentinel-1 SAFE product"))?;
            let folder = manifest
                .parent()
                .map(|p| p.to_string_lossy().into_owned())
                .unwrap_or_default();
            if folder.is_empty() {
                zip
            } else {
                format!("{zip}/{folder}")
            }
        } else {
            return Ok(None);
        };
        let trimmed = root.trim_end_matches('/');
        let folder = trimmed.rsplit('/').next().unwrap_or(trimmed);
        let name = folder.strip_suffix(".SAFE").unwrap_or(folder).to_string();
        Ok(Some(Self {
            input: path.to_path_buf(),
            root: trimmed.to_string(),
            name,
        }))
    }

    pub(super) fn file(&self, relative: &str) -> String {
        format!("{}/{relative}", self.root)
    }

    /// The names in a folder of the product.
    fn list(&self, folder: &str) -> Vec<String> {
        gdal::vsi::read_dir(self.file(folder), false)
            .unwrap_or_default()
            .iter()
            .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
            .collect()
    }

    /// A file of the product as text, read through GDAL's virtual file system.
    pub(super) fn read_text(&self, relative: &str) -> Result<String, WakelabError> {
        let name = self.file(relative);
        let c = CString::new(name.clone()).map_err(|e| safe_error(&self.input, e))?;
        let mut data: *mut u8 = std::ptr::null_mut();
        let mut size: u64 = 0;
        // SAFETY: GDAL allocates `data` (NUL-terminated, `size` bytes before the NUL), which is
        // copied and then freed with VSIFree.
        let ok = unsafe { gdal_sys::VSIIngestFile(std::ptr::null_mut(), c.as_ptr(), &mut data, &mut size, 1 << 30) };
        if ok == 0 || data.is_null() {
            return Err(safe_error(
                &self.input,
                format!("the product lacks {relative} (ESA's SAFE layout requires it)"),
            ));
        }
        let bytes = unsafe { std::slice::from_raw_parts(data, size as usize) }.to_vec();
        unsafe { gdal_sys::VSIFree(data as *mut std::ffi::c_void) };
        String::from_utf8(bytes).map_err(|_| safe_error(&self.input, format!("{relative} is not UTF-8 text")))
    }
}

/// The polarisation of an annotation or measurement file name
/// (`s1a-iw-grd-vv-<start>-<stop>-<orbit>-<take>-<image>.xml`), in capitals.
fn polarisation_of(name: &str) -> Option<String> {
    let parts: Vec<&str> = name.split('-').collect();
    (parts.len() >= 9 && parts[0].starts_with("s1")).then(|| parts[3].to_ascii_uppercase())
}

/// The files of one polarisation and the polarisations the product has.
pub(super) struct Files {
    pub stem: String,
    pub polarisation: String,
    pub available: Vec<String>,
}

pub(super) fn choose_files(safe: &SafeLocation, wanted: Option<&str>) -> Result<Files, WakelabError> {
    let annotations: Vec<String> = safe
        .list("annotation")
        .into_iter()
        .filter(|n| n.ends_with(".xml") && polarisation_of(n).is_some())
        .collect();
    if annotations.is_empty() {
        return Err(safe_error(
            &safe.input,
            "no product annotation (annotation/s1?-*.xml): not a complete Sentinel-1 SAFE product",
        ));
    }
    let mut available: Vec<String> = annotations.iter().filter_map(|n| polarisation_of(n)).collect();
    available.sort();
    available.dedup();
    let polarisation = match wanted {
        Some(p) => {
            let p = p.to_ascii_uppercase();
            if !available.contains(&p) {
                return Err(wakelab_core::ConfigError::new(
                    "--pol",
                    p,
                    format!("a polarisation the product holds: {}", available.join(", ")),
                )
                .into());
            }
            p
        }
        None => ["VV", "HH"]
            .into_iter()
            .find(|p| available.iter().any(|a| a == p))
            .map(str::to_string)
            .ok_or_else(|| {
                wakelab_core::ConfigError::new(
                    "--pol",
                    "VV or HH (the default)",
                    format!(
                        "a polarisation the product holds: {} (pass it with --pol)",
                        available.join(", ")
                    ),
                )
            })?,
    };
    let name = annotations
        .iter()
        .find(|n| polarisation_of(n).as_deref() == Some(polarisation.as_str()))
        .expect("chosen among the annotations");
    Ok(Files {
        stem: name.trim_end_matches(".xml").to_string(),
        polarisation,
        available,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_names_give_their_polarisation() {
        assert_eq!(
            polarisation_of("s1a-iw-grd-vh-20210119t031653-20210119t031718-036201-043ed0-002.xml").as_deref(),
            Some("VH")
        );
        assert_eq!(polarisation_of("calibration"), None);
    }
}

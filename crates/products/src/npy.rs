//! A bare `.npy` array (NumPy's format, NEP 1): its header is checked before any data is read,
//! so that a wrong file says what is wrong (its dimensions, its type, or how much of the data is
//! missing) instead of failing on the first type tried, and a crafted shape cannot ask for more
//! memory than the file holds.

use crate::{InputScale, PixelSpacing, Product, ProductMeta, Quantity, ReadOptions, ReadReport};
use ndarray::Array2;
use std::io::Read;
use std::path::Path;
use wakelab_core::WakelabError;

fn npy_error(path: &Path, message: impl ToString) -> WakelabError {
    WakelabError::Image {
        path: path.display().to_string(),
        message: message.to_string(),
    }
}

/// What the header says.
#[derive(Debug, PartialEq)]
struct Header {
    descr: String,
    shape: Vec<u64>,
    /// Bytes before the data.
    data_offset: u64,
}

/// The element types read, with their sizes.
const TYPES: [(&str, u64); 7] = [
    ("<f4", 4),
    ("<f8", 8),
    ("|u1", 1),
    ("<u2", 2),
    ("<i2", 2),
    ("<i4", 4),
    ("<u4", 4),
];

fn header(path: &Path) -> Result<Header, WakelabError> {
    let mut file = std::fs::File::open(path).map_err(|e| WakelabError::io(path, e))?;
    let mut lead = [0u8; 10];
    file.read_exact(&mut lead)
        .map_err(|_| npy_error(path, "shorter than an npy header: not an npy file"))?;
    if &lead[..6] != b"\x93NUMPY" {
        return Err(npy_error(path, "does not start with \\x93NUMPY: not an npy file"));
    }
    let (len, offset) = match lead[6] {
        1 => (u16::from_le_bytes([lead[8], lead[9]]) as u64, 10),
        2 | 3 => {
            let mut more = [0u8; 2];
            file.read_exact(&mut more)
                .map_err(|_| npy_error(path, "its header is cut short"))?;
            (u32::from_le_bytes([lead[8], lead[9], more[0], more[1]]) as u64, 12)
        }
        v => {
            return Err(npy_error(
                path,
                format!("npy format version {v} (this reader knows 1 to 3)"),
            ))
        }
    };
    if len > 1 << 20 {
        return Err(npy_error(
            path,
            format!("its header claims {len} bytes: a damaged file"),
        ));
    }
    let mut text = vec![0u8; len as usize];
    file.read_exact(&mut text)
        .map_err(|_| npy_error(path, "its header is cut short"))?;
    let text = String::from_utf8_lossy(&text);
    let field = |key: &str| -> Option<String> {
        let at = text.find(&format!("'{key}'"))? + key.len() + 2;
        let rest = text[at..].trim_start().strip_prefix(':')?.trim_start();
        if let Some(inner) = rest.strip_prefix('(') {
            return Some(inner[..inner.find(')')?].to_string());
        }
        if let Some(inner) = rest.strip_prefix('\'') {
            return Some(inner[..inner.find('\'')?].to_string());
        }
        Some(rest.split([',', '}']).next()?.trim().to_string())
    };
    let descr = field("descr").ok_or_else(|| npy_error(path, "its header has no 'descr'"))?;
    let shape = field("shape").ok_or_else(|| npy_error(path, "its header has no 'shape'"))?;
    let shape = shape
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| {
            s.parse::<u64>()
                .map_err(|_| npy_error(path, format!("its shape holds \"{s}\"")))
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Header {
        descr,
        shape,
        data_offset: offset + len,
    })
}

/// The 2-D array of an `.npy` file as f32 (types f4, f8, u1, u2, i2, i4, u4, little-endian),
/// refused, naming the file: not npy, another number of dimensions, another type, or a file
/// shorter (truncated) or longer than its shape says.
pub fn read_array(path: &Path) -> Result<Array2<f32>, WakelabError> {
    let h = header(path)?;
    if h.shape.len() != 2 {
        return Err(npy_error(
            path,
            format!(
                "a {}-D array of shape {:?}; wakelab reads single-band 2-D images (rows x columns): save one band, e.g. a[..., 0]",
                h.shape.len(),
                h.shape
            ),
        ));
    }
    let Some(&(_, size)) = TYPES.iter().find(|(d, _)| *d == h.descr) else {
        return Err(npy_error(
            path,
            format!("element type '{}' (read: {})", h.descr, TYPES.map(|t| t.0).join(", ")),
        ));
    };
    let expected = h.shape[0]
        .checked_mul(h.shape[1])
        .and_then(|n| n.checked_mul(size))
        .ok_or_else(|| npy_error(path, format!("its shape {:?} overflows", h.shape)))?;
    let actual = std::fs::metadata(path).map_err(|e| WakelabError::io(path, e))?.len() - h.data_offset;
    if actual != expected {
        return Err(npy_error(
            path,
            format!(
                "its shape {} x {} of '{}' needs {expected} bytes of data, the file holds {actual}: {}",
                h.shape[0],
                h.shape[1],
                h.descr,
                if actual < expected {
                    "truncated"
                } else {
                    "extra bytes after the data"
                }
            ),
        ));
    }
    let read = |e: ndarray_npy::ReadNpyError| npy_error(path, e);
    let image = match h.descr.as_str() {
        "<f4" => ndarray_npy::read_npy::<_, Array2<f32>>(path).map_err(read)?,
        "<f8" => ndarray_npy::read_npy::<_, Array2<f64>>(path)
            .map_err(read)?
            .mapv(|v| v as f32),
        "|u1" => ndarray_npy::read_npy::<_, Array2<u8>>(path)
            .map_err(read)?
            .mapv(f32::from),
        "<u2" => ndarray_npy::read_npy::<_, Array2<u16>>(path)
            .map_err(read)?
            .mapv(f32::from),
        "<i2" => ndarray_npy::read_npy::<_, Array2<i16>>(path)
            .map_err(read)?
            .mapv(f32::from),
        "<i4" => ndarray_npy::read_npy::<_, Array2<i32>>(path)
            .map_err(read)?
            .mapv(|v| v as f32),
        _ => ndarray_npy::read_npy::<_, Array2<u32>>(path)
            .map_err(read)?
            .mapv(|v| v as f32),
    };
    Ok(image)
}

/// A bare array as a product: no georeference, its spacing `--pixel-spacing` or unknown; NaN
/// and border zeros masked; radar values in the stated scale (linear unless told).
pub fn read(path: &Path, options: &ReadOptions) -> Result<Product, WakelabError> {
    let raw = read_array(path)?;
    let is_byte = header(path)?.descr == "|u1";
    let mut report = ReadReport::default();
    let scale = options.scale.unwrap_or(InputScale::Linear);
    let image = crate::raster::mask_and_scale(raw, None, None, options, scale, is_byte, &mut report, path)?;
    let stem = crate::stem_of(path);
    Ok(Product {
        path: path.to_path_buf(),
        frame: crate::Frame::none(image.dim()),
        meta: ProductMeta {
            format: "npy".into(),
            product_id: stem,
            scale: (options.quantity == Quantity::Sigma0).then_some(scale),
            calibrated: scale.calibrated(),
            pixel_spacing: options.pixel_spacing.map(|d| PixelSpacing {
                columns: d,
                rows: d,
                source: crate::SpacingSource::User,
            }),
            ..Default::default()
        },
        image,
        report,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::Array3;

    /// An npy file (version 1.0) with the given header fields and data.
    fn npy_bytes(descr: &str, shape: &str, data: &[u8]) -> Vec<u8> {
        let mut dict = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape}, }}");
        while (10 + dict.len() + 1) % 64 != 0 {
            dict.push(' ');
        }
        dict.push('\n');
        let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
        bytes.extend((dict.len() as u16).to_le_bytes());
        bytes.extend(dict.as_bytes());
        bytes.extend(data);
        bytes
    }

    fn message(r: Result<Array2<f32>, WakelabError>) -> String {
        r.unwrap_err().to_string()
    }

    #[test]
    fn wrong_files_say_what_is_wrong() {
        let dir = tempfile::tempdir().unwrap();
        let cube = dir.path().join("cube.npy");
        ndarray_npy::write_npy(&cube, &Array3::<f32>::zeros((2, 3, 4))).unwrap();
        assert!(message(read_array(&cube)).contains("a 3-D array of shape [2, 3, 4]"));

        let good = dir.path().join("good.npy");
        ndarray_npy::write_npy(&good, &Array2::<f32>::from_elem((20, 30), 1.5)).unwrap();
        assert_eq!(read_array(&good).unwrap()[[19, 29]], 1.5);

        let bytes = std::fs::read(&good).unwrap();
        let cut = dir.path().join("cut.npy");
        std::fs::write(&cut, &bytes[..bytes.len() - 100]).unwrap();
        let m = message(read_array(&cut));
        assert!(
            m.contains("needs 2400 bytes of data, the file holds 2300: truncated"),
            "{m}"
        );

        // a header claiming a huge shape over a little data: refused before any allocation
        let huge = dir.path().join("huge.npy");
        std::fs::write(&huge, npy_bytes("<f4", "(2000000, 3000000)", &[0u8; 64])).unwrap();
        let m = message(read_array(&huge));
        assert!(m.contains("2000000 x 3000000") && m.contains("truncated"), "{m}");

        let complex = dir.path().join("complex.npy");
        std::fs::write(&complex, npy_bytes("<c8", "(2, 2)", &[0u8; 32])).unwrap();
        assert!(message(read_array(&complex)).contains("element type '<c8'"));

        let not = dir.path().join("not.npy");
        std::fs::write(&not, b"hello, world").unwrap();
        assert!(message(read_array(&not)).contains("not an npy file"));
    }
}

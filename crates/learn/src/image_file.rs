//! A user's single-band image read for `wakelab detect`: `.npy`, TIFF or PNG, one band, finite
//! and not constant; anything else is refused with the file's name and what would be accepted.

use ndarray::Array2;
use std::path::Path;
use wakelab_core::WakelabError;

fn image_error(path: &Path, message: impl ToString) -> WakelabError {
    WakelabError::Image {
        path: path.display().to_string(),
        message: message.to_string(),
    }
}

/// Read a single-band image: `.npy` (2-D, f32, f64 or u8), `.tif`/`.tiff` (one sample per pixel,
/// any integer or float type) or `.png` (grey levels, 8 or 16 bits). Refused, naming the file:
/// colour or alpha channels (which band would it be?), NaN or infinite pixels (they would score
/// "no wake" silently), and a constant image (nothing to detect: a blank or masked product).
pub fn read_single_band(path: &Path) -> Result<Array2<f32>, WakelabError> {
    let image = read_pixels(path)?;
    crate::data::check_finite(&image, path)?;
    let first = image.iter().next().copied().unwrap_or(0.0);
    if image.iter().all(|&v| v == first) {
        return Err(image_error(
            path,
            format!("every pixel is {first}: a constant image holds no wake to find (a blank or masked product?)"),
        ));
    }
    Ok(image)
}

fn read_pixels(path: &Path) -> Result<Array2<f32>, WakelabError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    match ext.as_str() {
        "npy" => {
            if let Ok(a) = ndarray_npy::read_npy::<_, Array2<f32>>(path) {
                return Ok(a);
            }
            if let Ok(a) = ndarray_npy::read_npy::<_, Array2<f64>>(path) {
                return Ok(a.mapv(|v| v as f32));
            }
            ndarray_npy::read_npy::<_, Array2<u8>>(path)
                .map(|a| a.mapv(|v| v as f32))
                .map_err(|e| image_error(path, format!("not a 2-D f32, f64 or u8 array: {e}")))
        }
        "tif" | "tiff" => read_tiff(path),
        "png" => {
            let img = image::open(path).map_err(|e| image_error(path, e))?;
            let channels = img.color().channel_count();
            if channels != 1 {
                return Err(image_error(
                    path,
                    format!(
                        "has {channels} channels ({:?}); detect reads single-band images: save one band as a greyscale PNG, TIFF or npy",
                        img.color()
                    ),
                ));
            }
            let img = img.to_luma32f();
            let (w, h) = img.dimensions();
            Array2::from_shape_vec((h as usize, w as usize), img.into_raw()).map_err(|e| image_error(path, e))
        }
        other => Err(image_error(
            path,
            format!("unknown image type \"{other}\" (allowed: npy, tif, tiff, png)"),
        )),
    }
}

fn read_tiff(path: &Path) -> Result<Array2<f32>, WakelabError> {
    use tiff::decoder::{Decoder, DecodingResult};
    let file = std::fs::File::open(path).map_err(|e| WakelabError::io(path, e))?;
    let mut decoder = Decoder::new(std::io::BufReader::new(file)).map_err(|e| image_error(path, e))?;
    let (w, h) = decoder.dimensions().map_err(|e| image_error(path, e))?;
    let values: Vec<f32> = match decoder.read_image().map_err(|e| image_error(path, e))? {
        DecodingResult::F32(v) => v,
        DecodingResult::F64(v) => v.into_iter().map(|x| x as f32).collect(),
        DecodingResult::U8(v) => v.into_iter().map(f32::from).collect(),
        DecodingResult::U16(v) => v.into_iter().map(f32::from).collect(),
        DecodingResult::I16(v) => v.into_iter().map(f32::from).collect(),
        DecodingResult::U32(v) => v.into_iter().map(|x| x as f32).collect(),
        DecodingResult::I32(v) => v.into_iter().map(|x| x as f32).collect(),
        _ => return Err(image_error(path, "unsupported TIFF sample type")),
    };
    if values.len() != (w * h) as usize {
        return Err(image_error(
            path,
            "not a single-band image (more than one sample per pixel)",
        ));
    }
    Array2::from_shape_vec((h as usize, w as usize), values).map_err(|e| image_error(path, e))
}

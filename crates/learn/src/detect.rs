//! Detection on a user's own single-band image (npy, TIFF or PNG): the image is cut into tiles
//! of the detector's input size (half-tile overlap), each tile made an input as in training
//! ([`crate::data::detector_input`], radar pixels read in the given [`RadarScale`])
//! and classified; the scene's wake probability is the largest tile's, and the U-Net's masks are
//! stitched (overlaps averaged) into one mask of the whole image.

use crate::data::{detector_input, RadarScale};
use crate::evaluate::detect;
use crate::models::Architecture;
use crate::store::{Detector, ModelInfo};
use crate::train::{segment, Example};
use burn::tensor::Device;
use ndarray::{s, Array2, Axis};
use serde::Serialize;
use std::path::Path;
use wakelab_core::{ConfigError, WakelabError};

fn image_error(path: &Path, message: impl ToString) -> WakelabError {
    WakelabError::Image {
        path: path.display().to_string(),
        message: message.to_string(),
    }
}

/// Read a single-band image: `.npy` (2-D, f32, f64 or u8), `.tif`/`.tiff` (one sample per pixel,
/// any integer or float type) or `.png` (converted to grey levels).
pub fn read_single_band(path: &Path) -> Result<Array2<f32>, WakelabError> {
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
            let img = image::open(path).map_err(|e| image_error(path, e))?.to_luma32f();
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

/// One tile's result.
#[derive(Debug, Clone, Serialize)]
pub struct Tile {
    pub row: usize,
    pub col: usize,
    pub probability: f64,
}

/// Detection on one image.
#[derive(Debug, Clone, Serialize)]
pub struct Detection {
    /// Largest tile probability: the chance a wake is somewhere in the image.
    pub probability: f64,
    pub wake: bool,
    pub threshold: f64,
    pub tiles: Vec<Tile>,
    #[serde(skip)]
    pub mask: Option<Array2<f32>>,
}

impl Detection {
    /// "wake probability 0.912 (wake at threshold 0.5), 4 tile(s) of 64 x 64 px".
    pub fn describe(&self, tile_size: usize) -> String {
        format!(
            "wake probability {:.3} ({} at threshold {}), {} tile(s) of {tile_size} x {tile_size} px",
            self.probability,
            if self.wake { "wake" } else { "no wake" },
            self.threshold,
            self.tiles.len()
        )
    }
}

/// Tile origins along one axis of length `len` for tiles of `size` with half-tile steps; the last
/// tile ends at the border.
fn tile_starts(len: usize, size: usize) -> Vec<usize> {
    if len <= size {
        return vec![0];
    }
    let step = (size / 2).max(1);
    let mut starts: Vec<usize> = (0..=len - size).step_by(step).collect();
    if *starts.last().unwrap() != len - size {
        starts.push(len - size);
    }
    starts
}

/// Run a single-band detector on an image of any size at least the detector's input size; a
/// radar image's pixels are in `scale` (an infrared one's are brightness temperatures, K).
pub fn detect_image(
    detector: &Detector,
    info: &ModelInfo,
    image: &Array2<f32>,
    scale: RadarScale,
    device: &Device,
) -> Result<Detection, WakelabError> {
    let n = info.input_size;
    let Some(band) = info.bands.as_single() else {
        return Err(ConfigError::new(
            "--model",
            format!("a detector of {} bands ({})", info.image_channels(), info.bands),
            "a single-band detector",
        )
        .into());
    };
    let (h, w) = image.dim();
    if h < n || w < n {
        return Err(ConfigError::new(
            "IMAGE",
            format!("{h} x {w} pixels"),
            format!("at least the detector's input, {n} x {n} pixels"),
        )
        .into());
    }
    let mut origins = Vec::new();
    for &r in &tile_starts(h, n) {
        for &c in &tile_starts(w, n) {
            origins.push((r, c));
        }
    }
    let examples: Vec<Example> = origins
        .iter()
        .map(|&(r, c)| Example {
            image: detector_input(image.slice(s![r..r + n, c..c + n]).to_owned(), band, scale).insert_axis(Axis(0)),
            label: 0,
            mask: None,
        })
        .collect();
    let p = detect(detector, info.architecture, &examples, device);
    let mask = match (&detector.segmenter, info.architecture) {
        (Some(unet), Architecture::Unet) => {
            let masks = segment(unet, &examples, 4, device);
            let mut sum = Array2::<f32>::zeros((h, w));
            let mut count = Array2::<f32>::zeros((h, w));
            for (&(r, c), m) in origins.iter().zip(&masks) {
                sum.slice_mut(s![r..r + n, c..c + n]).zip_mut_with(m, |a, b| *a += b);
                count.slice_mut(s![r..r + n, c..c + n]).mapv_inplace(|v| v + 1.0);
            }
            Some(sum / count)
        }
        _ => None,
    };
    let probability = p.iter().cloned().fold(0.0, f64::max);
    Ok(Detection {
        probability,
        wake: probability > info.threshold,
        threshold: info.threshold,
        tiles: origins
            .iter()
            .zip(&p)
            .map(|(&(row, col), &probability)| Tile { row, col, probability })
            .collect(),
        mask,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_cover_the_image_with_half_overlap() {
        assert_eq!(tile_starts(100, 100), vec![0]);
        assert_eq!(tile_starts(64, 100), vec![0]);
        assert_eq!(tile_starts(250, 100), vec![0, 50, 100, 150]);
        assert_eq!(tile_starts(260, 100), vec![0, 50, 100, 150, 160]);
    }
}

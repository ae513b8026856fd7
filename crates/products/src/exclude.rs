//! `--exclude`: the user's raster of pixels to ignore (land, or anything else), any GDAL raster
//! or `.npy` of the input's size, masks its non-zero pixels.

use ndarray::Array2;
use std::path::Path;
use wakelab_core::WakelabError;

/// Set to NaN every pixel of `image` where the raster at `path` (any GDAL raster or `.npy`, of
/// the image's size) is non-zero; returns how many pixels it excludes. A raster of another
/// size is refused with both sizes.
pub fn exclude(image: &mut Array2<f32>, path: &Path) -> Result<usize, WakelabError> {
    let options = crate::ReadOptions {
        quantity: crate::Quantity::BrightnessTemperature,
        ..Default::default()
    };
    let values = if crate::extension(path) == "npy" {
        crate::npy::read_array(path)?
    } else {
        crate::raster::read_band(path, &options)?.0
    };
    if values.dim() != image.dim() {
        return Err(wakelab_core::ConfigError::new(
            "--exclude",
            format!("{} ({} x {} pixels)", path.display(), values.nrows(), values.ncols()),
            format!(
                "a raster of the input's size, {} x {} pixels, non-zero where excluded",
                image.nrows(),
                image.ncols()
            ),
        )
        .into());
    }
    let mut count = 0;
    image.zip_mut_with(&values, |v, &e| {
        if e != 0.0 && !e.is_nan() {
            if !v.is_nan() {
                count += 1;
            }
            *v = f32::NAN;
        }
    });
    Ok(count)
}

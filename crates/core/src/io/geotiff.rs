//! Single-band float32 TIFF images with GeoTIFF tags (GDAL, QGIS, rasterio and tifffile read
//! them): ModelPixelScale and ModelTiepoint place the pixels on the scene's metric (x, y) grid,
//! in a user-defined projected model (there is no Earth position for a simulated scene), plus an
//! 8-bit grey PNG quicklook with a stated linear stretch.

use crate::error::WakelabError;
use crate::io::atomic::AtomicFile;
use std::path::Path;
use tiff::encoder::{colortype, TiffEncoder};
use tiff::tags::Tag;

/// Where the image lies: the (x, y) of the top-left pixel's corner and the pixel spacing (m).
#[derive(Debug, Clone, Copy)]
pub struct Placement {
    pub top_left: (f64, f64),
    pub pixel_spacing: f64,
}

fn tiff_error(path: &Path, e: impl std::fmt::Display) -> WakelabError {
    WakelabError::Image {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

/// Write `values` (rows x cols, row-major) as a float32 GeoTIFF, atomically.
pub fn write_float_tiff(
    path: &Path,
    values: &[f32],
    rows: usize,
    cols: usize,
    at: Placement,
) -> Result<(), WakelabError> {
    assert_eq!(values.len(), rows * cols, "image size");
    let file = AtomicFile::new(path)?;
    {
        let f = std::fs::File::create(file.temporary_path()).map_err(|e| WakelabError::io(path, e))?;
        let mut tiff = TiffEncoder::new(std::io::BufWriter::new(f)).map_err(|e| tiff_error(path, e))?;
        let mut image = tiff
            .new_image::<colortype::Gray32Float>(cols as u32, rows as u32)
            .map_err(|e| tiff_error(path, e))?;
        let d = at.pixel_spacing;
        let enc = image.encoder();
        // ModelPixelScaleTag: (dx, dy, dz); y grows upwards in model space
        enc.write_tag(Tag::Unknown(33550), &[d, d, 0.0][..])
            .map_err(|e| tiff_error(path, e))?;
        // ModelTiepointTag: raster (0, 0, 0) at model (x, y, 0)
        enc.write_tag(
            Tag::Unknown(33922),
            &[0.0, 0.0, 0.0, at.top_left.0, at.top_left.1, 0.0][..],
        )
        .map_err(|e| tiff_error(path, e))?;
        // GeoKeyDirectoryTag: version 1.1.0, two keys: GTModelType = user-defined (32767),
        // GTRasterType = PixelIsArea (1)
        enc.write_tag(
            Tag::Unknown(34735),
            &[1u16, 1, 0, 2, 1024, 0, 1, 32767, 1025, 0, 1, 1][..],
        )
        .map_err(|e| tiff_error(path, e))?;
        image.write_data(values).map_err(|e| tiff_error(path, e))?;
    }
    file.commit()?;
    Ok(())
}

/// Write an 8-bit grey PNG of `values` stretched linearly from `lo` (black) to `hi` (white).
pub fn write_quicklook(
    path: &Path,
    values: &[f32],
    rows: usize,
    cols: usize,
    lo: f64,
    hi: f64,
) -> Result<(), WakelabError> {
    let span = (hi - lo).max(1e-30);
    let bytes: Vec<u8> = values
        .iter()
        .map(|&v| (((v as f64 - lo) / span).clamp(0.0, 1.0) * 255.0).round() as u8)
        .collect();
    let img = image::GrayImage::from_raw(cols as u32, rows as u32, bytes).expect("size");
    let file = AtomicFile::new(path)?;
    img.save_with_format(file.temporary_path(), image::ImageFormat::Png)
        .map_err(|e| tiff_error(path, e))?;
    file.commit()?;
    Ok(())
}

/// The q-quantile of the finite values.
pub fn quantile(values: &[f32], q: f64) -> f64 {
    let mut v: Vec<f32> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f32::total_cmp);
    v[((v.len() - 1) as f64 * q).round() as usize] as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn float_tiff_reads_back_with_its_geotags() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.tif");
        let values: Vec<f32> = (0..12).map(|i| i as f32 * 0.5).collect();
        write_float_tiff(
            &path,
            &values,
            3,
            4,
            Placement {
                top_left: (100.0, 50.0),
                pixel_spacing: 2.5,
            },
        )
        .unwrap();
        let mut dec = tiff::decoder::Decoder::new(std::fs::File::open(&path).unwrap()).unwrap();
        assert_eq!(dec.dimensions().unwrap(), (4, 3));
        match dec.read_image().unwrap() {
            tiff::decoder::DecodingResult::F32(v) => assert_eq!(v, values),
            other => panic!("not f32: {other:?}"),
        }
        let scale = dec.get_tag_f64_vec(Tag::Unknown(33550)).unwrap();
        assert_eq!(scale, vec![2.5, 2.5, 0.0]);
        let tie = dec.get_tag_f64_vec(Tag::Unknown(33922)).unwrap();
        assert_eq!(&tie[3..5], &[100.0, 50.0]);
    }
}

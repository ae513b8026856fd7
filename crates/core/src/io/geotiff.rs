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

/// GeoTIFF 1.1 tag numbers (OGC 19-008r4, Sec. 7).
const MODEL_PIXEL_SCALE: Tag = Tag::Unknown(33550);
const MODEL_TIEPOINT: Tag = Tag::Unknown(33922);
const MODEL_TRANSFORMATION: Tag = Tag::Unknown(34264);
const GEO_KEY_DIRECTORY: Tag = Tag::Unknown(34735);
const GEO_DOUBLE_PARAMS: Tag = Tag::Unknown(34736);
const GEO_ASCII_PARAMS: Tag = Tag::Unknown(34737);
/// The GeoAsciiParams tag's number, as a key's location.
const GEO_ASCII_PARAMS_CODE: u16 = 34737;
/// EPSG's unit code of the metre.
pub const LINEAR_UNIT_METRE: u16 = 9001;
/// The citation of a simulated scene's local CRS (GeoTIFF ASCII parameters end in `|`).
const LOCAL_CITATION: &str = "wakelab scene grid: local x east, y north, metres|";

/// A raster's GeoTIFF tags, as read from a user's file or made from a [`Placement`]: the raster
/// to model mapping (pixel scale and tiepoints, or a transformation matrix) and the CRS keys,
/// kept verbatim so that an output aligned with an input carries the input's CRS.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Georeference {
    /// ModelPixelScale (sx, sy, sz).
    pub pixel_scale: Option<Vec<f64>>,
    /// ModelTiepoint: (i, j, k, x, y, z) per tiepoint.
    pub tiepoints: Vec<f64>,
    /// ModelTransformation, 4 x 4 row-major.
    pub transformation: Option<Vec<f64>>,
    pub geo_keys: Vec<u16>,
    pub geo_doubles: Vec<f64>,
    pub geo_ascii: Option<String>,
}

impl Georeference {
    /// A simulated scene's grid: raster (0, 0) at the top-left corner `at.top_left`, square
    /// pixels, y up, in a local engineering CRS whose linear unit is the metre, as GDAL writes a
    /// LOCAL_CS (GTModelType user-defined 32767, PixelIsArea, a GTCitation, and
    /// ProjLinearUnits = 9001, EPSG's metre; GeoTIFF 1.1, OGC 19-008r4, Annex B).
    pub fn from_placement(at: Placement) -> Self {
        let d = at.pixel_spacing;
        Self {
            pixel_scale: Some(vec![d, d, 0.0]),
            tiepoints: vec![0.0, 0.0, 0.0, at.top_left.0, at.top_left.1, 0.0],
            transformation: None,
            // version 1.1.0, four keys in key order: GTModelType = user-defined, GTRasterType =
            // PixelIsArea, GTCitation (the ASCII parameters), ProjLinearUnits = metre
            geo_keys: vec![
                1,
                1,
                0,
                4,
                1024,
                0,
                1,
                32767,
                1025,
                0,
                1,
                1,
                1026,
                GEO_ASCII_PARAMS_CODE,
                LOCAL_CITATION.len() as u16,
                0,
                3076,
                0,
                1,
                LINEAR_UNIT_METRE,
            ],
            geo_doubles: Vec::new(),
            geo_ascii: Some(LOCAL_CITATION.to_string()),
        }
    }

    /// The pixel grid of an image that has no georeference: model (x, y) = (column, -row), one
    /// unit per pixel, in a user-defined model with no linear unit (it is not metres).
    pub fn pixel_grid() -> Self {
        Self {
            pixel_scale: Some(vec![1.0, 1.0, 0.0]),
            tiepoints: vec![0.0; 6],
            transformation: None,
            // GTModelType = user-defined, GTRasterType = PixelIsArea
            geo_keys: vec![1, 1, 0, 2, 1024, 0, 1, 32767, 1025, 0, 1, 1],
            geo_doubles: Vec::new(),
            geo_ascii: None,
        }
    }

    /// The GeoTIFF tags of a TIFF file; None when it has no raster to model mapping.
    pub fn read(path: &Path) -> Result<Option<Self>, WakelabError> {
        let file = std::fs::File::open(path).map_err(|e| WakelabError::io(path, e))?;
        let mut dec = tiff::decoder::Decoder::new(std::io::BufReader::new(file)).map_err(|e| tiff_error(path, e))?;
        let mut doubles = |tag| -> Result<Option<Vec<f64>>, WakelabError> {
            match dec.find_tag(tag).map_err(|e| tiff_error(path, e))? {
                Some(v) => Ok(Some(v.into_f64_vec().map_err(|e| tiff_error(path, e))?)),
                None => Ok(None),
            }
        };
        let pixel_scale = doubles(MODEL_PIXEL_SCALE)?;
        let tiepoints = doubles(MODEL_TIEPOINT)?.unwrap_or_default();
        let transformation = doubles(MODEL_TRANSFORMATION)?;
        let geo_doubles = doubles(GEO_DOUBLE_PARAMS)?.unwrap_or_default();
        if transformation.is_none() && (pixel_scale.is_none() || tiepoints.len() < 6) {
            return Ok(None);
        }
        let geo_keys = match dec.find_tag(GEO_KEY_DIRECTORY).map_err(|e| tiff_error(path, e))? {
            Some(v) => v.into_u16_vec().map_err(|e| tiff_error(path, e))?,
            None => Vec::new(),
        };
        let geo_ascii = match dec.find_tag(GEO_ASCII_PARAMS).map_err(|e| tiff_error(path, e))? {
            Some(v) => Some(v.into_string().map_err(|e| tiff_error(path, e))?),
            None => None,
        };
        Ok(Some(Self {
            pixel_scale,
            tiepoints,
            transformation,
            geo_keys,
            geo_doubles,
            geo_ascii,
        }))
    }

    /// The same ground for a raster whose pixel (i, j) covers this raster's pixels
    /// [i f, (i + 1) f) x [j f, (j + 1) f): the raster coordinates of every tiepoint divided by
    /// f, the pixel scale and the matrix's raster columns multiplied by it.
    pub fn coarsened(&self, factor: f64) -> Self {
        let mut g = self.clone();
        if let Some(s) = g.pixel_scale.as_mut() {
            s.iter_mut().take(2).for_each(|v| *v *= factor);
        }
        for point in g.tiepoints.chunks_mut(6) {
            point.iter_mut().take(2).for_each(|v| *v /= factor);
        }
        if let Some(m) = g.transformation.as_mut() {
            for row in m.chunks_mut(4) {
                row.iter_mut().take(2).for_each(|v| *v *= factor);
            }
        }
        g
    }

    /// Model (x, y) of raster point (column i, row j), pixel corners at integers.
    pub fn model_xy(&self, i: f64, j: f64) -> Option<(f64, f64)> {
        if let Some(m) = self.transformation.as_ref().filter(|m| m.len() >= 8) {
            return Some((m[0] * i + m[1] * j + m[3], m[4] * i + m[5] * j + m[7]));
        }
        let s = self.pixel_scale.as_ref().filter(|s| s.len() >= 2)?;
        let t = self.tiepoints.get(..6)?;
        Some((t[3] + (i - t[0]) * s[0], t[4] - (j - t[1]) * s[1]))
    }
}

/// Write `values` (rows x cols, row-major) as a float32 GeoTIFF on a simulated scene's grid,
/// atomically.
pub fn write_float_tiff(
    path: &Path,
    values: &[f32],
    rows: usize,
    cols: usize,
    at: Placement,
) -> Result<(), WakelabError> {
    write_georeferenced_tiff(path, values, rows, cols, &Georeference::from_placement(at))
}

/// Write `values` (rows x cols, row-major) as a float32 GeoTIFF with the tags of `geo`,
/// atomically.
pub fn write_georeferenced_tiff(
    path: &Path,
    values: &[f32],
    rows: usize,
    cols: usize,
    geo: &Georeference,
) -> Result<(), WakelabError> {
    assert_eq!(values.len(), rows * cols, "image size");
    let file = AtomicFile::new(path)?;
    {
        let f = std::fs::File::create(file.temporary_path()).map_err(|e| WakelabError::io(path, e))?;
        let mut tiff = TiffEncoder::new(std::io::BufWriter::new(f)).map_err(|e| tiff_error(path, e))?;
        let mut image = tiff
            .new_image::<colortype::Gray32Float>(cols as u32, rows as u32)
            .map_err(|e| tiff_error(path, e))?;
        let enc = image.encoder();
        let e = |e| tiff_error(path, e);
        if let Some(scale) = &geo.pixel_scale {
            enc.write_tag(MODEL_PIXEL_SCALE, &scale[..]).map_err(e)?;
        }
        if !geo.tiepoints.is_empty() {
            enc.write_tag(MODEL_TIEPOINT, &geo.tiepoints[..]).map_err(e)?;
        }
        if let Some(m) = &geo.transformation {
            enc.write_tag(MODEL_TRANSFORMATION, &m[..]).map_err(e)?;
        }
        if !geo.geo_keys.is_empty() {
            enc.write_tag(GEO_KEY_DIRECTORY, &geo.geo_keys[..]).map_err(e)?;
        }
        if !geo.geo_doubles.is_empty() {
            enc.write_tag(GEO_DOUBLE_PARAMS, &geo.geo_doubles[..]).map_err(e)?;
        }
        if let Some(text) = &geo.geo_ascii {
            enc.write_tag(GEO_ASCII_PARAMS, text.as_str()).map_err(e)?;
        }
        image.write_data(values).map_err(e)?;
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

/// The q-quantile of the finite values: the one at rank round((n - 1) q) in ascending order,
/// found by selection (linear time; the detector normalises every window by two medians).
pub fn quantile(values: &[f32], q: f64) -> f64 {
    let mut v: Vec<f32> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return 0.0;
    }
    let rank = ((v.len() - 1) as f64 * q).round() as usize;
    *v.select_nth_unstable_by(rank, f32::total_cmp).1 as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Selection gives the order statistic a full sort gives: ties, signed zeros and NaN included.
    #[test]
    fn quantile_is_the_sorted_order_statistic() {
        let mut x = 12345u32;
        let mut values: Vec<f32> = (0..1001)
            .map(|_| {
                x = x.wrapping_mul(1_103_515_245).wrapping_add(12345);
                ((x >> 16) % 97) as f32 - 48.0
            })
            .collect();
        values.extend([f32::NAN, -0.0, 0.0, f32::INFINITY]);
        let mut sorted: Vec<f32> = values.iter().copied().filter(|v| v.is_finite()).collect();
        sorted.sort_by(f32::total_cmp);
        for q in [0.0, 0.1, 0.5, 0.75, 1.0] {
            let expected = sorted[((sorted.len() - 1) as f64 * q).round() as usize];
            assert_eq!(quantile(&values, q).to_bits(), (expected as f64).to_bits(), "{q}");
        }
        assert_eq!(
            quantile(&[1.0, 2.0, 3.0, 4.0], 0.5),
            3.0,
            "the upper median of an even count"
        );
    }

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
        // the key directory, read as a GeoTIFF reader does: user-defined model whose linear
        // unit is EPSG 9001 (metre), its citation in the ASCII parameters
        let keys = dec.get_tag_u16_vec(Tag::Unknown(34735)).unwrap();
        let key = |id: u16| keys[4..].chunks(4).find(|k| k[0] == id).map(|k| k.to_vec());
        assert_eq!(keys[3] as usize, (keys.len() - 4) / 4);
        assert_eq!(key(1024), Some(vec![1024, 0, 1, 32767]));
        assert_eq!(key(3076), Some(vec![3076, 0, 1, 9001]));
        let citation = key(1026).unwrap();
        let ascii = dec.get_tag_ascii_string(Tag::Unknown(34737)).unwrap();
        let text = &ascii[citation[3] as usize..][..citation[2] as usize];
        assert!(text.contains("metres") && text.ends_with('|'), "{text}");
        let tie = dec.get_tag_f64_vec(Tag::Unknown(33922)).unwrap();
        assert_eq!(&tie[3..5], &[100.0, 50.0]);
        let geo = Georeference::read(&path).unwrap().expect("georeferenced");
        assert_eq!(geo.model_xy(0.0, 0.0), Some((100.0, 50.0)));
        assert_eq!(geo.model_xy(4.0, 3.0), Some((110.0, 42.5)));
    }

    #[test]
    fn a_users_crs_and_mapping_survive_coarsening() {
        // a UTM-like file: a tiepoint not at the origin and the CRS keys of EPSG:32632 with a
        // citation, as GDAL writes them
        let geo = Georeference {
            pixel_scale: Some(vec![10.0, 10.0, 0.0]),
            tiepoints: vec![2.0, 4.0, 0.0, 500_020.0, 6_000_000.0, 0.0],
            transformation: None,
            geo_keys: vec![1, 1, 0, 3, 1024, 0, 1, 1, 1025, 0, 1, 1, 3072, 0, 1, 32632],
            geo_doubles: vec![0.5],
            geo_ascii: Some("WGS 84 / UTM zone 32N|".into()),
        };
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("utm.tif");
        write_georeferenced_tiff(&path, &[0.0; 6], 2, 3, &geo).unwrap();
        let back = Georeference::read(&path).unwrap().unwrap();
        assert_eq!(back, geo);
        // raster (0, 0) lies 2 columns left of and 4 rows above the tiepoint
        assert_eq!(back.model_xy(0.0, 0.0), Some((500_000.0, 6_000_040.0)));
        // a map of 8 x 8 pixel blocks covers the same ground: its corner (1, 1) is pixel (8, 8)
        let coarse = back.coarsened(8.0);
        assert_eq!(coarse.model_xy(1.0, 1.0), back.model_xy(8.0, 8.0));
        assert_eq!(coarse.geo_keys, geo.geo_keys);
        // a transformation matrix coarsens the same way
        let matrix = Georeference {
            transformation: Some(vec![
                10.0, 2.0, 0.0, 100.0, 1.0, -10.0, 0.0, 200.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0,
            ]),
            ..Georeference::default()
        };
        assert_eq!(matrix.coarsened(4.0).model_xy(2.0, 3.0), matrix.model_xy(8.0, 12.0));
        // a plain TIFF has no georeference
        let plain = dir.path().join("plain.tif");
        let f = std::fs::File::create(&plain).unwrap();
        TiffEncoder::new(f)
            .unwrap()
            .write_image::<colortype::Gray32Float>(2, 1, &[1.0, 2.0])
            .unwrap();
        assert_eq!(Georeference::read(&plain).unwrap(), None);
    }
}

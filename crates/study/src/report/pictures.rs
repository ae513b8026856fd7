//! Pictures of fields for the HTML report: an image's values as shown (radar in dB), their
//! colour range, and a field rendered with its title, colour bar and caption as a PNG data URI.

use crate::Result;
use base64::Engine as _;
use ndarray::Array2;
use wakelab_core::io::picture::{Colormap, FieldPicture};

/// A rendered picture over `range` as a PNG data URI, for a self-contained page.
pub(crate) fn png_data_uri(picture: &FieldPicture, range: (f64, f64)) -> Result<String> {
    let img = picture.render_in(range);
    let mut bytes = std::io::Cursor::new(Vec::new());
    img.write_to(&mut bytes, image::ImageFormat::Png)?;
    Ok(format!(
        "data:image/png;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(bytes.get_ref())
    ))
}

/// A field as a PNG data URI: a square picture of `side` pixels on the sequential colour map over
/// `range`, with its title, colour bar in `units` and caption.
pub(crate) fn field_png(
    values: &[f32],
    (rows, cols): (usize, usize),
    title: String,
    units: &str,
    (side, caption): (u32, &str),
    range: (f64, f64),
) -> Result<String> {
    let picture = FieldPicture {
        values,
        rows,
        cols,
        title,
        units: units.to_string(),
        colormap: Colormap::Sequential,
        size: (side, side),
        caption: caption.to_string(),
    };
    png_data_uri(&picture, range)
}

/// An image's values as the report shows them: radar sigma0 in dB, infrared as it is (K).
pub(crate) fn display_values(image: &Array2<f32>, radar: bool) -> Vec<f32> {
    if radar {
        image.iter().map(|&v| 10.0 * v.max(1e-30).log10()).collect()
    } else {
        image.iter().copied().collect()
    }
}

/// Percentile range of values (2nd to 98th), as the dataset's quicklooks use.
pub(crate) fn stretch(values: &[f32]) -> (f64, f64) {
    let lo = wakelab_core::io::geotiff::quantile(values, 0.02);
    let hi = wakelab_core::io::geotiff::quantile(values, 0.98);
    if hi > lo {
        (lo, hi)
    } else {
        (lo, lo + 1.0)
    }
}

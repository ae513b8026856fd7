//! Pictures of fields for the HTML report: an image's values as shown (radar in dB), their
//! colour range, and a field drawn with its title, colour bar and caption as an SVG figure.

use super::figure::{Figure, Legend};
use crate::Result;
use ndarray::Array2;

/// A field as an inline SVG figure of `side` pixels over `range`, with its title, a colour bar in
/// `units` (or, for `units` "mask", the legend of a wake mask), the caption and, where the pixel
/// spacing is known, a scale bar.
pub(crate) fn field_svg(
    values: &[f32],
    shape: (usize, usize),
    title: String,
    units: &str,
    (side, caption): (f64, &str),
    range: (f64, f64),
    pixel_spacing: Option<f64>,
) -> Result<String> {
    let legend = if units == "mask" {
        Legend::Mask {
            absent: "no wake".into(),
            present: "wake".into(),
        }
    } else {
        Legend::Continuous { units: units.into() }
    };
    Figure {
        values,
        shape,
        title,
        legend,
        range,
        side,
        caption: caption.into(),
        pixel_spacing,
        marks: Vec::new(),
        marks_label: String::new(),
    }
    .svg()
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

//! A field of the report as an inline SVG figure: the raster as a PNG at its own resolution
//! (scaled by the browser, pixels kept sharp), with the title, colour bar, tick labels, units,
//! scale bar and caption as SVG text in the page's font, so they stay legible at any zoom. A
//! mask gets a legend of its two classes instead of a colour bar; detections are drawn as boxes.

use super::svg::{escape, tick_label, ticks};
use crate::Result;
use base64::Engine as _;
use image::{Rgb, RgbImage};
use std::fmt::Write as _;
use wakelab_core::io::picture::Colormap;

/// How a figure's colours are read.
pub(crate) enum Legend {
    /// A colour bar over the range, with its units.
    Continuous { units: String },
    /// Two classes: 0 and 1 of a mask, with their names.
    Mask { absent: String, present: String },
}

/// A rectangle on the field in its pixels: (top row, left column, rows, columns).
pub(crate) type Mark = (f64, f64, f64, f64);

/// A field to draw.
pub(crate) struct Figure<'a> {
    /// `values[row * cols + col]`, row 0 at the top.
    pub values: &'a [f32],
    /// (rows, columns).
    pub shape: (usize, usize),
    pub title: String,
    pub legend: Legend,
    pub range: (f64, f64),
    /// Side of the drawn field (CSS pixels).
    pub side: f64,
    pub caption: String,
    /// Ground size of a pixel (m): draws a scale bar.
    pub pixel_spacing: Option<f64>,
    /// Boxes drawn over the field (detections), and what they are.
    pub marks: Vec<Mark>,
    pub marks_label: String,
}

const TITLE_H: f64 = 22.0;
const LEGEND_W: f64 = 96.0;
const LINE_H: f64 = 14.0;
/// Colour of detection boxes (Okabe & Ito's vermillion, seen on viridis and on grey).
const MARK_COLOUR: &str = "#D55E00";

fn hex([r, g, b]: [u8; 3]) -> String {
    format!("#{r:02x}{g:02x}{b:02x}")
}

/// A "nice" ground length near a fifth of `extent` metres: 1, 2 or 5 times a power of ten.
fn scale_length(extent: f64) -> f64 {
    let target = extent / 5.0;
    let magnitude = 10f64.powf(target.log10().floor());
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * magnitude)
        .find(|&l| l <= target)
        .unwrap_or(magnitude)
}

fn length_label(metres: f64) -> String {
    if metres >= 1000.0 {
        format!("{} km", wakelab_core::io::text::number(metres / 1000.0))
    } else {
        format!("{} m", wakelab_core::io::text::number(metres))
    }
}

impl Figure<'_> {
    /// The raster as a PNG data URI at the field's own resolution.
    fn raster(&self) -> Result<String> {
        let (rows, cols) = self.shape;
        let (lo, hi) = self.range;
        let mask = matches!(self.legend, Legend::Mask { .. });
        let img = RgbImage::from_fn(cols as u32, rows as u32, |x, y| {
            let v = self.values[y as usize * cols + x as usize] as f64;
            Rgb(if !v.is_finite() {
                [128, 128, 128]
            } else if mask {
                if v >= 0.5 {
                    [253, 231, 37]
                } else {
                    [68, 1, 84]
                }
            } else {
                Colormap::Sequential.colour((v - lo) / (hi - lo))
            })
        });
        let mut bytes = std::io::Cursor::new(Vec::new());
        img.write_to(&mut bytes, image::ImageFormat::Png)?;
        Ok(format!(
            "data:image/png;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(bytes.get_ref())
        ))
    }

    /// The figure as an `<svg class="field">` element.
    pub fn svg(&self) -> Result<String> {
        let (rows, cols) = self.shape;
        let side = self.side;
        let (w, h) = if cols >= rows {
            (side, side * rows as f64 / cols as f64)
        } else {
            (side * cols as f64 / rows as f64, side)
        };
        let caption = wakelab_core::io::picture::wrap(&self.caption, ((w + LEGEND_W) / 6.2) as usize);
        let width = w + LEGEND_W;
        let height = TITLE_H + h + 6.0 + LINE_H * (caption.len() as f64 + 1.0);
        let mut s = format!(
            r#"<svg class="field" xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.0} {height:.0}" font-family="sans-serif" font-size="11" role="img" aria-label="{}">"#,
            escape(&self.title)
        );
        let _ = write!(
            s,
            r#"<text x="0" y="15" font-size="13" font-weight="bold">{}</text>"#,
            escape(&self.title)
        );
        let _ = write!(
            s,
            r#"<image x="0" y="{TITLE_H}" width="{w:.1}" height="{h:.1}" preserveAspectRatio="none" style="image-rendering:pixelated" href="{}"/>"#,
            self.raster()?
        );
        let (sx, sy) = (w / cols as f64, h / rows as f64);
        for &(top, left, r, c) in &self.marks {
            let _ = write!(
                s,
                r#"<rect x="{:.1}" y="{:.1}" width="{:.1}" height="{:.1}" fill="none" stroke="{MARK_COLOUR}" stroke-width="1.5"/>"#,
                left * sx,
                TITLE_H + top * sy,
                c * sx,
                r * sy
            );
        }
        if let Some(dx) = self.pixel_spacing {
            let length = scale_length(cols as f64 * dx);
            let bar = length / dx * sx;
            let y = TITLE_H + h - 10.0;
            let _ = write!(
                s,
                r#"<rect x="6" y="{:.1}" width="{:.1}" height="16" fill="white" fill-opacity="0.75"/><line x1="10" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="black" stroke-width="3"/><text x="{:.1}" y="{:.1}" text-anchor="middle" font-size="10">{}</text>"#,
                y - 12.0,
                bar + 8.0,
                10.0 + bar,
                10.0 + bar / 2.0,
                y - 3.0,
                length_label(length)
            );
        }
        let lx = w + 10.0;
        match &self.legend {
            Legend::Continuous { units } => {
                let (lo, hi) = self.range;
                let _ = write!(
                    s,
                    r#"<defs><linearGradient id="{id}" x1="0" y1="1" x2="0" y2="0">"#,
                    id = self.gradient_id()
                );
                for k in 0..=8 {
                    let t = k as f64 / 8.0;
                    let _ = write!(
                        s,
                        r#"<stop offset="{t:.3}" stop-color="{}"/>"#,
                        hex(Colormap::Sequential.colour(t))
                    );
                }
                let _ = write!(
                    s,
                    r#"</linearGradient></defs><rect x="{lx:.1}" y="{TITLE_H}" width="12" height="{h:.1}" fill="url(#{})" stroke="black" stroke-width="0.5"/>"#,
                    self.gradient_id()
                );
                for t in ticks(lo, hi) {
                    let y = TITLE_H + h * (1.0 - (t - lo) / (hi - lo));
                    let _ = write!(
                        s,
                        r#"<line x1="{:.1}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="black"/><text x="{:.1}" y="{:.1}">{}</text>"#,
                        lx + 12.0,
                        lx + 15.0,
                        lx + 18.0,
                        y + 4.0,
                        tick_label(t)
                    );
                }
                let _ = write!(
                    s,
                    r#"<text x="{lx:.1}" y="{:.1}">{}</text>"#,
                    TITLE_H + h + 14.0,
                    escape(units)
                );
            }
            Legend::Mask { absent, present } => {
                for (k, (colour, name)) in [("#fde725", present), ("#440154", absent)].iter().enumerate() {
                    let y = TITLE_H + 4.0 + 18.0 * k as f64;
                    let _ = write!(
                        s,
                        r#"<rect x="{lx:.1}" y="{y:.1}" width="12" height="12" fill="{colour}" stroke="black" stroke-width="0.5"/><text x="{:.1}" y="{:.1}">{}</text>"#,
                        lx + 16.0,
                        y + 10.0,
                        escape(name)
                    );
                }
            }
        }
        let mut line_y = TITLE_H + h + 6.0 + LINE_H;
        if !self.marks.is_empty() {
            let _ = write!(
                s,
                r#"<rect x="0" y="{:.1}" width="10" height="8" fill="none" stroke="{MARK_COLOUR}" stroke-width="1.5"/><text x="14" y="{line_y:.1}">{}</text>"#,
                line_y - 8.0,
                escape(&self.marks_label)
            );
        }
        for line in &caption {
            line_y += LINE_H;
            let _ = write!(
                s,
                r##"<text x="0" y="{line_y:.1}" fill="#444">{}</text>"##,
                escape(line)
            );
        }
        s.push_str("</svg>");
        Ok(s)
    }

    /// A gradient id unique to this figure's title (several figures share one page).
    fn gradient_id(&self) -> String {
        let slug: String = self
            .title
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
            .collect();
        format!("bar-{slug}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_bars_are_round_lengths_near_a_fifth_of_the_picture() {
        assert_eq!(scale_length(5120.0), 1000.0);
        assert_eq!(scale_length(320.0), 50.0);
        assert_eq!(scale_length(2560.0), 500.0);
        assert_eq!(length_label(1000.0), "1 km");
        assert_eq!(length_label(50.0), "50 m");
    }

    #[test]
    fn a_figure_is_svg_text_around_its_raster() {
        let values = [0.0f32, 1.0, 0.5, f32::NAN];
        let figure = Figure {
            values: &values,
            shape: (2, 2),
            title: "C <wake>".into(),
            legend: Legend::Continuous { units: "dB".into() },
            range: (0.0, 1.0),
            side: 100.0,
            caption: "2 x 2 px".into(),
            pixel_spacing: Some(10.0),
            marks: vec![(0.0, 0.0, 1.0, 1.0)],
            marks_label: "detection".into(),
        };
        let svg = figure.svg().unwrap();
        assert!(svg.starts_with("<svg class=\"field\"") && svg.ends_with("</svg>"));
        assert!(svg.contains("C &lt;wake&gt;") && svg.contains(">dB<") && svg.contains(">2 m<"));
        assert!(svg.contains("href=\"data:image/png;base64,") && svg.contains(MARK_COLOUR));
        // the colour bar's ticks are round numbers, not four decimals
        assert!(svg.contains(">0.4<") && svg.contains(">1<") && !svg.contains("0.4000"));
    }
}

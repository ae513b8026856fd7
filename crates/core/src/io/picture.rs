//! PNG pictures of 2D fields with a title and a labelled colour bar.
//!
//! The field is resampled (nearest cell) to the requested picture size, coloured with a
//! perceptually uniform sequential map (viridis, for magnitudes) or a blue-white-red diverging map
//! (for signed anomalies, centred on zero), and framed with a colour bar whose end and middle
//! values are printed with an 8x8 bitmap font, so no font files are needed. The colour range
//! spans the 0.5th to 99.5th percentiles (for a diverging map: +- the 99.5th percentile of |v|),
//! so a few extreme cells do not wash out the picture; values beyond it take the end colours.

use crate::error::WakelabError;
use crate::io::atomic::AtomicFile;
use image::{Rgb, RgbImage};
use std::path::Path;

/// Colour maps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Colormap {
    /// viridis (van der Walt & Smith 2015), for magnitudes.
    Sequential,
    /// blue-white-red, symmetric about zero, for signed fields.
    Diverging,
}

impl Colormap {
    /// The colour map of a field: diverging for a signed field, sequential for a magnitude.
    pub fn for_field(signed: bool) -> Self {
        if signed {
            Colormap::Diverging
        } else {
            Colormap::Sequential
        }
    }

    /// Colour of `t` in [0, 1].
    pub fn colour(&self, t: f64) -> [u8; 3] {
        const VIRIDIS: [[f64; 3]; 9] = [
            [68.0, 1.0, 84.0],
            [71.0, 44.0, 122.0],
            [59.0, 81.0, 139.0],
            [44.0, 113.0, 142.0],
            [33.0, 144.0, 141.0],
            [39.0, 173.0, 129.0],
            [92.0, 200.0, 99.0],
            [170.0, 220.0, 50.0],
            [253.0, 231.0, 37.0],
        ];
        const BWR: [[f64; 3]; 5] = [
            [33.0, 102.0, 172.0],
            [146.0, 197.0, 222.0],
            [247.0, 247.0, 247.0],
            [244.0, 165.0, 130.0],
            [178.0, 24.0, 43.0],
        ];
        let stops: &[[f64; 3]] = match self {
            Colormap::Sequential => &VIRIDIS,
            Colormap::Diverging => &BWR,
        };
        let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 };
        let x = t * (stops.len() - 1) as f64;
        let i = (x.floor() as usize).min(stops.len() - 2);
        let f = x - i as f64;
        let mut c = [0u8; 3];
        for (ch, out) in c.iter_mut().enumerate() {
            *out = (stops[i][ch] * (1.0 - f) + stops[i + 1][ch] * f).round() as u8;
        }
        c
    }
}

/// A field to draw: `values[row * cols + col]`, row 0 at the top of the picture.
#[derive(Debug, Clone)]
pub struct FieldPicture<'a> {
    pub values: &'a [f32],
    pub rows: usize,
    pub cols: usize,
    pub title: String,
    /// Label of the colour bar (quantity and units).
    pub units: String,
    pub colormap: Colormap,
    /// Picture size of the field area in pixels (width, height).
    pub size: (u32, u32),
    /// Axis note printed under the field (for example the extent in metres).
    pub caption: String,
}

const MARGIN: u32 = 10;
const TITLE_H: u32 = 28;
const BAR_W: u32 = 18;
const LABEL_W: u32 = 110;
const LINE_H: u32 = 12;

impl FieldPicture<'_> {
    /// Colour range: +- the 99.5th percentile of |v| for a diverging map, the 0.5th..99.5th
    /// percentiles otherwise.
    pub fn range(&self) -> (f64, f64) {
        let mut finite: Vec<f64> = self
            .values
            .iter()
            .filter(|v| v.is_finite())
            .map(|&v| v as f64)
            .collect();
        if finite.is_empty() {
            return (0.0, 1.0);
        }
        let quantile = |sorted: &[f64], q: f64| sorted[((sorted.len() - 1) as f64 * q).round() as usize];
        match self.colormap {
            Colormap::Diverging => {
                finite.iter_mut().for_each(|v| *v = v.abs());
                finite.sort_by(f64::total_cmp);
                let m = quantile(&finite, 0.995).max(1e-30);
                (-m, m)
            }
            Colormap::Sequential => {
                finite.sort_by(f64::total_cmp);
                let (lo, hi) = (quantile(&finite, 0.005), quantile(&finite, 0.995));
                if hi > lo {
                    (lo, hi)
                } else {
                    (lo, lo + 1e-30_f64.max(lo.abs() * 1e-6))
                }
            }
        }
    }

    /// Render to an RGB image.
    pub fn render(&self) -> RgbImage {
        self.render_in(self.range())
    }

    /// Render with the colour range `(lo, hi)` (pictures meant to be compared share one).
    pub fn render_in(&self, (lo, hi): (f64, f64)) -> RgbImage {
        let (w, h) = self.size;
        let total_w = MARGIN + w + MARGIN + BAR_W + 6 + LABEL_W;
        let caption = wrap(&self.caption, ((total_w - 2 * MARGIN) / 8) as usize);
        let total_h = TITLE_H + h + 8 + LINE_H * caption.len() as u32 + MARGIN;
        let mut img = RgbImage::from_pixel(total_w, total_h, Rgb([255, 255, 255]));
        for py in 0..h {
            let row = ((py as f64 + 0.5) / h as f64 * self.rows as f64) as usize;
            for px in 0..w {
                let col = ((px as f64 + 0.5) / w as f64 * self.cols as f64) as usize;
                let v = self.values[row.min(self.rows - 1) * self.cols + col.min(self.cols - 1)] as f64;
                let c = if v.is_finite() {
                    self.colormap.colour((v - lo) / (hi - lo))
                } else {
                    [128, 128, 128]
                };
                img.put_pixel(MARGIN + px, TITLE_H + py, Rgb(c));
            }
        }
        let bar_x = MARGIN + w + MARGIN;
        for py in 0..h {
            let t = 1.0 - (py as f64 + 0.5) / h as f64;
            let c = self.colormap.colour(t);
            for px in 0..BAR_W {
                img.put_pixel(bar_x + px, TITLE_H + py, Rgb(c));
            }
        }
        let black = Rgb([0, 0, 0]);
        draw_text(&mut img, MARGIN, 6, &self.title, 2, black);
        let lx = bar_x + BAR_W + 6;
        draw_text(&mut img, lx, TITLE_H, &format_value(hi), 1, black);
        draw_text(
            &mut img,
            lx,
            TITLE_H + h / 2 - 4,
            &format_value(0.5 * (lo + hi)),
            1,
            black,
        );
        draw_text(&mut img, lx, TITLE_H + h - 8, &format_value(lo), 1, black);
        draw_text(
            &mut img,
            lx,
            TITLE_H + h / 2 + 12,
            &format!("[{}]", self.units),
            1,
            black,
        );
        for (i, line) in caption.iter().enumerate() {
            draw_text(&mut img, MARGIN, TITLE_H + h + 8 + LINE_H * i as u32, line, 1, black);
        }
        img
    }

    /// Render and write the PNG atomically.
    pub fn write_png(&self, path: &Path) -> Result<(), WakelabError> {
        let img = self.render();
        let file = AtomicFile::new(path)?;
        img.save_with_format(file.temporary_path(), image::ImageFormat::Png)
            .map_err(|e| WakelabError::Image {
                path: path.display().to_string(),
                message: e.to_string(),
            })?;
        file.commit()?;
        Ok(())
    }
}

/// Split `text` into lines of at most `width` characters at spaces.
pub fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines = Vec::new();
    let mut line = String::new();
    for word in text.split_whitespace() {
        if !line.is_empty() && line.len() + 1 + word.len() > width {
            lines.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
    }
    if !line.is_empty() {
        lines.push(line);
    }
    lines
}

/// Short, readable number for a colour-bar label.
pub fn format_value(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if !(1e-3..1e4).contains(&a) {
        format!("{v:.2e}")
    } else {
        format!("{v:.4}")
    }
}

/// Draw ASCII text with the 8x8 font of `font8x8`, scaled by `scale`.
pub fn draw_text(img: &mut RgbImage, x: u32, y: u32, text: &str, scale: u32, colour: Rgb<u8>) {
    use font8x8::UnicodeFonts;
    let mut cx = x;
    for ch in text.chars() {
        let glyph = font8x8::BASIC_FONTS.get(ch).unwrap_or([0; 8]);
        for (gy, bits) in glyph.iter().enumerate() {
            for gx in 0..8u32 {
                if bits & (1 << gx) != 0 {
                    for sy in 0..scale {
                        for sx in 0..scale {
                            let px = cx + gx * scale + sx;
                            let py = y + gy as u32 * scale + sy;
                            if px < img.width() && py < img.height() {
                                img.put_pixel(px, py, colour);
                            }
                        }
                    }
                }
            }
        }
        cx += 8 * scale;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn diverging_map_is_white_at_zero_and_range_is_symmetric() {
        assert_eq!(Colormap::Diverging.colour(0.5), [247, 247, 247]);
        let v = [-1.0f32, 0.5, 2.0, 0.0];
        let p = FieldPicture {
            values: &v,
            rows: 2,
            cols: 2,
            title: "t".into(),
            units: "u".into(),
            colormap: Colormap::Diverging,
            size: (20, 20),
            caption: String::new(),
        };
        assert_eq!(p.range(), (-2.0, 2.0));
        let img = p.render();
        // the top-left cell is -1: blue-ish (more blue than red)
        let px = img.get_pixel(MARGIN + 2, TITLE_H + 2);
        assert!(px[2] > px[0]);
    }

    #[test]
    fn captions_wrap_at_spaces() {
        assert_eq!(wrap("a bb ccc dddd", 6), vec!["a bb", "ccc", "dddd"]);
    }
}

//! Calibration of one Sentinel-1 line: sigma0 = (|DN|^2 - eta) / A^2 per pixel (module doc of
//! [`super`]), the tables expanded across the image's width once.

use super::annotation::{AzimuthBlock, Noise};
use super::lut;

/// The per-pixel noise along one image line, eta in DN^2.
fn noise_row(noise: &NoiseRows, line: usize, out: &mut [f64]) {
    match noise {
        NoiseRows::Range(rows) => rows.row_into(line, out),
        NoiseRows::RangeAzimuth(rows, blocks) => {
            rows.row_into(line, out);
            for block in blocks {
                if line < block.first_line || line > block.last_line {
                    continue;
                }
                let factor = block.at(line as f64);
                let end = (block.last_sample + 1).min(out.len());
                for v in &mut out[block.first_sample.min(end)..end] {
                    *v *= factor;
                }
            }
        }
    }
}

/// [`Noise`] expanded across the image's width.
enum NoiseRows {
    Range(lut::LutRows),
    RangeAzimuth(lut::LutRows, Vec<AzimuthBlock>),
}

/// The calibration of one product: sigma0 from digital numbers, row by row.
pub struct Calibration {
    sigma: lut::LutRows,
    noise: Option<NoiseRows>,
    width: usize,
}

impl Calibration {
    /// From the calibration's `sigmaNought` LUT and, to remove noise, the noise annotation.
    pub fn new(sigma: &lut::SparseLut, noise: Option<&Noise>, width: usize) -> Self {
        let noise = noise.map(|n| match n {
            Noise::Range(r) => NoiseRows::Range(r.rows(width)),
            Noise::RangeAzimuth { range, azimuth } => NoiseRows::RangeAzimuth(range.rows(width), azimuth.clone()),
        });
        Self {
            sigma: sigma.rows(width),
            noise,
            width,
        }
    }

    /// sigma0 of image line `line` from its digital numbers `dn` into `out`: NaN on the row's
    /// leading and trailing zeros (no data), the noise-equivalent sigma0 where noise removal
    /// leaves zero or less; returns how many pixels were floored.
    pub fn row(&self, line: usize, dn: &[u16], out: &mut [f32]) -> usize {
        let mut a = vec![0.0; self.width];
        let mut eta = vec![0.0; self.width];
        self.sigma.row_into(line, &mut a);
        if let Some(noise) = &self.noise {
            noise_row(noise, line, &mut eta);
        }
        let first = dn.iter().position(|&v| v != 0).unwrap_or(dn.len());
        let last = dn.iter().rposition(|&v| v != 0).map_or(first, |p| p + 1);
        let mut floored = 0;
        for (p, o) in out.iter_mut().enumerate() {
            if p < first || p >= last {
                *o = f32::NAN;
                continue;
            }
            let power = dn[p] as f64 * dn[p] as f64;
            let gain = a[p] * a[p];
            let (value, raised) = crate::scale::floored_at_noise((power - eta[p]) / gain, eta[p] / gain);
            *o = value;
            floored += raised as usize;
        }
        floored
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lut::{LutVector, SparseLut};

    /// One row by hand: sigma0 = (DN^2 - eta) / A^2 with A = 500 and eta = 100 x 2 (range LUT
    /// times the azimuth block's factor); border zeros are no data; a pixel below the noise is
    /// floored at eta / A^2.
    #[test]
    fn a_row_is_calibrated_as_esa_defines_it() {
        let flat = |value: f64| {
            SparseLut::new(vec![LutVector {
                line: 0.0,
                pixels: vec![0.0, 5.0],
                values: vec![value, value],
            }])
            .unwrap()
        };
        let noise = Noise::RangeAzimuth {
            range: flat(100.0),
            azimuth: vec![AzimuthBlock {
                first_line: 0,
                last_line: 10,
                first_sample: 0,
                last_sample: 5,
                lines: vec![0.0, 10.0],
                values: vec![2.0, 2.0],
            }],
        };
        let calibration = Calibration::new(&flat(500.0), Some(&noise), 6);
        let dn = [0u16, 300, 10, 1000, 0, 0];
        let mut out = [0.0f32; 6];
        let floored = calibration.row(3, &dn, &mut out);
        assert!(out[0].is_nan() && out[4].is_nan() && out[5].is_nan());
        assert_eq!(out[1], ((300.0f64 * 300.0 - 200.0) / 250_000.0) as f32);
        assert_eq!(out[3], ((1e6f64 - 200.0) / 250_000.0) as f32);
        assert_eq!(floored, 1);
        assert_eq!(out[2], (200.0f64 / 250_000.0) as f32);
        let raw = Calibration::new(&flat(500.0), None, 6);
        raw.row(3, &dn, &mut out);
        assert_eq!(out[2], (100.0f64 / 250_000.0) as f32);
    }
}

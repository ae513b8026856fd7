//! Sentinel-1's sparse look-up tables: vectors of values at given pixels, one vector at each of
//! a few image lines (the calibration's sigmaNought, the noise's range LUT). ESA's product
//! specification (S1-RS-MDA-52-7441, Table 6-5 ff.) and its calibration note (ESA-EOPG-CSCOP-TN-
//! 0002, "Sentinel-1 Level 1 Radiometric Calibration", Eq. 1) ask for bilinear interpolation in
//! line and pixel between the given points; outside the first and last vector or point the edge
//! value holds.

/// One vector: the values at its pixels on one line.
#[derive(Debug, Clone, PartialEq)]
pub struct LutVector {
    pub line: f64,
    pub pixels: Vec<f64>,
    pub values: Vec<f64>,
}

/// Vectors in ascending line order.
#[derive(Debug, Clone, PartialEq)]
pub struct SparseLut {
    pub vectors: Vec<LutVector>,
}

/// Where `x` falls among the ascending `knots`: the lower index and the weight of the upper one
/// (clamped to the ends: weight 0 at or before the first knot, the last knot with weight 0 at
/// or after it).
pub fn bracket(knots: &[f64], x: f64) -> (usize, f64) {
    let n = knots.len();
    if n < 2 || x <= knots[0] {
        return (0, 0.0);
    }
    if x >= knots[n - 1] {
        return (n - 1, 0.0);
    }
    let upper = knots.partition_point(|&k| k <= x);
    let (lo, hi) = (knots[upper - 1], knots[upper]);
    (upper - 1, (x - lo) / (hi - lo))
}

impl LutVector {
    /// The vector linearly interpolated at every pixel 0..width.
    pub fn across(&self, width: usize) -> Vec<f64> {
        (0..width)
            .map(|p| {
                let (i, t) = bracket(&self.pixels, p as f64);
                if t == 0.0 {
                    self.values[i]
                } else {
                    self.values[i] * (1.0 - t) + self.values[i + 1] * t
                }
            })
            .collect()
    }
}

impl SparseLut {
    /// Vectors sorted by line; refused when empty or a vector's pixels and values differ in
    /// count or its pixels do not ascend.
    pub fn new(mut vectors: Vec<LutVector>) -> Result<Self, String> {
        if vectors.is_empty() {
            return Err("no vectors".into());
        }
        for v in &vectors {
            if v.pixels.len() != v.values.len() || v.pixels.is_empty() {
                return Err(format!(
                    "the vector at line {} has {} pixels and {} values",
                    v.line,
                    v.pixels.len(),
                    v.values.len()
                ));
            }
            if v.pixels.windows(2).any(|w| w[1] <= w[0]) {
                return Err(format!("the vector at line {} has pixels out of order", v.line));
            }
        }
        vectors.sort_by(|a, b| a.line.total_cmp(&b.line));
        Ok(Self { vectors })
    }

    /// The table at one (line, pixel): bilinear between the bracketing vectors and pixels.
    pub fn at(&self, line: f64, pixel: f64) -> f64 {
        let lines: Vec<f64> = self.vectors.iter().map(|v| v.line).collect();
        let (i, t) = bracket(&lines, line);
        let in_vector = |v: &LutVector| {
            let (j, u) = bracket(&v.pixels, pixel);
            if u == 0.0 {
                v.values[j]
            } else {
                v.values[j] * (1.0 - u) + v.values[j + 1] * u
            }
        };
        let a = in_vector(&self.vectors[i]);
        if t == 0.0 {
            a
        } else {
            a * (1.0 - t) + in_vector(&self.vectors[i + 1]) * t
        }
    }

    /// A row evaluator for an image `width` pixels wide: each vector interpolated across the
    /// width once, so that a whole row costs one blend per pixel.
    pub fn rows(&self, width: usize) -> LutRows {
        LutRows {
            lines: self.vectors.iter().map(|v| v.line).collect(),
            across: self.vectors.iter().map(|v| v.across(width)).collect(),
        }
    }
}

/// [`SparseLut`] with every vector expanded across the image's width.
#[derive(Debug, Clone)]
pub struct LutRows {
    lines: Vec<f64>,
    across: Vec<Vec<f64>>,
}

impl LutRows {
    /// The table along image line `line` into `out` (one value per pixel).
    pub fn row_into(&self, line: usize, out: &mut [f64]) {
        let (i, t) = bracket(&self.lines, line as f64);
        let a = &self.across[i];
        if t == 0.0 {
            out.copy_from_slice(&a[..out.len()]);
        } else {
            let b = &self.across[i + 1];
            for (o, (x, y)) in out.iter_mut().zip(a.iter().zip(b)) {
                *o = x * (1.0 - t) + y * t;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table() -> SparseLut {
        SparseLut::new(vec![
            LutVector {
                line: 10.0,
                pixels: vec![0.0, 40.0, 99.0],
                values: vec![100.0, 200.0, 300.0],
            },
            LutVector {
                line: 0.0,
                pixels: vec![0.0, 40.0, 99.0],
                values: vec![0.0, 40.0, 80.0],
            },
        ])
        .unwrap()
    }

    /// A bilinear function is reproduced exactly by bilinear interpolation, and the row
    /// evaluator agrees with the point one.
    #[test]
    fn bilinear_between_vectors_and_held_outside() {
        let lut = table();
        // line 5, pixel 20: halfway between (0 -> 20) and (100 -> 150): 85
        assert!((lut.at(5.0, 20.0) - 85.0).abs() < 1e-12);
        // at a knot
        assert_eq!(lut.at(10.0, 40.0), 200.0);
        // beyond the last line and pixel: the edge values
        assert_eq!(lut.at(50.0, 150.0), 300.0);
        assert_eq!(lut.at(-3.0, -1.0), 0.0);
        let rows = lut.rows(100);
        let mut row = vec![0.0; 100];
        for line in [0, 3, 7, 10, 12] {
            rows.row_into(line, &mut row);
            for (p, &v) in row.iter().enumerate() {
                assert!((v - lut.at(line as f64, p as f64)).abs() < 1e-9, "{line} {p}");
            }
        }
    }

    #[test]
    fn malformed_vectors_are_refused() {
        let bad = LutVector {
            line: 0.0,
            pixels: vec![0.0, 5.0],
            values: vec![1.0],
        };
        assert!(SparseLut::new(vec![bad]).unwrap_err().contains("2 pixels and 1 values"));
        assert!(SparseLut::new(Vec::new()).is_err());
        let unordered = LutVector {
            line: 0.0,
            pixels: vec![5.0, 0.0],
            values: vec![1.0, 2.0],
        };
        assert!(SparseLut::new(vec![unordered]).unwrap_err().contains("out of order"));
    }
}

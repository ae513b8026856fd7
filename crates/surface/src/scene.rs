//! The scene grid and resampling of surface-map fields onto it.
//!
//! A scene is `size` x `size` pixels: columns run along x, the distance behind the stern
//! (increasing to the right), rows run across the track from port (top) to starboard. Values
//! come from the surface map by bilinear interpolation; outside the simulated wake (beyond the
//! hydro grid's core or upstream of the initial data plane) the sea is undisturbed.

use ndarray::Array2;
use wakelab_core::config::SceneConfig;

/// Pixel-centre coordinates of a scene.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneGrid {
    /// x of each column (m behind the stern).
    pub x: Vec<f64>,
    /// y of each row (m, positive to port; decreasing down the rows).
    pub y: Vec<f64>,
    pub pixel_spacing: f64,
}

impl SceneGrid {
    pub fn new(c: &SceneConfig) -> Self {
        let n = c.size;
        let d = c.pixel_spacing;
        let half = n as f64 / 2.0;
        Self {
            x: (0..n).map(|i| c.along_track + (i as f64 + 0.5 - half) * d).collect(),
            y: (0..n).map(|i| c.cross_track + (half - i as f64 - 0.5) * d).collect(),
            pixel_spacing: d,
        }
    }

    pub fn size(&self) -> usize {
        self.x.len()
    }
}

/// A field on a uniform (x, y) map, x-major.
pub struct MapField<'a> {
    pub x: &'a [f64],
    pub y: &'a [f64],
    pub values: &'a [f64],
}

/// Fractional index of `v` in the uniform axis `axis`, or None outside it.
fn locate(axis: &[f64], v: f64) -> Option<(usize, f64)> {
    let n = axis.len();
    if n < 2 {
        return None;
    }
    let step = (axis[n - 1] - axis[0]) / (n - 1) as f64;
    let t = (v - axis[0]) / step;
    if t < 0.0 || t > (n - 1) as f64 {
        return None;
    }
    let i = (t.floor() as usize).min(n - 2);
    Some((i, t - i as f64))
}

/// Resample `field` onto the scene; `ambient` outside the map. Result is (rows, cols).
pub fn resample(scene: &SceneGrid, field: &MapField, ambient: f64) -> Array2<f64> {
    let n = scene.size();
    let cols = field.y.len();
    let mut out = Array2::from_elem((n, n), ambient);
    let xs: Vec<Option<(usize, f64)>> = scene.x.iter().map(|&x| locate(field.x, x)).collect();
    for (r, &y) in scene.y.iter().enumerate() {
        let Some((j, fy)) = locate(field.y, y) else { continue };
        for (c, xi) in xs.iter().enumerate() {
            let Some((i, fx)) = *xi else { continue };
            let v = |ii: usize, jj: usize| field.values[ii * cols + jj];
            out[[r, c]] = (1.0 - fx) * ((1.0 - fy) * v(i, j) + fy * v(i, j + 1))
                + fx * ((1.0 - fy) * v(i + 1, j) + fy * v(i + 1, j + 1));
        }
    }
    out
}

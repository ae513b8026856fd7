//! The cross-wake (y, z) grid of the 2D+t domain (spec 2.1.2, Fig. 2.3).
//!
//! y runs across the track (0 on the ship's centreline, positive to port so that x forward, y, z up
//! is right-handed), z is up with
//! the rigid lid at z = 0. The core is uniform in y; each damping beach has `beach_cells` cells
//! whose width grows geometrically away from the core (the spec's "progressively longer" cells).
//! z is uniform. Cell `j, k` has centre `(y_centres[j], z_centres[k])`; k = 0 is the top cell.

use crate::config::GridConfig;
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Serialize)]
pub struct CrossGrid {
    /// y of the cell faces (ny + 1 values, increasing).
    pub y_faces: Vec<f64>,
    /// y of the cell centres (ny values).
    pub y_centres: Vec<f64>,
    /// Cell widths (ny values).
    pub dy: Vec<f64>,
    /// Uniform vertical spacing (m).
    pub dz: f64,
    /// z of the cell centres, top (k = 0) to bottom (nz values, negative).
    pub z_centres: Vec<f64>,
    /// Index range of the uniform core in y.
    pub core: std::ops::Range<usize>,
    /// Depth of the domain (m).
    pub depth: f64,
}

impl CrossGrid {
    /// Build the grid of a [`GridConfig`].
    pub fn new(config: &GridConfig) -> Self {
        let dy_core = config.core_width / config.core_cells as f64;
        let beach = beach_widths(dy_core, config.beach_width, config.beach_cells);
        let mut dy: Vec<f64> = beach.iter().rev().copied().collect();
        dy.extend(std::iter::repeat_n(dy_core, config.core_cells));
        dy.extend(beach.iter().copied());
        let half = 0.5 * config.core_width + config.beach_width;
        let mut y_faces = Vec::with_capacity(dy.len() + 1);
        let mut y = -half;
        y_faces.push(y);
        for w in &dy {
            y += w;
            y_faces.push(y);
        }
        let y_centres = y_faces.windows(2).map(|f| 0.5 * (f[0] + f[1])).collect();
        let nz = config.depth_cells;
        let dz = config.depth / nz as f64;
        let z_centres = (0..nz).map(|k| -(k as f64 + 0.5) * dz).collect();
        let start = config.beach_cells;
        Self {
            y_faces,
            y_centres,
            dy,
            dz,
            z_centres,
            core: start..start + config.core_cells,
            depth: config.depth,
        }
    }

    /// Number of cells across (ny).
    pub fn ny(&self) -> usize {
        self.dy.len()
    }

    /// Number of cells in depth (nz).
    pub fn nz(&self) -> usize {
        self.z_centres.len()
    }

    /// Total number of cells.
    pub fn cells(&self) -> usize {
        self.ny() * self.nz()
    }

    /// Width of the uniform core cells (m).
    pub fn core_dy(&self) -> f64 {
        self.dy[self.core.start]
    }

    /// Distance between the centres of cells j - 1 and j (m), for 1 <= j < ny.
    pub fn dy_centres(&self, j: usize) -> f64 {
        self.y_centres[j] - self.y_centres[j - 1]
    }

    /// Distance (m) from the edge of the core into a beach: 0 in the core.
    pub fn beach_depth(&self, j: usize) -> f64 {
        let y = self.y_centres[j];
        let lo = self.y_faces[self.core.start];
        let hi = self.y_faces[self.core.end];
        if y < lo {
            lo - y
        } else if y > hi {
            y - hi
        } else {
            0.0
        }
    }
}

/// Widths of the beach cells, nearest the core first: geometric growth `dy_core * r^i`,
/// i = 1..=n, with r chosen so the widths sum to `width` (r = 1 when the widths fit uniformly).
fn beach_widths(dy_core: f64, width: f64, n: usize) -> Vec<f64> {
    if n == 0 || width <= 0.0 {
        return Vec::new();
    }
    let total = |r: f64| (1..=n).map(|i| dy_core * r.powi(i as i32)).sum::<f64>();
    let (mut lo, mut hi) = (1e-3, 2.0);
    while total(hi) < width {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if total(mid) < width {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let r = 0.5 * (lo + hi);
    (1..=n).map(|i| dy_core * r.powi(i as i32)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::{Preset, WakelabConfig};

    #[test]
    fn paper_grid_matches_spec_2_1_2() {
        let g = CrossGrid::new(&WakelabConfig::with_preset(Preset::Paper).grid);
        assert_eq!(g.ny(), 4001 + 2 * 101);
        assert_eq!(g.nz(), 201);
        assert!((g.core_dy() - 2000.0 / 4001.0).abs() < 1e-12);
        assert!((g.y_faces[0] + 1500.0).abs() < 1e-6);
        assert!((g.y_faces[g.ny()] - 1500.0).abs() < 1e-6);
        // beach cells grow away from the core
        assert!(g.dy[0] > g.dy[100] && g.dy[100] > g.core_dy());
        assert!((g.dz - 300.0 / 201.0).abs() < 1e-12);
        assert!((g.y_faces[g.core.start] + 1000.0).abs() < 1e-6);
    }
}

/// The wake's track in pixel space, for the dataset's records.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WakeGeometry {
    /// The ship's course in the image, degrees clockwise from up, in [0, 360).
    pub heading_deg: f64,
    /// Whether the stern lies inside the image.
    pub ship_in_scene: bool,
    /// (row, column) of the stern, pixel centres at whole numbers, when it is in the image.
    pub stern_pixel: Option<[f64; 2]>,
    /// Distances behind the stern (m) where the track enters and leaves the image, if it does.
    pub along_track_covered_m: Option<[f64; 2]>,
}

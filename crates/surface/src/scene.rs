//! The scene grid, its placement on the wake, and resampling of surface-map fields onto it.
//!
//! A scene is `size` x `size` pixels of a map seen from above: columns run east (x, to the
//! right), rows run south (y, northing, decreasing down the rows), both in metres from the ship's
//! stern at the moment of imaging. The ship's course in the image is `scene.heading`, degrees
//! clockwise from up (north), as a compass heading; the scene's centre lies `along_track` behind
//! the stern and `cross_track` to port of the track.
//!
//! The hydro stage's surface map lives in the track frame: x behind the stern, y to port. Every
//! pixel's track-frame position comes from the rotation below, and map fields are sampled there
//! bilinearly; outside the simulated wake (beyond the hydro grid's core, upstream of the initial
//! data plane, or ahead of the ship) the sea is undisturbed. Directions that the configuration
//! gives relative to the ship (wind, swell, look, sun) enter the heading frame (x forward, y to
//! port), which [`SceneGrid::heading_frame`] and [`SceneGrid::scene_frame`] connect to the image.

use ndarray::Array2;
use rayon::prelude::*;
use wakelab_core::config::SceneConfig;
pub use wakelab_core::grid::WakeGeometry;

/// Pixel-centre coordinates of a scene and its orientation on the ship's track.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneGrid {
    /// Easting of each column (m from the stern, increasing to the right).
    pub x: Vec<f64>,
    /// Northing of each row (m from the stern, decreasing down the rows).
    pub y: Vec<f64>,
    pub pixel_spacing: f64,
    /// The ship's course in the image (radians clockwise from up).
    pub heading: f64,
    /// sin and cos of the heading, computed once: every pixel's frame change uses them.
    rotation: (f64, f64),
}

impl SceneGrid {
    pub fn new(c: &SceneConfig) -> Self {
        let n = c.size;
        let d = c.pixel_spacing;
        let half = n as f64 / 2.0;
        let heading = c.heading.to_radians();
        // the scene centre: along_track astern and cross_track to port of the stern
        let (e0, n0) = heading_to_scene(heading, -c.along_track, c.cross_track);
        Self {
            x: (0..n).map(|i| e0 + (i as f64 + 0.5 - half) * d).collect(),
            y: (0..n).map(|i| n0 + (half - i as f64 - 0.5) * d).collect(),
            pixel_spacing: d,
            heading,
            rotation: heading.sin_cos(),
        }
    }

    pub fn size(&self) -> usize {
        self.x.len()
    }

    /// A scene-frame vector (east, north) in the heading frame (forward, port).
    pub fn heading_frame(&self, east: f64, north: f64) -> (f64, f64) {
        rotate_to_heading(self.rotation, east, north)
    }

    /// A heading-frame vector (forward, port) in the scene frame (east, north).
    pub fn scene_frame(&self, forward: f64, port: f64) -> (f64, f64) {
        rotate_to_scene(self.rotation, forward, port)
    }

    /// A pixel-grid wavenumber (k_col along the columns, eastward; k_row along the rows,
    /// southward) in the heading frame: [`heading_frame_wavenumber`] for this scene.
    pub fn heading_frame_wavenumber(&self, k_col: f64, k_row: f64) -> (f64, f64) {
        rotate_to_heading(self.rotation, k_col, -k_row)
    }

    /// A pixel's track-frame position: (m behind the stern, m to port).
    pub fn track_position(&self, row: usize, col: usize) -> (f64, f64) {
        let (forward, port) = self.heading_frame(self.x[col], self.y[row]);
        (-forward, port)
    }

    /// The fractional (row, column) of a track-frame position (m behind the stern, m to port),
    /// pixel centres at whole numbers.
    pub fn pixel_of(&self, behind: f64, port: f64) -> (f64, f64) {
        let (e, n) = self.scene_frame(-behind, port);
        let d = self.pixel_spacing;
        ((self.y[0] - n) / d, (e - self.x[0]) / d)
    }

    /// The farthest distance behind the stern any pixel of the scene lies at.
    pub fn farthest_astern(&self) -> f64 {
        let n = self.size() - 1;
        [(0, 0), (0, n), (n, 0), (n, n)]
            .iter()
            .map(|&(r, c)| self.track_position(r, c).0)
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// Where the wake's track lies in the image: see [`WakeGeometry`].
    pub fn wake_geometry(&self) -> WakeGeometry {
        let n = self.size();
        let last = n as f64 - 1.0;
        let inside = |(r, c): (f64, f64)| (-0.5..=last + 0.5).contains(&r) && (-0.5..=last + 0.5).contains(&c);
        // the track line, sampled every tenth of a pixel over the scene's extent
        let reach = self.farthest_astern() + self.pixel_spacing;
        let step = 0.1 * self.pixel_spacing;
        let steps = (reach / step).ceil().max(0.0) as usize;
        let covered: Vec<f64> = (0..=steps)
            .map(|i| i as f64 * step)
            .filter(|&x| inside(self.pixel_of(x, 0.0)))
            .collect();
        let stern = self.pixel_of(0.0, 0.0);
        let compass = self.heading.to_degrees().rem_euclid(360.0);
        WakeGeometry {
            heading_deg: compass,
            ship_in_scene: inside(stern),
            stern_pixel: inside(stern).then_some([stern.0, stern.1]),
            along_track_covered_m: match (covered.first(), covered.last()) {
                (Some(&a), Some(&b)) => Some([a, b]),
                _ => None,
            },
        }
    }
}

/// A pixel-grid wavenumber (k_col along the columns, eastward; k_row along the rows, southward)
/// in the heading frame (forward, port) of a ship whose course in the image is `heading`
/// (radians clockwise from up).
pub fn heading_frame_wavenumber(k_col: f64, k_row: f64, heading: f64) -> (f64, f64) {
    scene_to_heading(heading, k_col, -k_row)
}

/// A scene-frame vector (east, north) in the heading frame (forward, port): the inverse of
/// [`heading_to_scene`].
fn scene_to_heading(heading: f64, east: f64, north: f64) -> (f64, f64) {
    rotate_to_heading(heading.sin_cos(), east, north)
}

fn heading_to_scene(heading: f64, forward: f64, port: f64) -> (f64, f64) {
    rotate_to_scene(heading.sin_cos(), forward, port)
}

/// [`scene_to_heading`] with the heading's (sin, cos) given.
fn rotate_to_heading((s, c): (f64, f64), east: f64, north: f64) -> (f64, f64) {
    (east * s + north * c, -east * c + north * s)
}

/// [`heading_to_scene`] with the heading's (sin, cos) given.
fn rotate_to_scene((s, c): (f64, f64), forward: f64, port: f64) -> (f64, f64) {
    (forward * s - port * c, forward * c + port * s)
}

/// A field on a uniform (x, y) map, x-major.
pub struct MapField<'a> {
    pub x: &'a [f64],
    pub y: &'a [f64],
    pub values: &'a [f64],
}

/// A uniform axis: its first value and the inverse of its step.
struct UniformAxis {
    start: f64,
    per_step: f64,
    last: usize,
}

impl UniformAxis {
    fn new(axis: &[f64]) -> Option<Self> {
        let n = axis.len();
        (n >= 2).then(|| Self {
            start: axis[0],
            per_step: (n - 1) as f64 / (axis[n - 1] - axis[0]),
            last: n - 1,
        })
    }

    /// Fractional index of `v`: the cell and the weight of its upper node; None outside.
    fn locate(&self, v: f64) -> Option<(usize, f64)> {
        let t = (v - self.start) * self.per_step;
        if !(0.0..=self.last as f64).contains(&t) {
            return None;
        }
        let i = (t as usize).min(self.last - 1);
        Some((i, t - i as f64))
    }
}

/// Resample `field` (track frame) onto the scene at each pixel's track-frame position; `ambient`
/// outside the map. Result is (rows, cols); rows in parallel.
pub fn resample(scene: &SceneGrid, field: &MapField, ambient: f64) -> Array2<f64> {
    let n = scene.size();
    let cols = field.y.len();
    let mut out = Array2::from_elem((n, n), ambient);
    let (Some(ax), Some(ay)) = (UniformAxis::new(field.x), UniformAxis::new(field.y)) else {
        return out;
    };
    // a pixel's track position is affine in its column: one step east moves it by
    // (-d forward, d port) in the heading frame
    let (step_forward, step_port) = scene.heading_frame(scene.pixel_spacing, 0.0);
    out.axis_iter_mut(ndarray::Axis(0))
        .into_par_iter()
        .enumerate()
        .for_each(|(r, mut row)| {
            let (behind0, port0) = scene.track_position(r, 0);
            for (c, out) in row.iter_mut().enumerate() {
                let behind = behind0 - c as f64 * step_forward;
                let port = port0 + c as f64 * step_port;
                let (Some((i, fx)), Some((j, fy))) = (ax.locate(behind), ay.locate(port)) else {
                    continue;
                };
                let v = |ii: usize, jj: usize| field.values[ii * cols + jj];
                *out = (1.0 - fx) * ((1.0 - fy) * v(i, j) + fy * v(i, j + 1))
                    + fx * ((1.0 - fy) * v(i + 1, j) + fy * v(i + 1, j + 1));
            }
        });
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(heading: f64, along: f64, cross: f64) -> SceneGrid {
        SceneGrid::new(&SceneConfig {
            pixel_spacing: 10.0,
            size: 64,
            along_track: along,
            cross_track: cross,
            heading,
            other_wakes: Vec::new(),
            centre: None,
        })
    }

    /// The two frames are rotations of each other: a vector keeps its length, and a round trip
    /// returns it; the ship's forward direction points along the compass heading.
    #[test]
    fn frames_are_a_rotation_by_the_heading() {
        for h in [0.0, 37.0, 90.0, 200.0, 270.0, 359.0] {
            let g = scene(h, 500.0, 0.0);
            let (e, n) = g.scene_frame(1.0, 0.0);
            let want = (h.to_radians().sin(), h.to_radians().cos());
            assert!((e - want.0).abs() < 1e-12 && (n - want.1).abs() < 1e-12);
            // port is 90 degrees anticlockwise (seen from above) of forward
            let (pe, pn) = g.scene_frame(0.0, 1.0);
            assert!((e * pn - n * pe - 1.0).abs() < 1e-12, "port is to the left of forward");
            let (a, b) = g.heading_frame(3.0, -4.0);
            assert!((a.hypot(b) - 5.0).abs() < 1e-12);
            let (e2, n2) = g.scene_frame(a, b);
            assert!((e2 - 3.0).abs() < 1e-12 && (n2 + 4.0).abs() < 1e-12);
        }
    }

    /// The scene centre lies along_track behind the stern and cross_track to port.
    #[test]
    fn the_centre_is_where_the_placement_says() {
        let g = scene(123.0, 700.0, -150.0);
        // the centre is between pixels 31 and 32 in both directions
        let (b1, p1) = g.track_position(31, 31);
        let (b2, p2) = g.track_position(32, 32);
        assert!((0.5 * (b1 + b2) - 700.0).abs() < 1e-9);
        assert!((0.5 * (p1 + p2) + 150.0).abs() < 1e-9);
        let (r, c) = g.pixel_of(700.0, -150.0);
        assert!((r - 31.5).abs() < 1e-9 && (c - 31.5).abs() < 1e-9);
    }

    /// A scene centred 200 m behind the stern holds the ship; one 2 km behind does not.
    #[test]
    fn the_geometry_says_where_the_ship_is() {
        let near = scene(90.0, 200.0, 0.0).wake_geometry();
        assert!(near.ship_in_scene);
        // heading east: the stern sits 200 m (20 px) right of the centre, on the middle row
        let [r, c] = near.stern_pixel.unwrap();
        assert!((r - 31.5).abs() < 1e-9 && (c - 51.5).abs() < 1e-9, "{r} {c}");
        let [a, b] = near.along_track_covered_m.unwrap();
        assert!(a == 0.0 && (b - 520.0).abs() < 1.0, "{a} {b}");
        let far = scene(90.0, 2000.0, 0.0).wake_geometry();
        assert!(!far.ship_in_scene && far.stern_pixel.is_none());
        let [a, b] = far.along_track_covered_m.unwrap();
        assert!((a - 1680.0).abs() < 1.0 && (b - 2320.0).abs() < 1.0, "{a} {b}");
        // a scene 1 km to port of the track does not see it
        assert_eq!(scene(90.0, 2000.0, 1000.0).wake_geometry().along_track_covered_m, None);
    }
}

//! wakelab-ships: ships and their wakes in a SAR image, by the field's classic detectors, as an
//! analyst works a scene (Eldhuset 1996; Graziano et al. 2017; Karakus et al. 2020): find the
//! ships, look for each ship's wake, and read from the wake where the ship went and how fast.
//!
//! - [`cfar`]: ships as bright targets, by a two-parameter CFAR on the image in dB (guard and
//!   background windows in metres, a stated false-alarm probability), clustered into targets,
//!   azimuth ambiguities and sidelobe ghosts rejected, masked pixels (NaN) left out;
//! - [`lines`]: the wake searches' settings and their measure of a line (its contrast with its
//!   sides, and its evidence: the contrast weighed by the share of the line in the image);
//! - [`wake`]: each ship's wake, by a Radon search of the normalised image along rays from the
//!   ship's true position (the detected return is displaced in azimuth by its range velocity),
//!   the dark turbulent trough with the bright arms of the narrow V beside it, or where there is
//!   no trough a bright arm alone;
//! - [`refusal`]: why a ship has no wake: its best trough and bright arm, and the test each
//!   failed;
//! - [`promotion`]: where a search finds no wake at all, its best faint line promoted to one at
//!   a lower significance;
//! - [`sidelobes`]: the directions of the scene's sidelobe streaks, measured on its bright
//!   targets, along which no bright arm is sought;
//! - [`free_wake`]: the free wakes, whose ship has left the image or is not seen, by the Radon
//!   transform of the whole image;
//! - [`kelvin`]: the ship's speed from the curve in the spectrum on which its Kelvin waves lie.
//!
//! Everything works on linear sigma0 (NaN for no data) in the image's pixels, with the
//! [`Geometry`] that places them: no physics model, no deep learning.

pub mod cfar;
pub mod free_wake;
pub mod kelvin;
pub mod land;
pub mod lines;
pub mod promotion;
pub mod radon;
pub mod refusal;
pub mod sidelobes;
pub mod wake;

use cfar::{find_ships, CfarOptions, ShipSearch};
use free_wake::free_wakes;
use ndarray::{Array2, ArrayView2};
use serde::Serialize;
use wake::{ship_wake, NoWake, Wake, WakeOptions};

/// Where the image's pixels lie: their ground spacing and the radar's geometry.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Geometry {
    /// Ground distance between rows and between columns (m).
    pub spacing: (f64, f64),
    /// The platform's flight (azimuth) direction in the image, degrees clockwise from up (a
    /// ground-range product in radar geometry: 0 or 180, along the rows).
    pub azimuth_deg: f64,
    /// The horizontal direction the radar looks in (degrees clockwise from up): the azimuth
    /// plus 90 for a right-looking sensor (Sentinel-1, TerraSAR-X, COSMO-SkyMed by default).
    pub look_deg: f64,
    /// Incidence angle at the scene (degrees).
    pub incidence_deg: f64,
    /// Slant range over the platform's velocity, R/V (s), where the product's orbit tells it:
    /// a moving ship's return is displaced in azimuth by R v_r / V.
    pub range_over_velocity: Option<f64>,
}

impl Geometry {
    /// A square-pixel image of `spacing` metres whose flight runs up its rows and whose radar
    /// looks to the right (along its columns), at `incidence_deg`.
    pub fn along_rows(spacing: f64, incidence_deg: f64, range_over_velocity: Option<f64>) -> Self {
        Self {
            spacing: (spacing, spacing),
            azimuth_deg: 0.0,
            look_deg: 90.0,
            incidence_deg,
            range_over_velocity,
        }
    }

    /// The ground distance (m) of a step of (rows, columns) pixels.
    pub fn metres(&self, rows: f64, cols: f64) -> f64 {
        (rows * self.spacing.0).hypot(cols * self.spacing.1)
    }

    /// A unit step on the ground in direction `heading_deg` (clockwise from up) in pixels:
    /// (rows, columns) per metre.
    pub fn step(&self, heading_deg: f64) -> (f64, f64) {
        let (s, c) = heading_deg.to_radians().sin_cos();
        (-c / self.spacing.0, s / self.spacing.1)
    }

    /// The direction (degrees clockwise from up, in [0, 360)) of a step of (rows, columns)
    /// pixels.
    pub fn heading_of(&self, rows: f64, cols: f64) -> f64 {
        let (north, east) = (-rows * self.spacing.0, cols * self.spacing.1);
        east.atan2(north).to_degrees().rem_euclid(360.0)
    }
}

/// What the searches found in an image: the ships (with the targets rejected as ghosts) and the
/// wakes, each ship's first, then the free ones; where neither was found, the best faint line
/// promoted to a wake where it reaches [`WakeOptions::promote_min_z`].
#[derive(Debug, Clone, Serialize)]
pub struct Findings {
    pub ships: ShipSearch,
    pub wakes: Vec<Wake>,
    /// The ships without a wake (their index in `ships.ships`), each with its best trough and
    /// bright arm and why they were refused.
    pub no_wake: Vec<(usize, NoWake)>,
    /// The directions of the scene's sidelobe streaks (degrees clockwise from up in the image,
    /// in [0, 180)), along which no bright arm was sought ([`sidelobes`]).
    pub sidelobe_axes_deg: Vec<f64>,
    /// The land found in the image and left out of the searches (true: land), where the
    /// search sought it ([`CfarOptions::land`]).
    #[serde(skip)]
    pub land: Option<Array2<bool>>,
}

/// The scale (m) over which the wake searches take the sea's local mean.
pub const BACKGROUND_M: f64 = 2000.0;

/// Ships, their wakes and the free wakes of `image` (linear sigma0, NaN for no data).
pub fn search(image: ArrayView2<f32>, geometry: &Geometry, cfar: &CfarOptions, wakes: &WakeOptions) -> Findings {
    search_polarised(image, None, geometry, cfar, wakes)
}

/// [`search`] with the ships sought in `cross`, the product's cross-polarised band (VH, HV) on
/// the same grid, where one is given: the sea's cross-polarised return is 6-10 dB weaker than
/// its co-polarised one while a ship's dihedrals depolarise, so ships stand further above their
/// sea there (Crisp 2004; SNAP's and the field's dual-pol ship detectors use it). The wakes, which
/// are a modulation of the sea's co-polarised Bragg return, are sought in `image`.
pub fn search_polarised(
    image: ArrayView2<f32>,
    cross: Option<ArrayView2<f32>>,
    geometry: &Geometry,
    cfar: &CfarOptions,
    wakes: &WakeOptions,
) -> Findings {
    let land = cfar
        .land
        .map(|o| land::land_mask(image, geometry, &o))
        .filter(|l| l.iter().any(|&v| v));
    // ships are sought in the whole image, so that the land's bright returns still stand in
    // the backgrounds and still reject their sidelobes (a bright target masked out would leave
    // its sidelobes at sea as ships); a target whose centre lies on land is not a ship
    let mut ships = find_ships(cross.unwrap_or(image), geometry, cfar);
    let sea_image = land.as_ref().map(|l| {
        let at = |s: &cfar::Ship| {
            let (r, c) = (s.row.round().max(0.0) as usize, s.col.round().max(0.0) as usize);
            l.get((r, c)).copied().unwrap_or(false)
        };
        let (on_land, at_sea): (Vec<_>, Vec<_>) = ships.ships.drain(..).partition(|s| at(s));
        ships.ships = at_sea;
        ships.on_land = on_land.iter().map(|s| (s.row, s.col)).collect();
        // the wakes are sought in the sea alone: land is no data to them
        let mut sea = image.to_owned();
        ndarray::Zip::from(&mut sea).and(l).for_each(|v, &is_land| {
            if is_land {
                *v = f32::NAN;
            }
        });
        sea
    });
    let image = sea_image.as_ref().map_or(image, |a| a.view());
    let mut normalised = radon::SearchImage::new(image, geometry, BACKGROUND_M);
    normalised.sidelobe_axes = sidelobes::sidelobe_axes(&normalised.fine, &ships.ships);
    let (mut found, mut no_wake) = (Vec::new(), Vec::new());
    for (i, ship) in ships.ships.iter().enumerate() {
        match ship_wake(&normalised, ship, i, wakes) {
            Ok(wake) => found.push(wake),
            Err(refused) => no_wake.push((i, *refused)),
        }
    }
    let free = free_wakes(&normalised, &found, wakes);
    found.extend(free);
    if found.is_empty() {
        if let Some(wake) = promotion::promote_best_faint_line(&normalised, &ships.ships, &no_wake, wakes) {
            no_wake.retain(|(i, _)| Some(*i) != wake.ship);
            found.push(wake);
        }
    }
    Findings {
        sidelobe_axes_deg: normalised.sidelobe_axes.clone(),
        ships,
        wakes: found,
        no_wake,
        land,
    }
}

/// `a - b` folded into [-180, 180) degrees.
pub fn angle_difference(a: f64, b: f64) -> f64 {
    (a - b + 180.0).rem_euclid(360.0) - 180.0
}

/// The angle between two lines of directions `a` and `b` (degrees, in [0, 90]): a line has
/// no direction, so a direction and its reverse are the same line.
pub fn line_difference(a: f64, b: f64) -> f64 {
    let e = angle_difference(a, b).abs();
    e.min(180.0 - e)
}

/// Standard gravity (m/s^2), for the Kelvin wavelength.
pub const GRAVITY: f64 = 9.806_65;

/// Fully developed speckle of `looks` looks (a mean of exponentials) over a mean sigma0, from a
/// seeded generator: the open sea the tests and benchmarks search.
#[cfg(test)]
pub(crate) fn speckle(rows: usize, cols: usize, looks: usize, mean: f64, seed: u64) -> ndarray::Array2<f32> {
    use rand::SeedableRng;
    use rand_distr::{Distribution, Exp1};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    ndarray::Array2::from_shape_fn((rows, cols), |_| {
        let s: f64 = (0..looks).map(|_| -> f64 { Exp1.sample(&mut rng) }).sum();
        (mean * s / looks as f64) as f32
    })
}

/// 500 x 600 pixels of 10 m: a city on the left half (its mean 10 dB over the sea's, a fifth
/// of its pixels, its buildings, 20 dB over that) beside four-look open sea on the right.
#[cfg(test)]
pub(crate) fn city_beside_the_sea() -> ndarray::Array2<f32> {
    use rand::{RngExt, SeedableRng};
    let mut image = speckle(500, 600, 4, 0.01, 5);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
    for v in image.slice_mut(ndarray::s![.., ..300]).iter_mut() {
        *v *= if rng.random::<f64>() < 0.2 { 1000.0 } else { 10.0 };
    }
    image
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_and_headings_are_inverse_on_a_rectangular_grid() {
        let g = Geometry {
            spacing: (10.0, 5.0),
            ..Geometry::along_rows(10.0, 35.0, None)
        };
        for heading in [0.0, 30.0, 90.0, 200.0, 359.0] {
            let (r, c) = g.step(heading);
            assert!((g.metres(r, c) - 1.0).abs() < 1e-12);
            assert!(angle_difference(g.heading_of(r, c), heading).abs() < 1e-9, "{heading}");
        }
        // up is north: a step of one row up is heading 0, one column right heading 90
        assert!((g.heading_of(-1.0, 0.0) - 0.0).abs() < 1e-12);
        assert!((g.heading_of(0.0, 1.0) - 90.0).abs() < 1e-12);
        assert_eq!(angle_difference(10.0, 350.0), 20.0);
        assert_eq!(angle_difference(350.0, 10.0), -20.0);
        assert_eq!(line_difference(350.0, 10.0), 20.0);
        assert_eq!(line_difference(190.0, 10.0), 0.0);
        assert_eq!(line_difference(100.0, 10.0), 90.0);
        assert_eq!(line_difference(280.0, 90.0), 10.0);
    }

    /// A ship 3 dB over its sea in VV (speckle hides it from the CFAR) and 25 dB over the
    /// sea in VH, its trough 3 dB dark in VV for 2.5 km behind it: the co-polarised search finds
    /// no ship, the dual-polarised one finds it in VH and its wake in VV.
    #[test]
    fn the_cross_polarised_band_shows_the_ship_the_co_polarised_its_wake() {
        let g = Geometry::along_rows(10.0, 35.0, None);
        let mut co = speckle(400, 300, 4, 0.01, 3);
        let mut cross = speckle(400, 300, 4, 0.0005, 4);
        co.slice_mut(ndarray::s![86..336, 147..153]).mapv_inplace(|v| v * 0.5);
        co.slice_mut(ndarray::s![74..86, 149..152]).mapv_inplace(|v| v * 2.0);
        cross.slice_mut(ndarray::s![74..86, 149..152]).fill(0.15);
        let (cfar, wakes) = (CfarOptions::default(), WakeOptions::default());
        let copol = search(co.view(), &g, &cfar, &wakes);
        assert!(copol.ships.ships.is_empty(), "{:?}", copol.ships.ships);
        let dual = search_polarised(co.view(), Some(cross.view()), &g, &cfar, &wakes);
        assert_eq!(dual.ships.ships.len(), 1, "{:?}", dual.ships.ships);
        let ship = &dual.ships.ships[0];
        assert!(
            (ship.row - 80.0).abs() < 2.0 && (ship.col - 150.0).abs() < 2.0,
            "{ship:?}"
        );
        let wake = dual.wakes.iter().find(|w| w.ship == Some(0)).expect("its wake");
        assert!(angle_difference(wake.course_deg.unwrap(), 0.0).abs() < 3.0, "{wake:?}");
    }

    /// Land beside the sea: a city (its mean 10 dB over the sea's, a fifth of its pixels 20 dB
    /// over that, six towers 50 dB over it) and a ship at sea a kilometre off its shore. With
    /// land left out (the default) the ship alone is found and the towers are targets on land;
    /// searched as sea, the towers are ships too.
    #[test]
    fn land_is_left_out_of_the_searches() {
        let g = Geometry::along_rows(10.0, 35.0, None);
        let mut image = city_beside_the_sea();
        for k in 0..6 {
            let (r, c) = (40 + 80 * k, 50 + 40 * k);
            image.slice_mut(ndarray::s![r..r + 3, c..c + 3]).fill(1e4);
        }
        image.slice_mut(ndarray::s![244..256, 400..403]).fill(3.0);
        let (cfar, wakes) = (CfarOptions::default(), WakeOptions::default());
        let found = search(image.view(), &g, &cfar, &wakes);
        assert_eq!(found.ships.ships.len(), 1, "{:?}", found.ships.ships);
        let ship = &found.ships.ships[0];
        assert!(
            (ship.row - 250.0).abs() < 2.0 && (ship.col - 401.0).abs() < 2.0,
            "{ship:?}"
        );
        assert_eq!(found.ships.on_land.len(), 6, "the towers: {:?}", found.ships.on_land);
        let land = found.land.expect("the city is land");
        let city = land.slice(ndarray::s![.., ..300]);
        assert!(city.iter().filter(|&&l| l).count() as f64 > 0.95 * city.len() as f64);
        let all = search(image.view(), &g, &CfarOptions { land: None, ..cfar }, &wakes);
        let on_land = all.ships.ships.iter().filter(|s| s.col < 300.0).count();
        assert_eq!(on_land, 6, "{:?}", all.ships.ships);
    }

    /// What a user can hand `detect` without a panic: an image all no-data, one smaller than
    /// every window, one of a constant value. Nothing is found in any.
    #[test]
    fn degenerate_images_find_nothing_and_do_not_panic() {
        let g = Geometry::along_rows(10.0, 35.0, None);
        let (cfar, wakes) = (CfarOptions::default(), WakeOptions::default());
        for image in [
            ndarray::Array2::from_elem((64, 64), f32::NAN),
            ndarray::Array2::from_elem((3, 5), 0.01f32),
            ndarray::Array2::from_elem((200, 200), 0.01f32),
        ] {
            let found = search(image.view(), &g, &cfar, &wakes);
            assert!(found.ships.ships.is_empty() && found.wakes.is_empty(), "{found:?}");
        }
    }
}

//! A synthetic scene with one ship and its wake, shared by the tests of the searches.

use rand::{RngExt, SeedableRng};
use wakelab_ships::cfar::{CfarOptions, Ship};
use wakelab_ships::wake::{Wake, WakeOptions};
use wakelab_ships::Geometry;

/// 4-look speckle at 10 m of `rows` x `cols`, a ship at `ship` (3 pixels across, 12
/// along its course) sailing along `course` (0: up, 270: left), its trough 3 dB dark and 60
/// m wide for 3 km behind it.
pub fn ship_scene(rows: usize, cols: usize, ship: (usize, usize), course: u32) -> ndarray::Array2<f32> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let mut image = ndarray::Array2::from_shape_fn((rows, cols), |_| {
        let s: f64 = (0..4).map(|_| -(1.0 - rng.random::<f64>()).ln()).sum();
        (0.01 * s / 4.0) as f32
    });
    let (r, c) = ship;
    let (hull, trough) = match course {
        0 => (
            ndarray::s![r - 6..r + 6, c - 1..c + 2],
            ndarray::s![r + 6..r + 306, c - 3..c + 3],
        ),
        270 => (
            ndarray::s![r - 1..r + 2, c - 6..c + 6],
            ndarray::s![r - 3..r + 3, c + 6..c + 306],
        ),
        _ => unreachable!("the tests' courses"),
    };
    image.slice_mut(trough).mapv_inplace(|v| v * 0.5);
    image.slice_mut(hull).fill(3.0);
    image
}

/// What the search of the whole image at once finds: one ship and its wake.
pub fn whole_search(image: &ndarray::Array2<f32>, g: &Geometry) -> (Ship, Wake) {
    let whole = wakelab_ships::search(image.view(), g, &CfarOptions::default(), &WakeOptions::default());
    assert_eq!(whole.ships.ships.len(), 1, "{:?}", whole.ships.ships);
    let wake = whole.wakes.iter().find(|w| w.ship == Some(0)).expect("the ship's wake");
    assert!(wake.length_m > 2500.0, "{wake:?}");
    (whole.ships.ships[0].clone(), wake.clone())
}

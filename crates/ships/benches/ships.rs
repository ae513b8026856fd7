//! The ship and wake searches on 100 km^2 of 10 m pixels (1000 x 1000, 4-look speckle, one ship
//! with its wake): the land mask, the CFAR, the normalisation, one ship's wake search, the free
//! wakes, and the whole search, whose time is the "per 100 km^2" figure; and the whole search
//! without the land mask, side by side. One ship's wake search is also timed on a wake with no
//! trough, only a bright arm, where the search takes both passes (the trough's, then the
//! arm's). The scene's sidelobe axes are timed on twelve targets, the most the search measures.
//! The whole search is timed again with its trough under the least z, so that the search
//! refuses it and promotes it as the image's best faint line (`promotion`).

use criterion::{criterion_group, criterion_main, Criterion};
use ndarray::Array2;
use rand::SeedableRng;
use rand_distr::{Distribution, Exp1};
use wakelab_ships::cfar::{find_ships, CfarOptions};
use wakelab_ships::free_wake::free_wakes;
use wakelab_ships::land::{land_mask, LandOptions};
use wakelab_ships::radon::SearchImage;
use wakelab_ships::sidelobes::sidelobe_axes;
use wakelab_ships::wake::{ship_wake, WakeOptions};
use wakelab_ships::{search, Geometry, BACKGROUND_M};

/// The scene; its wake a trough (`bright` false) or a bright arm 1 pixel wide, 3 dB bright.
fn scene(bright: bool) -> (Array2<f32>, Geometry) {
    let g = Geometry::along_rows(10.0, 35.0, Some(110.0));
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
    let mut image = Array2::from_shape_fn((1000, 1000), |_| {
        (0.01 * (0..4).map(|_| -> f64 { Exp1.sample(&mut rng) }).sum::<f64>() / 4.0) as f32
    });
    // a wake 3 km long from (500, 500) heading 210 (the ship on course 30), 3 dB dark, 40 m wide
    let (ur, uc) = g.step(210.0);
    let (vr, vc) = g.step(300.0);
    let (across, gain) = if bright { (0, 2.0) } else { (2, 0.5) };
    for i in 5..300 {
        for j in -across..=across {
            let (r, c) = (
                500.0 + ur * 10.0 * i as f64 + vr * 10.0 * j as f64,
                500.0 + uc * 10.0 * i as f64 + vc * 10.0 * j as f64,
            );
            image[[r.round() as usize, c.round() as usize]] *= gain;
        }
    }
    for r in 495..505 {
        for c in 498..502 {
            image[[r, c]] = 3.0;
        }
    }
    (image, g)
}

fn bench(c: &mut Criterion) {
    let (image, g) = scene(false);
    let (cfar, wakes) = (CfarOptions::default(), WakeOptions::default());
    let mut group = c.benchmark_group("ships_100km2");
    group.sample_size(10);
    group.bench_function("land_mask", |b| {
        b.iter(|| land_mask(image.view(), &g, &LandOptions::default()))
    });
    group.bench_function("cfar", |b| b.iter(|| find_ships(image.view(), &g, &cfar)));
    group.bench_function("normalise", |b| {
        b.iter(|| SearchImage::new(image.view(), &g, BACKGROUND_M))
    });
    let ships = find_ships(image.view(), &g, &cfar);
    let normalised = SearchImage::new(image.view(), &g, BACKGROUND_M);
    group.bench_function("ship_wake", |b| {
        b.iter(|| ship_wake(&normalised, &ships.ships[0], 0, &wakes))
    });
    let twelve = vec![ships.ships[0].clone(); 12];
    group.bench_function("sidelobe_axes_12_targets", |b| {
        b.iter(|| sidelobe_axes(&normalised.fine, &twelve))
    });
    let (arm_image, _) = scene(true);
    let arm_ships = find_ships(arm_image.view(), &g, &cfar);
    let arm_normalised = SearchImage::new(arm_image.view(), &g, BACKGROUND_M);
    group.bench_function("ship_wake_bright_arm", |b| {
        b.iter(|| ship_wake(&arm_normalised, &arm_ships.ships[0], 0, &wakes))
    });
    group.bench_function("free_wakes", |b| b.iter(|| free_wakes(&normalised, &[], &wakes)));
    group.bench_function("search", |b| b.iter(|| search(image.view(), &g, &cfar, &wakes)));
    // the same scene with the trough under the least z (and no free wake sought), so that the
    // search refuses it as a faint line and promotes it: the ship's trough and arm passes, then
    // the trough's again at the rule's z
    let z = ship_wake(&normalised, &ships.ships[0], 0, &wakes)
        .expect("the trough")
        .z;
    let promoting = WakeOptions {
        min_z: z + 1.0,
        along_hull_min_z: z + 1.0,
        promote_min_z: z - 0.5,
        free_min_z: f64::INFINITY,
        ..wakes
    };
    assert!(search(image.view(), &g, &cfar, &promoting).wakes[0].promoted);
    group.bench_function("search_promoting_its_faint_line", |b| {
        b.iter(|| search(image.view(), &g, &cfar, &promoting))
    });
    let sea_only = CfarOptions { land: None, ..cfar };
    group.bench_function("search_without_land_mask", |b| {
        b.iter(|| search(image.view(), &g, &sea_only, &wakes))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

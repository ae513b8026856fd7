//! All five images (S, C, X, MWIR, LWIR) of a 1024 x 1024 scene, given the surface stage's
//! output for the `quick` wake (computed once, not timed); and a scene like a real acquisition
//! (the scenes like real acquisitions: heading, slicks, wind variation, speckle, noise,
//! bunching, IR NETD and blur), surface stage plus five images, end to end.

// As in the `wakelab` binary, whose allocator keeps large buffers instead of handing them back
// to the kernel (page faults and zeroing) each time.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

use criterion::{criterion_group, criterion_main, Criterion};
use rayon::prelude::*;
use wakelab_core::units::RadarBand;
use wakelab_core::WakelabConfig;
use wakelab_sensors::image_formation::{form_sar_image, SarFormation};
use wakelab_sensors::{render_ir, render_sar, IrBand, IrScene, SarScene};

fn sensors(c: &mut Criterion) {
    let cfg = WakelabConfig::from_toml_str(
        "[scene]\nsize = 1024\npixel_spacing = 5.0\nalong_track = 6000.0\n",
        "bench",
    )
    .expect("valid");
    let map = wakelab_hydro::simulate_surface_map(&cfg).expect("wake");
    let scene = wakelab_surface::simulate_surface(&cfg, Some(&map));
    let mut g = c.benchmark_group("sensors_1024");
    g.sample_size(10);
    g.bench_function("five_images", |b| {
        b.iter(|| {
            let sar: Vec<_> = RadarBand::ALL
                .iter()
                .map(|&band| render_sar(&cfg, &scene, band))
                .collect();
            let ir: Vec<_> = IrBand::ALL.iter().map(|&band| render_ir(&cfg, &scene, band)).collect();
            (sar, ir)
        })
    });
    g.bench_function("sar_c_band", |b| b.iter(|| render_sar(&cfg, &scene, RadarBand::C)));
    // the kernels: 4-look speckle with noise over 1024^2, and one band's radar set-up (the
    // spectrum's slope variances and breakers), which the wind table repeats at 8 winds
    let uniform = ndarray::Array2::from_elem((1024, 1024), 0.05);
    let formation = SarFormation {
        looks: 4,
        resolution_pixels: 1.0,
        nesz: 1e-3,
    };
    g.bench_function("speckle_4_looks", |b| b.iter(|| form_sar_image(&uniform, formation, 3)));
    g.bench_function("radar_sea_setup", |b| {
        b.iter(|| wakelab_sensors::sar_image::radar_sea(&cfg, &scene, RadarBand::C).tilt_variance)
    });
    g.bench_function("ir_lwir", |b| b.iter(|| render_ir(&cfg, &scene, IrBand::Lwir)));
    let real = WakelabConfig::from_toml_str(
        "[scene]\nsize = 1024\npixel_spacing = 5.0\nalong_track = 6000.0\n[sar]\nlooks = 4\nnoise_floor = true\nvelocity_bunching = true\n",
        "bench",
    )
    .expect("valid");
    g.bench_function("sar_c_band_speckle_noise_bunching", |b| {
        b.iter(|| render_sar(&real, &scene, RadarBand::C))
    });
    let acquisition = WakelabConfig::from_toml_str(
        "[scene]\nsize = 1024\npixel_spacing = 5.0\nalong_track = 6000.0\nheading = 30.0\n\
         [slicks]\ncoverage = 0.15\n[environment.wind]\nvariability = 0.2\n\
         [sar]\nlooks = 4\nnoise_floor = true\nvelocity_bunching = true\n[ir]\nnoise = true\nresolution = 10.0\n",
        "bench",
    )
    .expect("valid");
    g.bench_function("acquisition_surface_and_five_images", |b| {
        b.iter(|| {
            let scene = wakelab_surface::simulate_surface(&acquisition, Some(&map));
            // the bands side by side, as the dataset renders them (independent images)
            let (radar, infrared) = (SarScene::new(&acquisition, &scene), IrScene::new(&acquisition, &scene));
            rayon::join(
                || {
                    RadarBand::ALL
                        .par_iter()
                        .map(|&band| radar.render(band))
                        .collect::<Vec<_>>()
                },
                || {
                    IrBand::ALL
                        .par_iter()
                        .map(|&band| infrared.render(band))
                        .collect::<Vec<_>>()
                },
            )
        })
    });
    g.bench_function("acquisition_surface_only", |b| {
        b.iter(|| wakelab_surface::simulate_surface(&acquisition, Some(&map)))
    });
    g.finish();
}

criterion_group!(benches, sensors);
criterion_main!(benches);

//! Scenes like real acquisitions, checked through the whole chain (surface stage and SAR): the
//! look direction acts through the physics, slicks and low-wind patches are dark as observed,
//! and the seed decides every random draw.

use std::sync::OnceLock;
use wakelab_core::units::RadarBand;
use wakelab_core::WakelabConfig;
use wakelab_hydro::SurfaceMap;
use wakelab_sensors::{gmf::cmod5n, render_sar};
use wakelab_surface::simulate_surface;

const BASE: &str =
    "[time]\nduration = 600.0\n[sea]\nwindow = 32\n[scene]\nsize = 128\npixel_spacing = 10.0\nalong_track = 1500.0\n";

fn config(extra: &str) -> WakelabConfig {
    WakelabConfig::from_toml_str(&format!("{BASE}{extra}"), "test").unwrap()
}

fn map() -> &'static SurfaceMap {
    static MAP: OnceLock<SurfaceMap> = OnceLock::new();
    MAP.get_or_init(|| wakelab_hydro::simulate_surface_map(&config("")).unwrap())
}

fn mean_where(v: &ndarray::Array2<f64>, keep: impl Fn(usize) -> bool) -> f64 {
    let (s, n) = v
        .iter()
        .enumerate()
        .filter(|(i, _)| keep(*i))
        .fold((0.0, 0usize), |(s, n), (_, x)| (s + x, n + 1));
    s / n as f64
}

/// The wake's C-band contrast (dB) over its mask, against the paired no-wake scene.
fn wake_contrast(extra: &str) -> f64 {
    let c = config(extra);
    let (with, without) = (simulate_surface(&c, Some(map())), simulate_surface(&c, None));
    let m = &with.bragg.iter().find(|b| b.band == RadarBand::C).unwrap().modulation;
    let mask: Vec<bool> = m.iter().map(|v| (v - 1.0).abs() > 0.05).collect();
    let (a, b) = (
        render_sar(&c, &with, RadarBand::C).sigma0,
        render_sar(&c, &without, RadarBand::C).sigma0,
    );
    10.0 * (mean_where(&a, |i| mask[i]) / mean_where(&b, |i| mask[i])).log10()
}

/// Looking along the track or across it changes which current gradients the Bragg waves feel
/// and the wind's angle to them: the wake's contrast changes, not only its picture's rotation
/// (the image's geometry is the same in both).
#[test]
fn the_look_direction_changes_the_wake_signature() {
    let across = wake_contrast("[platform]\nlook_direction = 90.0\n");
    let along = wake_contrast("[platform]\nlook_direction = 0.0\n");
    let oblique = wake_contrast("[platform]\nlook_direction = 45.0\n");
    eprintln!("C-band wake contrast: across {across:.2} dB, along {along:.2} dB, 45 deg {oblique:.2} dB");
    assert!((across - along).abs() > 0.5, "across {across} along {along}");
    assert!((oblique - along).abs() > 0.1 && (oblique - across).abs() > 0.1);
}

/// Slicks darken the sea in every radar band, more at the shorter Bragg waves; C band's damping
/// ratio in the slicks' cores lies in the range Gade et al. (1998, J. Geophys. Res. 103, 18851)
/// observed for biogenic and methyl-oleate slicks at 3-7 m/s, about 3-10 dB.
#[test]
fn slicks_are_dark_by_the_film_physics() {
    let c = config("[slicks]\ncoverage = 0.3\n[environment.swell]\ndirection = \"calm\"\n");
    let scene = simulate_surface(&c, None);
    let mask = scene.slick_mask.clone().expect("slicks");
    let m = &scene.bragg.iter().find(|b| b.band == RadarBand::C).unwrap().modulation;
    // the slicks' cores: where the C-band Bragg waves are damped by at least half their most
    let deepest = m.iter().cloned().fold(f64::INFINITY, f64::min);
    let core: Vec<bool> = m.iter().map(|&v| v < 0.5 * (1.0 + deepest)).collect();
    let open: Vec<bool> = mask.iter().map(|&s| s == 0).collect();
    let mut db = vec![];
    for band in RadarBand::ALL {
        let s = render_sar(&c, &scene, band).sigma0;
        let contrast = 10.0 * (mean_where(&s, |i| open[i]) / mean_where(&s, |i| core[i])).log10();
        eprintln!("{band:?}: slick cores {contrast:.2} dB darker than the open sea");
        db.push(contrast);
    }
    assert!(db[0] > 0.5 && db[0] < db[1] && db[1] <= db[2] + 0.5, "{db:?}");
    assert!((3.0..=10.0).contains(&db[1]), "C band {}", db[1]);
}

/// Low-wind patches: each pixel's sigma0 follows its own wind. Over the scene's windiest and
/// calmest tenths, the C-band VV ratio matches CMOD5.N's (Hersbach 2010) at their mean winds
/// within 2 dB, and the calm tenth is darker.
#[test]
fn low_wind_patches_are_as_dark_as_cmod5n_says() {
    let c = config(
        "[environment.wind]\nspeed = 6.0\nvariability = 0.3\ngust_length = 300.0\n[environment.swell]\ndirection = \"calm\"\n",
    );
    let scene = simulate_surface(&c, None);
    let wind = scene.wind_speed.clone().expect("a variable wind");
    let mut sorted: Vec<f64> = wind.iter().cloned().collect();
    sorted.sort_by(f64::total_cmp);
    let (lo, hi) = (sorted[sorted.len() / 10], sorted[sorted.len() * 9 / 10]);
    let s = render_sar(&c, &scene, RadarBand::C).sigma0;
    let w: Vec<f64> = wind.iter().cloned().collect();
    let calm = |i: usize| w[i] <= lo;
    let windy = |i: usize| w[i] >= hi;
    let model = 10.0 * (mean_where(&s, windy) / mean_where(&s, calm)).log10();
    let wind_array = ndarray::Array2::from_shape_vec(wind.raw_dim(), w.clone()).unwrap();
    let (u_calm, u_windy) = (mean_where(&wind_array, calm), mean_where(&wind_array, windy));
    // upwind along the look direction: wind 0 deg from the heading, look 90 deg: crosswind
    let cmod =
        10.0 * (cmod5n(u_windy, c.platform.incidence, 90.0) / cmod5n(u_calm, c.platform.incidence, 90.0)).log10();
    eprintln!("winds {u_calm:.2} and {u_windy:.2} m/s: wakelab {model:.2} dB, CMOD5.N {cmod:.2} dB");
    assert!(model > 1.0, "the calm patches are darker");
    assert!((model - cmod).abs() < 2.0, "wakelab {model} CMOD5.N {cmod}");
}

/// The whole chain's open sea against what C-band scatterometers observe: the surface stage
/// and the image of C-band VV at the default 35 degrees and 10 m pixels, 3-15 m/s, the radar
/// looking cross-, down- and up-wind. A perfect SAR's mean sigma0 lies within 2 dB of CMOD5.N
/// (Hersbach 2010); a real one's (4 looks, velocity bunching, the noise floor) is that mean plus
/// its NESZ (Sentinel-1 IW's -22 dB) within 0.2 dB: speckle and bunching keep the mean, thermal
/// noise adds its power, as in a real instrument's low-wind images.
#[test]
fn the_open_seas_sigma0_is_cmod5ns_plus_the_noise_floor() {
    for wind in [3.0, 5.0, 10.0, 15.0] {
        // the look is 90 degrees from the heading: wind towards 0, 90, 270 is cross-, down-, up-wind
        for direction in [0.0, 90.0, 270.0] {
            let mean_db = |real: bool| {
                let c = config(&format!(
                    "[environment.wind]\nspeed = {wind}\ndirection = {direction}\n[environment.swell]\n\
                     direction = \"calm\"\n[sar]\nlooks = {}\nnoise_floor = {real}\nvelocity_bunching = {real}\n",
                    if real { 4 } else { 0 }
                ));
                let s = render_sar(&c, &simulate_surface(&c, None), RadarBand::C).sigma0;
                (10.0 * s.mean().unwrap().log10(), c)
            };
            let ((perfect, c), (real, _)) = (mean_db(false), mean_db(true));
            // CMOD5.N's direction is 0 looking up-wind
            let relative = direction - c.platform.look_direction;
            let cmod = 10.0 * cmod5n(wind, c.platform.incidence, 180.0 - relative).log10();
            let nesz = c.sar.nesz_db(RadarBand::C);
            let with_noise = 10.0 * (10f64.powf(perfect / 10.0) + 10f64.powf(nesz / 10.0)).log10();
            eprintln!(
                "{wind} m/s, wind {relative} deg from the look: perfect {perfect:+.2} dB, CMOD5.N {cmod:+.2}, \
                 real {real:+.2} (perfect + NESZ {with_noise:+.2})"
            );
            assert!(
                (perfect - cmod).abs() < 2.0,
                "{wind} {direction}: {perfect} vs CMOD5.N {cmod}"
            );
            assert!(
                (real - with_noise).abs() < 0.2,
                "{wind} {direction}: {real} vs {with_noise}"
            );
        }
    }
}

/// The same configuration gives the same image, bit for bit; another seed changes the sea, the
/// slicks, the wind's patches and the speckle.
#[test]
fn the_seed_decides_every_random_draw() {
    let extra =
        "[slicks]\ncoverage = 0.2\n[environment.wind]\nvariability = 0.2\n[sar]\nlooks = 4\nnoise_floor = true\n";
    let a = config(extra);
    let scene_a = simulate_surface(&a, Some(map()));
    let img_a = render_sar(&a, &scene_a, RadarBand::X).sigma0;
    let again = simulate_surface(&a, Some(map()));
    assert_eq!(
        render_sar(&a, &again, RadarBand::X).sigma0,
        img_a,
        "same config, same bytes"
    );
    let mut b = a.clone();
    b.seed += 1;
    let scene_b = simulate_surface(&b, Some(map()));
    assert_ne!(scene_a.surface.elevation, scene_b.surface.elevation, "sea");
    assert_ne!(scene_a.slick_mask, scene_b.slick_mask, "slicks");
    assert_ne!(scene_a.wind_speed, scene_b.wind_speed, "wind");
    // the speckle alone: seed b's image formation on seed a's surface
    assert_ne!(render_sar(&b, &scene_a, RadarBand::X).sigma0, img_a, "speckle");
}

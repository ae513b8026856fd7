//! The wake placed in the scene: its mask lies along the configured heading and starts where the
//! ship is; natural slicks damp the Bragg waves in wake and no-wake scenes alike.

use std::sync::OnceLock;
use wakelab_core::units::RadarBand;
use wakelab_core::WakelabConfig;
use wakelab_hydro::SurfaceMap;
use wakelab_surface::scene::SceneGrid;
use wakelab_surface::simulate_surface;

const BASE: &str = "[time]\nduration = 600.0\n[sea]\nwindow = 32\n";

fn config(extra: &str) -> WakelabConfig {
    WakelabConfig::from_toml_str(&format!("{BASE}{extra}"), "test").unwrap()
}

/// One surface map for every test (the scene's placement does not change the hydro stage).
fn map() -> &'static SurfaceMap {
    static MAP: OnceLock<SurfaceMap> = OnceLock::new();
    MAP.get_or_init(|| {
        wakelab_hydro::simulate_surface_map(&config("[scene]\nsize = 128\nalong_track = 1000.0\n")).unwrap()
    })
}

/// The C-band wake mask of a scene, as the dataset draws it (|N/N0 - 1| > 5 %: without slicks or
/// wind variation the no-wake scene's N is N0).
fn wake_mask(c: &WakelabConfig) -> ndarray::Array2<bool> {
    let scene = simulate_surface(c, Some(map()));
    let m = &scene.bragg.iter().find(|b| b.band == RadarBand::C).unwrap().modulation;
    m.mapv(|v| (v - 1.0).abs() > 0.05)
}

/// Orientation (degrees anticlockwise from east, in [0, 180)) of the principal axis of a mask's
/// pixels, from their second moments.
fn principal_axis(mask: &ndarray::Array2<bool>) -> f64 {
    let pts: Vec<(f64, f64)> = mask
        .indexed_iter()
        .filter(|(_, &m)| m)
        .map(|((r, c), _)| (c as f64, -(r as f64)))
        .collect();
    let n = pts.len() as f64;
    let (me, mn) = pts.iter().fold((0.0, 0.0), |(a, b), p| (a + p.0 / n, b + p.1 / n));
    let (mut see, mut snn, mut sen) = (0.0, 0.0, 0.0);
    for (e, nn) in &pts {
        see += (e - me).powi(2);
        snn += (nn - mn).powi(2);
        sen += (e - me) * (nn - mn);
    }
    (0.5 * (2.0 * sen).atan2(see - snn)).to_degrees().rem_euclid(180.0)
}

#[test]
fn the_wake_mask_lies_along_the_heading_over_the_full_circle() {
    for heading in [0.0, 33.0, 90.0, 137.0, 180.0, 222.0, 270.0, 301.0, 359.0] {
        let c = config(&format!(
            "[scene]\nsize = 128\npixel_spacing = 10.0\nalong_track = 2500.0\nheading = {heading}\n"
        ));
        let mask = wake_mask(&c);
        let count = mask.iter().filter(|&&m| m).count();
        // compass heading to an angle anticlockwise from east
        let want = (90.0f64 - heading).rem_euclid(180.0);
        let got = principal_axis(&mask);
        let diff = ((got - want + 90.0).rem_euclid(180.0) - 90.0).abs();
        eprintln!("heading {heading}: axis {got:.2} deg vs {want:.2} ({count} mask pixels)");
        assert!(count > 500, "a wake in the scene");
        assert!(diff < 2.0, "heading {heading}: principal axis off by {diff:.2} deg");
    }
}

/// With the stern inside the image, the mask begins at the stern's pixel (the hydro map starts
/// at the initial data plane, half a ship length astern) and nothing lies ahead of the ship.
#[test]
fn with_the_ship_in_the_scene_the_wake_starts_at_the_stern() {
    for heading in [60.0f64, 200.0] {
        let c = config(&format!(
            "[scene]\nsize = 128\npixel_spacing = 10.0\nalong_track = 300.0\nheading = {heading}\n"
        ));
        let grid = SceneGrid::new(&c.scene);
        let geometry = grid.wake_geometry();
        assert!(geometry.ship_in_scene);
        let [r0, c0] = geometry.stern_pixel.unwrap();
        // unit vector of the ship's course in (column, row) steps
        let h = heading.to_radians();
        let (dc, dr) = (h.sin(), -h.cos());
        let mask = wake_mask(&c);
        // distance of each mask pixel ahead of the stern along the course (pixels)
        let ahead = mask
            .indexed_iter()
            .filter(|(_, &m)| m)
            .map(|((r, col), _)| (col as f64 - c0) * dc + (r as f64 - r0) * dr)
            .fold(f64::NEG_INFINITY, f64::max);
        let start = -map().x[0] / c.scene.pixel_spacing;
        eprintln!("heading {heading}: stern at ({r0:.1}, {c0:.1}), mask front {ahead:.2} px, map starts {start:.2} px");
        assert!(
            (ahead - start).abs() < 1.5,
            "the wake starts {ahead:.2} px ahead of the stern, want {start:.2}"
        );
    }
}

/// A slick damps the Bragg waves by the film physics (Eq. (2.69)) and nothing outside it; its
/// damping grows with the Bragg wavenumber from S to X band, as observed for biogenic films at
/// low to moderate wind (Gade et al. 1998, J. Geophys. Res. 103, 18851). The sigma0 it makes is
/// checked against their damping ratios in the sensors' tests.
#[test]
fn natural_slicks_damp_the_bragg_waves_more_at_shorter_waves() {
    let c = config("[scene]\nsize = 128\npixel_spacing = 10.0\nalong_track = 2500.0\n[slicks]\ncoverage = 0.3\n");
    let scene = simulate_surface(&c, None);
    let mask = scene.slick_mask.as_ref().expect("slicks");
    let mut ratios = vec![];
    for band in RadarBand::ALL {
        let m = &scene.bragg.iter().find(|b| b.band == band).unwrap().modulation;
        let inside: Vec<f64> = m.iter().zip(mask).filter(|(_, &s)| s == 1).map(|(v, _)| *v).collect();
        let outside: Vec<f64> = m.iter().zip(mask).filter(|(_, &s)| s == 0).map(|(v, _)| *v).collect();
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        // slick centres: the lowest decile inside the slicks
        let mut sorted = inside.clone();
        sorted.sort_by(f64::total_cmp);
        let core = sorted[sorted.len() / 10];
        eprintln!(
            "{band:?}: N/N0 outside {:.3}, inside {:.3}, slick core {core:.3} ({:.1} dB)",
            mean(&outside),
            mean(&inside),
            -10.0 * core.log10()
        );
        assert_eq!(mean(&outside), 1.0, "no damping off the slicks");
        ratios.push(1.0 / core);
    }
    assert!(ratios[0] < ratios[1] && ratios[1] < ratios[2], "{ratios:?}");
}

/// A "slick" cleaner than the open sea (no film where the sea has its 3 mN/m) damps less, so
/// its Bragg waves grow above the open sea's (N/N0 > 1), and stay bounded even at 1.5 m/s where
/// the waves' relaxation is slow (r at most 10, as under the wake's converging currents).
#[test]
fn a_film_free_patch_is_rougher_and_bounded() {
    let c = config(
        "[scene]\nsize = 128\npixel_spacing = 10.0\nalong_track = 2500.0\n[slicks]\ncoverage = 0.3\nelasticity = 0.0\n\
         [environment.wind]\nspeed = 3.0\n",
    );
    let scene = simulate_surface(&c, None);
    let mask = scene.slick_mask.as_ref().unwrap();
    for b in &scene.bragg {
        let inside: Vec<f64> = b
            .modulation
            .iter()
            .zip(mask)
            .filter(|(_, &s)| s == 1)
            .map(|(v, _)| *v)
            .collect();
        let max = inside.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        let mean = inside.iter().sum::<f64>() / inside.len() as f64;
        eprintln!("{:?}: film-free patches N/N0 mean {mean:.3}, max {max:.3}", b.band);
        assert!(
            mean > 1.0 && max <= 10.0 + 1e-9 && max.is_finite(),
            "{:?}: {mean} {max}",
            b.band
        );
    }
}

/// Other wakes are the same wake placed again (`[[scene.other_wakes]]`): a scene whose own wake
/// lies 8 km off it and whose other wake has a one-wake scene's placement holds that scene's
/// wake, field for field; a scene of two wakes on different courses marks both lines, the union
/// of the single wakes' masks (but where they cross); a misplaced other wake is refused by name.
#[test]
fn other_wakes_are_the_same_wake_placed_again() {
    let scene = "[scene]\nsize = 128\npixel_spacing = 10.0\n";
    let placed = |along: f64, cross: f64, heading: f64| {
        format!("along_track = {along}\ncross_track = {cross}\nheading = {heading}\n")
    };
    let other =
        |along: f64, cross: f64, heading: f64| format!("[[scene.other_wakes]]\n{}", placed(along, cross, heading));
    let one = config(&format!("{scene}{}", placed(2500.0, 0.0, 33.0)));
    let moved = config(&format!(
        "{scene}{}{}",
        placed(2500.0, 8000.0, 33.0),
        other(2500.0, 0.0, 33.0)
    ));
    let (a, b) = (
        simulate_surface(&one, Some(map())),
        simulate_surface(&moved, Some(map())),
    );
    assert_eq!(a.temperature_anomaly, b.temperature_anomaly);
    assert_eq!(a.surfactant, b.surfactant);
    for (x, y) in a.bragg.iter().zip(&b.bragg) {
        assert_eq!(x.modulation, y.modulation, "{:?}", x.band);
        assert_eq!(x.breaking, y.breaking, "{:?}", x.band);
    }

    let crossing = config(&format!("{scene}{}", placed(2500.0, 0.0, 120.0)));
    let both = config(&format!(
        "{scene}{}{}",
        placed(2500.0, 0.0, 33.0),
        other(2500.0, 0.0, 120.0)
    ));
    let (m1, m2, m12) = (wake_mask(&one), wake_mask(&crossing), wake_mask(&both));
    assert!(m1.iter().any(|&m| m) && m2.iter().any(|&m| m));
    let agree = ndarray::Zip::from(&m1)
        .and(&m2)
        .and(&m12)
        .fold(0usize, |n, &a, &b, &ab| n + usize::from((a || b) == ab));
    assert!(
        agree as f64 >= 0.98 * m12.len() as f64,
        "{agree} of {} pixels",
        m12.len()
    );

    let misplaced = format!("{BASE}{scene}{}{}", placed(2500.0, 0.0, 33.0), other(1.0e6, 0.0, 33.0));
    let err = WakelabConfig::from_toml_str(&misplaced, "test").unwrap_err();
    assert!(err.to_string().contains("scene.other_wakes[0].along_track"), "{err}");
}

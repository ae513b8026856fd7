//! The ships step of `wakelab run`: the classic ship and wake detectors ([`wakelab_ships`])
//! proven where the truth is known. The study's base sea and SAR (speckle, noise, velocity
//! bunching) image its ship in C-band VV on scenes of 5 km, with the ship inside: speeds of 6, 9
//! and 12 m/s, any course, any look, R/V drawn over the spaceborne 40-130 s, winds of 4-10 m/s
//! and incidences of 25-45 degrees; then the same seas without the ship (false alarms); and
//! scenes whose ship has sailed out, leaving its wake alone (free wakes). Against the truth:
//! ship detection (the return where its range velocity displaces it) and false alarms per 100
//! km^2, wake detection, the course's error, and both speeds' errors where they are reported.
//! Beside them, fine scenes prove the speed read from the Kelvin waves, which
//! C band at 10 m and 4 looks does not resolve above its clutter: X band at 2.5 m (a
//! TerraSAR-X StripMap product's pixel), 1 or 4 looks, half of them without the swell.
//! It writes `ships/ships.json`, which the report renders.

use super::context::{fnv_hex, step_time, write_results};
use super::ship_windows::{score_detectors, DetectorScore, ShipWindows, Trial};
use crate::{Result, StepTime};
use ndarray::Array2;
use rand::{RngExt, SeedableRng};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::time::Instant;
use wakelab_core::units::RadarBand;
use wakelab_core::{WakelabConfig, WakelabError};
use wakelab_dataset::study::Study;
use wakelab_ships::cfar::CfarOptions;
use wakelab_ships::promotion::promote_best_faint_line;
use wakelab_ships::radon::SearchImage;
use wakelab_ships::wake::ship_wake;
use wakelab_ships::wake::WakeOptions;
use wakelab_ships::{angle_difference, line_difference, search, Geometry, BACKGROUND_M};
use wakelab_surface::scene::SceneGrid;

/// The ships' speeds (m/s), scenes per speed with the ship in view, and scenes of free wakes.
pub const SPEEDS: [f64; 3] = [6.0, 9.0, 12.0];
const SCENES_PER_SPEED: usize = 8;
const FREE_SCENES: usize = 3;
/// The scenes' side (pixels) and spacing (m): 5.12 km.
const SIDE: usize = 512;
pub(crate) const SPACING: f64 = 10.0;
/// The scene centre behind the stern (m): the ship in view 1.2 km off the centre, or sailed out
/// of it (4.5 km) for the free wakes.
const IN_VIEW: f64 = 1200.0;
const SAILED_OUT: f64 = 4500.0;
/// The fine scenes: how many, their spacing (m) and band.
const FINE_SCENES: usize = 12;
pub(crate) const FINE_SPACING: f64 = 2.5;
const FINE_BAND: RadarBand = RadarBand::X;

/// The layout of `ships.json` and what the step computes: a file of another layout (an older
/// wakelab's) is recomputed, not read with fields missing.
const RESULTS_FORMAT: &str = "scenes-24-cnn-fusion-fine-12-kelvin-curve-no-wake-along-hull";

/// One simulated scene and what the detectors found in it.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SceneResult {
    pub speed: f64,
    pub course: f64,
    /// The look direction in the image (degrees clockwise from up), the incidence (degrees),
    /// R/V (s) and the wind (m/s).
    pub look: f64,
    pub incidence: f64,
    pub range_over_velocity: f64,
    pub wind: f64,
    /// The band, pixel spacing (m), looks and the swell's amplitude (m) of the image.
    #[serde(default = "c_band")]
    pub band: RadarBand,
    #[serde(default = "ten_metres")]
    pub pixel_spacing: f64,
    #[serde(default)]
    pub looks: u32,
    #[serde(default)]
    pub swell_m: f64,
    /// Whether the ship is in view (else only its wake is).
    pub ship_in_view: bool,
    /// Whether a detected ship lies within its length of where the return should be, and the
    /// detected ships that do not (false alarms), in this scene and in its twin without a ship.
    pub ship_found: bool,
    pub false_ships: usize,
    pub false_ships_without: usize,
    /// The ship's wake found along its track (anchored on the found ship with its axis within
    /// 20 degrees of the track, or free within 10), its course error (degrees; for a free wake
    /// the axis's, modulo 180) and the speeds read (m/s) or why not.
    pub wake_found: bool,
    /// Wakes found that are not the ship's (anchored on a false ship or off the track, or free
    /// and off its track), in this scene and in its twin without the ship (every wake there).
    #[serde(default)]
    pub false_wakes: usize,
    #[serde(default)]
    pub false_wakes_without: usize,
    pub course_error: Option<f64>,
    /// The course's uncertainty the search gave (degrees; anchored wakes only).
    #[serde(default)]
    pub course_sigma: Option<f64>,
    pub speed_offset: Option<f64>,
    pub speed_kelvin: Option<f64>,
    pub no_speed: Vec<String>,
    /// Where the ship was found and its wake was not: the tests its best trough and its best
    /// bright arm failed ("z 3.1 / z 2.4"), or "off the track" where the wake found from it
    /// runs another way.
    #[serde(default)]
    pub no_wake: Option<String>,
    /// The classic search anchored on the detected ship in the twin without the ship: a wake
    /// found there is a false alarm.
    #[serde(default)]
    pub wake_found_without: bool,
    /// The CNN's largest window probability around the detected ship, in the scene and in its
    /// twin without the ship (None: no ship detected, or no detector fits the scenes).
    #[serde(default)]
    pub cnn_with: Option<f64>,
    #[serde(default)]
    pub cnn_without: Option<f64>,
    /// Seconds the search took on this scene, and its area (km^2).
    pub seconds: f64,
    pub km2: f64,
}

fn c_band() -> RadarBand {
    RadarBand::C
}

fn ten_metres() -> f64 {
    SPACING
}

/// `ships/ships.json`: the step's key and seconds, and every scene.
#[derive(Serialize, Deserialize)]
pub struct ShipsResults {
    key: String,
    seconds: f64,
    pub scenes: Vec<SceneResult>,
    /// The CNN's decision threshold and window footprint (m), when the run has a C-band
    /// detector that fits the scenes' spacing.
    #[serde(default)]
    pub cnn_threshold: Option<f64>,
    #[serde(default)]
    pub cnn_footprint_m: Option<f64>,
    /// The wake detectors on the detected ships (classic, CNN, their fusions).
    #[serde(default)]
    pub wake_detectors: Vec<DetectorScore>,
    /// The fine X-band scenes (the Kelvin speed's proof), scored alike.
    #[serde(default)]
    pub fine: Vec<SceneResult>,
}

fn results_file(run_dir: &Path) -> PathBuf {
    run_dir.join("ships").join("ships.json")
}

/// What the ships step wrote into `run_dir`.
pub fn load_ships(run_dir: &Path) -> Result<ShipsResults> {
    let file = results_file(run_dir);
    let text = std::fs::read_to_string(&file).map_err(|e| WakelabError::io(&file, e))?;
    serde_json::from_str(&text).map_err(|e| anyhow::anyhow!("{}: {e}", file.display()))
}

/// The configuration of scene `k` of the step (`in_view`: the ship in the image) at `spacing`
/// (m), None when the study's simulated wake is too short for it: the scene (512 pixels on a
/// side, else 256 or 128) must end within the wake, and hold the ship (at most half its
/// half-side off its centre) or not.
pub(crate) fn scene_config(
    base: &WakelabConfig,
    k: usize,
    speed: f64,
    in_view: bool,
    spacing: f64,
) -> Option<WakelabConfig> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(base.seed ^ (0x5415_0000 + k as u64));
    let mut c = base.clone();
    c.seed = base.seed.wrapping_add(1000 + k as u64);
    c.ship.speed = speed;
    c.scene.pixel_spacing = spacing;
    c.scene.cross_track = 0.0;
    c.scene.heading = rng.random_range(0.0..360.0);
    c.scene.other_wakes.clear();
    c.platform.look_direction = rng.random_range(0.0..360.0);
    c.platform.incidence = rng.random_range(25.0..45.0);
    c.sar.range_to_velocity = rng.random_range(40.0..130.0);
    c.sar.velocity_bunching = true;
    c.environment.wind.speed = [4.0, 7.0, 10.0][k % 3];
    c.environment.wind.direction = rng.random_range(0.0..360.0);
    c.slicks.coverage = 0.0;
    let (sin, cos) = c.scene.heading.to_radians().sin_cos();
    [SIDE, SIDE / 2, SIDE / 4].into_iter().find_map(|size| {
        let half = 0.5 * size as f64 * spacing;
        // how far the scene reaches along the track either side of its centre
        let reach = half * (sin.abs() + cos.abs());
        let along = if in_view {
            IN_VIEW.min(0.5 * half)
        } else {
            SAILED_OUT.max(reach + 500.0)
        };
        let mut scene = c.clone();
        scene.scene.size = size;
        scene.scene.along_track = along;
        (along + reach <= scene.wake_end() && scene.validate().is_ok()).then_some(scene)
    })
}

/// Fine scene `j`: X band at 2.5 m, 2.56 km on a side (a moving ship's return lies hundreds of
/// metres from its wake), the ship 640 m behind the centre; speeds as the main scenes', 1 or 4
/// looks and winds of 4 or 7 m/s in every combination with them, the study's swell on the first
/// six and none on the rest (a swell of about a Kelvin wavelength along the track is the
/// speed's hardest confusion).
fn fine_scene_config(base: &WakelabConfig, j: usize) -> Option<WakelabConfig> {
    let mut c = scene_config(base, 100 + j, SPEEDS[j % SPEEDS.len()], true, FINE_SPACING)?;
    c.scene.size = 2 * SIDE;
    c.scene.along_track = 0.25 * c.scene.size as f64 * FINE_SPACING;
    c.sar.looks = [1, 4][j % 2];
    c.environment.wind.speed = [4.0, 7.0][(j / 3) % 2];
    if j >= FINE_SCENES / 2 {
        c.environment.swell.amplitude = 0.0;
    }
    let reach = 0.5 * c.scene.size as f64 * FINE_SPACING * std::f64::consts::SQRT_2;
    (c.validate().is_ok() && c.scene.along_track + reach <= c.wake_end()).then_some(c)
}

/// The image geometry of a scene: its look and flight directions in the image (clockwise from
/// up; the configuration's look direction turns counter-clockwise from the ship's heading).
pub fn scene_geometry(c: &WakelabConfig) -> Geometry {
    let look = (c.scene.heading - c.platform.look_direction).rem_euclid(360.0);
    Geometry {
        spacing: (c.scene.pixel_spacing, c.scene.pixel_spacing),
        azimuth_deg: (look - 90.0).rem_euclid(360.0),
        look_deg: look,
        incidence_deg: c.platform.incidence,
        range_over_velocity: Some(c.sar.range_to_velocity),
    }
}

/// Where the ship's return should appear (fractional pixels): the hull's centre moved back
/// along the flight direction by R/V times its velocity away from the radar.
fn expected_return(c: &WakelabConfig, grid: &SceneGrid, g: &Geometry) -> (f64, f64) {
    let centre = grid.pixel_of(-0.5 * c.ship.length, 0.0);
    let v_away = c.ship.speed * c.platform.look_direction.to_radians().cos() * c.platform.incidence.to_radians().sin();
    let (ar, ac) = g.step(g.azimuth_deg);
    let shift = -c.sar.range_to_velocity * v_away;
    (centre.0 + ar * shift, centre.1 + ac * shift)
}

/// Scene `k`: render it with and without its ship, search both and score the findings.
fn run_scene(
    c: &WakelabConfig,
    run_dir: &Path,
    in_view: bool,
    band: RadarBand,
    cnn: Option<&ShipWindows>,
) -> Result<SceneResult> {
    c.validate()?;
    let map = wakelab_dataset::hydro_map(&run_dir.join("dataset"), c)?;
    let with = wakelab_surface::simulate_surface(c, Some(&map));
    let without = wakelab_surface::simulate_surface(c, None);
    let image = |scene| -> Array2<f32> { wakelab_sensors::render_sar(c, scene, band).sigma0.mapv(|v| v as f32) };
    let (wake_image, plain) = (image(&with), image(&without));
    let g = scene_geometry(c);
    let (cfar, wakes) = (CfarOptions::default(), WakeOptions::default());
    let start = Instant::now();
    let found = search(wake_image.view(), &g, &cfar, &wakes);
    let seconds = start.elapsed().as_secs_f64();
    let control = search(plain.view(), &g, &cfar, &wakes);
    let expected = expected_return(c, &with.grid, &g);
    let tolerance = c.ship.length.max(100.0);
    let near = |s: &wakelab_ships::cfar::Ship| g.metres(s.row - expected.0, s.col - expected.1) <= tolerance;
    let found_ship = in_view.then(|| found.ships.ships.iter().position(near)).flatten();
    // the same ship's surroundings in the twin without it: what each wake detector says there
    let (mut wake_found_without, mut cnn_with, mut cnn_without) = (false, None, None);
    if let Some(i) = found_ship {
        let ship = &found.ships.ships[i];
        let twin = SearchImage::new(plain.view(), &g, BACKGROUND_M);
        // as the search would report it: its wake, or its best faint line promoted to one
        wake_found_without = match ship_wake(&twin, ship, i, &wakes) {
            Ok(_) => true,
            Err(refused) => promote_best_faint_line(&twin, &found.ships.ships, &[(i, *refused)], &wakes).is_some(),
        };
        if let Some(cnn) = cnn {
            let spacing = c.scene.pixel_spacing;
            cnn_with = Some(cnn.score(&wake_image, (ship.row, ship.col), spacing)?);
            cnn_without = Some(cnn.score(&plain, (ship.row, ship.col), spacing)?);
        }
    }
    let false_ships = found.ships.ships.len() - usize::from(found_ship.is_some());
    let wake = match found_ship {
        // the ship's wake, if it lies along the track: one on another line (a swell's trough,
        // a streak) is a false wake, not a found one with a large course error
        Some(i) => found
            .wakes
            .iter()
            .find(|w| w.ship == Some(i) && along_track(w.axis_deg, c.scene.heading, 20.0)),
        // the ship out of view: a free wake along the track
        None if !in_view => found
            .wakes
            .iter()
            .find(|w| w.ship.is_none() && along_track(w.axis_deg, c.scene.heading, 10.0)),
        None => None,
    };
    let no_wake = match (found_ship, wake) {
        (Some(i), None) => Some(match found.no_wake.iter().find(|(k, _)| *k == i) {
            Some((_, n)) => format!("{} / {}", n.trough.brief(), n.bright_arm.brief()),
            None => "off the track".to_string(),
        }),
        _ => None,
    };
    let mut no_speed = Vec::new();
    let (mut speed_offset, mut speed_kelvin) = (None, None);
    if let Some(readings) = wake.and_then(|w| w.speed.as_ref()) {
        match &readings.offset {
            Ok(s) => speed_offset = Some(s.value),
            Err(why) => no_speed.push(format!("offset: {why}")),
        }
        match &readings.kelvin {
            Ok(k) => speed_kelvin = Some(k.speed.value),
            Err(why) => no_speed.push(format!("Kelvin: {why}")),
        }
    }
    let course_error = wake.map(|w| match w.course_deg {
        Some(course) => angle_difference(course, c.scene.heading),
        None => {
            let e = angle_difference(w.axis_deg, c.scene.heading);
            if e.abs() > 90.0 {
                e - 180.0f64.copysign(e)
            } else {
                e
            }
        }
    });
    Ok(SceneResult {
        speed: c.ship.speed,
        course: c.scene.heading,
        look: g.look_deg,
        incidence: c.platform.incidence,
        range_over_velocity: c.sar.range_to_velocity,
        wind: c.environment.wind.speed,
        band,
        pixel_spacing: c.scene.pixel_spacing,
        looks: c.sar.looks,
        swell_m: c.environment.swell.amplitude,
        ship_in_view: in_view,
        ship_found: found_ship.is_some(),
        false_ships,
        false_ships_without: control.ships.ships.len(),
        wake_found: wake.is_some(),
        false_wakes: found.wakes.len() - usize::from(wake.is_some()),
        false_wakes_without: control.wakes.len(),
        course_error,
        course_sigma: wake.and_then(|w| w.course_sigma_deg),
        speed_offset,
        speed_kelvin,
        no_speed,
        no_wake,
        wake_found_without,
        cnn_with,
        cnn_without,
        seconds,
        km2: (c.scene.size as f64 * c.scene.pixel_spacing / 1000.0).powi(2),
    })
}

/// Whether a line of direction `axis_deg` runs along a track of `heading` to within `within`
/// degrees, either way (a wake's axis points back along its course; a reversed wake lies on
/// the right line, and its course error says so).
fn along_track(axis_deg: f64, heading: f64, within: f64) -> bool {
    line_difference(axis_deg, heading) < within
}

/// The ships step: every scene searched and scored (reused when the base configuration and
/// wakelab's version are unchanged).
pub fn ships_step(run_dir: &Path, study: &Study) -> Result<StepTime> {
    let start = Instant::now();
    let base = study.base_config()?;
    let cnn = ShipWindows::load(run_dir, SPACING)?;
    // the searches' settings too: results of other settings are not these
    let key = fnv_hex(&format!(
        "{base:?} {} detector {:?} {RESULTS_FORMAT} {:?} {:?}",
        env!("CARGO_PKG_VERSION"),
        cnn.as_ref().map(|c| c.hash),
        CfarOptions::default(),
        WakeOptions::default()
    ));
    if let Ok(found) = load_ships(run_dir) {
        if found.key == key {
            return Ok(step_time("ships", start, Some(found.seconds)));
        }
    }
    let mut configs = Vec::new();
    for (s, &speed) in SPEEDS.iter().enumerate() {
        for j in 0..SCENES_PER_SPEED {
            let k = s * SCENES_PER_SPEED + j;
            configs.extend(scene_config(&base, k, speed, true, SPACING).map(|c| (c, true)));
        }
    }
    for j in 0..FREE_SCENES {
        let k = SPEEDS.len() * SCENES_PER_SPEED + j;
        configs.extend(scene_config(&base, k, SPEEDS[j % SPEEDS.len()], false, SPACING).map(|c| (c, false)));
    }
    let scenes = configs
        .iter()
        .map(|(c, in_view)| run_scene(c, run_dir, *in_view, RadarBand::C, cnn.as_ref()))
        .collect::<Result<Vec<_>>>()?;
    let fine = (0..FINE_SCENES)
        .filter_map(|j| fine_scene_config(&base, j))
        .map(|c| run_scene(&c, run_dir, true, FINE_BAND, None))
        .collect::<Result<Vec<_>>>()?;
    let cnn_threshold = cnn.as_ref().map(ShipWindows::threshold);
    let trials: Vec<Trial> = scenes
        .iter()
        .enumerate()
        .filter(|(_, s)| s.ship_found)
        .flat_map(|(k, s)| {
            let trial = |label: u8, classic: bool, cnn: Option<f64>| Trial {
                scene: k,
                label,
                classic: if classic { 1.0 } else { 0.0 },
                cnn: cnn.unwrap_or(0.0),
            };
            [
                trial(1, s.wake_found, s.cnn_with),
                trial(0, s.wake_found_without, s.cnn_without),
            ]
        })
        .collect();
    let wake_detectors = match cnn_threshold {
        Some(t) if !trials.is_empty() => score_detectors(&trials, t),
        _ => Vec::new(),
    };
    let results = ShipsResults {
        key,
        seconds: start.elapsed().as_secs_f64(),
        scenes,
        cnn_threshold,
        cnn_footprint_m: cnn.as_ref().map(|c| c.footprint_m(SPACING)),
        wake_detectors,
        fine,
    };
    write_results(&results_file(run_dir), &results)?;
    Ok(step_time("ships", start, None))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A scene's look and flight directions: a ship heading east (90) seen by a radar looking
    /// along its course (look direction 0) looks east and flies north.
    #[test]
    fn the_scene_geometry_turns_the_look_into_the_image() {
        let mut c = WakelabConfig::default();
        c.scene.heading = 90.0;
        c.platform.look_direction = 0.0;
        let g = scene_geometry(&c);
        assert_eq!((g.look_deg, g.azimuth_deg), (90.0, 0.0));
        // looking to port (90 counter-clockwise from the course): north
        c.platform.look_direction = 90.0;
        assert_eq!(scene_geometry(&c).look_deg, 0.0);
    }

    /// A wake runs back along its ship's course: its axis 180 degrees from the heading is on
    /// the track, 15 degrees off is within 20, a reversed one (axis = heading) is on the line,
    /// and a line across the track (90 degrees, a swell's trough) is not, nor is one 25 off.
    #[test]
    fn a_wake_is_scored_only_along_its_track() {
        assert!(along_track(270.0, 90.0, 20.0));
        assert!(along_track(285.0, 90.0, 20.0));
        assert!(along_track(5.0, 350.0, 20.0));
        assert!(along_track(350.0, 170.0, 20.0));
        assert!(!along_track(0.0, 90.0, 20.0));
        assert!(!along_track(295.0, 90.0, 20.0));
        assert!(!along_track(285.0, 90.0, 10.0));
    }

    /// Every scene of the default study's base is a valid configuration.
    #[test]
    fn the_scenes_are_valid() {
        let study = Study::from_toml_str(wakelab_dataset::study::DEFAULT_STUDY, "default").unwrap();
        let base = study.base_config().unwrap();
        for k in 0..SPEEDS.len() * SCENES_PER_SPEED + FREE_SCENES {
            for in_view in [true, false] {
                let c = scene_config(&base, k, 9.0, in_view, SPACING).expect("a scene that fits");
                c.validate().unwrap();
                assert_eq!(c.scene.size, SIDE);
            }
        }
        for j in 0..FINE_SCENES {
            let c = fine_scene_config(&base, j).expect("a fine scene that fits");
            assert_eq!((c.scene.size, c.scene.pixel_spacing), (2 * SIDE, FINE_SPACING));
        }
    }
}

//! wakelab-dataset: stage 4 of the pipeline (spec chapter 4 opening, Fig. 4.3, Algorithm 2): a
//! parametric study rendered into a labelled dataset on disk.
//!
//! [`render_dataset`] renders every wake/no-wake pair of a [`Study`] (in parallel, resumable: a scene
//! is done when its `scene.json`, written last and atomically, holds the [`render_key`] of what
//! the study renders now; a scene of another key is rendered again) and [`write_manifest`]
//! gathers the finished scenes into `manifest.json`, `manifest.csv` and `splits.json`. The
//! expensive hydro run is done once per distinct (ship, environment, grid, time) and cached on
//! disk under `cache/`, keyed by a hash of exactly those inputs.

pub mod learning;
mod manifest;
pub mod render;
pub mod shard;
pub mod slurm;
pub mod study;
pub mod transfer;

pub use manifest::write_manifest;
use ndarray_npy::write_npy;
use rayon::prelude::*;
use render::render_pair;
use serde::Serialize;
pub use shard::{shard_indices, Shard};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;
use study::{ScenePair, Study};
use wakelab_core::io::geotiff::{quantile, write_quicklook};
use wakelab_core::io::write_atomically;
use wakelab_core::{WakelabConfig, WakelabError};
use wakelab_hydro::{HydroInputs, SurfaceMap};
pub use wakelab_schema::dataset::{KelvinRecord, SceneGeoreference, SceneRecord};
use wakelab_surface::kelvin::ThinShip;

/// Wall time per stage (s), summed over the scenes rendered in this run.
#[derive(Debug, Clone, Default, Serialize)]
pub struct StageTimes {
    pub hydro: f64,
    pub surface: f64,
    pub sensors: f64,
    pub writing: f64,
    pub scenes_rendered: usize,
    pub scenes_skipped: usize,
    /// Scenes found in the directory but rendered from another configuration (re-rendered).
    pub scenes_stale: usize,
}

impl StageTimes {
    /// One line for a terminal: scenes rendered in `wall` seconds, their rate and the time of
    /// each stage.
    pub fn describe(&self, wall: f64) -> String {
        format!(
            "rendered {} scenes ({} already done{}) in {wall:.1} s: {:.1} scenes/min; hydro {:.1} s, then per core: surface {:.1} s, sensors {:.1} s, writing {:.1} s",
            self.scenes_rendered,
            self.scenes_skipped,
            match self.scenes_stale {
                0 => String::new(),
                n => format!(", {n} re-rendered: made from another configuration"),
            },
            self.scenes_rendered as f64 / wall * 60.0,
            self.hydro,
            self.surface,
            self.sensors,
            self.writing
        )
    }
}

/// FNV-1a 64-bit hash of bytes, text or a file's (stable across runs and platforms, for cache keys).
pub fn fnv(bytes: impl AsRef<[u8]>) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes.as_ref() {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// The hydro stage's cache key: the hash of exactly what it reads ([`HydroInputs`]).
pub fn hydro_key(config: &WakelabConfig) -> String {
    format!("{:016x}", fnv(HydroInputs::of(config).key_text()))
}

/// The surface map of a hydro case, from the cache or simulated (and cached).
pub fn hydro_map(dir: &Path, config: &WakelabConfig) -> Result<SurfaceMap, WakelabError> {
    let case = dir.join("cache").join(format!("hydro-{}", hydro_key(config)));
    let file = case.join("surface_map.nc");
    if file.exists() {
        return wakelab_hydro::output::read_surface_map(&file);
    }
    std::fs::create_dir_all(&case).map_err(|e| WakelabError::io(&case, e))?;
    let map = wakelab_hydro::simulate_surface_map(config)?;
    wakelab_hydro::output::write_surface_map(&case, config, &map)?;
    // read back what was cached, so a first run and a resumed run use identical f32 values
    wakelab_hydro::output::read_surface_map(&file)
}

/// Progress reports of a study run.
pub enum Progress {
    Hydro { done: usize, total: usize },
    Scene { done: usize, total: usize },
}

/// Render the pairs of `study` selected by `shard` into `dir`, skipping finished scenes.
/// `stop_after` ends the run after that many newly rendered pairs (to test resuming).
pub fn render_dataset(
    study: &Study,
    dir: &Path,
    shard: Option<Shard>,
    stop_after: Option<usize>,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<StageTimes, WakelabError> {
    let pairs = study.pairs()?;
    let selected: Vec<usize> = match shard {
        Some(s) => shard_indices(pairs.len(), s),
        None => (0..pairs.len()).collect(),
    };
    std::fs::create_dir_all(dir).map_err(|e| WakelabError::io(dir, e))?;
    let mut stale = 0;
    let mut todo: Vec<&ScenePair> = Vec::new();
    for pair in selected.iter().map(|&i| &pairs[i]) {
        let key = render_key(study, pair);
        let (w, n) = pair.ids();
        let states = [scene_state(dir, &w, &key), scene_state(dir, &n, &key)];
        if states.iter().all(|s| *s == SceneState::Done) {
            continue;
        }
        // a scene of another configuration goes whole: no file of it may outlive the re-render
        for (id, state) in [(&w, states[0]), (&n, states[1])] {
            if state == SceneState::Stale {
                stale += 1;
                let sdir = scene_dir(dir, id);
                std::fs::remove_dir_all(&sdir).map_err(|e| WakelabError::io(&sdir, e))?;
            }
        }
        todo.push(pair);
    }
    let mut times = StageTimes {
        scenes_skipped: 2 * (selected.len() - todo.len()),
        scenes_stale: stale,
        ..Default::default()
    };
    let todo: Vec<&ScenePair> = match stop_after {
        Some(k) => todo.into_iter().take(k).collect(),
        None => todo,
    };
    // one hydro run per distinct key, in order
    let mut maps: BTreeMap<String, SurfaceMap> = BTreeMap::new();
    let keys: Vec<String> = {
        let mut k: Vec<String> = todo.iter().map(|p| hydro_key(&p.config)).collect();
        k.dedup();
        let mut seen = std::collections::BTreeSet::new();
        k.retain(|x| seen.insert(x.clone()));
        k
    };
    let t0 = Instant::now();
    for (i, key) in keys.iter().enumerate() {
        let pair = todo
            .iter()
            .find(|p| &hydro_key(&p.config) == key)
            .expect("key of a pair");
        maps.insert(key.clone(), hydro_map(dir, &pair.config)?);
        progress(Progress::Hydro {
            done: i + 1,
            total: keys.len(),
        });
    }
    times.hydro = t0.elapsed().as_secs_f64();
    let done = Mutex::new(0usize);
    let render_time = Mutex::new((0.0f64, 0.0f64, 0.0f64));
    todo.par_iter()
        .map(|pair| -> Result<(), WakelabError> {
            let map = &maps[&hydro_key(&pair.config)];
            let (rendered, surface, sensors) = render_pair(pair, map, &study.study.bands);
            let t = Instant::now();
            write_pair(dir, study, pair, &rendered)?;
            let written = t.elapsed().as_secs_f64();
            {
                let mut rt = render_time.lock().expect("lock");
                rt.0 += surface;
                rt.1 += sensors;
                rt.2 += written;
            }
            let mut d = done.lock().expect("lock");
            *d += 1;
            progress(Progress::Scene {
                done: *d,
                total: todo.len(),
            });
            Ok(())
        })
        .collect::<Result<Vec<()>, _>>()?;
    let (surface, sensors, writing) = *render_time.lock().expect("lock");
    times.surface = surface;
    times.sensors = sensors;
    times.writing = writing;
    times.scenes_rendered = 2 * todo.len();
    Ok(times)
}

fn scene_dir(dir: &Path, id: &str) -> PathBuf {
    dir.join("scenes").join(id)
}

/// Hash of everything a pair's scenes are rendered from: their configuration, the study's bands
/// and its label policy (`min_visibility`).
pub fn render_key(study: &Study, pair: &ScenePair) -> String {
    let what = serde_json::json!({
        "config": pair.config,
        "combination": pair.combination,
        "bands": study.study.bands,
        "min_visibility": study.study.min_visibility,
    });
    format!("{:016x}", fnv(what.to_string()))
}

/// Whether a scene in the dataset directory is finished and rendered from `key`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum SceneState {
    Missing,
    Done,
    /// Finished, but from another configuration (or by a wakelab that wrote no key).
    Stale,
}

fn scene_state(dir: &Path, id: &str, key: &str) -> SceneState {
    let Ok(text) = std::fs::read_to_string(scene_dir(dir, id).join("scene.json")) else {
        return SceneState::Missing;
    };
    let written: Option<serde_json::Value> = serde_json::from_str(&text).ok();
    match written
        .as_ref()
        .and_then(|v| v.get("render_key"))
        .and_then(|k| k.as_str())
    {
        Some(k) if k == key => SceneState::Done,
        _ => SceneState::Stale,
    }
}

/// Write both scenes of a pair: images, quicklooks and masks first, `scene.json` last.
fn write_pair(
    dir: &Path,
    study: &Study,
    pair: &ScenePair,
    rendered: &render::RenderedPair,
) -> Result<(), WakelabError> {
    let bands = &rendered.bands;
    let (wake_id, no_wake_id) = pair.ids();
    let key = render_key(study, pair);
    for (id, is_wake) in [(&wake_id, true), (&no_wake_id, false)] {
        let sdir = scene_dir(dir, id);
        std::fs::create_dir_all(&sdir).map_err(|e| WakelabError::io(&sdir, e))?;
        let rel = |p: &Path| p.strip_prefix(dir).expect("inside the dataset").display().to_string();
        let kelvin = match (&rendered.kelvin_mask, is_wake) {
            (Some(mask), true) => {
                let path = sdir.join("mask_kelvin.npy");
                write_npy_atomically(&path, mask)?;
                Some(kelvin_record(&pair.config, bands, rel(&path)))
            }
            _ => None,
        };
        let mut images = BTreeMap::new();
        let mut masks = BTreeMap::new();
        let mut visibility = BTreeMap::new();
        let mut label_by_band = BTreeMap::new();
        for b in bands {
            let image = if is_wake { &b.wake } else { &b.no_wake };
            let npy = sdir.join(format!("{}.npy", b.band));
            write_npy_atomically(&npy, image)?;
            let mask = if is_wake { b.mask.clone() } else { b.mask.mapv(|_| 0u8) };
            let mask_path = sdir.join(format!("mask_{}.npy", b.band));
            write_npy_atomically(&mask_path, &mask)?;
            let (rows, cols) = image.dim();
            let display: Vec<f32> = if b.band.is_radar() {
                image
                    .iter()
                    .map(|&v| (10.0 * (v.max(1e-30) as f64).log10()) as f32)
                    .collect()
            } else {
                image.iter().copied().collect()
            };
            // both scenes of a pair share the wake scene's stretch, so they compare by eye
            let wake_display: Vec<f32> = if b.band.is_radar() {
                b.wake
                    .iter()
                    .map(|&v| (10.0 * (v.max(1e-30) as f64).log10()) as f32)
                    .collect()
            } else {
                b.wake.iter().copied().collect()
            };
            let (lo, hi) = (quantile(&wake_display, 0.02), quantile(&wake_display, 0.98));
            write_quicklook(&sdir.join(format!("{}.png", b.band)), &display, rows, cols, lo, hi)?;
            images.insert(b.band, rel(&npy));
            masks.insert(b.band, rel(&mask_path));
            let v = if is_wake { b.visibility.0 } else { b.visibility.1 };
            visibility.insert(b.band, v);
            label_by_band.insert(b.band, u8::from(is_wake && v >= study.study.min_visibility));
        }
        let record = SceneRecord {
            id: id.clone(),
            pair: pair.index,
            label: u8::from(is_wake),
            label_by_band,
            visibility,
            seed: pair.seed,
            environment: pair.environment_key(),
            parameters: pair.combination.clone(),
            images,
            masks,
            geometry: is_wake.then(|| wakelab_surface::scene::SceneGrid::new(&pair.config.scene).wake_geometry()),
            split: None,
            kelvin,
            georeference: Some(SceneGeoreference::new(
                pair.config.scene.size,
                pair.config.scene.pixel_spacing,
                pair.config.scene.centre,
            )),
            render_key: key.clone(),
        };
        write_atomically(
            sdir.join("scene.json"),
            serde_json::to_string_pretty(&record).expect("serialisable").as_bytes(),
        )?;
    }
    Ok(())
}

/// The Kelvin wake's record of a wake scene: its hull and the ship's cross section per radar
/// band rendered.
fn kelvin_record(config: &WakelabConfig, bands: &[render::BandPair], mask: String) -> KelvinRecord {
    let ship = ThinShip::new(&config.ship, config.kelvin.hull, config.environment.gravity);
    let ship_rcs_m2 = bands
        .iter()
        .filter_map(|b| {
            render::radar_band(b.band)
                .map(|r| (b.band, wakelab_sensors::sar_image::ship_cross_section(config, &ship, r)))
        })
        .collect();
    KelvinRecord {
        hull: config.kelvin.hull,
        ship_rcs_m2,
        mask,
    }
}

/// Write `a` as an npy file at `path` through a temporary file (no half-written file on failure).
pub fn write_npy_atomically<A: ndarray_npy::WritableElement>(
    path: &Path,
    a: &ndarray::Array2<A>,
) -> Result<(), WakelabError> {
    let file = wakelab_core::io::AtomicFile::new(path)?;
    write_npy(file.temporary_path(), a).map_err(|e| WakelabError::Image {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    file.commit()?;
    Ok(())
}

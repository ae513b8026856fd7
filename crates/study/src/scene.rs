//! `wakelab scene` and `wakelab wake`: the wake of one configuration with a progress bar, then
//! the sea surface of the configured scene and its five images (SAR in S, C and X band, IR in
//! MWIR and LWIR), written with their pictures.

use crate::Result;
use std::path::{Path, PathBuf};
use std::time::Instant;
use wakelab_core::config::WakelabConfig;
use wakelab_core::io::write_atomically;
use wakelab_core::units::RadarBand;
use wakelab_products::band::BAND_ITEM;
use wakelab_products::cog::{rewrite_as_cog, BandInfo, INCIDENCE, SPACING_COLUMNS, SPACING_ROWS};
use wakelab_products::Frame;

/// The files of a rendered scene and the wall time of its two stages.
pub struct RenderedScene {
    pub files: Vec<PathBuf>,
    pub surface_seconds: f64,
    pub sensor_seconds: f64,
}

impl RenderedScene {
    /// What was rendered and how long it took, a line a stage.
    pub fn describe(&self, cfg: &WakelabConfig) -> String {
        let (n, dx) = (cfg.scene.size, cfg.scene.pixel_spacing);
        format!(
            "sea surface: {n} x {n} scene at {dx:.1} m, {:.1} s\nSAR (S, C, X) and IR (MWIR, LWIR) images: {:.1} s",
            self.surface_seconds, self.sensor_seconds
        )
    }
}

/// Where the scene's images lie: in the local UTM zone, north up, when `scene.centre` places the
/// scene on the Earth; else on a local grid in metres, said so in the CRS's name.
fn scene_frame(cfg: &WakelabConfig, grid: &wakelab_surface::scene::SceneGrid) -> Result<Frame> {
    let (n, d) = (grid.size(), grid.pixel_spacing);
    Ok(match cfg.scene.centre {
        Some(c) => Frame::utm((c.latitude, c.longitude), c.utm_epsg(), d, (n, n))
            .map_err(|e| anyhow::anyhow!("placing the scene in UTM zone EPSG:{}: {e}", c.utm_epsg()))?,
        None => Frame::local((grid.x[0] - 0.5 * d, grid.y[0] + 0.5 * d), d, (n, n)),
    })
}

/// The GeoTIFFs among `files` rewritten as Cloud-Optimised GeoTIFFs on `frame`: tiled,
/// compressed, with overviews, nodata, the band's description and unit (from the image's
/// sidecar) and where the grid lies.
fn as_cogs(files: &[PathBuf], frame: &Frame, cfg: &WakelabConfig, band: &str) -> Result<()> {
    for tif in files.iter().filter(|f| f.extension().is_some_and(|e| e == "tif")) {
        let sidecar: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(tif.with_extension("json"))?)?;
        let text = |key: &str| sidecar[key].as_str().unwrap_or_default().to_string();
        let grid = match cfg.scene.centre {
            Some(c) => format!(
                "WGS 84 / UTM (EPSG:{}), north up, centre at {} N, {} E",
                c.utm_epsg(),
                c.latitude,
                c.longitude
            ),
            None => "local: metres on the scene's grid, not placed on the Earth (set scene.centre)".into(),
        };
        // "1 (linear)" in the sidecar is the unit "1" of linear sigma0 that readers know
        let unit = text("units");
        let unit = unit.strip_suffix(" (linear)").unwrap_or(&unit);
        let info = BandInfo {
            description: &format!("{} ({band})", text("quantity")),
            unit,
            metadata: vec![
                (BAND_ITEM.to_string(), band.to_ascii_uppercase()),
                ("WAKELAB_SCENE_ID".to_string(), cfg.scene_id()),
                ("WAKELAB_GRID".to_string(), grid),
                // a local grid's spacing is not ground a reader can measure from a CRS
                (SPACING_ROWS.to_string(), cfg.scene.pixel_spacing.to_string()),
                (SPACING_COLUMNS.to_string(), cfg.scene.pixel_spacing.to_string()),
                (INCIDENCE.to_string(), cfg.platform.incidence.to_string()),
            ],
        };
        rewrite_as_cog(tif, frame, &info)?;
    }
    Ok(())
}

/// The surface stage on the wake's surface map, then every band's image, written into `dir`.
pub fn render_scene(cfg: &WakelabConfig, map: &wakelab_hydro::SurfaceMap, dir: &Path) -> Result<RenderedScene> {
    let start = Instant::now();
    let scene = wakelab_surface::simulate_surface(cfg, Some(map));
    let mut files = wakelab_surface::output::write_surface_scene(dir, cfg, &scene)?;
    let surface_seconds = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let frame = scene_frame(cfg, &scene.grid)?;
    let radar = wakelab_sensors::SarScene::new(cfg, &scene);
    for band in RadarBand::ALL {
        let image = radar.render(band);
        let written = wakelab_sensors::output::write_sar(dir, cfg, &scene.grid, &image)?;
        as_cogs(&written, &frame, cfg, band.name())?;
        files.extend(written);
    }
    let infrared = wakelab_sensors::IrScene::new(cfg, &scene);
    for band in wakelab_sensors::IrBand::ALL {
        let image = infrared.render(band);
        let written = wakelab_sensors::output::write_ir(dir, cfg, &scene.grid, &image)?;
        as_cogs(&written, &frame, cfg, image.info.band)?;
        files.extend(written);
    }
    Ok(RenderedScene {
        files,
        surface_seconds,
        sensor_seconds: start.elapsed().as_secs_f64(),
    })
}

/// `wakelab scene` (`images`) and `wakelab wake`: the wake of `cfg` in `dir`, then (for a scene)
/// its sea surface and every band's image; each finished part described to `say`.
pub fn scene_command(
    cfg: &WakelabConfig,
    dir: &Path,
    quiet: bool,
    images: bool,
    say: &mut dyn FnMut(String),
) -> Result<()> {
    let start = Instant::now();
    let wake = simulate_wake(cfg, dir, quiet)?;
    say(wake.describe(cfg, start.elapsed().as_secs_f64()));
    wake.files.iter().for_each(|f| say(format!("wrote {}", f.display())));
    if images {
        let rendered = render_scene(cfg, &wake.map, dir)?;
        say(rendered.describe(cfg));
        rendered
            .files
            .iter()
            .for_each(|f| say(format!("wrote {}", f.display())));
        let seconds = start.elapsed().as_secs_f64();
        say(format!(
            "study finished in {seconds:.1} s; results in {}",
            dir.display()
        ));
    }
    Ok(())
}

/// The wake of a configuration, its files and the solver's steps.
pub struct SimulatedWake {
    pub map: wakelab_hydro::SurfaceMap,
    pub files: Vec<PathBuf>,
    pub steps: usize,
}

impl SimulatedWake {
    /// How much wake was simulated, in how many steps and `seconds` of wall time.
    pub fn describe(&self, cfg: &WakelabConfig, seconds: f64) -> String {
        let duration = cfg.time.duration;
        let km = cfg.ship.speed * duration / 1000.0;
        format!(
            "wake simulated: {duration:.0} s of wake ({km:.1} km) in {} steps, {seconds:.1} s wall",
            self.steps
        )
    }
}

/// The hydro stage (spec 2.1) in `dir` with the configuration beside its files, showing the
/// simulated time and the solver's rate on a progress bar unless `quiet`.
pub fn simulate_wake(cfg: &WakelabConfig, dir: &Path, quiet: bool) -> Result<SimulatedWake> {
    std::fs::create_dir_all(dir).map_err(|e| anyhow::anyhow!("creating {}: {e}", dir.display()))?;
    write_atomically(dir.join("config.toml"), cfg.to_toml_string().as_bytes())?;
    let template = "{spinner} wake [{bar:40}] {pos}/{len} s simulated | {msg} | {elapsed_precise} elapsed, {eta} left";
    let bar = crate::progress_bar(quiet, cfg.time.duration.ceil() as u64, template);
    let mut last_steps = (0usize, Instant::now());
    let mut rate = 0.0;
    let (run, outputs) = wakelab_hydro::output::run_hydro_stage(cfg, dir, &mut |t, steps| {
        let now = Instant::now();
        let dt = now.duration_since(last_steps.1).as_secs_f64();
        if dt > 0.5 {
            rate = (steps - last_steps.0) as f64 / dt;
            last_steps = (steps, now);
        }
        bar.set_position(t.floor() as u64);
        bar.set_message(format!("step {steps}, {rate:.1} steps/s"));
        Ok(())
    })?;
    bar.finish_and_clear();
    Ok(SimulatedWake {
        map: run.surface_map(cfg, cfg.output.map_dx),
        files: outputs.files,
        steps: outputs.steps,
    })
}

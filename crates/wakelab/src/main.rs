//! The `wakelab` command: parses arguments, calls the pipeline's stages and writes their output.

use anyhow::{Context, Result};
use clap::{Args, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
use std::time::Instant;
use wakelab_core::config::{Polarisation, Preset, WakelabConfig};
use wakelab_core::io::write_atomically;
use wakelab_core::units::RadarBand;

/// wakelab: simulate a ship's persistent wake from first principles, render what SAR and
/// infrared sensors would see, and train and fuse the detectors that find it.
///
/// Start with `wakelab run`: it runs the whole study on the embedded default configuration
/// (today: the hydrodynamic wake simulation and its pictures) and writes everything into
/// runs/default/. `wakelab config show` prints every setting; copy it to a file, change what you
/// need and pass it back with --config.
#[derive(Parser, Debug)]
#[command(name = "wakelab", version, about, long_about, propagate_version = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Args, Debug, Clone)]
struct ConfigArgs {
    /// TOML configuration file; values it leaves out keep their embedded defaults.
    #[arg(long, short, value_name = "FILE")]
    config: Option<PathBuf>,
    /// Grid and time preset: `quick` (coarse, seconds) or `paper` (the spec's grid, minutes).
    /// Overrides the file's `preset`.
    #[arg(long, value_name = "NAME")]
    preset: Option<Preset>,
}

impl ConfigArgs {
    fn load(&self) -> Result<WakelabConfig> {
        let (text, origin) = match &self.config {
            Some(path) => (
                std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?,
                path.display().to_string(),
            ),
            None => (String::new(), "<embedded default>".to_string()),
        };
        Ok(WakelabConfig::from_toml_str_with_preset(&text, &origin, self.preset)?)
    }

    /// The configuration with the command line's --wind and --incidence applied, validated.
    fn load_with(&self, wind: Option<f64>, incidence: Option<f64>) -> Result<WakelabConfig> {
        let mut cfg = self.load()?;
        if let Some(w) = wind {
            cfg.environment.wind.speed = w;
        }
        if let Some(i) = incidence {
            cfg.platform.incidence = i;
        }
        cfg.validate()?;
        Ok(cfg)
    }
}

/// Options of the commands that run stages.
#[derive(Args, Debug, Clone)]
struct RunArgs {
    #[command(flatten)]
    config: ConfigArgs,
    /// Run directory (default: the configuration's output.dir).
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run the whole study (today: the wake simulation and the sea surface of its scene).
    Run(RunArgs),
    /// Simulate the ship's wake only (stage 1, spec 2.1) and write its files.
    Wake(RunArgs),
    /// The initial data plane of the ship (spec Eqs. 2.26-2.62): its derived scalars.
    Idp {
        #[command(flatten)]
        config: ConfigArgs,
        /// Print the scalars as JSON.
        #[arg(long)]
        json: bool,
        /// Also write the IDP fields on the grid (idp.nc and pictures) into DIR.
        #[arg(long, value_name = "DIR")]
        write: Option<PathBuf>,
    },
    /// The background sea of a wind (and the configured swell): Hs, peak frequency, mean-square
    /// slopes and the spectral density at the S, C and X Bragg wavenumbers.
    Spectrum {
        #[command(flatten)]
        config: ConfigArgs,
        /// Wind speed at 10 m (m/s); default: environment.wind.speed.
        #[arg(long, value_name = "M/S")]
        wind: Option<f64>,
        /// Radar incidence angle (degrees); default: platform.incidence.
        #[arg(long, value_name = "DEG")]
        incidence: Option<f64>,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Infrared optics of sea water: n, kappa, Fresnel reflectances and emissivity at a
    /// wavelength, and the IR radiance of a flat sea in both bands for the configured geometry.
    Optics {
        #[command(flatten)]
        config: ConfigArgs,
        /// Wavelength (micrometres).
        #[arg(long, value_name = "UM", default_value_t = 11.0)]
        wavelength: f64,
        /// Practical salinity (PSU); default: the surface salinity.
        #[arg(long)]
        salinity: Option<f64>,
        /// Temperature (deg C); default: the surface temperature.
        #[arg(long)]
        temperature: Option<f64>,
        /// Incidence angle (degrees); default: platform.incidence.
        #[arg(long, value_name = "DEG")]
        incidence: Option<f64>,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Render a parametric study into a labelled dataset (stage 4): wake and no-wake scenes in
    /// every band, wake masks, visibility, manifest (CSV, JSON) and train/test splits.
    Dataset {
        /// Study file (TOML), or `default` / `paper` for the embedded studies.
        #[arg(long, value_name = "FILE", default_value = "default")]
        study: String,
        /// Dataset directory.
        #[arg(long, value_name = "DIR")]
        out: PathBuf,
        /// Render only pairs with index % N == K, given as K/N (one Slurm array task).
        #[arg(long, value_name = "K/N")]
        shard: Option<String>,
        /// Only gather finished scenes into the manifest and splits.
        #[arg(long)]
        merge: bool,
        /// Write a Slurm job-array script into DIR instead of rendering.
        #[arg(long)]
        emit_slurm: bool,
        /// Array tasks of the Slurm script.
        #[arg(long, default_value_t = 16)]
        tasks: usize,
        /// No progress bar.
        #[arg(long)]
        quiet: bool,
    },
    /// SAR tools.
    Sar {
        #[command(subcommand)]
        action: SarAction,
    },
    /// Inspect the configuration.
    Config {
        #[command(subcommand)]
        action: ConfigAction,
    },
}

#[derive(Subcommand, Debug)]
enum SarAction {
    /// sigma0 of the undisturbed sea for a wind, band, polarisation and incidence (spec Eqs.
    /// 3.1-3.2), to compare against the geophysical model functions you know.
    Sigma0 {
        #[command(flatten)]
        config: ConfigArgs,
        /// Wind speed at 10 m (m/s); default: environment.wind.speed.
        #[arg(long, value_name = "M/S")]
        wind: Option<f64>,
        /// Band: S, C or X.
        #[arg(long, default_value = "C")]
        band: String,
        /// Polarisation: vv or hh; default: sar.polarisation.
        #[arg(long)]
        polarisation: Option<String>,
        /// Incidence angle (degrees); default: platform.incidence.
        #[arg(long, value_name = "DEG")]
        incidence: Option<f64>,
        /// Look direction relative to the wind direction (degrees; 0: looking down-wind).
        #[arg(long, value_name = "DEG", default_value_t = 90.0)]
        look: f64,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
}

#[derive(Subcommand, Debug)]
enum ConfigAction {
    /// Print the effective configuration as TOML (a valid --config file).
    Show {
        #[command(flatten)]
        config: ConfigArgs,
    },
}

fn main() {
    let cli = Cli::parse();
    if let Err(e) = dispatch(cli) {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}

fn dispatch(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Run(args) => {
            let cfg = args.config.load()?;
            let dir = args.out.unwrap_or_else(|| PathBuf::from(&cfg.output.dir));
            let start = Instant::now();
            let map = run_wake(&cfg, &dir, args.quiet)?;
            let t_surface = Instant::now();
            let scene = wakelab_surface::simulate_surface(&cfg, Some(&map));
            let mut files = wakelab_surface::output::write_surface_scene(&dir, &cfg, &scene)?;
            eprintln!(
                "sea surface: {n} x {n} scene at {:.1} m, {:.1} s",
                cfg.scene.pixel_spacing,
                t_surface.elapsed().as_secs_f64(),
                n = cfg.scene.size
            );
            let t_sensors = Instant::now();
            for band in RadarBand::ALL {
                let image = wakelab_sensors::render_sar(&cfg, &scene, band);
                files.extend(wakelab_sensors::output::write_sar(&dir, &cfg, &scene.grid, &image)?);
            }
            for band in wakelab_sensors::IrBand::ALL {
                let image = wakelab_sensors::render_ir(&cfg, &scene, band);
                files.extend(wakelab_sensors::output::write_ir(&dir, &cfg, &scene.grid, &image)?);
            }
            eprintln!(
                "SAR (S, C, X) and IR (MWIR, LWIR) images: {:.1} s",
                t_sensors.elapsed().as_secs_f64()
            );
            for f in files {
                eprintln!("wrote {}", f.display());
            }
            eprintln!(
                "study finished in {:.1} s; results in {}",
                start.elapsed().as_secs_f64(),
                dir.display()
            );
            Ok(())
        }
        Command::Wake(args) => {
            let cfg = args.config.load()?;
            let dir = args.out.unwrap_or_else(|| PathBuf::from(&cfg.output.dir));
            run_wake(&cfg, &dir, args.quiet).map(|_| ())
        }
        Command::Spectrum {
            config,
            wind,
            incidence,
            json,
        } => {
            let cfg = config.load_with(wind, incidence)?;
            let report = spectrum_report(&cfg);
            if json {
                println!("{}", serde_json::to_string_pretty(&report)?);
            } else {
                print_json_table(&serde_json::to_value(&report)?);
            }
            Ok(())
        }
        Command::Idp { config, json, write } => {
            let cfg = config.load()?;
            let idp = wakelab_hydro::initial_data_plane(&cfg);
            if json {
                println!("{}", serde_json::to_string_pretty(&idp.scalars)?);
            } else {
                print_idp(&idp.scalars);
            }
            if let Some(dir) = write {
                for f in wakelab_hydro::output::write_idp_fields(&dir, &cfg)? {
                    eprintln!("wrote {}", f.display());
                }
            }
            Ok(())
        }
        Command::Dataset {
            study,
            out,
            shard,
            merge,
            emit_slurm,
            tasks,
            quiet,
        } => run_dataset(&study, &out, shard.as_deref(), merge, emit_slurm, tasks, quiet),
        Command::Optics {
            config,
            wavelength,
            salinity,
            temperature,
            incidence,
            json,
        } => {
            let mut cfg = config.load()?;
            if let Some(i) = incidence {
                if !(0.0..90.0).contains(&i) {
                    anyhow::bail!("--incidence {i}: must be in [0, 90) degrees");
                }
                // the optics hold at any angle; the flat-sea radiance uses it as the view angle
                cfg.platform.incidence = i;
            }
            if !(0.2..=200.0).contains(&wavelength) {
                anyhow::bail!("--wavelength {wavelength}: must be in [0.2, 200] micrometres");
            }
            let env = &cfg.environment;
            let s = salinity.unwrap_or(env.salinity.at_depth(0.0));
            let t = temperature.unwrap_or(env.temperature.at_depth(0.0));
            if !(0.0..=42.0).contains(&s) || !(-2.0..=40.0).contains(&t) {
                anyhow::bail!("--salinity must be in [0, 42] PSU and --temperature in [-2, 40] deg C");
            }
            let index = wakelab_sensors::optics::seawater_index(wavelength, s, t);
            let theta = cfg.platform.incidence.to_radians();
            let (rho_s, rho_p) =
                wakelab_sensors::optics::fresnel_reflectance(wakelab_sensors::optics::N_AIR, index, theta);
            let flat: Vec<serde_json::Value> = wakelab_sensors::IrBand::ALL
                .iter()
                .map(|&band| {
                    let view = wakelab_sensors::ir::IrView::new(&cfg, band);
                    let terms = view.facet(0.0, 0.0, env.temperature.at_depth(0.0) + 273.15);
                    let (lo, hi) = band.range();
                    serde_json::json!({
                        "band": band.name(),
                        "wavelength_range_um": [lo, hi],
                        "radiance": terms.total(),
                        "brightness_temperature_k": wakelab_sensors::planck::brightness_temperature(lo, hi, terms.total()),
                        "terms": terms,
                    })
                })
                .collect();
            let report = serde_json::json!({
                "wavelength_um": wavelength,
                "salinity": s,
                "temperature_c": t,
                "incidence_deg": cfg.platform.incidence,
                "n": index.re,
                "kappa": -index.im,
                "rho_s": rho_s,
                "rho_p": rho_p,
                "rho": 0.5 * (rho_s + rho_p),
                "emissivity": 1.0 - 0.5 * (rho_s + rho_p),
                "flat_sea_radiance": flat,
            });
            if json {
                println!("{}", serde_json::to_string_pretty(&report)?);
            } else {
                print_json_table(&report);
            }
            Ok(())
        }
        Command::Sar {
            action:
                SarAction::Sigma0 {
                    config,
                    wind,
                    band,
                    polarisation,
                    incidence,
                    look,
                    json,
                },
        } => {
            let mut cfg = config.load_with(wind, incidence)?;
            if let Some(p) = polarisation {
                cfg.sar.polarisation = match p.to_lowercase().as_str() {
                    "vv" => Polarisation::Vv,
                    "hh" => Polarisation::Hh,
                    other => anyhow::bail!("--polarisation {other}: must be vv or hh"),
                };
            }
            cfg.validate()?;
            let band = match band.to_uppercase().as_str() {
                "S" => RadarBand::S,
                "C" => RadarBand::C,
                "X" => RadarBand::X,
                other => anyhow::bail!("--band {other}: must be S, C or X"),
            };
            let sea = wakelab_surface::background_spectrum(&cfg);
            let env = &cfg.environment;
            let eps = wakelab_sensors::permittivity::seawater_permittivity(
                band.frequency(),
                env.temperature.at_depth(0.0),
                env.salinity.at_depth(0.0),
            );
            let report = wakelab_sensors::sar::sigma0_of_sea(
                &sea,
                band,
                eps,
                cfg.sar.polarisation,
                (env.wind.direction - look).to_radians(),
                cfg.platform.incidence,
                cfg.scene.pixel_spacing,
            );
            if json {
                println!("{}", serde_json::to_string_pretty(&report)?);
            } else {
                print_json_table(&serde_json::to_value(&report)?);
            }
            Ok(())
        }
        Command::Config {
            action: ConfigAction::Show { config },
        } => {
            print!("{}", config.load()?.to_toml_string());
            Ok(())
        }
    }
}

fn print_idp(s: &wakelab_hydro::IdpScalars) {
    print_json_table(&serde_json::to_value(s).expect("serialisable"));
}

/// Print a JSON object as aligned `key = value` lines.
fn print_json_table(value: &serde_json::Value) {
    if let serde_json::Value::Object(map) = value {
        for (k, v) in map {
            match v {
                serde_json::Value::Array(items) => {
                    for item in items {
                        println!("{k}:");
                        print_json_table(item);
                    }
                }
                _ => println!("{k:>26} = {}", v.as_f64().map_or(v.to_string(), |x| format!("{x:.6e}"))),
            }
        }
    }
}

/// What `wakelab spectrum` reports.
#[derive(serde::Serialize)]
struct SpectrumReport {
    model: wakelab_core::config::SpectrumModel,
    wind_speed: f64,
    wind_direction_deg: f64,
    swell_amplitude: f64,
    swell_wavelength: f64,
    #[serde(flatten)]
    summary: wakelab_surface::spectrum::SpectrumSummary,
    incidence_deg: f64,
    look_direction_deg: f64,
    bragg: Vec<BraggReport>,
}

#[derive(serde::Serialize)]
struct BraggReport {
    band: &'static str,
    frequency_hz: f64,
    bragg_wavenumber: f64,
    bragg_wavelength_m: f64,
    /// F(k_B) towards the sensor (m^4).
    density_towards: f64,
    /// F(-k_B) away from the sensor (m^4).
    density_away: f64,
    /// Omnidirectional Psi(k_B) (m^3).
    omnidirectional: f64,
}

fn spectrum_report(cfg: &WakelabConfig) -> SpectrumReport {
    let sea = wakelab_surface::background_spectrum(cfg);
    let bragg = wakelab_core::units::RadarBand::ALL
        .iter()
        .map(|&band| {
            let (t, a) = wakelab_surface::bragg_vectors(cfg, band);
            let k = t.magnitude();
            BraggReport {
                band: band.name(),
                frequency_hz: band.frequency(),
                bragg_wavenumber: k,
                bragg_wavelength_m: 2.0 * std::f64::consts::PI / k,
                density_towards: sea.directional(t.kx, t.ky),
                density_away: sea.directional(a.kx, a.ky),
                omnidirectional: sea.wind_omni(k),
            }
        })
        .collect();
    let env = &cfg.environment;
    SpectrumReport {
        model: cfg.sea.spectrum,
        wind_speed: env.wind.speed,
        wind_direction_deg: env.wind.direction,
        swell_amplitude: if env.swell.angle().is_some() {
            env.swell.amplitude
        } else {
            0.0
        },
        swell_wavelength: env.swell.wavelength,
        // slopes of all waves longer than 6 mm (k < 1000 rad/m, the gravity-capillary range)
        summary: sea.summary(1000.0),
        incidence_deg: cfg.platform.incidence,
        look_direction_deg: cfg.platform.look_direction,
        bragg,
    }
}

fn run_wake(cfg: &WakelabConfig, dir: &Path, quiet: bool) -> Result<wakelab_hydro::SurfaceMap> {
    let start = Instant::now();
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    write_atomically(dir.join("config.toml"), cfg.to_toml_string().as_bytes())?;
    let duration = cfg.time.duration;
    let bar = if quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(duration.ceil() as u64)
    };
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} wake [{bar:40}] {pos}/{len} s simulated | {msg} | {elapsed_precise} elapsed, {eta} left",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
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
    eprintln!(
        "wake simulated: {:.0} s of wake ({:.1} km) in {} steps, {:.1} s wall",
        duration,
        cfg.ship.speed * duration / 1000.0,
        outputs.steps,
        start.elapsed().as_secs_f64()
    );
    for f in &outputs.files {
        eprintln!("wrote {}", f.display());
    }
    Ok(run.surface_map(cfg, cfg.output.map_dx))
}

fn load_study(name: &str) -> Result<wakelab_data::study::Study> {
    use wakelab_data::study::{Study, DEFAULT_STUDY, PAPER_STUDY};
    let path = Path::new(name);
    Ok(match name {
        _ if path.exists() => Study::from_file(path)?,
        "default" => Study::from_toml_str(DEFAULT_STUDY, "<embedded default study>")?,
        "paper" => Study::from_toml_str(PAPER_STUDY, "<embedded paper study>")?,
        _ => anyhow::bail!("--study {name}: no such file (or use `default` or `paper`)"),
    })
}

fn run_dataset(
    study_name: &str,
    out: &Path,
    shard: Option<&str>,
    merge: bool,
    emit_slurm: bool,
    tasks: usize,
    quiet: bool,
) -> Result<()> {
    let study = load_study(study_name)?;
    let pairs = study.pairs()?.len();
    if emit_slurm {
        if tasks == 0 || tasks > 100_000 {
            anyhow::bail!("--tasks {tasks}: must be in [1, 100000]");
        }
        let exe = std::env::current_exe()?.display().to_string();
        let script = wakelab_data::slurm::slurm_script(Path::new(study_name), out, tasks.min(pairs), 2, &exe);
        std::fs::create_dir_all(out)?;
        let path = out.join("wakelab_dataset.slurm");
        write_atomically(&path, script.as_bytes())?;
        eprintln!(
            "wrote {} ({} pairs over {} tasks)",
            path.display(),
            pairs,
            tasks.min(pairs)
        );
        return Ok(());
    }
    let shard = match shard {
        None => None,
        Some(text) => {
            let parsed = text
                .split_once('/')
                .and_then(|(k, n)| Some((k.parse::<usize>().ok()?, n.parse::<usize>().ok()?)))
                .filter(|&(k, n)| n > 0 && k < n);
            let Some((k, n)) = parsed else {
                anyhow::bail!("--shard {text}: must be K/N with 0 <= K < N");
            };
            Some(wakelab_data::Shard { shard: k, count: n })
        }
    };
    let start = Instant::now();
    if !merge {
        let bar = if quiet {
            ProgressBar::hidden()
        } else {
            ProgressBar::new(pairs as u64)
        };
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner} {msg} [{bar:40}] {pos}/{len} | {per_sec} | {elapsed_precise}, {eta} left",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        bar.set_message("hydro");
        let times = wakelab_data::run_study(&study, out, shard, None, &|p| match p {
            wakelab_data::Progress::Hydro { done, total } => {
                bar.set_message(format!("hydro {done}/{total}"));
            }
            wakelab_data::Progress::Scene { done, total } => {
                bar.set_message("scene pairs");
                bar.set_length(total as u64);
                bar.set_position(done as u64);
            }
        })?;
        bar.finish_and_clear();
        let wall = start.elapsed().as_secs_f64();
        eprintln!(
            "rendered {} scenes ({} already done) in {wall:.1} s: {:.1} scenes/min; hydro {:.1} s, then per core: surface {:.1} s, sensors {:.1} s, writing {:.1} s",
            times.scenes_rendered,
            times.scenes_skipped,
            times.scenes_rendered as f64 / wall * 60.0,
            times.hydro,
            times.surface,
            times.sensors,
            times.writing
        );
        write_atomically(
            out.join("timing.json"),
            serde_json::to_string_pretty(&times)?.as_bytes(),
        )?;
    }
    if shard.is_none() || merge {
        let records = wakelab_data::write_manifest(&study, out)?;
        eprintln!(
            "manifest: {} scenes ({} expected) in {}",
            records.len(),
            2 * pairs,
            out.display()
        );
    }
    Ok(())
}

//! The `wakelab` command: parses arguments, calls the pipeline's stages and writes their output.

use anyhow::{Context, Result};
use clap::{Args, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
use std::time::Instant;
use wakelab_core::config::{Preset, WakelabConfig};
use wakelab_core::io::write_atomically;

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
    /// Run the whole study (today: the wake simulation, its NetCDF files and pictures).
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
    /// Inspect the configuration.
    Config {
        #[command(subcommand)]
        action: ConfigAction,
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
        Command::Run(args) | Command::Wake(args) => {
            let cfg = args.config.load()?;
            let dir = args.out.unwrap_or_else(|| PathBuf::from(&cfg.output.dir));
            run_wake(&cfg, &dir, args.quiet)
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
        Command::Config {
            action: ConfigAction::Show { config },
        } => {
            print!("{}", config.load()?.to_toml_string());
            Ok(())
        }
    }
}

fn print_idp(s: &wakelab_hydro::IdpScalars) {
    let value = serde_json::to_value(s).expect("serialisable");
    if let serde_json::Value::Object(map) = value {
        for (k, v) in map {
            println!("{k:>10} = {}", v.as_f64().map_or(v.to_string(), |x| format!("{x:.6e}")));
        }
    }
}

fn run_wake(cfg: &WakelabConfig, dir: &Path, quiet: bool) -> Result<()> {
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
    let (_, outputs) = wakelab_hydro::output::run_hydro_stage(cfg, dir, &mut |t, steps| {
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
    Ok(())
}

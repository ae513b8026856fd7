//! The `wakelab` command: parses arguments, calls the pipeline's stages and writes their output.

mod cli;
mod dataset;
mod learn;
mod reports;
mod run;
mod study;

use clap::Parser;
use cli::{Cli, Command, ConfigAction, SarAction};

pub type Result<T> = anyhow::Result<T>;

// Training allocates and frees large activation buffers every step; glibc's allocator returns
// them to the kernel each time (page faults and zeroing: a measured third of a "base" training
// step). mimalloc keeps them.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() {
    let cli = Cli::parse();
    if let Err(e) = dispatch(cli) {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}

fn dispatch(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Run(args) => study::run_study_command(&args),
        Command::Scene(args) => run::run_pipeline(&args),
        Command::Wake(args) => run::run_wake_only(&args),
        Command::Idp { config, json, write } => reports::idp(&config, json, write.as_deref()),
        Command::Spectrum {
            config,
            wind,
            incidence,
            json,
        } => reports::spectrum(&config, wind, incidence, json),
        Command::Optics {
            config,
            wavelength,
            salinity,
            temperature,
            incidence,
            json,
        } => reports::optics(&config, wavelength, salinity, temperature, incidence, json),
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
        } => reports::sar_sigma0(&config, wind, &band, polarisation.as_deref(), incidence, look, json),
        Command::Dataset {
            study,
            out,
            shard,
            merge,
            emit_slurm,
            tasks,
            quiet,
        } => dataset::run_dataset(&study, &out, shard.as_deref(), merge, emit_slurm, tasks, quiet),
        Command::Train { learn, arch, model } => learn::run_train(&learn, &arch, model.as_deref()),
        Command::Eval {
            learn,
            arch,
            repetitions,
            json,
        } => learn::run_eval(&learn, &arch, repetitions, json),
        Command::Detect {
            image,
            model,
            mask,
            device,
            json,
        } => learn::run_detect(&image, &model, &device, mask.as_deref(), json),
        Command::Config {
            action: ConfigAction::Show { config },
        } => {
            print!("{}", config.load()?.to_toml_string());
            Ok(())
        }
    }
}

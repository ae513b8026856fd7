//! The `wakelab` command: parses arguments, calls the pipeline's stages and writes their output.

mod cli;
mod dataset;
mod detect;
mod learn;
mod reports;
mod scene;
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
    wakelab_learn::device::keep_freed_pages();
    let cli = Cli::parse();
    if let Err(e) = dispatch(cli) {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}

fn dispatch(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Run(args) => study::run_study_command(&args, cli.quiet),
        Command::Scene(args) => scene::run_pipeline(&args, cli.quiet),
        Command::Wake(args) => scene::run_wake_only(&args, cli.quiet),
        Command::Idp(args) => reports::idp(&args),
        Command::Spectrum(args) => reports::spectrum(&args),
        Command::Optics(args) => reports::optics(&args),
        Command::Sar {
            action: SarAction::Sigma0(args),
        } => reports::sar_sigma0(&args),
        Command::Dataset(args) => dataset::run_dataset(&args, cli.quiet),
        Command::Train(args) => learn::run_train(&args, cli.quiet),
        Command::Eval(args) => learn::run_eval(&args, cli.quiet),
        Command::Detect(args) => detect::run_detect(&args, cli.quiet),
        Command::Calibrate(args) => detect::run_calibrate(&args, cli.quiet),
        Command::Config {
            action: ConfigAction::Show { config },
        } => reports::config_show(&config),
    }
}

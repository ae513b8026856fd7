//! `wakelab run`: the whole study of a study file, from physics to fused detections and a report
//! (the workflow of the spec's Fig. 2.1). Stages, each in its own folder of the run directory:
//!
//! 1. `dataset/`: the study's wakes, sea surfaces and SAR/IR images (stages 1-4 of the pipeline);
//! 2. `learn/<input>/`: Algorithm 2 for every architecture on one input (a band, or bands as
//!    channels), with the perturbed test images of the robustness study;
//! 3. `learn/held_out/`: the classifiers trained with one environment held out at a time;
//! 4. `fusion/`: decision-level fusion (Bayes, Dempster-Shafer) of the single-band outputs;
//! 5. `report/`: HTML, Markdown and CSV.
//!
//! A learning stage is reused when its key (a hash of the manifest, the `[learning]` table, the
//! input and wakelab's version) matches the one stored beside its outputs; the dataset stage
//! skips every finished scene. Fusion and the report are cheap and always rebuilt.

mod html;
mod radar;
mod report;
mod stages;
mod svg;

use crate::cli::StudyArgs;
use crate::Result;
use indicatif::{ProgressBar, ProgressStyle};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;
use std::time::Instant;
use wakelab_core::config::Preset;
use wakelab_core::io::write_atomically;

/// Wall time of one stage of this run.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct StageTime {
    pub stage: String,
    /// Seconds this run spent.
    pub seconds: f64,
    /// Seconds the stage took when it was computed (equal to `seconds` unless reused).
    pub computed_seconds: f64,
    pub reused: bool,
}

/// The single progress display of a run: one bar, re-used stage after stage, showing the stage,
/// the item, the rate and the time left.
pub struct Display {
    bar: ProgressBar,
    stages: usize,
}

impl Display {
    fn new(quiet: bool, stages: usize) -> Self {
        let bar = if quiet {
            ProgressBar::hidden()
        } else {
            ProgressBar::new(1)
        };
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner} {prefix:<22} [{bar:30}] {percent:>3}% | {msg} | {elapsed_precise}, {eta} left",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        Self { bar, stages }
    }

    /// Start stage `k` (1-based) with `units` of work.
    pub fn stage(&self, k: usize, name: &str, units: u64) {
        self.bar.set_prefix(format!("stage {k}/{} {name}", self.stages));
        self.bar.set_length(units.max(1));
        self.bar.set_position(0);
        self.bar.reset_eta();
    }

    pub fn advance(&self, units: u64, message: String) {
        self.bar.inc(units);
        self.bar.set_message(message);
    }

    pub fn set(&self, position: u64, message: String) {
        self.bar.set_position(position);
        self.bar.set_message(message);
    }

    /// Print a line above the bar.
    pub fn println(&self, line: String) {
        if self.bar.is_hidden() {
            eprintln!("{line}");
        } else {
            self.bar.println(line);
        }
    }

    fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// `wakelab run`.
pub fn run_study_command(args: &StudyArgs) -> Result<()> {
    let name = match (&args.study, args.preset) {
        (Some(s), _) => s.clone(),
        (None, Some(Preset::Paper)) => "paper".to_string(),
        (None, _) => "default".to_string(),
    };
    let study = crate::dataset::load_study(&name)?;
    let dir = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("runs").join(&study.study.name));
    let device = wakelab_learn::device::parse_device(&args.device)?;
    std::fs::create_dir_all(&dir)?;
    write_atomically(dir.join("study.toml"), toml::to_string(&study)?.as_bytes())?;
    let start = Instant::now();
    let display = Display::new(args.quiet, 5);
    let result = stages::run_stages(&study, &dir, &device, &display);
    display.finish();
    let mut run = result?;
    let report_start = Instant::now();
    let files = report::write_report(&dir, &study, &run)?;
    run.times.push(StageTime {
        stage: "report".into(),
        seconds: report_start.elapsed().as_secs_f64(),
        computed_seconds: report_start.elapsed().as_secs_f64(),
        reused: false,
    });
    write_atomically(
        dir.join("timing.json"),
        serde_json::to_string_pretty(&run.times)?.as_bytes(),
    )?;
    report::print_summary(&run);
    for t in &run.times {
        eprintln!(
            "  {:<26} {:>8.1} s{}",
            t.stage,
            t.seconds,
            if t.reused {
                format!(" (reused; computed in {:.1} s)", t.computed_seconds)
            } else {
                String::new()
            }
        );
    }
    let total = start.elapsed().as_secs_f64();
    eprintln!("study \"{}\" finished in {total:.1} s", study.study.name);
    for f in files {
        eprintln!("wrote {}", f.display());
    }
    Ok(())
}

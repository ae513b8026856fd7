//! wakelab-study: the crate that joins the pipeline's stages (spec Fig. 2.1: hydrodynamics,
//! ocean surface, sensors, data, learning, fusion) into a study, and renders its report; the
//! `wakelab` binary only parses, calls and prints.
//!
//! `wakelab run`: the whole study of a study file, in named steps ([`steps`]), each writing its
//! results to its own folder of the run directory and reused when its inputs have not changed:
//!
//! - dataset (`dataset/`): the study's wakes, sea surfaces and SAR/IR images (pipeline stages
//!   1-4), every finished scene skipped;
//! - learning (`learn/<input>/`): Algorithm 2 for every architecture on one input (a band, or
//!   bands as channels), with the perturbed test images of the robustness study;
//! - held-out (`learn/held_out*/`): the classifiers trained with one environment, and one third
//!   of the wake ages, held out at a time;
//! - fusion (`fusion/`): decision-level fusion (Bayes, Dempster-Shafer) of the single bands;
//! - scan (`whole_scene/`): each band's detector scanned over one scene eight chips wide;
//! - environments (`environments/`): the spec's calm, head and following seas per radar band,
//!   and the open sea's sigma0 against CMOD5.N;
//! - ships (`ships/`): the classic ship and wake detectors ([`wakelab_ships`]) on simulated
//!   scenes whose truth is known: detection, false alarms, course and speed errors;
//! - report (`report/`): HTML, Markdown and CSV, rendered from what the steps wrote ([`report`]
//!   runs no physics and trains nothing).
//!
//! `wakelab run --stage learning --input NAME` and `--stage held-out` run one learning step on a
//! finished dataset, as the jobs of `wakelab run --emit-slurm` ([`slurm`]) do side by side.
//!
//! A learning step is reused when its key (a hash of the manifest, the `[learning]` table, the
//! input and wakelab's version) matches the one stored beside its outputs; the scan's key adds
//! its scene and detectors, the environments' the study's base configuration. Fusion and the
//! report are cheap and always rebuilt.

pub mod corroboration;
pub mod dataset;
pub mod dry_run;
pub mod learning;
pub mod output;
mod plan;
pub mod product_scan;
pub mod products;
pub mod progress_log;
pub mod report;
pub mod scan;
pub mod scan_windows;
pub mod scene;
pub mod sea_findings;
pub mod shipped;
pub mod slurm;
pub mod steps;
pub mod transfer;

use indicatif::{ProgressBar, ProgressStyle};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::time::Instant;
use wakelab_core::io::write_atomically;
use wakelab_learn::device::Device;

/// Errors of a study run: any stage's, with the path or field it concerns.
pub type Result<T> = anyhow::Result<T>;

/// Wall time of one step of this run.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct StepTime {
    /// The step's name (`timing.json` keeps the key "stage" its readers know).
    #[serde(rename = "stage")]
    pub step: String,
    /// Seconds this run spent.
    pub seconds: f64,
    /// Seconds the step took when it was computed (equal to `seconds` unless reused).
    pub computed_seconds: f64,
    pub reused: bool,
}

/// "dataset      16.6 s", with "(reused; computed in 16.6 s)" for a reused step.
impl std::fmt::Display for StepTime {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:<26} {:>8.1} s", self.step, self.seconds)?;
        if self.reused {
            write!(f, " (reused; computed in {:.1} s)", self.computed_seconds)?;
        }
        Ok(())
    }
}

/// A progress bar of `length` units drawn with indicatif's `template` (hidden when `quiet`): the
/// one style every long command of wakelab shares. Where stderr is not a terminal (a batch job's
/// log) the bar becomes log lines: one when the step changes and one every 30 s.
pub fn progress_bar(quiet: bool, length: u64, template: &str) -> ProgressBar {
    use std::io::IsTerminal;
    let bar = if quiet {
        ProgressBar::hidden()
    } else if std::io::stderr().is_terminal() {
        ProgressBar::new(length)
    } else {
        ProgressBar::with_draw_target(Some(length), progress_log::LogLines::target())
    };
    bar.set_style(style(template, "items"));
    bar
}

/// Indicatif's `template` with `{rate}` as "1.2 <unit>/s" (indicatif's own `{per_sec}` has no
/// unit).
pub fn style(template: &str, unit: &'static str) -> ProgressStyle {
    ProgressStyle::with_template(template)
        .expect("valid template")
        .with_key(
            "rate",
            move |s: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                let _ = write!(
                    w,
                    "{} {unit}/s",
                    wakelab_core::io::text::number((s.per_sec() * 10.0).round() / 10.0)
                );
            },
        )
        .progress_chars("=> ")
}

/// A (done, total) reporter that shows `what` on `bar`, restarting the bar when the phase changes:
/// one bar for a command's successive phases (a product's rows read, then its windows scored).
pub fn follow_on(bar: &ProgressBar, what: &'static str) -> impl FnMut(usize, usize) {
    let bar = bar.clone();
    move |done, total| {
        if bar.message() != what {
            bar.set_message(what);
            bar.reset();
        }
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    }
}

/// The single progress display of a run: one bar, re-used step after step, counting the step's
/// own work in its unit, with the time left in the step and, where an earlier run in the same
/// directory timed the later steps, in the whole run.
pub struct Display {
    bar: ProgressBar,
    steps: usize,
    /// The steps of the directory's previous run and what each took to compute (s), in order.
    previous: Vec<(String, f64)>,
    /// "; the rest ~3 min (last run)" for the current step.
    later: std::sync::Mutex<String>,
    /// The bar is a log (stderr is no terminal): each step's start is printed as a line.
    log: bool,
}

const DISPLAY_TEMPLATE: &str =
    "{spinner} {prefix:<22} [{bar:30}] {pos}/{len} | {rate} | {msg} | {elapsed_precise}, {eta} left in step";

impl Display {
    pub(crate) fn new(quiet: bool, steps: usize, dir: &Path) -> Self {
        let previous = std::fs::read_to_string(dir.join("timing.json"))
            .ok()
            .and_then(|t| serde_json::from_str::<Vec<StepTime>>(&t).ok())
            .map(|times| times.into_iter().map(|t| (t.step, t.computed_seconds)).collect())
            .unwrap_or_default();
        use std::io::IsTerminal;
        Self {
            bar: progress_bar(quiet, 1, DISPLAY_TEMPLATE),
            steps,
            previous,
            later: std::sync::Mutex::new(String::new()),
            log: !quiet && !std::io::stderr().is_terminal(),
        }
    }

    /// Start step `k` (1-based) with `units` of work counted in `unit`.
    pub fn step(&self, k: usize, name: &str, units: u64, unit: &'static str) {
        self.bar.set_style(style(DISPLAY_TEMPLATE, unit));
        self.bar.set_length(units.max(1));
        self.bar.set_position(0);
        self.bar.reset_eta();
        let after: Vec<f64> = self
            .previous
            .iter()
            .skip_while(|(step, _)| step != name)
            .skip(1)
            .map(|(_, s)| *s)
            .collect();
        *self.later.lock().expect("display") = if after.is_empty() {
            String::new()
        } else {
            format!(
                "; later steps ~{} (last run)",
                wakelab_core::io::text::duration(after.iter().sum())
            )
        };
        self.bar
            .set_message(self.later.lock().expect("display").trim_start_matches("; ").to_string());
        self.bar.set_prefix(format!("step {k}/{} {name}", self.steps));
        if self.log {
            let later = self.later.lock().expect("display").clone();
            self.println(format!("step {k}/{} {name}: {units} {unit}{later}", self.steps));
        }
    }

    /// Re-count the step in another `unit` (its phases: wakes simulated, then scenes rendered).
    pub fn phase(&self, unit: &'static str, done: u64, total: u64, message: String) {
        if self.bar.length() != Some(total.max(1)) {
            self.bar.set_style(style(DISPLAY_TEMPLATE, unit));
            self.bar.set_length(total.max(1));
            self.bar.reset_eta();
        }
        self.set(done, message);
    }

    pub fn advance(&self, units: u64, message: String) {
        self.bar.inc(units);
        self.bar.set_message(message + &self.later.lock().expect("display"));
    }

    pub fn set(&self, position: u64, message: String) {
        self.bar.set_position(position);
        self.bar.set_message(message + &self.later.lock().expect("display"));
    }

    /// Print a line above the bar.
    pub fn println(&self, line: String) {
        if self.bar.is_hidden() {
            eprintln!("{line}");
        } else {
            self.bar.println(line);
        }
    }

    pub(crate) fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// The study of a name: a study TOML file, or the embedded `default` or `paper` study.
pub fn load_study(name: &str) -> Result<wakelab_dataset::study::Study> {
    use wakelab_dataset::study::{Study, DEFAULT_STUDY, PAPER_STUDY, TRANSFER_STUDY};
    let path = Path::new(name);
    Ok(match name {
        _ if path.exists() => Study::from_file(path)?,
        "default" => Study::from_toml_str(DEFAULT_STUDY, "<embedded default study>")?,
        "paper" => Study::from_toml_str(PAPER_STUDY, "<embedded paper study>")?,
        "transfer" => Study::from_toml_str(TRANSFER_STUDY, "<embedded transfer study>")?,
        _ => anyhow::bail!("--study {name}: no such file (or use `default`, `paper` or `transfer`)"),
    })
}

/// Refuses a transfer study where only a chip study's steps apply (`--dry-run`, `--emit-slurm`,
/// `--stage`): its run is one step, `wakelab run --study transfer`.
pub(crate) fn chip_study_only(study: &wakelab_dataset::study::Study, flag: &str) -> Result<()> {
    if study.transfer.is_some() {
        anyhow::bail!(
            "{flag} applies to a chip study; study \"{}\" is a transfer study: run it whole with `wakelab run --study FILE` (its run time is in docs/results.md)",
            study.study.name
        );
    }
    Ok(())
}

/// `study` with its transfer plan's `sea_images` and `wake_images` set to the folders given
/// (`wakelab run --sea-images DIR --wake-images DIR`); refused for a study without a
/// `[transfer]` table.
pub fn with_real_images(
    mut study: wakelab_dataset::study::Study,
    sea: Option<&Path>,
    wakes: Option<&Path>,
) -> Result<wakelab_dataset::study::Study> {
    for (flag, dir) in [("--sea-images", sea), ("--wake-images", wakes)] {
        let Some(dir) = dir else { continue };
        let plan = study.transfer.as_mut().ok_or_else(|| {
            anyhow::anyhow!(
                "{flag} {}: only the transfer study trains on real images (pass --study transfer)",
                dir.display()
            )
        })?;
        match flag {
            "--sea-images" => plan.sea_images = Some(dir.to_path_buf()),
            _ => plan.wake_images = Some(dir.to_path_buf()),
        }
        plan.validate().map_err(|e| anyhow::anyhow!("{flag}: {e}"))?;
    }
    Ok(study)
}

/// What a finished study run leaves: its steps' times (for the summary) and the report's files.
pub struct StudyOutcome {
    pub run: steps::StudyRun,
    pub files: Vec<PathBuf>,
    /// Wall time of the whole run (s).
    pub seconds: f64,
}

impl StudyOutcome {
    /// Each step's time, the run's and the files written, a line each.
    pub fn describe(&self, study_name: &str) -> String {
        let mut lines: Vec<String> = self.run.times.iter().map(|t| format!("  {t}")).collect();
        lines.push(format!("study \"{study_name}\" finished in {:.1} s", self.seconds));
        lines.extend(self.files.iter().map(|f| format!("wrote {}", f.display())));
        lines.join("\n")
    }
}

/// The number of steps a full run shows in its progress display.
const STEPS: usize = 8;

/// `wakelab run`: every step of `study` in `dir` (reusing what is finished), then the report.
/// `quiet` hides the progress bar.
pub fn run_study(
    study: &wakelab_dataset::study::Study,
    dir: &Path,
    device: &Device,
    quiet: bool,
) -> Result<StudyOutcome> {
    std::fs::create_dir_all(dir).map_err(|e| anyhow::anyhow!("{}: {e}", dir.display()))?;
    write_atomically(dir.join("study.toml"), toml::to_string(study)?.as_bytes())?;
    let start = Instant::now();
    let started = chrono::Utc::now().format("%Y-%m-%d %H:%M UTC").to_string();
    let display = Display::new(quiet, STEPS, dir);
    let result = steps::run_steps(study, dir, device, &display);
    display.finish();
    let mut run = result?;
    run.started = started;
    run.device = wakelab_learn::device::describe_device(device);
    // the report's wall-time table holds the report's own time: it is rendered once to time it,
    // then again with that time (a fraction of a second)
    let report_start = Instant::now();
    report::write_report(dir, study, &run)?;
    let seconds = report_start.elapsed().as_secs_f64();
    run.times.push(StepTime {
        step: "report".into(),
        seconds,
        computed_seconds: seconds,
        reused: false,
    });
    let files = report::write_report(dir, study, &run)?;
    write_atomically(
        dir.join("timing.json"),
        serde_json::to_string_pretty(&run.times)?.as_bytes(),
    )?;
    Ok(StudyOutcome {
        run,
        files,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// `wakelab run`: the study's run (the chip study, or a transfer study's when it has a
/// `[transfer]` table), its summary printed on stdout; returns what it did, a line each.
pub fn run_and_describe(
    study: &wakelab_dataset::study::Study,
    dir: &Path,
    device: &Device,
    real: Option<&Path>,
    quiet: bool,
) -> Result<String> {
    if study.transfer.is_some() {
        return Ok(transfer::run_transfer(study, dir, device, real, quiet)?.join("\n"));
    }
    if let Some(real) = real {
        anyhow::bail!(
            "--real {}: real images score the transfer study's detectors; use it with --study transfer (or a \
             study file with a [transfer] table)",
            real.display()
        );
    }
    let outcome = run_study(study, dir, device, quiet)?;
    report::print_summary(&outcome.run);
    Ok(outcome.describe(&study.study.name))
}

/// `wakelab run --stage ...`: one learning step of `study` in `dir`, on its finished dataset.
pub fn run_one_step(
    study: &wakelab_dataset::study::Study,
    dir: &Path,
    step: &steps::OneStep,
    device: &Device,
    quiet: bool,
) -> Result<StepTime> {
    chip_study_only(study, "--stage")?;
    let display = Display::new(quiet, STEPS, dir);
    let result = steps::run_one_step(study, dir, step, device, &display);
    display.finish();
    result
}

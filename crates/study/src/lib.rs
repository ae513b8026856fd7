//! wakelab-study: the crate that joins the pipeline's stages into a study (data, learn and
//! fusion) and writes its report; the `wakelab` binary only parses, calls and prints.
//!
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
//! `wakelab run --stage learning --input NAME` and `--stage held-out` run one learning stage on a
//! finished dataset, as the jobs of `wakelab run --emit-slurm` ([`slurm`]) do side by side.
//!
//! A learning stage is reused when its key (a hash of the manifest, the `[learning]` table, the
//! input and wakelab's version) matches the one stored beside its outputs; the dataset stage
//! skips every finished scene. Fusion and the report are cheap and always rebuilt.

pub mod dataset;
pub mod environments;
mod held_out;
mod html;
pub mod learning;
pub mod mask_quality;
pub mod output;
mod pictures;
mod plan;
pub mod product_scan;
mod radar;
pub mod report;
pub mod scan;
pub mod scene;
pub mod slurm;
pub mod stability;
pub mod stages;
mod svg;
mod test_scenes;
pub mod visibility;
mod whole_scene;

use indicatif::{ProgressBar, ProgressStyle};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::time::Instant;
use wakelab_core::io::write_atomically;
use wakelab_learn::device::Device;

/// Errors of a study run: any stage's, with the path or field it concerns.
pub type Result<T> = anyhow::Result<T>;

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

/// "dataset      16.6 s", with "(reused; computed in 16.6 s)" for a reused stage.
impl std::fmt::Display for StageTime {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:<26} {:>8.1} s", self.stage, self.seconds)?;
        if self.reused {
            write!(f, " (reused; computed in {:.1} s)", self.computed_seconds)?;
        }
        Ok(())
    }
}

/// A progress bar of `length` units drawn with indicatif's `template` (hidden when `quiet`): the
/// one style every long command of wakelab shares.
pub fn progress_bar(quiet: bool, length: u64, template: &str) -> ProgressBar {
    let bar = if quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(length)
    };
    bar.set_style(
        ProgressStyle::with_template(template)
            .expect("valid template")
            .progress_chars("=> "),
    );
    bar
}

/// The single progress display of a run: one bar, re-used stage after stage, showing the stage,
/// the item, the rate and the time left.
pub struct Display {
    bar: ProgressBar,
    stages: usize,
}

impl Display {
    fn new(quiet: bool, stages: usize) -> Self {
        let template = "{spinner} {prefix:<22} [{bar:30}] {percent:>3}% | {msg} | {elapsed_precise}, {eta} left";
        Self {
            bar: progress_bar(quiet, 1, template),
            stages,
        }
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

/// The study of a name: a study TOML file, or the embedded `default` or `paper` study.
pub fn load_study(name: &str) -> Result<wakelab_dataset::study::Study> {
    use wakelab_dataset::study::{Study, DEFAULT_STUDY, PAPER_STUDY};
    let path = Path::new(name);
    Ok(match name {
        _ if path.exists() => Study::from_file(path)?,
        "default" => Study::from_toml_str(DEFAULT_STUDY, "<embedded default study>")?,
        "paper" => Study::from_toml_str(PAPER_STUDY, "<embedded paper study>")?,
        _ => anyhow::bail!("--study {name}: no such file (or use `default` or `paper`)"),
    })
}

/// What a finished study run leaves: its stages (for the summary) and the report's files.
pub struct StudyOutcome {
    pub run: stages::StudyRun,
    pub files: Vec<PathBuf>,
    /// Wall time of the whole run (s).
    pub seconds: f64,
}

impl StudyOutcome {
    /// Each stage's time, the run's and the files written, a line each.
    pub fn describe(&self, study_name: &str) -> String {
        let mut lines: Vec<String> = self.run.times.iter().map(|t| format!("  {t}")).collect();
        lines.push(format!("study \"{study_name}\" finished in {:.1} s", self.seconds));
        lines.extend(self.files.iter().map(|f| format!("wrote {}", f.display())));
        lines.join("\n")
    }
}

/// `wakelab run`: every stage of `study` in `dir` (reusing what is finished), then the report.
/// `quiet` hides the progress bar.
pub fn run_study(study: &wakelab_dataset::study::Study, dir: &Path, device: &Device, quiet: bool) -> Result<StudyOutcome> {
    std::fs::create_dir_all(dir).map_err(|e| anyhow::anyhow!("{}: {e}", dir.display()))?;
    write_atomically(dir.join("study.toml"), toml::to_string(study)?.as_bytes())?;
    let start = Instant::now();
    let started = chrono::Utc::now().format("%Y-%m-%d %H:%M UTC").to_string();
    let display = Display::new(quiet, 5);
    let result = stages::run_stages(study, dir, device, &display);
    display.finish();
    let mut run = result?;
    run.started = started;
    run.device = wakelab_learn::device::describe_device(device);
    // the report's wall-time table holds the report's own time: it is written once to time it,
    // then again with that time (a fraction of a second)
    let report_start = Instant::now();
    report::write_report(dir, study, &run)?;
    let seconds = report_start.elapsed().as_secs_f64();
    run.times.push(StageTime {
        stage: "report".into(),
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

/// `wakelab run --stage ...`: one learning stage of `study` in `dir`, on its finished dataset.
pub fn run_one_stage(
    study: &wakelab_dataset::study::Study,
    dir: &Path,
    stage: &stages::OneStage,
    device: &Device,
    quiet: bool,
) -> Result<StageTime> {
    let display = Display::new(quiet, 5);
    let result = stages::run_one_stage(study, dir, stage, device, &display);
    display.finish();
    result
}

//! The report of a study run: it renders what the run's steps wrote into the run directory
//! (the learning results, the whole-scene scan in `whole_scene/`, the spec's environments in
//! `environments/`) as HTML, Markdown and CSV, and runs no physics and trains nothing. The
//! tables mirror the spec's Tables 4.4-4.6 and 5.1-5.3, with the paper's own numbers beside ours.

mod calibration;
mod environments;
mod figure;
mod html;
mod learning_tables;
mod mask_quality;
mod pictures;
mod radar;
mod ships;
mod stability;
pub(crate) mod svg;
pub mod table;
mod test_scenes;
mod visibility;
mod whole_scene;

pub use learning_tables::{confusion_rows, paper_value};
use learning_tables::{confusion_table, fusion_table, sar_ir_table, single_input_table, timing_table};
pub use table::Table;

use crate::steps::calibration::load_calibration;
use crate::steps::environments::load_environments;
use crate::steps::ships::load_ships;
use crate::steps::whole_scene::load_whole_scene;
use crate::steps::StudyRun;
use crate::Result;
use std::path::{Path, PathBuf};
use wakelab_core::io::write_atomically;
use wakelab_core::WakelabError;
use wakelab_dataset::study::Study;
use wakelab_learn::models::Architecture;
use wakelab_schema::band::Band;
use wakelab_schema::fusion_row::Source;

/// Every result table, in report order (timing is separate: it differs run to run).
pub fn result_tables(run: &StudyRun) -> Vec<Table> {
    let mut tables: Vec<Table> = Architecture::ALL.iter().map(|&a| single_input_table(run, a)).collect();
    tables.extend(Architecture::ALL.iter().map(|&a| fusion_table(run, a)));
    tables.push(sar_ir_table(run));
    tables.push(confusion_table(run));
    tables.push(stability::robustness_table(run));
    tables.push(stability::score_change_table(run));
    tables.push(mask_quality::mask_iou_table(run));
    tables.push(test_scenes::test_scene_table(run));
    let bands: Vec<Band> = run.inputs.iter().filter_map(|i| i.as_single()).collect();
    tables.push(visibility::visibility_table(&run.dataset.records, &run.outputs, &bands));
    tables
}

/// Write `report/`: the HTML page, `report.md` and one CSV per table; returns the paths.
pub fn write_report(dir: &Path, study: &Study, run: &StudyRun) -> Result<Vec<PathBuf>> {
    let out = dir.join("report");
    let tables_dir = out.join("tables");
    std::fs::create_dir_all(&tables_dir).map_err(|e| WakelabError::io(&tables_dir, e))?;
    let mut tables = result_tables(run);
    let scans = load_whole_scene(dir)?;
    tables.push(whole_scene::whole_scene_table(&scans));
    let whole_scene_html = whole_scene::whole_scene_html(&scans)?;
    let environments = load_environments(dir)?;
    tables.push(environments::environment_table(
        &environments.contrasts,
        environments.along_track,
    ));
    let ships = load_ships(dir)?;
    tables.push(ships::ships_table(&ships));
    tables.extend(ships::wake_detectors_table(&ships));
    tables.push(ships::ships_scene_table(&ships));
    tables.extend(ships::fine_scene_table(&ships));
    let calibrated = load_calibration(dir)?;
    tables.push(calibration::calibration_table(&calibrated));
    tables.extend(calibration::open_sea_table(&calibrated));
    tables.extend(calibration::window_normalisation_table(&calibrated));
    let timing = timing_table(run);
    let mut markdown = format!(
        "# wakelab study \"{}\"\n\nwakelab {}, run {} on {}; {} scenes; see report.html for pictures and plots.\n\n",
        study.study.name,
        env!("CARGO_PKG_VERSION"),
        run.started,
        run.device,
        run.dataset.records.len()
    );
    for t in tables.iter().chain(std::iter::once(&timing)) {
        markdown.push_str(&t.markdown());
        write_atomically(tables_dir.join(format!("{}.csv", t.id)), t.csv().as_bytes())?;
    }
    let md = write_atomically(out.join("report.md"), markdown.as_bytes())?;
    // the radar-physics figures, also as files a user can open or put in a paper
    let mut figures = radar::sigma0_against_cmod5n(&environments.sigma0);
    figures.extend(radar::across_wake_contrast(run)?);
    let names = [
        "sigma0_vs_cmod5n_upwind",
        "sigma0_vs_cmod5n_crosswind",
        "across_wake_contrast",
    ];
    let svgs: Vec<String> = figures.iter().map(|f| f.to_svg()).collect();
    for (name, svg) in names.iter().zip(&svgs) {
        write_atomically(out.join(format!("{name}.svg")), svg.as_bytes())?;
    }
    let reliability = calibration::reliability_plot(&calibrated, "C").map(|p| p.to_svg());
    if let Some(svg) = &reliability {
        write_atomically(out.join("reliability_C.svg"), svg.as_bytes())?;
    }
    let page = html::report_page(
        study,
        run,
        &tables,
        &timing,
        &svgs,
        &whole_scene_html,
        reliability.as_deref(),
    )?;
    let html = write_atomically(out.join("report.html"), page.as_bytes())?;
    Ok(vec![html, md, tables_dir])
}

/// The headline numbers on the terminal.
pub fn print_summary(run: &StudyRun) {
    let fusions: std::collections::BTreeSet<Source> = run.fusion.iter().map(|(s, _)| s.bands.clone()).collect();
    let rows: Vec<Source> = run.inputs.iter().cloned().map(Source::Input).chain(fusions).collect();
    let w = rows.iter().map(|r| r.to_string().len()).max().unwrap_or(5).max(5);
    println!("test MCC, mean over {} repetitions:", run.plan.repetitions);
    print!("{:<w$}", "input");
    for a in Architecture::ALL {
        print!(" {:>6}", a.name());
    }
    println!();
    for input in rows {
        print!("{input:<w$}");
        for a in Architecture::ALL {
            let s = run
                .summaries
                .iter()
                .chain(run.fusion.iter().map(|(s, _)| s))
                .find(|s| s.bands == input && s.architecture == a);
            match s {
                Some(s) => print!(" {:>6.2}", s.mcc),
                None => print!(" {:>6}", "-"),
            }
        }
        println!();
    }
}

//! The transfer study's report (issue 38, item 8): `report/transfer.md` and
//! `report/tables/transfer.csv`, one row per footprint: false alarms per 100 km^2 and per 1,000
//! km^2 on simulated open sea with look-alikes (where the threshold was set, and unseen), wake
//! recall on whole scenes, the window-level AUC, and the reliability diagram of the
//! probabilities.

use super::real::RealResults;
use super::real_report;
use super::results::{RealSeaThreshold, TransferDetector, TransferResults};
use crate::report::svg::{LinePlot, Series};
use crate::Result;
use std::fmt::Write;
use std::path::{Path, PathBuf};
use wakelab_core::io::write_atomically;
use wakelab_schema::architecture::{ClassifierHead, InputForm};

/// One line: what the detector of a footprint does.
pub fn describe(d: &TransferDetector) -> String {
    format!(
        "  {:.2} km window ({:.0} m pixels): threshold {:.4} for {:.1} alarms per 1,000 km^2; unseen open sea {:.1} per 1,000 km^2; wakes found {}/{} (unseen seas {}/{}); look-alike test set {:.1} per 1,000 km^2, {} alarm(s) on its {} ships without a wake, wakes found {}/{}; window AUC {}",
        d.footprint / 1000.0,
        d.spacing,
        d.threshold,
        d.alarms_at_threshold,
        d.unseen_alarms,
        d.wakes_found,
        d.scenes,
        d.unseen_wakes_found,
        d.unseen_scenes,
        d.look_alikes.alarms,
        d.look_alikes.ship_alarms,
        d.look_alikes.ships,
        d.look_alikes.wakes_found,
        d.unseen_scenes,
        d.window_auc.map_or("-".into(), |a| format!("{a:.3}")),
    )
}

const HEADER: [&str; 24] = [
    "footprint_m",
    "spacing_m",
    "training_windows",
    "track_windows",
    "track_windows_wake_shows",
    "track_visibility_quartiles",
    "track_visibility_above_3",
    "sea_visibility_quartiles",
    "sea_visibility_above_3",
    "threshold",
    "alarms_per_1000_km2_at_0.5",
    "alarms_per_1000_km2",
    "alarms_per_100_km2",
    "wakes_found_at_0.5",
    "wakes_found",
    "scenes",
    "unseen_alarms_per_1000_km2",
    "unseen_wakes_found",
    "unseen_scenes",
    "look_alike_alarms_per_1000_km2",
    "look_alike_ships",
    "look_alike_alarms_on_ships",
    "look_alike_wakes_found",
    "window_auc",
];

/// The real sea's strongest alarms, with their images: the first place to look for a wake left
/// undrawn in the "wake-free" sea, which would raise the threshold.
fn strongest_sea_alarms(r: &RealSeaThreshold) -> String {
    if r.strongest.is_empty() {
        return String::new();
    }
    let mut md = format!(
        "Its {} strongest alarms there (pixels of each image as given; look there for a wake not drawn, which raises the threshold):\n\n| image | row | column | probability |\n| --- | --- | --- | --- |\n",
        r.strongest.len()
    );
    for a in &r.strongest {
        md += &format!("| {} | {:.0} | {:.0} | {:.4} |\n", a.image, a.row, a.col, a.probability);
    }
    md + "\n"
}

fn row(d: &TransferDetector) -> Vec<String> {
    vec![
        format!("{:.0}", d.footprint),
        format!("{:.0}", d.spacing),
        d.training_windows.to_string(),
        d.track_windows.to_string(),
        d.track_windows_shown.to_string(),
        d.track_visibility.map_or(String::new(), |v| v.describe()),
        d.track_visibility
            .map_or(String::new(), |v| format!("{:.2}", v.above_3)),
        d.sea_visibility.map_or(String::new(), |v| v.describe()),
        d.sea_visibility.map_or(String::new(), |v| format!("{:.2}", v.above_3)),
        format!("{:.4}", d.threshold),
        format!("{:.1}", d.alarms_at_half),
        format!("{:.2}", d.alarms_at_threshold),
        format!("{:.3}", d.alarms_at_threshold / 10.0),
        d.wakes_found_at_half.to_string(),
        d.wakes_found.to_string(),
        d.scenes.to_string(),
        format!("{:.2}", d.unseen_alarms),
        d.unseen_wakes_found.to_string(),
        d.unseen_scenes.to_string(),
        format!("{:.2}", d.look_alikes.alarms),
        d.look_alikes.ships.to_string(),
        d.look_alikes.ship_alarms.to_string(),
        d.look_alikes.wakes_found.to_string(),
        d.window_auc.map_or(String::new(), |a| format!("{a:.3}")),
    ]
}

/// The table as CSV.
pub fn csv(results: &TransferResults) -> String {
    let mut text = HEADER.join(",") + "\n";
    for d in &results.detectors {
        text += &(row(d).join(",") + "\n");
    }
    text
}

/// The Markdown page.
pub fn markdown(results: &TransferResults) -> String {
    let p = &results.plan;
    let mut md = String::from("# Transfer: detectors for real C-band images\n\n");
    let _ = writeln!(
        md,
        "{} training scenes of 5.12 km at 10 m ({} delivered as 8-bit display images), each with its ship and wake and without; winds {}-{} m/s, incidence {}-{} degrees, {}-{} looks, NESZ {} to {} dB, slicks over {}-{} % of the sea{}; {} epochs of \"{}\" reading {}{}.\n",
        results.training_scenes,
        results.display_scenes,
        p.wind_speed[0],
        p.wind_speed[1],
        p.incidence[0],
        p.incidence[1],
        p.looks[0],
        p.looks[1],
        p.nesz[0],
        p.nesz[1],
        100.0 * p.slick_coverage[0],
        100.0 * p.slick_coverage[1],
        if p.look_alike_training {
            ", and the look-alike test set's look-alikes (windows on them as negatives, the wake windows where the wake shows, the classes balanced)"
        } else {
            ""
        },
        p.epochs,
        p.architecture,
        match p.input {
            InputForm::Pixels => "the windows' pixels",
            InputForm::LineSums => "the windows' line sums (Radon transform)",
            InputForm::LineSumsShipsMasked => "the windows' line sums (Radon transform), ships' returns masked out",
        },
        match p.head {
            ClassifierHead::Flatten => "",
            ClassifierHead::GlobalMax => ", its last map pooled to each channel's largest response",
        },
    );
    if let Some(dir) = &p.sea_images {
        let _ = writeln!(
            md,
            "Each training wake that shows was also drawn onto {} windows of the real images of `{}` (`--sea-images`), each beside the same real window without it (counted in `training_windows`).\n",
            super::real_sea::PER_WAKE,
            dir.display()
        );
    }
    if let Some(dir) = &p.wake_images {
        let _ = writeln!(
            md,
            "Training also took {} windows along each wake drawn on the real images of `{}` (`--wake-images`), and as many of the same images at least {} windows from every drawn wake, without a wake (counted in `training_windows`). Score the detectors on other images.\n",
            super::real_wakes::PER_WAKE,
            dir.display(),
            super::real_wakes::CLEAR_OF_WAKES
        );
    }
    let strong = match p.strong_targets {
        [0, 0] => String::new(),
        [few, many] => format!(" and {few}-{many} strong targets with their sidelobe crosses"),
    };
    let _ = writeln!(
        md,
        "Each detector's threshold holds {} alarm(s) per 1,000 km^2 on the calibration step's open sea with slicks (and on real sea, where given: below); \"unseen\" is open sea it was neither trained nor thresholded on. The look-alike test set is that unseen sea again with {}-{} ships without a wake{strong} per scene and an internal-wave packet, a rain cell and a current front each in {:.0} % of the scenes; its alarms within 500 m of a ship without a wake are counted apart as well. A wake is found when an alarm lies within 500 m of its track.\n",
        results.alarms_target,
        p.wakeless_ships[0],
        p.wakeless_ships[1],
        100.0 * p.look_alike_fraction,
    );
    for d in &results.detectors {
        if let Some(r) = &d.real_sea {
            let _ = writeln!(
                md,
                "The {:.2} km detector's threshold also holds that rate on the real sea of `--sea-images` ({:.0} km^2 in {} image(s) scanned), where the rate alone needs {:.4}: it is {:.4}, with {:.1} alarms per 1,000 km^2 there.\n",
                d.footprint / 1000.0,
                r.km2,
                r.images,
                r.threshold,
                d.threshold,
                r.alarms_at_threshold
            );
            md += &strongest_sea_alarms(r);
        }
    }
    md += "Of the training windows cut on a wake's track (`track_windows`), `track_windows_wake_shows` are those in which the wake shows against the sea at the detector's spacing: a strip along the track, averaged over the window, whose change from the same sea without the ship exceeds 3 times the sea profile's strip-to-strip deviation (speckle after averaging, the sea's texture, its slicks). In the others only the ship at the wake's apex, if in view, sets the window apart. `track_visibility` is the wake's visibility in those windows as delivered, measured as on real images (below): its strongest strip within 150 m of the track against the strips beyond 250 m, in the sea profile's strip-to-strip deviations; quartiles, and the share above 3. `sea_visibility` is the same measure on the same windows of the sea without the ship: the measure's floor (the largest of a dozen strips of speckle and sea).\n\n";
    md += &format!("| {} |\n", HEADER.join(" | "));
    md += &format!("|{}\n", " --- |".repeat(HEADER.len()));
    for d in &results.detectors {
        md += &format!("| {} |\n", row(d).join(" | "));
    }
    md
}

/// The reliability diagram of every footprint's detector on the unseen seas' windows.
pub fn reliability_plot(results: &TransferResults) -> LinePlot {
    LinePlot {
        title: "Reliability, transfer detectors (unseen seas' windows)".into(),
        x_label: "mean wake probability in the bin".into(),
        y_label: "share of windows on a wake".into(),
        x_range: Some((0.0, 1.0)),
        y_range: Some((0.0, 1.0)),
        series: results
            .detectors
            .iter()
            .map(|d| Series {
                name: format!("{:.2} km", d.footprint / 1000.0),
                points: d
                    .reliability
                    .iter()
                    .filter_map(|b| Some((b.mean_score?, b.observed?)))
                    .collect(),
            })
            .collect(),
        diagonal: true,
        paired: false,
    }
}

/// The reliability section of the page: per detector, the bins and the expected calibration
/// error.
fn reliability_markdown(results: &TransferResults) -> String {
    let mut md = String::from(
        "\n## Calibration\n\nReliability of the probabilities on the unseen seas' windows: every window within half a window of a wake's track against every window of the open sea (as a scan of a scene with one wake meets them), in 10 bins; the probabilities are not temperature-scaled (temperature 1). ![reliability](transfer_reliability.svg)\n\n| detector | bin | windows | mean probability | share on a wake |\n| --- | --- | --- | --- | --- |\n",
    );
    for d in &results.detectors {
        for b in d.reliability.iter().filter(|b| b.count > 0) {
            let _ = writeln!(
                md,
                "| {:.2} km | {:.1}-{:.1} | {} | {:.3} | {:.3} |",
                d.footprint / 1000.0,
                b.lo,
                b.hi,
                b.count,
                b.mean_score.unwrap_or(f64::NAN),
                b.observed.unwrap_or(f64::NAN)
            );
        }
    }
    md += "\n";
    for d in &results.detectors {
        let _ = writeln!(
            md,
            "- {:.2} km: expected calibration error {:.3}.",
            d.footprint / 1000.0,
            d.calibration_error
        );
    }
    md
}

/// Write `report/transfer.md`, `report/transfer_reliability.svg` and
/// `report/tables/transfer.csv`, with the real images' section and
/// `report/tables/transfer_real.csv` where `real` scored them; the files written.
pub fn write_report(dir: &Path, results: &TransferResults, real: Option<&RealResults>) -> Result<Vec<PathBuf>> {
    let tables = dir.join("report").join("tables");
    std::fs::create_dir_all(&tables).map_err(|e| wakelab_core::WakelabError::io(&tables, e))?;
    let (md, table) = (dir.join("report").join("transfer.md"), tables.join("transfer.csv"));
    let plot = dir.join("report").join("transfer_reliability.svg");
    write_atomically(&plot, reliability_plot(results).to_svg().as_bytes())?;
    let mut text = markdown(results) + &reliability_markdown(results);
    let mut written = vec![md.clone(), plot, table.clone()];
    if let Some(real) = real {
        text += &real_report::markdown(real);
        let real_table = tables.join("transfer_real.csv");
        write_atomically(&real_table, real_report::csv(real).as_bytes())?;
        written.push(real_table);
        if !real.search.is_empty() {
            let search_table = tables.join("transfer_real_search.csv");
            write_atomically(&search_table, real_report::search_csv(real).as_bytes())?;
            written.push(search_table);
        }
    }
    write_atomically(&md, text.as_bytes())?;
    write_atomically(&table, csv(results).as_bytes())?;
    Ok(written)
}

//! The report's tables and figure of the calibration step ([`crate::steps::calibration`]): each
//! detector's temperature and calibration error on its test chips, the C-band detectors' alarms
//! on simulated open sea with look-alikes and the wakes they find at the study's threshold and
//! at the threshold set for the stated alarm rate, and the reliability diagram.

use super::svg::{LinePlot, Series};
use super::table::{Cell, Table};
use crate::steps::calibration::{CalibrationResults, DetectorCalibration, FOUND_WITHIN_M};
use wakelab_learn::calibration::ReliabilityBin;

/// Each detector's temperature and its test chips' calibration error before and after.
pub fn calibration_table(results: &CalibrationResults) -> Table {
    let rows = results
        .detectors
        .iter()
        .map(|d| {
            vec![
                d.input.name().into(),
                d.architecture.name().into(),
                Cell::number(d.temperature, 2),
                Cell::count(d.test_chips),
                Cell::number(d.ece_raw, 3),
                Cell::number(d.ece_calibrated, 3),
                Cell::number(d.brier_raw, 3),
                Cell::number(d.brier_calibrated, 3),
            ]
        })
        .collect();
    Table {
        id: "calibration".into(),
        title: "Calibrated probabilities".into(),
        caption: "Each saved detector's temperature T (its logit divided by T; T > 1: it was over-confident), \
                  fitted on its own test chips, and the expected calibration error (ECE, 10 bins) and Brier \
                  score of all repetitions' test chips before and after, each chip scaled by a temperature \
                  fitted on the other half of its repetition's chips. Scaling keeps the order of the scores: \
                  MCC at 0.5 and AUC are unchanged."
            .into(),
        header: [
            "input",
            "network",
            "T",
            "test chips",
            "ECE raw",
            "ECE calibrated",
            "Brier raw",
            "Brier calibrated",
        ]
        .map(String::from)
        .to_vec(),
        rows,
    }
}

/// Alarms per 1,000 km^2 with their count on the area.
fn rate(per_1000: f64, km2: f64) -> Cell {
    let count = (per_1000 * km2 / 1000.0).round() as usize;
    Cell::number(per_1000, 2).and("count", count.to_string(), format!("{per_1000:.2} ({count})"))
}

/// The C-band detectors on open sea with look-alikes; None without such a detector.
pub fn open_sea_table(results: &CalibrationResults) -> Option<Table> {
    let rows: Vec<Vec<Cell>> = results
        .detectors
        .iter()
        .filter_map(|d| d.open_sea.as_ref().map(|o| (d, o)))
        .map(|(d, o)| {
            vec![
                d.architecture.name().into(),
                rate(o.alarms_at_study_threshold, o.km2),
                Cell::count_of(o.wakes_found_at_study_threshold, o.scenes),
                rate(o.off_wake_alarms_at_study_threshold, o.km2),
                Cell::number(o.threshold, 4),
                rate(o.alarms_at_threshold, o.km2),
                Cell::count_of(o.wakes_found, o.scenes),
                rate(o.off_wake_alarms, o.km2),
            ]
        })
        .collect();
    let first = results.detectors.iter().find_map(|d| d.open_sea.as_ref())?;
    Some(Table {
        id: "open_sea_alarms".into(),
        title: "Alarms on open sea and the threshold for a stated rate (C band)".into(),
        caption: format!(
            "The C-band detectors, calibrated, scan {} simulated scenes of 5.12 km ({:.0} km^2) of open sea \
             with look-alikes (natural slicks over 5-30 % of the sea in long thin filaments, wind varying by \
             up to 30 %; winds 4-10 m/s, any look), windows at half their side apart; an alarm is a window \
             above the threshold that overlaps no stronger one. Then the same seas with a ship and its wake: \
             a wake is found when an alarm lies within {FOUND_WITHIN_M:.0} m of its track. At the study's \
             threshold {}, and at the least threshold that holds {} alarm per 1,000 km^2 on the open sea \
             (stored in `detectors/C_<network>.safetensors`, which `wakelab detect --model` reads). Alarm \
             rates per 1,000 km^2, their counts in brackets.",
            first.scenes, first.km2, first.study_threshold, results.alarms_target
        ),
        header: [
            "network",
            "open-sea alarms at 0.5",
            "wakes found at 0.5",
            "alarms off the wake at 0.5",
            "threshold for the rate",
            "open-sea alarms",
            "wakes found",
            "alarms off the wake",
        ]
        .map(String::from)
        .to_vec(),
        rows,
    })
}

fn points(bins: &[ReliabilityBin]) -> Vec<(f64, f64)> {
    bins.iter().filter_map(|b| Some((b.mean_score?, b.observed?))).collect()
}

/// The reliability diagram of the single-band `band` detectors: observed wake share against
/// the mean probability per bin, calibrated (solid) and raw (dashed).
pub fn reliability_plot(results: &CalibrationResults, band: &str) -> Option<LinePlot> {
    let detectors: Vec<&DetectorCalibration> = results.detectors.iter().filter(|d| d.input.name() == band).collect();
    if detectors.is_empty() {
        return None;
    }
    let series = detectors
        .iter()
        .flat_map(|d| {
            [
                Series {
                    name: format!("{} calibrated", d.architecture.name()),
                    points: points(&d.bins_calibrated),
                },
                Series {
                    name: format!("{} raw", d.architecture.name()),
                    points: points(&d.bins_raw),
                },
            ]
        })
        .collect();
    Some(LinePlot {
        title: format!("Reliability, {band} band test chips"),
        x_label: "mean wake probability in the bin".into(),
        y_label: "share of wake chips".into(),
        x_range: Some((0.0, 1.0)),
        y_range: Some((0.0, 1.0)),
        series,
        diagonal: true,
        paired: true,
    })
}

/// What the windows' own normalisation does on the open sea (C band); None without such a
/// detector.
pub fn window_normalisation_table(results: &CalibrationResults) -> Option<Table> {
    let rows: Vec<Vec<Cell>> = results
        .detectors
        .iter()
        .filter_map(|d| d.open_sea.as_ref().map(|o| (d, &o.normalisation)))
        .map(|(d, w)| {
            let optional = |v: Option<f64>| v.map_or(Cell::Missing, |v| Cell::number(v, 2));
            vec![
                d.architecture.name().into(),
                optional(w.rho_spread_probability),
                Cell::number(w.probability_least_spread, 2),
                Cell::number(w.probability_most_spread, 2),
                Cell::number(w.spread_open_sea, 2),
                Cell::number(w.spread_on_wake, 2),
                Cell::number(w.probability_open_sea, 2),
                Cell::number(w.probability_on_wake, 2),
                optional(w.auc_probability),
                optional(w.auc_spread),
            ]
        })
        .collect();
    let (first, w) = results
        .detectors
        .iter()
        .find_map(|d| d.open_sea.as_ref().map(|o| (o, &o.normalisation)))?;
    Some(Table {
        id: "window_normalisation".into(),
        title: "What each window's own normalisation does on open sea (C band)".into(),
        caption: format!(
            "Each window is normalised by the median and robust spread (1.4826 MAD) of its own dB, which \
             stretches a window of plain sea to the contrast of a wake window. The same scans as the table \
             above: {} open-sea windows of {} scenes, and {} windows whose centre lies within half a window \
             of a wake's track. Spearman's rho of an open-sea window's spread and its probability; the mean \
             probability of the fifth of open-sea windows of least and of most spread; the median spread (dB) \
             and probability of open-sea and wake windows; and the ROC AUC of wake against open-sea windows \
             by the probability and by the spread alone.",
            w.open_sea_windows, first.scenes, w.wake_windows
        ),
        header: [
            "network",
            "rho(spread, p)",
            "p, least spread",
            "p, most spread",
            "spread open sea (dB)",
            "spread on wake (dB)",
            "p open sea",
            "p on wake",
            "AUC by p",
            "AUC by spread",
        ]
        .map(String::from)
        .to_vec(),
        rows,
    })
}

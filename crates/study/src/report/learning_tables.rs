//! The learning tables: Tables 4.4-4.6 and 5.1-5.3 with the paper's own numbers beside ours,
//! SAR + IR fusion, confusion counts and the wall time of every step.

use super::table::{Cell, Table};
use crate::steps::StudyRun;
use wakelab_learn::evaluate::Summary;
use wakelab_learn::models::Architecture;
use wakelab_schema::band::{Band, Input};
use wakelab_schema::fusion_row::{Method, Source};

/// The paper's MCC and accuracy (Tables 4.4-4.6 and 5.1-5.3) for a row of ours.
pub fn paper_value(architecture: Architecture, row: &str) -> Option<(f64, f64)> {
    use Architecture::*;
    Some(match (architecture, row) {
        (Base, "C") => (0.81, 0.91),
        (Base, "S") => (0.29, 0.61),
        (Base, "X") => (0.48, 0.73),
        (Cls, "C") => (0.89, 0.94),
        (Cls, "S") => (0.17, 0.54),
        (Cls, "X") => (0.25, 0.56),
        (Unet, "C") => (1.00, 1.00),
        (Unet, "S") => (0.83, 0.91),
        (Unet, "X") => (0.89, 0.94),
        (Base, "S+X") => (0.26, 0.63),
        (Base, "Bayes classifier (S, X)") => (0.57, 0.74),
        (Base, "Dempster-Shafer (S, X)") => (0.43, 0.66),
        (Cls, "S+X") => (0.20, 0.59),
        (Cls, "Bayes classifier (S, X)") => (0.27, 0.60),
        (Cls, "Dempster-Shafer (S, X)") => (0.21, 0.54),
        (Unet, "S+X") => (0.97, 0.99),
        (Unet, "Bayes classifier (S, X)") => (1.00, 1.00),
        (Unet, "Dempster-Shafer (S, X)") => (0.89, 0.94),
        _ => return None,
    })
}

fn paper_cells(architecture: Architecture, row: &Source) -> [Cell; 2] {
    match paper_value(architecture, &row.to_string()) {
        Some((mcc, acc)) => [Cell::number(mcc, 2), Cell::percent(acc, 0)],
        None => [Cell::Missing, Cell::Missing],
    }
}

fn auc(s: &Summary) -> Cell {
    s.roc_auc.map_or(Cell::Missing, |a| Cell::number(a, 2))
}

/// Test MCC, mean ± sample standard deviation over the repetitions.
pub(crate) fn mcc_cell(s: &Summary) -> Cell {
    Cell::mean_std(s.mcc, s.mcc_spread, s.repetitions, false)
}

/// Test accuracy, mean ± sample standard deviation over the repetitions.
fn accuracy_cell(s: &Summary) -> Cell {
    Cell::mean_std(s.accuracy, s.accuracy_spread, s.repetitions, true)
}

fn conflict_cell(conflict: Option<f64>) -> Cell {
    conflict.map_or(Cell::Missing, |k| Cell::number(k, 3))
}

fn is_dempster_shafer(s: &Summary) -> bool {
    s.bands.fusion().is_some_and(|f| f.method == Method::DempsterShafer)
}

/// The spec's table number of an architecture's single-band table and fusion table.
fn table_numbers(a: Architecture) -> (&'static str, &'static str) {
    match a {
        Architecture::Base => ("4.4", "5.1"),
        Architecture::Cls => ("4.5", "5.2"),
        Architecture::Unet => ("4.6", "5.3"),
    }
}

/// Tables 4.4-4.6: every input of one architecture.
pub(crate) fn single_input_table(run: &StudyRun, a: Architecture) -> Table {
    let (number, _) = table_numbers(a);
    let rows = run
        .inputs
        .iter()
        .filter_map(|input| run.summaries.iter().find(|s| s.bands == *input && s.architecture == a))
        .map(|s| {
            let [pm, pa] = paper_cells(a, &s.bands);
            vec![
                s.bands.to_string().into(),
                mcc_cell(s),
                accuracy_cell(s),
                auc(s),
                pm,
                pa,
            ]
        })
        .collect();
    Table {
        id: format!("table_{}_{a}", number.replace('.', "_")),
        title: format!("Table {number}: \"{a}\" classifier, per input"),
        caption: format!(
            "Test MCC and accuracy, mean ± sample standard deviation over {} repetitions of Algorithm 2; \
             ROC AUC of the pooled test outputs. Inputs with + are bands as channels (feature-level fusion). \
             The paper's columns are its Table {number} (S, C, X) and Table {} (S+X).",
            run.plan.repetitions,
            table_numbers(a).1
        ),
        header: ["input", "MCC", "accuracy", "AUC", "paper MCC", "paper accuracy"]
            .map(String::from)
            .to_vec(),
        rows,
    }
}

/// Tables 5.1-5.3: feature- and decision-level fusion of one architecture.
pub(crate) fn fusion_table(run: &StudyRun, a: Architecture) -> Table {
    let (_, number) = table_numbers(a);
    let mut rows = Vec::new();
    for input in run.inputs.iter().filter(|i| i.is_fused()) {
        if let Some(s) = run.summaries.iter().find(|s| s.bands == *input && s.architecture == a) {
            rows.push(fusion_row(a, s, "feature level", None));
        }
    }
    for (s, k) in run.fusion.iter().filter(|(s, _)| s.architecture == a) {
        let conflict = is_dempster_shafer(s).then_some(*k);
        rows.push(fusion_row(a, s, "decision level", conflict));
    }
    Table {
        id: format!("table_{}_{a}", number.replace('.', "_")),
        title: format!("Table {number}: fusion with the \"{a}\" classifier"),
        caption: format!(
            "Feature level: one classifier on bands as channels. Decision level: the single-band \
             classifiers' test outputs of each repetition fused by the Bayes classifier (each source \
             weighted by its TP/FP/TN/FN on its own training images, erratum 11) or by Dempster's rule \
             (pignistic probability of wake, with the mean conflict k). Mean ± sample standard deviation \
             over {} repetitions; the paper's columns are its Table {number}.",
            run.plan.repetitions
        ),
        header: [
            "fusion",
            "level",
            "MCC",
            "accuracy",
            "mean conflict k",
            "paper MCC",
            "paper accuracy",
        ]
        .map(String::from)
        .to_vec(),
        rows,
    }
}

fn fusion_row(a: Architecture, s: &Summary, level: &str, conflict: Option<f64>) -> Vec<Cell> {
    let [pm, pa] = paper_cells(a, &s.bands);
    vec![
        s.bands.to_string().into(),
        level.into(),
        mcc_cell(s),
        accuracy_cell(s),
        conflict_cell(conflict),
        pm,
        pa,
    ]
}

/// Every fusion involving an infrared band (the spec's 5.4 and future work).
pub(crate) fn sar_ir_table(run: &StudyRun) -> Table {
    let mut rows = Vec::new();
    for a in Architecture::ALL {
        for input in run.inputs.iter().filter(|i| i.is_fused() && i.has_infrared()) {
            if let Some(s) = run.summaries.iter().find(|s| s.bands == *input && s.architecture == a) {
                rows.push(sar_ir_row(a, s, "feature level", None));
            }
        }
        for (s, k) in run
            .fusion
            .iter()
            .filter(|(s, _)| s.architecture == a && s.bands.has_infrared())
        {
            rows.push(sar_ir_row(a, s, "decision level", is_dempster_shafer(s).then_some(*k)));
        }
        for band in [Band::C, Band::Mwir, Band::Lwir] {
            if let Some(s) = run
                .summaries
                .iter()
                .find(|s| s.bands == Input::single(band) && s.architecture == a)
            {
                rows.push(sar_ir_row(a, s, "single band", None));
            }
        }
    }
    Table {
        id: "sar_ir_fusion".into(),
        title: "SAR + IR fusion".into(),
        caption: "Radar and infrared together (spec 5.4, future work of 6.2): C-band SAR with LWIR as \
                  channels of one input, decision-level fusion of C with LWIR and of all five bands, \
                  beside the single bands they combine. The paper has no numbers for these."
            .into(),
        header: ["architecture", "input", "level", "MCC", "accuracy", "mean conflict k"]
            .map(String::from)
            .to_vec(),
        rows,
    }
}

fn sar_ir_row(a: Architecture, s: &Summary, level: &str, conflict: Option<f64>) -> Vec<Cell> {
    vec![
        a.to_string().into(),
        s.bands.to_string().into(),
        level.into(),
        mcc_cell(s),
        accuracy_cell(s),
        conflict_cell(conflict),
    ]
}

/// Every row's counts summed over the repetitions.
pub fn confusion_rows(run: &StudyRun) -> Vec<Summary> {
    let mut rows: Vec<Summary> = Vec::new();
    for a in Architecture::ALL {
        rows.extend(run.summaries.iter().filter(|s| s.architecture == a).cloned());
        rows.extend(
            run.fusion
                .iter()
                .filter(|(s, _)| s.architecture == a)
                .map(|(s, _)| s.clone()),
        );
    }
    rows
}

pub(crate) fn confusion_table(run: &StudyRun) -> Table {
    Table {
        id: "confusion".into(),
        title: "Confusion counts".into(),
        caption: "True/false positives and negatives of the test images, summed over the repetitions \
                  (positive: wake)."
            .into(),
        header: ["architecture", "input or fusion", "TP", "FN", "FP", "TN"]
            .map(String::from)
            .to_vec(),
        rows: confusion_rows(run)
            .iter()
            .map(|s| {
                vec![
                    s.architecture.to_string().into(),
                    s.bands.to_string().into(),
                    Cell::count(s.tp as usize),
                    Cell::count(s.fn_ as usize),
                    Cell::count(s.fp as usize),
                    Cell::count(s.tn as usize),
                ]
            })
            .collect(),
    }
}

pub(crate) fn timing_table(run: &StudyRun) -> Table {
    let total = |f: fn(&crate::StepTime) -> f64| Cell::number(run.times.iter().map(f).sum::<f64>(), 1);
    Table {
        id: "timing".into(),
        title: "Wall time per step".into(),
        caption: "Seconds of this run; a reused step shows the time it took when it was computed.".into(),
        header: ["step", "this run (s)", "computed in (s)", "reused"]
            .map(String::from)
            .to_vec(),
        rows: run
            .times
            .iter()
            .map(|t| {
                vec![
                    t.step.clone().into(),
                    Cell::number(t.seconds, 1),
                    Cell::number(t.computed_seconds, 1),
                    if t.reused { "yes" } else { "no" }.into(),
                ]
            })
            .chain(std::iter::once(vec![
                "total".into(),
                total(|t| t.seconds),
                total(|t| t.computed_seconds),
                Cell::Missing,
            ]))
            .collect(),
    }
}

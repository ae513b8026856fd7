//! `wakelab train` and `wakelab eval`: the learning step on a dataset directory; the study crate
//! trains and writes ([`wakelab_study::learning`]), this draws the progress and prints.

use crate::cli::{EvalArgs, TrainArgs};
use crate::Result;
use indicatif::ProgressBar;
use wakelab_study::learning::{eval_command, summary_table, train_command};

/// A bar of epochs, and what advances it by one epoch (the epochs in all, what was trained).
fn epoch_bar(quiet: bool) -> (ProgressBar, impl FnMut(u64, String) + Send) {
    let template = "{spinner} {msg} [{bar:30}] {pos}/{len} epochs | {elapsed_precise}, {eta} left";
    let bar = wakelab_study::progress_bar(quiet, 0, template);
    let shown = bar.clone();
    let advance = move |total, message| {
        shown.set_length(total);
        shown.inc(1);
        shown.set_message(message);
    };
    (bar, advance)
}

/// `wakelab eval`: Algorithm 2 on a dataset.
pub fn run_eval(eval: &EvalArgs, quiet: bool) -> Result<()> {
    let (bar, mut advance) = epoch_bar(quiet);
    let request = eval.learn.request();
    let (arch, reps, study) = (&eval.arch, eval.repetitions, eval.study.as_deref());
    let done = eval_command(&request, arch, reps, study, &mut advance)?;
    bar.finish_and_clear();
    if eval.json {
        println!("{}", serde_json::to_string_pretty(&done.evaluation.summaries)?);
        return Ok(());
    }
    print!("{}", summary_table(&done.evaluation.summaries));
    if !done.fusion.is_empty() {
        println!("\ndecision-level fusion (Bayes weights from each source's training images):");
        let fused: Vec<_> = done.fusion.iter().map(|(s, _)| s.clone()).collect();
        print!("{}", summary_table(&fused));
    }
    eprintln!(
        "wrote outputs, metrics, curves, fusion and models into {}",
        done.dir.display()
    );
    Ok(())
}

/// `wakelab train`: one detector on the dataset's training split, tested on its test split.
pub fn run_train(train: &TrainArgs, quiet: bool) -> Result<()> {
    let (bar, mut advance) = epoch_bar(quiet);
    let request = train.learn.request();
    let trained = train_command(&request, train.arch, train.model.as_deref(), &mut advance)?;
    bar.finish_and_clear();
    eprintln!(
        "saved {} (PyTorch layout: {})",
        trained.path.display(),
        trained.export.display()
    );
    if let Some((n, c, auc)) = trained.test {
        let auc = auc.map(|a| format!("{a:.3}")).unwrap_or_else(|| "-".into());
        println!("test split ({n} scenes): {c}, AUC {auc}");
    }
    Ok(())
}

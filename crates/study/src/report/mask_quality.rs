//! The report's table of the U-Net's wake masks against the physics masks: how much
//! of each test wake the "unet" detector's mask covers, per input.

use super::table::{Cell, Table};
use crate::steps::StudyRun;
use wakelab_learn::masks::{summarise_masks, MASK_LEVEL};

/// Mean IoU (± sample standard deviation over repetitions), the share of masks reaching IoU 0.5 and the number
/// of test wake scenes, per input.
pub fn mask_iou_table(run: &StudyRun) -> Table {
    let rows = run
        .inputs
        .iter()
        .map(|input| {
            let mut row: Vec<Cell> = vec![input.to_string().into()];
            match summarise_masks(&run.mask_scores, input) {
                Some((mean, spread, share, scenes)) => row.extend([
                    Cell::mean_std(mean, spread, run.plan.repetitions, false),
                    Cell::percent(share, 0),
                    Cell::count(scenes),
                ]),
                None => row.extend([Cell::Missing, Cell::Missing, Cell::count(0)]),
            }
            row
        })
        .collect();
    Table {
        id: "mask_iou".into(),
        title: "U-Net wake masks against the physics masks".into(),
        caption: format!(
            "Intersection over union of the \"unet\" detector's U-Net mask and the scene's physics \
             wake mask (both above {MASK_LEVEL}), over the test wake scenes of every repetition: \
             mean ± standard deviation of the repetitions' means, and the share of scenes whose mask reaches \
             IoU 0.5. A fused input's truth is its first band's mask. Not in the spec, which judges \
             the U-Net only through its classifier."
        ),
        header: ["input", "mean IoU", "IoU ≥ 0.5", "test wake scenes"]
            .map(String::from)
            .to_vec(),
        rows,
    }
}

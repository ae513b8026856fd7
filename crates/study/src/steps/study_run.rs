//! What the learning steps of a study run produced, together, for the scan step and the report.

use crate::StepTime;
use wakelab_dataset::learning::LearningPlan;
use wakelab_fusion::decision::FusedOutput;
use wakelab_learn::data::Dataset;
use wakelab_learn::evaluate::{CurvePoint, Output, Summary};
use wakelab_learn::masks::MaskScore;
use wakelab_learn::robustness::Perturbation;
use wakelab_schema::band::Input;

/// Everything a study run produced, for the report.
pub struct StudyRun {
    pub dataset: Dataset,
    pub plan: LearningPlan,
    /// Inputs evaluated: single bands, then the feature-level fusions.
    pub inputs: Vec<Input>,
    /// Kept outputs of every input: train, test and perturbed test splits.
    pub outputs: Vec<Output>,
    pub curves: Vec<CurvePoint>,
    /// The U-Net masks' IoU on the test wake scenes of every input.
    pub mask_scores: Vec<MaskScore>,
    /// Test metrics per input and architecture (Tables 4.4-4.6, 5.1's feature-level rows).
    pub summaries: Vec<Summary>,
    pub perturbations: Vec<Perturbation>,
    /// The held-out axis's values, one per group, and the held-out outputs.
    pub held_out_groups: Vec<String>,
    pub held_out: Vec<Output>,
    /// The held-out geometry bins ("heading in [0, 90)") and their outputs.
    pub held_out_geometry_groups: Vec<String>,
    pub held_out_geometry: Vec<Output>,
    /// Decision-level fusion: fused outputs and their metrics with the mean conflict.
    pub fused: Vec<FusedOutput>,
    pub fusion: Vec<(Summary, f64)>,
    pub times: Vec<StepTime>,
    /// When the run started (UTC) and the device it trained on, for the report's header.
    pub started: String,
    pub device: String,
}

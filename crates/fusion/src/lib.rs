//! wakelab-fusion: stage 6 of the pipeline (spec chapter 5). This first part holds the
//! decision-level rules: the Bayes classifier of Eqs. (5.1)-(5.5) and Dempster-Shafer
//! combination (Eq. (5.6)) with belief, plausibility (erratum 10), conflict and the pignistic
//! probability.

pub mod bayes;
pub mod decision;
pub mod dempster;

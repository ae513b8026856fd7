//! The report's table of the spec's environments, from what the environments step wrote
//! ([`crate::steps::environments`]), beside what the spec's Figs. 3.1-3.2 show.

use super::table::{Cell, Table};
use crate::steps::environments::{EnvironmentContrast, VISIBLE_DB};
use wakelab_core::config::NamedDirection;
use wakelab_core::units::RadarBand;

/// What the spec's figures show for `band` in `environment` (Fig. 3.2 is C band only; Fig. 3.1,
/// the three bands, does not state its swell).
pub fn spec_figure(environment: NamedDirection, band: RadarBand) -> &'static str {
    match (band, environment) {
        (RadarBand::C, NamedDirection::Calm) => "Fig. 3.2: no noticeable persistent wake",
        (RadarBand::C, _) => "Fig. 3.2: wake visible; Fig. 3.1: bright streak",
        (RadarBand::S, _) => "Fig. 3.1 (swell not stated): bright, with a dark outline",
        (RadarBand::X, _) => "Fig. 3.1 (swell not stated): bright streak",
    }
}

/// The table of the spec's environments ([`crate::steps::environments::spec_environments`]).
pub fn environment_table(rows: &[EnvironmentContrast], along_track: f64) -> Table {
    Table {
        id: "spec_environments".into(),
        title: "The spec's environments: bright or dark".into(),
        caption: format!(
            "The study's base sea, wind, ship and sensors (a perfect SAR, no slicks) without swell, with head \
             swell and with following swell (the spec's Fig. 3.2), {along_track:.0} m behind the stern: the \
             darkest and brightest row across the wake, wake scene over no-wake scene. A wake brightens \
             where its converging currents' refraction source R beats its extra damping d (steady state \
             mu / (mu + d - R) > 1): R is the largest across the wake, d and the Bragg waves' relaxation \
             rate mu are where R is largest. \"none\": within {VISIBLE_DB} dB."
        ),
        header: [
            "environment",
            "band",
            "darkest (dB)",
            "brightest (dB)",
            "wakelab",
            "spec",
            "R (1/s)",
            "d (1/s)",
            "mu (1/s)",
        ]
        .map(String::from)
        .to_vec(),
        rows: rows
            .iter()
            .map(|r| {
                vec![
                    format!("{:?}", r.environment).to_lowercase().into(),
                    r.band.name().into(),
                    Cell::signed(r.darkest_db, 2),
                    Cell::signed(r.brightest_db, 2),
                    r.verdict().into(),
                    spec_figure(r.environment, r.band).into(),
                    Cell::scientific(r.refraction, 1),
                    Cell::scientific(r.damping, 1),
                    Cell::scientific(r.relaxation, 1),
                ]
            })
            .collect(),
    }
}

//! The report's whole-scene detection: the table and pictures of what the scan step wrote
//! ([`crate::steps::whole_scene`]).

use super::pictures::{display_values, field_png, stretch};
use super::table::{Cell, Table};
use crate::steps::whole_scene::{WholeScene, CHIP_FALSE_ALARMS, SLICKS};
use crate::Result;
use std::fmt::Write as _;

/// A share as a whole percentage, missing when there is none.
fn percent(share: Option<f64>) -> Cell {
    share.map_or(Cell::Missing, |v| Cell::percent(v, 0))
}

/// The scans as a table, one row per band.
pub fn whole_scene_table(scans: &[WholeScene]) -> Table {
    let rows = scans
        .iter()
        .map(|w| &w.numbers)
        .map(|w| {
            vec![
                w.band.to_string().into(),
                Cell::number(w.probability, 2),
                if w.peak_on_wake { "yes" } else { "no" }.into(),
                w.mean_on_wake.map_or(Cell::Missing, |m| Cell::number(m, 2)),
                w.mean_off_wake.map_or(Cell::Missing, |m| Cell::number(m, 2)),
                Cell::percent(w.false_alarm_cells, 0),
                w.chip_threshold.map_or(Cell::Missing, |c| Cell::number(c.threshold, 2)),
                percent(w.chip_threshold.map(|c| c.false_alarm_cells)),
                percent(w.chip_threshold.map(|c| c.wake_cells)),
                percent(w.chip_threshold.and_then(|c| c.slick_cells)),
                percent(w.chip_threshold.map(|c| c.open_sea_cells)),
            ]
        })
        .collect();
    let Some(first) = scans.first().map(|w| &w.numbers) else {
        return Table {
            id: "whole_scene".into(),
            title: "Detection on a whole scene".into(),
            caption: "Not run: the study's simulated wake is too short for a scene of two chips or more.".into(),
            header: vec!["band".into()],
            rows: Vec::new(),
        };
    };
    Table {
        id: "whole_scene".into(),
        title: "Detection on a whole scene".into(),
        caption: format!(
            "The study's first pair's sea made {chips} chips wide ({side} x {side} px of {dx} m), natural slicks \
             over {slicks:.0}% of it and {count} wake(s) of the study's ship ({wakes}), scanned by each band's \
             \"base\" detector (its last repetition) with windows of its input at half that stride. Cells on the \
             wake hold a pixel of the band's physics mask (all wakes); a false-alarm cell is an off-wake cell at \
             or above the threshold ({threshold}). The chips' threshold is the one that flags {chips_fa:.0}% of the \
             detector's no-wake test chips (the same repetition's): the share of off-wake cells above it says \
             whether that false-alarm rate holds on a whole scene, the share of wake cells above it what is found; \
             the off-wake cells are split into those holding a natural slick's pixel and the open sea.",
            chips = first.chips,
            side = first.side,
            dx = first.pixel_spacing,
            slicks = 100.0 * SLICKS,
            count = first.wakes.len(),
            wakes = first
                .wakes
                .iter()
                .map(|w| format!(
                    "{:.1} km behind the stern, course {:.0} degrees, {:.0} m off the centre",
                    w.along_track / 1000.0,
                    w.heading,
                    w.cross_track.abs()
                ))
                .collect::<Vec<_>>()
                .join("; "),
            threshold = first.threshold,
            chips_fa = 100.0 * CHIP_FALSE_ALARMS,
        ),
        header: [
            "band",
            "scene probability",
            "peak on the wake",
            "mean on the wake",
            "mean off the wake",
            "false-alarm cells",
            "chips' 5% threshold",
            "false-alarm cells there",
            "wake cells there",
            "slick cells flagged there",
            "open-sea cells flagged there",
        ]
        .map(String::from)
        .to_vec(),
        rows,
    }
}

/// The scans as HTML: per band, the image, the probability map and the wake mask.
pub fn whole_scene_html(scans: &[WholeScene]) -> Result<String> {
    let mut s = String::new();
    for scan in scans {
        let w = &scan.numbers;
        let caption = format!("{0} x {0} px", w.side);
        let units = if w.band.is_radar() { "dB" } else { "K" };
        let display = display_values(&scan.image, w.band.is_radar());
        let map: Vec<f32> = scan.map.iter().copied().collect();
        let mask: Vec<f32> = scan.mask.iter().map(|&m| f32::from(m)).collect();
        let square = (w.side, w.side);
        let _ = write!(s, "<h4>{}</h4><div class=\"grid\">", w.band);
        for (values, shape, title, units, range) in [
            (&display, square, "scene", units, stretch(&display)),
            (&map, scan.map.dim(), "wake probability", "probability", (0.0, 1.0)),
            (&mask, square, "wake mask", "1 = wake", (0.0, 1.0)),
        ] {
            let title = format!("{} {title}", w.band);
            let png = field_png(values, shape, title.clone(), units, (256, &caption), range)?;
            let _ = write!(s, "<figure><img alt=\"{title}\" src=\"{png}\"></figure>");
        }
        s.push_str("</div>");
    }
    Ok(s)
}

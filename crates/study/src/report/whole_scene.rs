//! The report's whole-scene detection: the table and pictures of what the scan step wrote
//! ([`crate::steps::whole_scene`]).

use super::figure::{Figure, Legend, Mark};
use super::pictures::{display_values, stretch};
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

/// The map's cells at or above `threshold`, as boxes in the pixels of a field of `side`.
fn flagged_cells(map: &ndarray::Array2<f32>, threshold: f64, side: usize) -> Vec<Mark> {
    let (rows, cols) = map.dim();
    let (ch, cw) = (side as f64 / rows as f64, side as f64 / cols as f64);
    map.indexed_iter()
        .filter(|(_, &p)| p as f64 >= threshold)
        .map(|((r, c), _)| (r as f64 * ch, c as f64 * cw, ch, cw))
        .collect()
}

/// The scans as HTML: per band, the image and the probability map with the cells the chips'
/// threshold flags drawn on both, and the wake mask; each with a scale bar.
pub fn whole_scene_html(scans: &[WholeScene]) -> Result<String> {
    let mut s = String::new();
    for scan in scans {
        let w = &scan.numbers;
        let caption = format!("{0} x {0} px of {1} m", w.side, w.pixel_spacing);
        let units = if w.band.is_radar() {
            "sigma0 (dB)"
        } else {
            "brightness temperature (K)"
        };
        let display = display_values(&scan.image, w.band.is_radar());
        let map: Vec<f32> = scan.map.iter().copied().collect();
        let mask: Vec<f32> = scan.mask.iter().map(|&m| f32::from(m)).collect();
        let square = (w.side, w.side);
        let (marks, marks_label) = match w.chip_threshold {
            Some(c) => (
                flagged_cells(&scan.map, c.threshold, w.side),
                format!("cells at or above the chips' threshold {:.2}", c.threshold),
            ),
            None => (Vec::new(), String::new()),
        };
        let map_cell = w.side as f64 / scan.map.ncols() as f64 * w.pixel_spacing;
        let _ = write!(s, "<h4>{}</h4><div class=\"grid\">", w.band);
        let mask_legend = || Legend::Mask {
            absent: "no wake".into(),
            present: "wake".into(),
        };
        let figures = [
            (
                &display,
                square,
                "scene",
                Legend::Continuous { units: units.into() },
                stretch(&display),
                w.pixel_spacing,
                true,
            ),
            (
                &map,
                scan.map.dim(),
                "wake probability",
                Legend::Continuous {
                    units: "probability".into(),
                },
                (0.0, 1.0),
                map_cell,
                true,
            ),
            (
                &mask,
                square,
                "wake mask",
                mask_legend(),
                (0.0, 1.0),
                w.pixel_spacing,
                false,
            ),
        ];
        for (values, shape, title, legend, range, spacing, marked) in figures {
            let scale = if shape == square {
                1.0
            } else {
                shape.1 as f64 / w.side as f64
            };
            let figure = Figure {
                values,
                shape,
                title: format!("{} {title}", w.band),
                legend,
                range,
                side: 280.0,
                caption: caption.clone(),
                pixel_spacing: Some(spacing),
                marks: if marked {
                    marks
                        .iter()
                        .map(|&(t, l, r, c)| (t * scale, l * scale, r * scale, c * scale))
                        .collect()
                } else {
                    Vec::new()
                },
                marks_label: marks_label.clone(),
            };
            let _ = write!(s, "<figure>{}</figure>", figure.svg()?);
        }
        s.push_str("</div>");
    }
    Ok(s)
}

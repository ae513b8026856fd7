//! The report's grid of test scenes: for every band and wind speed, the test scenes of
//! the first repetition that "base" scored highest and lowest among the wake scenes and among
//! the no-wake scenes, with every architecture's score and whether it decided right. Picked by
//! score, not by hand, so the grid shows the detectors' clearest hits and their worst mistakes.

use super::table::{Cell as TableCell, Table};
use crate::steps::StudyRun;
use crate::Result;
use base64::Engine as _;
use image::{imageops, GrayImage, Luma};
use ndarray::Array2;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use wakelab_learn::models::Architecture;
use wakelab_schema::band::{Band, Input};
use wakelab_schema::dataset::SceneRecord;
use wakelab_schema::split::Split;

/// Side of a thumbnail in the HTML grid (pixels; nearest-neighbour upscaled).
const THUMBNAIL: u32 = 128;

/// Which of a wind speed's test scenes a grid cell shows: a wake or a no-wake scene, the one
/// "base" scored highest or lowest.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Case {
    wake: bool,
    highest: bool,
}

impl Case {
    const ALL: [Case; 4] = [
        Case {
            wake: true,
            highest: true,
        },
        Case {
            wake: true,
            highest: false,
        },
        Case {
            wake: false,
            highest: true,
        },
        Case {
            wake: false,
            highest: false,
        },
    ];

    fn label(self) -> u8 {
        u8::from(self.wake)
    }

    fn name(self) -> &'static str {
        match (self.wake, self.highest) {
            (true, true) => "wake (highest base score)",
            (true, false) => "wake (lowest base score)",
            (false, true) => "no wake (highest base score)",
            (false, false) => "no wake (lowest base score)",
        }
    }
}

/// One cell of the grid: a test scene and each architecture's score on it.
struct Cell<'a> {
    band: Band,
    case: Case,
    record: &'a SceneRecord,
    scores: Vec<(Architecture, f64)>,
}

/// The first repetition's test scores of single-band input `band`: scene id -> architecture -> score.
fn test_scores(run: &StudyRun, band: Band) -> BTreeMap<&str, BTreeMap<Architecture, f64>> {
    let input = Input::single(band);
    let mut scores: BTreeMap<&str, BTreeMap<Architecture, f64>> = BTreeMap::new();
    for o in run
        .outputs
        .iter()
        .filter(|o| o.bands == input && o.repetition == 0 && o.split == Split::Test)
    {
        scores
            .entry(o.scene.as_str())
            .or_default()
            .insert(o.architecture, o.output);
    }
    scores
}

/// The grid's cells, band by band, wind speed by wind speed, in [`Case::ALL`]'s order.
fn cells(run: &StudyRun) -> Vec<Cell<'_>> {
    let records: BTreeMap<&str, &SceneRecord> = run.dataset.records.iter().map(|r| (r.id.as_str(), r)).collect();
    let mut out = Vec::new();
    for band in run.inputs.iter().filter_map(|i| i.as_single()) {
        let scores = test_scores(run, band);
        let scored: Vec<(&SceneRecord, &BTreeMap<Architecture, f64>)> = scores
            .iter()
            .filter_map(|(id, s)| Some((*records.get(id)?, s)))
            .filter(|(_, s)| s.contains_key(&Architecture::Base))
            .collect();
        let mut winds: Vec<f64> = scored.iter().map(|(r, _)| r.parameters.wind_speed).collect();
        winds.sort_by(f64::total_cmp);
        winds.dedup();
        for wind in winds {
            for case in Case::ALL {
                let candidates = scored
                    .iter()
                    .filter(|(r, _)| r.parameters.wind_speed == wind && r.label == case.label());
                let base = |s: &&BTreeMap<Architecture, f64>| s[&Architecture::Base];
                let order = |a: &&(&SceneRecord, &BTreeMap<Architecture, f64>),
                             b: &&(&SceneRecord, &BTreeMap<Architecture, f64>)| {
                    base(&a.1).total_cmp(&base(&b.1)).then(b.0.id.cmp(&a.0.id))
                };
                let pick = if case.highest {
                    candidates.max_by(order)
                } else {
                    candidates.min_by(order)
                };
                if let Some((record, s)) = pick {
                    out.push(Cell {
                        band,
                        case,
                        record,
                        scores: s.iter().map(|(&a, &v)| (a, v)).collect(),
                    });
                }
            }
        }
    }
    out
}

/// "0.81 right" / "0.45 wrong" against the study's threshold.
fn verdict(score: f64, label: u8, threshold: f64) -> String {
    format!("{score:.2} {}", right_or_wrong(score, label, threshold))
}

fn right_or_wrong(score: f64, label: u8, threshold: f64) -> &'static str {
    if (score >= threshold) == (label == 1) {
        "right"
    } else {
        "wrong"
    }
}

/// The grid as a table: one row per cell, with the scene's conditions and each score.
pub fn test_scene_table(run: &StudyRun) -> Table {
    let threshold = run.plan.threshold;
    let rows = cells(run)
        .iter()
        .map(|c| {
            let p = &c.record.parameters;
            let mut row = vec![
                c.band.to_string().into(),
                TableCell::plain(p.wind_speed),
                c.case.name().into(),
                c.record.id.clone().into(),
                TableCell::number(p.incidence, 0),
                TableCell::number(p.along_track / 1000.0, 1),
                TableCell::number(c.record.visibility.get(&c.band).copied().unwrap_or(0.0), 2),
            ];
            for a in Architecture::ALL {
                row.push(
                    c.scores
                        .iter()
                        .find(|(x, _)| *x == a)
                        .map_or(TableCell::Missing, |&(_, v)| {
                            TableCell::number(v, 2).and(
                                "verdict",
                                right_or_wrong(v, c.case.label(), threshold).into(),
                                verdict(v, c.case.label(), threshold),
                            )
                        }),
                );
            }
            row
        })
        .collect();
    let mut header: Vec<String> = [
        "band",
        "wind (m/s)",
        "scene",
        "id",
        "incidence (deg)",
        "behind the stern (km)",
        "visibility",
    ]
    .map(String::from)
    .to_vec();
    header.extend(Architecture::ALL.iter().map(|a| format!("{a}")));
    Table {
        id: "test_scenes".into(),
        title: "Test scenes across conditions, with each detector's score".into(),
        caption: format!(
            "For each band and wind speed, the first repetition's test scenes that \"base\" scored highest \
             and lowest among the wake and among the no-wake scenes; each architecture's wake probability, \
             right or wrong at the threshold {threshold}. Visibility is the wake's contrast to clutter over \
             its mask; for a no-wake scene, the same measure under its pair's mask (what chance alone \
             shows). The HTML report shows the images."
        ),
        header,
        rows,
    }
}

/// A thumbnail of a scene's image in `band` (radar in dB), stretched over its 2nd-98th percentile.
fn thumbnail(run: &StudyRun, record: &SceneRecord, band: Band) -> Result<String> {
    let image: Array2<f32> = ndarray_npy::read_npy(run.dataset.dir.join(&record.images[&band]))?;
    let values = super::pictures::display_values(&image, band.is_radar());
    let (lo, hi) = super::pictures::stretch(&values);
    let (rows, cols) = image.dim();
    let small = GrayImage::from_fn(cols as u32, rows as u32, |x, y| {
        let v = (values[y as usize * cols + x as usize] as f64 - lo) / (hi - lo);
        Luma([(255.0 * v.clamp(0.0, 1.0)).round() as u8])
    });
    let big = imageops::resize(&small, THUMBNAIL, THUMBNAIL, imageops::FilterType::Nearest);
    let mut bytes = std::io::Cursor::new(Vec::new());
    big.write_to(&mut bytes, image::ImageFormat::Png)?;
    Ok(format!(
        "data:image/png;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(bytes.get_ref())
    ))
}

/// The grid as HTML: per band, one row of thumbnails per wind speed, each captioned with its
/// conditions and every architecture's verdict.
pub fn test_scene_grid(run: &StudyRun) -> Result<String> {
    let threshold = run.plan.threshold;
    let all = cells(run);
    if all.is_empty() {
        return Ok("<p>No single-band test outputs.</p>".into());
    }
    let mut s = String::new();
    for band in run.inputs.iter().filter_map(|i| i.as_single()) {
        let _ = write!(s, "<h4>{band}</h4><div class=\"grid\">");
        for c in all.iter().filter(|c| c.band == band) {
            let p = &c.record.parameters;
            let scores: Vec<String> = c
                .scores
                .iter()
                .map(|&(a, v)| format!("{a} {}", verdict(v, c.case.label(), threshold)))
                .collect();
            let _ = write!(
                s,
                "<figure><img alt=\"{id}\" src=\"{src}\"><figcaption>{case}<br>{wind} m/s, {inc:.0}°, {km:.1} km \
                 behind · {id}<br>{scores}</figcaption></figure>",
                id = c.record.id,
                src = thumbnail(run, c.record, band)?,
                case = c.case.name(),
                wind = p.wind_speed,
                inc = p.incidence,
                km = p.along_track / 1000.0,
                scores = scores.join(" · "),
            );
        }
        s.push_str("</div>");
    }
    Ok(s)
}

//! The report's table of the ships step ([`crate::steps::ships`]): the classic ship and wake
//! detectors against the truth of simulated scenes, with the targets they are held to.

use super::table::{Cell, Table};
use crate::steps::ships::{SceneResult, ShipsResults};

/// The median of `values` (None when empty).
fn median(mut values: Vec<f64>) -> Option<f64> {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    (n > 0).then(|| {
        if n % 2 == 1 {
            values[n / 2]
        } else {
            0.5 * (values[n / 2 - 1] + values[n / 2])
        }
    })
}

fn share(k: usize, n: usize) -> Cell {
    if n == 0 {
        Cell::Missing
    } else {
        Cell::count_of(k, n)
    }
}

fn or_dash(v: Option<f64>, cell: impl Fn(f64) -> Cell) -> Cell {
    v.map_or(Cell::Missing, cell)
}

/// A target the measure must stay under (CSV column "target under").
fn under(limit: f64, shown: &str) -> Cell {
    Cell::Value {
        shown: format!("under {shown}"),
        parts: vec![("under", wakelab_core::io::text::number(limit))],
    }
}

fn yes(b: bool) -> Cell {
    if b { "yes" } else { "no" }.into()
}

/// Relative errors (%) of the speeds `read` reports against the truth.
fn speed_errors(scenes: &[&SceneResult], read: impl Fn(&SceneResult) -> Option<f64>) -> Vec<f64> {
    scenes
        .iter()
        .filter_map(|s| read(s).map(|v| 100.0 * (v - s.speed).abs() / s.speed))
        .collect()
}

/// `count` false alarms in `area` km^2 as a rate per 100 km^2, with the count and the area.
fn per_100_km2(count: usize, area: f64) -> Cell {
    let rate = 100.0 * count as f64 / area.max(1e-9);
    Cell::number(rate, 2)
        .and("count", count.to_string(), String::new())
        .and(
            "area (km^2)",
            format!("{area:.0}"),
            format!("{rate:.2} ({count} in {area:.0} km^2)"),
        )
}

/// The summary table.
pub fn ships_table(results: &ShipsResults) -> Table {
    let in_view: Vec<&SceneResult> = results.scenes.iter().filter(|s| s.ship_in_view).collect();
    let free: Vec<&SceneResult> = results.scenes.iter().filter(|s| !s.ship_in_view).collect();
    let found: Vec<&SceneResult> = in_view.iter().copied().filter(|s| s.ship_found).collect();
    let anchored: Vec<&SceneResult> = found.iter().copied().filter(|s| s.wake_found).collect();
    let false_ships: usize = results
        .scenes
        .iter()
        .map(|s| s.false_ships + s.false_ships_without)
        .sum();
    // every scene twice (with and without its ship)
    let area = 2.0 * results.scenes.iter().map(|s| s.km2).sum::<f64>();
    let course = median(anchored.iter().filter_map(|s| s.course_error.map(f64::abs)).collect());
    // how often the course's stated uncertainty holds its error
    let with_sigma: Vec<(f64, f64)> = anchored
        .iter()
        .filter_map(|s| s.course_error.zip(s.course_sigma))
        .collect();
    let covered = with_sigma.iter().filter(|(e, sigma)| e.abs() <= *sigma).count();
    let offset = speed_errors(&anchored, |s| s.speed_offset);
    let kelvin = speed_errors(&anchored, |s| s.speed_kelvin);
    // the fine X-band scenes: Kelvin speeds read on the wakes found there
    let fine_anchored: Vec<&SceneResult> = results.fine.iter().filter(|s| s.wake_found).collect();
    let fine_kelvin = speed_errors(&fine_anchored, |s| s.speed_kelvin);
    let free_found: Vec<&SceneResult> = free.iter().copied().filter(|s| s.wake_found).collect();
    let free_axis = median(free_found.iter().filter_map(|s| s.course_error.map(f64::abs)).collect());
    // a median relative error in percent, with how many speeds it is over
    let percent = |v: &Vec<f64>| match median(v.clone()) {
        Some(m) => Cell::number(m, 1).and("n", v.len().to_string(), format!("{m:.1}% (n = {})", v.len())),
        None => Cell::Missing,
    };
    let false_wakes: usize = results
        .scenes
        .iter()
        .map(|s| s.false_wakes + s.false_wakes_without)
        .sum();
    let rows = vec![
        vec![
            "ships detected".into(),
            share(found.len(), in_view.len()),
            Cell::Missing,
        ],
        vec![
            "false ships per 100 km^2".into(),
            per_100_km2(false_ships, area),
            Cell::Missing,
        ],
        vec![
            "wakes of detected ships found".into(),
            share(anchored.len(), found.len()),
            Cell::Missing,
        ],
        vec![
            "false wakes per 100 km^2".into(),
            per_100_km2(false_wakes, area),
            Cell::Missing,
        ],
        vec![
            "median course error (deg)".into(),
            or_dash(course, |m| Cell::number(m, 1)),
            under(5.0, "5 deg"),
        ],
        vec![
            "course errors within their stated uncertainty".into(),
            share(covered, with_sigma.len()),
            Cell::Missing,
        ],
        vec![
            "median speed error (%), azimuth offset".into(),
            percent(&offset),
            under(15.0, "15%"),
        ],
        vec![
            "median speed error (%), Kelvin wavelength".into(),
            percent(&kelvin),
            under(15.0, "15%"),
        ],
        vec![
            "fine X-band scenes: wakes found; Kelvin speeds read".into(),
            if results.fine.is_empty() {
                Cell::Missing
            } else {
                let read = fine_anchored.iter().filter(|s| s.speed_kelvin.is_some()).count();
                format!("{} / {}; {read}", fine_anchored.len(), results.fine.len()).into()
            },
            Cell::Missing,
        ],
        vec![
            "median speed error (%), Kelvin wavelength, fine X-band scenes".into(),
            percent(&fine_kelvin),
            under(15.0, "15%"),
        ],
        vec![
            "free wakes found (ship sailed out)".into(),
            share(free_found.len(), free.len()),
            Cell::Missing,
        ],
        vec![
            "median axis error of free wakes (deg)".into(),
            or_dash(free_axis, |m| Cell::number(m, 1)),
            Cell::Missing,
        ],
    ];
    Table {
        id: "ships_and_wakes".into(),
        title: "Ships and wakes: the classic detectors on simulated scenes".into(),
        caption: format!(
            "The study's base sea and SAR image its ship in C-band VV on {n} scenes of {km2:.1} km^2 in all at 10 m (5.12 km \
             on a side where the study's wake is long enough): {in_view} \
             with the ship in view (6, 9 and 12 m/s, any course and look, R/V over 40-130 s, winds 4-10 m/s, \
             incidence 25-45 deg), {free} with the ship sailed out of view (its wake alone); each also without its \
             ship. Ships: a two-parameter CFAR in dB (guard 500 m, background 800 m, P_fa 1e-6), found when a \
             detected ship lies within its length of where its range velocity displaces its return. Wakes: the \
             Radon search along rays from apexes on the return's azimuth line (the ship's course from the apex, \
             speed from the apex's azimuth offset and R/V, and from the Kelvin waves' wavenumbers), and the free \
             wakes' Radon search of the whole image (axis only: 180 deg ambiguous). Speeds where reported; the \
             offset is no speed for tracks within 15 deg of the azimuth, the Kelvin waves none where they are not \
             resolved, not over the sea beside the wake, or where that sea holds waves on the same curve. The fine scenes: {fine} X-band scenes of 2.56 km at 2.5 m (1 or 4 looks, half \
             of them without the swell), the same speeds, scored alike (the table \"Fine X-band scenes\").",
            fine = results.fine.len(),
            n = results.scenes.len(),
            km2 = results.scenes.iter().map(|s| s.km2).sum::<f64>(),
            in_view = in_view.len(),
            free = free.len(),
        ),
        header: ["measure", "wakelab", "target"].map(String::from).to_vec(),
        rows,
    }
}

/// The wake detectors on the same detected ships: the classic search, the CNN, and their
/// fusions (None when the run had no CNN that fits the scenes).
pub fn wake_detectors_table(results: &ShipsResults) -> Option<Table> {
    let (threshold, footprint) = (results.cnn_threshold?, results.cnn_footprint_m?);
    if results.wake_detectors.is_empty() {
        return None;
    }
    let rows = results
        .wake_detectors
        .iter()
        .map(|d| {
            vec![
                d.detector.as_str().into(),
                share(d.wakes_found as usize, d.wakes as usize),
                share(d.false_alarms as usize, d.controls as usize),
                Cell::number(d.mcc, 2),
                or_dash(d.auc, |a| Cell::number(a, 2)),
            ]
        })
        .collect();
    Some(Table {
        id: "ship_wake_detectors".into(),
        title: "Wake detectors on the same ships: the classic search, the CNN and their fusion".into(),
        caption: format!(
            "For every detected ship of the scenes with the ship in view: its wake sought by the classic Radon \
             search from the ship, and by the study's C-band \"base\" CNN ({footprint:.0} m windows a quarter \
             window apart, centred within {radius:.0} m of the ship; wake when the largest probability reaches the \
             detector's threshold {threshold:.2}); then the same surroundings in the scene's twin without the ship, \
             where a wake found is a false alarm. Bayes fusion (spec Eqs. (5.1)-(5.5)) and Dempster-Shafer (discounted \
             masses, pignistic decision) weigh each source by its rates on the other scenes (leave one scene out). \
             AUC: the area under the ROC curve of each detector's outputs over the scenes and their twins.",
            radius = crate::steps::ship_windows::RADIUS_M,
        ),
        header: [
            "wake detector",
            "wakes found",
            "false alarms (twin without the ship)",
            "MCC",
            "AUC",
        ]
        .map(String::from)
        .to_vec(),
        rows,
    })
}

/// Every scene's truth and findings.
pub fn ships_scene_table(results: &ShipsResults) -> Table {
    let rows = scene_rows(&results.scenes);
    Table {
        id: "ships_scenes".into(),
        title: "Ships and wakes, scene by scene".into(),
        caption: "Each simulated scene: the ship's speed (m/s), course, the radar's look in the image (deg clockwise \
                  from up), R/V (s) and the wind (m/s); what was found (false ships and wakes: in the scene and its \
                  twin without the ship); the CNN's largest window probability around the detected ship in the scene \
                  and in its twin; the course error (deg) and the speeds read (m/s) from the azimuth offset and from \
                  the Kelvin waves; where the ship was found and its wake was not, the test its best trough and its \
                  best bright arm failed (z: significance among the directions from the ship, 5 needed, 4 for a line along the ship's return)."
            .into(),
        header: scene_header(),
        rows,
    }
}

/// The fine X-band scenes' truth and findings (None when the run has none).
pub fn fine_scene_table(results: &ShipsResults) -> Option<Table> {
    if results.fine.is_empty() {
        return None;
    }
    let mut header = scene_header();
    header.splice(0..0, ["looks", "swell (m)"].map(String::from));
    let rows = results
        .fine
        .iter()
        .zip(scene_rows(&results.fine))
        .map(|(s, row)| {
            let mut row = row;
            row.splice(0..0, [Cell::count(s.looks as usize), Cell::number(s.swell_m, 1)]);
            row
        })
        .collect();
    Some(Table {
        id: "ships_fine_scenes".into(),
        title: "Fine X-band scenes: the Kelvin speed where the waves are resolved".into(),
        caption: "X band at 2.5 m, 2.56 km on a side, each with its looks and swell amplitude, its ship 640 m behind \
                  the centre; columns as in \"Ships and wakes, scene by scene\" (no CNN fits this spacing). \
                  The transverse Kelvin wavelength 2 pi U^2 / g is 23, 52 and 92 m at 6, 9 and 12 m/s: 9-37 pixels; \
                  the speed is read from the curve k = g / (U^2 cos^2 theta) on which every Kelvin wave lies."
            .into(),
        header,
        rows,
    })
}

fn scene_rows(scenes: &[SceneResult]) -> Vec<Vec<Cell>> {
    scenes
        .iter()
        .map(|s| {
            vec![
                Cell::number(s.speed, 0),
                Cell::number(s.course, 0),
                Cell::number(s.look, 0),
                Cell::number(s.range_over_velocity, 0),
                Cell::number(s.wind, 0),
                yes(s.ship_in_view),
                yes(s.ship_found),
                Cell::count(s.false_ships + s.false_ships_without),
                yes(s.wake_found),
                Cell::count(s.false_wakes + s.false_wakes_without),
                or_dash(s.cnn_with, |p| Cell::number(p, 2)),
                or_dash(s.cnn_without, |p| Cell::number(p, 2)),
                or_dash(s.course_error, |e| Cell::signed(e, 1)),
                or_dash(s.speed_offset, |v| Cell::number(v, 1)),
                or_dash(s.speed_kelvin, |v| Cell::number(v, 1)),
                s.no_wake.clone().map_or(Cell::Missing, Cell::Text),
            ]
        })
        .collect()
}

fn scene_header() -> Vec<String> {
    [
        "speed",
        "course",
        "look",
        "R/V",
        "wind",
        "ship in view",
        "ship found",
        "false ships",
        "wake found",
        "false wakes",
        "CNN (scene)",
        "CNN (twin)",
        "course error",
        "speed (offset)",
        "speed (Kelvin)",
        "why no wake (trough / arm)",
    ]
    .map(String::from)
    .to_vec()
}

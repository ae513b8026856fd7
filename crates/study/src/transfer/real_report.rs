//! The real images' part of the transfer report (`wakelab run --study transfer --real DIR`):
//! per detector, the wakes found and the false alarms; per image, where the detections fell.
//! Markdown for `report/transfer.md`, CSV for `report/tables/transfer_real.csv`.

use super::real::{RealResults, RealScore, RealSummary};
use super::real_search::{SearchScore, SearchSummary, AXIS_WITHIN_DEG};
use super::real_ships::SHIP_WITHIN_M;
use std::fmt::Write;

const HEADER: [&str; 14] = [
    "image",
    "footprint_m",
    "wakes",
    "detections",
    "false_alarms",
    "found",
    "peak_on_wake",
    "peak_by_chance",
    "peak_by_line",
    "strongest_on_wake",
    "first_on_wake",
    "km2",
    "wake_visibility",
    "skipped",
];

fn row(s: &RealScore) -> Vec<String> {
    vec![
        s.image.replace(',', ";"),
        format!("{:.0}", s.footprint),
        s.wakes.to_string(),
        s.detections.to_string(),
        s.false_alarms.to_string(),
        if s.wakes == 0 {
            "-".into()
        } else {
            s.found().to_string()
        },
        s.peak_on_wake.to_string(),
        s.peak_by_chance.map_or("-".into(), |p| format!("{p:.3}")),
        s.peak_by_line.map_or("-".into(), |on| on.to_string()),
        s.strongest_on_wake.to_string(),
        s.first_on_wake.map_or("-".into(), |r| r.to_string()),
        format!("{:.2}", s.km2),
        s.wake_visibility
            .iter()
            .map(|v| v.map_or("-".into(), |v| format!("{v:.1}")))
            .collect::<Vec<_>>()
            .join(" "),
        s.skipped
            .as_deref()
            .map_or(String::new(), |why| why.replace([',', '|', '\n'], ";")),
    ]
}

/// The per-image table as CSV.
pub fn csv(real: &RealResults) -> String {
    let mut text = HEADER.join(",") + "\n";
    for s in &real.scores {
        text += &(row(s).join(",") + "\n");
    }
    text
}

/// A rate per 100 km^2 to `decimals`, "-" where no area was scanned.
fn per_100_km2(rate: Option<f64>, decimals: usize) -> String {
    rate.map_or("-".into(), |r| format!("{r:.decimals$}"))
}

/// The wake images whose peak would lie on a wake were their windows scored at random.
fn by_chance(s: &RealSummary) -> String {
    s.peak_on_wake_by_chance.map_or("-".into(), |c| format!("{c:.1}"))
}

/// The wake images whose peak a detector of lines alone would place on a wake.
fn by_line(s: &RealSummary) -> String {
    s.peak_on_wake_by_line.map_or("-".into(), |n| n.to_string())
}

/// One line per detector: what it did on the user's images.
pub fn describe(s: &RealSummary) -> String {
    format!(
        "  real images, {:.2} km window: wakes found {}/{} (peak on a wake in {}, {} by chance, {} by the strongest line alone; strongest detection on the wake in {}), {:.1} false alarms per wake image; no-wake images without an alarm {}/{}; {} false alarms per 100 km^2; {} image(s) skipped; wake visibility {}",
        s.footprint / 1000.0,
        s.found,
        s.wake_images,
        s.peak_on_wake,
        by_chance(s),
        by_line(s),
        s.strongest_on_wake,
        s.false_alarms_per_wake_image,
        s.no_wake_images_without_alarm,
        s.no_wake_images,
        per_100_km2(s.false_alarms_per_100_km2, 2),
        s.skipped,
        s.wake_visibility.map_or("-".into(), |v| format!("{} (quartiles)", v.describe()))
    )
}

/// The Markdown section.
pub fn markdown(real: &RealResults) -> String {
    let mut md = String::from("\n## Real images\n\n");
    let _ = writeln!(
        md,
        "The images of `{}` with their wakes as annotated (`--real`), scanned by `wakelab detect` with the detectors above, frozen with their thresholds. A wake is found when a detection or the map's peak (where the strongest window places its wake: the middle of the contrast along that window's strongest line) lies within 500 m of it; every other detection is a false alarm. A peak lands on a wake by chance too, most often on an image not much larger than a window and cut around its ship: \"by chance\" is how many peaks would, were each image's windows scored at random (each window equally likely the strongest, its peak placed by the same rule), the sum of `peak_by_chance`. \"By the line\" is how many peaks a detector of lines alone would place on a wake: each image's window of the strongest line's contrast (the largest |line sum|, the classic Radon-plane detector's choice), placed by the same rule (`peak_by_line`); what the network learnt shows as peaks beyond both. An image a detector could not scan (one filling under half its window, unreadable) is left out of its figures and says why in the table's last column.\n",
        real.dir.display()
    );
    md += "The wakes' visibility is measured as in the training windows above, on each wake's image as the detector sees it (read and averaged as `detect` does), in windows of the detector's side a quarter, half and three quarters along it (the median of the three; a wake drawn in longitude and latitude is not measured).\n\n";
    md += "| detector | wakes found | peak on a wake (by chance; by the line) | strongest detection on the wake | false alarms per wake image | no-wake images without an alarm | false alarms per 100 km^2 | wake visibility: quartiles, share above 3 |\n";
    md += "| --- | --- | --- | --- | --- | --- | --- | --- |\n";
    for s in &real.summaries {
        let visibility = s
            .wake_visibility
            .map_or("-".into(), |v| format!("{}, {:.2}", v.describe(), v.above_3));
        let _ = writeln!(
            md,
            "| {:.2} km | {}/{} | {} ({}; {}) | {}/{} | {:.1} | {}/{} | {} | {visibility} |",
            s.footprint / 1000.0,
            s.found,
            s.wake_images,
            s.peak_on_wake,
            by_chance(s),
            by_line(s),
            s.strongest_on_wake,
            s.wake_images,
            s.false_alarms_per_wake_image,
            s.no_wake_images_without_alarm,
            s.no_wake_images,
            per_100_km2(s.false_alarms_per_100_km2, 2)
        );
    }
    md += &format!("\n| {} |\n|{}\n", HEADER.join(" | "), " --- |".repeat(HEADER.len()));
    for s in &real.scores {
        md += &format!("| {} |\n", row(s).join(" | "));
    }
    md + &search_markdown(real)
}

const SEARCH_HEADER: [&str; 18] = [
    "image",
    "wakes",
    "ships",
    "search_wakes",
    "found",
    "false_wakes",
    "axis_errors_deg",
    "skipped",
    "drawn_ships",
    "ships_found",
    "false_ships",
    "seen_by_both",
    "seen_by_both_found",
    "faint_lines",
    "faint_on_wake",
    "missed_under_faint",
    "promoted",
    "promoted_found",
];

fn search_row(s: &SearchScore) -> Vec<String> {
    vec![
        s.image.replace(',', ";"),
        s.wakes.to_string(),
        s.ships.to_string(),
        s.search_wakes.to_string(),
        s.found.to_string(),
        s.false_wakes.to_string(),
        s.axis_errors_deg
            .iter()
            .map(|e| format!("{e:.1}"))
            .collect::<Vec<_>>()
            .join(" "),
        s.skipped
            .as_deref()
            .map_or(String::new(), |why| why.replace([',', '|', '\n'], ";")),
    ]
    .into_iter()
    .chain(
        // blank where the image's ships are not drawn
        s.drawn_ships
            .map_or([None; 3], |d| [Some(d.drawn), Some(d.found), Some(d.false_ships)])
            .map(|n| n.map_or(String::new(), |n| n.to_string())),
    )
    .chain(
        [
            s.seen_by_both,
            s.seen_by_both_found,
            s.faint_lines,
            s.faint_on_wake,
            s.missed_under_faint,
            s.promoted,
            s.promoted_found,
        ]
        .map(|n| n.to_string()),
    )
    .collect()
}

/// The classic search's per-image table as CSV.
pub fn search_csv(real: &RealResults) -> String {
    let mut text = SEARCH_HEADER.join(",") + "\n";
    for s in &real.search {
        text += &(search_row(s).join(",") + "\n");
    }
    text
}

/// The ship search against the drawn ships, where any image draws them.
fn describe_ships(s: &SearchSummary) -> Option<String> {
    (s.ship_images > 0).then(|| {
        format!(
            "ships drawn in {} image(s): {}/{} found, {:.2} false ships per image ({} per 100 km^2)",
            s.ship_images,
            s.ships_found,
            s.drawn_ships,
            s.false_ships_per_image,
            per_100_km2(s.false_ships_per_100_km2, 1)
        )
    })
}

/// One line: what the classic search did on the user's images.
pub fn describe_search(s: &SearchSummary) -> String {
    let line = format!(
        "  real images, classic ship and wake search: a wake found in {}/{} wake images, {} of them with at most one false wake ({}/{} wakes, median axis error {}), {:.1} false wakes per wake image; no-wake images without a wake {}/{}; {:.1} ships per image; {} image(s) skipped",
        s.images_found,
        s.wake_images,
        s.images_found_one_false,
        s.wakes_found,
        s.wakes,
        s.median_axis_error_deg.map_or("-".into(), |e| format!("{e:.1} deg")),
        s.false_wakes_per_wake_image,
        s.no_wake_images_clean,
        s.no_wake_images,
        s.ships_per_image,
        s.skipped
    );
    let line = format!(
        "{line}; read with the CNN: {}; faint lines (a ship's best line refused for its significance alone, for review): {}",
        describe_together(s),
        describe_faint(s)
    );
    match describe_ships(s) {
        Some(ships) => format!("{line}; {ships}"),
        None => line,
    }
}

/// The search read with the first detector's windows, over the wake images.
fn describe_together(s: &SearchSummary) -> String {
    format!(
        "{}/{} wakes seen by both on a drawn wake, {}/{} of the line search alone",
        s.seen_by_both_found, s.seen_by_both, s.line_search_only_found, s.line_search_only
    )
}

/// The faint lines: how many, how many on a drawn wake, and what a reviewer of them sees.
fn describe_faint(s: &SearchSummary) -> String {
    format!(
        "{} faint line(s), {} on a drawn wake; a wake found or under a faint line in {}/{} wake images; no-wake images with a faint line {}/{}; wakes promoted from a faint line (among the wakes above) {}, {} on a drawn wake",
        s.faint_lines, s.faint_on_wake, s.images_found_or_faint, s.wake_images, s.no_wake_images_with_faint, s.no_wake_images, s.promoted, s.promoted_found
    )
}

/// The classic search's Markdown section (none where it did not run).
fn search_markdown(real: &RealResults) -> String {
    let Some(s) = &real.search_summary else {
        return String::new();
    };
    let mut md = String::from("\n### The classic ship and wake search on the same images\n\n");
    let _ = writeln!(
        md,
        "`wakelab detect`'s own ship (CFAR) and wake (Radon) searches, run once per image at the first detector's spacing, as `detect` with that detector runs them. A reported wake finds a drawn one when the two lines come within 500 m of each other and their axes differ by at most {AXIS_WITHIN_DEG:.0} degrees (modulo 180: a drawn wake has no direction, so the course is not checked); every other reported wake is a false wake. Ships are scored only on the images whose ships are drawn (features of `\"kind\": \"ship\"`, or `\"ships_drawn\": true`): a drawn ship is found when a reported ship's centre lies within {SHIP_WITHIN_M:.0} m of it (or one scanned pixel, where that is larger), and every other reported ship is a false ship; elsewhere ships are counted, not scored.\n"
    );
    md += "| wake images with a wake found | ... with at most one false wake | wakes found | median axis error (deg) | false wakes per wake image | no-wake images without a wake | ships per image |\n";
    md += "| --- | --- | --- | --- | --- | --- | --- |\n";
    let _ = writeln!(
        md,
        "| {}/{} | {}/{} | {}/{} | {} | {:.1} | {}/{} | {:.1} |",
        s.images_found,
        s.wake_images,
        s.images_found_one_false,
        s.wake_images,
        s.wakes_found,
        s.wakes,
        s.median_axis_error_deg.map_or("-".into(), |e| format!("{e:.1}")),
        s.false_wakes_per_wake_image,
        s.no_wake_images_clean,
        s.no_wake_images,
        s.ships_per_image
    );
    let _ = writeln!(
        md,
        "\nThe search's wakes read with the first detector's windows as `detect` reads them (a window within 500 m of a reported wake's line sees it; `seen_by_both` below): {}.",
        describe_together(s)
    );
    let _ = writeln!(
        md,
        "\nWhere a ship's best trough or arm passes every test but its significance, `detect` gives it as a faint line (`faint_line` in the ship's `no_wake`, dotted on the overlay), for an analyst to review, not as a wake; where an image's search reports no wake at all, its faint line of the largest z is promoted to its wake when that z is at least {} (`promoted`, dashed on the overlay; counted among the wakes above). Scored by the rule above: {}.",
        wakelab_ships::wake::WakeOptions::default().promote_min_z,
        describe_faint(s)
    );
    if let Some(ships) = describe_ships(s) {
        let _ = writeln!(md, "\nThe ship search against the drawn ships: {ships}.");
    }
    md += &format!(
        "\n| {} |\n|{}\n",
        SEARCH_HEADER.join(" | "),
        " --- |".repeat(SEARCH_HEADER.len())
    );
    for s in &real.search {
        md += &format!("| {} |\n", search_row(s).join(" | "));
    }
    md
}

//! `wakelab run --study transfer --real DIR` (issue 38, item 8): the study's detectors, frozen
//! with their thresholds, scanned over a user's real images by `wakelab detect`'s own path
//! ([`crate::products::detect`]), each image scored against its wakes as the user drew them.
//!
//! `DIR` holds images (any input `detect` reads) and, beside each, `NAME.geojson`: a
//! FeatureCollection whose LineStrings are the image's wakes (none: an image without a wake). A
//! foreign member `"wakelab"` says how to read the image: `coordinates` (`"lonlat"`, GeoJSON's
//! own and the default, or `"pixel"`: [column, row] of the image's pixels), `pixel_spacing_m`
//! and `scale` (as `detect --pixel-spacing`, `--scale`) and `exclude` (a land mask beside it, as
//! `--exclude`). A wake is found when a detection or the map's peak lies within 500 m of it
//! (the study's rule on simulated scenes); every other detection is a false alarm. Features of
//! `"kind": "ship"` (Points, or Polygons such as a dataset's boxes) are the image's ships, which
//! score the classic ship search ([`super::real_ships`]).

use super::real_search::{metres_from, score_search, summarise_search, SearchScore, SearchSummary};
use super::real_ships::{score_ships, DrawnShip, SHIP_WITHIN_M};
use super::visibility::{self, Spread};
use crate::product_scan::{open_product, ScanProgress};
use crate::products::{detect, DetectRequest};
use crate::sea_findings::ShipSearch;
use crate::steps::calibration::FOUND_WITHIN_M;
use crate::steps::open_sea::distance_to_segment;
use crate::Result;
use anyhow::{anyhow, Context};
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::path::{Path, PathBuf};
use wakelab_learn::detect::ScanOptions;
use wakelab_learn::peak_chance::{peak_by_chance, peak_by_line};
use wakelab_products::{InputScale, ReadOptions, Source};
use wakelab_schema::band::Band;

/// How an image is read and where its wakes are, from its `NAME.geojson`.
#[derive(Debug, Clone, PartialEq)]
pub struct Annotation {
    pub image: PathBuf,
    /// Wakes as polylines: (column, row) pixels, or (longitude, latitude) with `lonlat`.
    pub wakes: Vec<Vec<(f64, f64)>>,
    pub lonlat: bool,
    pub pixel_spacing: Option<f64>,
    pub scale: Option<InputScale>,
    pub exclude: Option<PathBuf>,
    /// The ships drawn, where the file draws them (a ship feature, or `"ships_drawn": true`);
    /// none where ships are not drawn, and are then counted, not scored.
    pub ships: Option<Vec<DrawnShip>>,
}

impl Annotation {
    /// How `detect` reads the image: the scale, the pixels to leave out and the spacing its
    /// GeoJSON states.
    pub fn read_options(&self) -> ReadOptions {
        ReadOptions {
            scale: self.scale,
            exclude: self.exclude.clone(),
            pixel_spacing: self.pixel_spacing,
            ..Default::default()
        }
    }
}

/// How one detector did on one image.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RealScore {
    pub image: String,
    pub footprint: f64,
    pub wakes: usize,
    pub detections: usize,
    /// Detections more than 500 m from every wake.
    pub false_alarms: usize,
    /// Whether the map's peak (where the strongest window places its wake,
    /// [`wakelab_learn::detect::Peak`]), and the strongest detection, lie within 500 m of a wake.
    pub peak_on_wake: bool,
    /// The chance that the peak lies within 500 m of a wake were the same windows scored at
    /// random ([`wakelab_learn::peak_chance`]): what `peak_on_wake` is worth on this image. None
    /// for wakes drawn in longitude and latitude, and for an image not scanned.
    #[serde(default)]
    pub peak_by_chance: Option<f64>,
    /// Whether a detector of lines alone would place its peak on a wake: the window of the
    /// strongest line's contrast, placed as the peak is ([`wakelab_learn::peak_chance::peak_by_line`]),
    /// within 500 m of a wake. The baseline the network has to beat besides chance. None as for
    /// `peak_by_chance`.
    #[serde(default)]
    pub peak_by_line: Option<bool>,
    pub strongest_on_wake: bool,
    /// Rank (1: the strongest) of the first detection on a wake.
    pub first_on_wake: Option<usize>,
    /// Area scanned (km^2, the cells a window scored).
    pub km2: f64,
    /// Each wake's visibility in the image as the detector sees it ([`visibility::along`];
    /// none for wakes drawn in longitude and latitude).
    #[serde(default)]
    pub wake_visibility: Vec<Option<f64>>,
    pub notes: Vec<String>,
    /// Why the detector could not scan the image (filling under half its window, unreadable): such an
    /// image is left out of the summary and listed in the report.
    #[serde(default)]
    pub skipped: Option<String>,
}

impl RealScore {
    /// The issue's rule: a detection or the map's peak within 500 m of a wake.
    pub fn found(&self) -> bool {
        self.wakes > 0 && (self.peak_on_wake || self.first_on_wake.is_some())
    }
}

/// Every `NAME.geojson` of `dir` with the image beside it (same name, another extension or a
/// directory such as a `.SAFE`), sorted by name.
pub fn annotations(dir: &Path) -> Result<Vec<Annotation>> {
    let entries =
        std::fs::read_dir(dir).with_context(|| format!("--real {}: not a readable directory", dir.display()))?;
    let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    paths.sort();
    let mut found = Vec::new();
    for geojson in paths.iter().filter(|p| p.extension().is_some_and(|e| e == "geojson")) {
        let stem = geojson.file_stem().unwrap_or_default();
        let image = paths
            .iter()
            .find(|p| *p != geojson && p.file_stem() == Some(stem))
            .ok_or_else(|| anyhow!("{}: no image of that name beside it", geojson.display()))?;
        found.push(read_annotation(geojson, image)?);
    }
    if found.is_empty() {
        return Err(anyhow!(
            "--real {}: no NAME.geojson wake annotations there (each image needs one; an empty FeatureCollection \
             for an image without a wake)",
            dir.display()
        ));
    }
    Ok(found)
}

/// One image's annotation file.
pub fn read_annotation(geojson: &Path, image: &Path) -> Result<Annotation> {
    let text = std::fs::read_to_string(geojson).with_context(|| format!("{}: cannot read", geojson.display()))?;
    let doc: Value = serde_json::from_str(&text).with_context(|| format!("{}: not JSON", geojson.display()))?;
    let bad = |what: String| anyhow!("{}: {what}", geojson.display());
    if doc["type"] != "FeatureCollection" {
        return Err(bad("not a GeoJSON FeatureCollection".into()));
    }
    let how = &doc["wakelab"];
    let lonlat = match how["coordinates"].as_str() {
        None | Some("lonlat") => true,
        Some("pixel") => false,
        Some(other) => {
            return Err(bad(format!(
                "wakelab.coordinates \"{other}\": allowed are \"lonlat\" and \"pixel\""
            )))
        }
    };
    let pixel_spacing = match &how["pixel_spacing_m"] {
        Value::Null => None,
        v => Some(v.as_f64().filter(|m| *m > 0.0 && *m <= 1000.0).ok_or_else(|| {
            bad(format!(
                "wakelab.pixel_spacing_m {v}: a ground spacing in metres, above 0 and at most 1000"
            ))
        })?),
    };
    let scale = match how["scale"].as_str() {
        None => None,
        Some(s) => Some(
            s.parse::<InputScale>()
                .map_err(|e| bad(format!("wakelab.scale: {e}")))?,
        ),
    };
    let exclude = how["exclude"]
        .as_str()
        .map(|f| geojson.parent().unwrap_or(Path::new(".")).join(f));
    let ships_drawn = match &how["ships_drawn"] {
        Value::Null => false,
        v => v
            .as_bool()
            .ok_or_else(|| bad(format!("wakelab.ships_drawn {v}: true or false")))?,
    };
    let (mut wakes, mut ships) = (Vec::new(), Vec::new());
    for (i, feature) in doc["features"].as_array().into_iter().flatten().enumerate() {
        let kind = feature["properties"]["kind"].as_str();
        let geometry = &feature["geometry"];
        if kind == Some("ship") {
            ships.push(DrawnShip::from_geometry(geometry).map_err(|e| bad(format!("features[{i}]: {e}")))?);
            continue;
        }
        if kind.is_some_and(|k| k != "wake") {
            continue;
        }
        let lines: Vec<&Value> = match geometry["type"].as_str() {
            Some("LineString") => vec![&geometry["coordinates"]],
            Some("MultiLineString") => geometry["coordinates"].as_array().into_iter().flatten().collect(),
            other => {
                return Err(bad(format!(
                    "features[{i}]: a wake is a LineString or MultiLineString, not {}",
                    other.unwrap_or("a feature without a geometry type")
                )))
            }
        };
        for line in lines {
            let points: Option<Vec<(f64, f64)>> = line
                .as_array()
                .into_iter()
                .flatten()
                .map(|p| Some((p.get(0)?.as_f64()?, p.get(1)?.as_f64()?)))
                .collect();
            match points {
                Some(p) if p.len() >= 2 => wakes.push(p),
                _ => return Err(bad(format!("features[{i}]: a wake needs two or more [x, y] positions"))),
            }
        }
    }
    let ships = (ships_drawn || !ships.is_empty()).then_some(ships);
    Ok(Annotation {
        image: image.to_path_buf(),
        wakes,
        lonlat,
        pixel_spacing,
        scale,
        exclude,
        ships,
    })
}

/// Metres from a point to the nearest wake: in pixels scaled by the spacing (x: columns, y:
/// rows), or for longitude and latitude on the plane tangent at the point.
fn to_wakes(point: (f64, f64), annotation: &Annotation, spacing: (f64, f64)) -> f64 {
    let project = |q: (f64, f64)| metres_from(q, point, annotation.lonlat, spacing);
    annotation
        .wakes
        .iter()
        .flat_map(|w| {
            w.windows(2)
                .map(|s| distance_to_segment((0.0, 0.0), (project(s[0]), project(s[1]))))
        })
        .fold(f64::INFINITY, f64::min)
}

/// A point of `detections.json` as the annotation places it: (column, row), or (lon, lat).
fn place(point: &Value, lonlat: bool) -> Option<(f64, f64)> {
    if lonlat {
        Some((point["lon"].as_f64()?, point["lat"].as_f64()?))
    } else {
        Some((point["product_col"].as_f64()?, point["product_row"].as_f64()?))
    }
}

/// Scan `annotation`'s image with the detector `model` (of `footprint` m) on the CPU, as
/// `detect` does by default, writing `detect`'s files into `out`, and score it; with `search`,
/// also run `detect`'s classic ship and wake search and score that
/// ([`super::real_search`]).
pub fn score_image(
    annotation: &Annotation,
    model: &Path,
    footprint: f64,
    out: &Path,
    search: bool,
) -> Result<(RealScore, Option<SearchScore>)> {
    let image = &annotation.image;
    let read = annotation.read_options();
    let request = DetectRequest {
        image,
        model: Some(model),
        read: read.clone(),
        options: ScanOptions::default(),
        device: "cpu",
        out: Some(out.to_path_buf()),
        mask: None,
        // the user asked for these images: one of another band is scored, and its note says so
        force: true,
        // seconds to minutes on a real image with many bright targets: once per image
        search_sea: search.then(ShipSearch::default),
    };
    let progress = ScanProgress {
        reading: &mut |_, _| {},
        scanning: &mut |_, _| {},
    };
    let found = detect(request, progress).with_context(|| format!("--real: {}", image.display()))?;
    let text = std::fs::read_to_string(&found.files.detections)?;
    let written: Value = serde_json::from_str(&text)?;
    let lonlat = annotation.lonlat;
    if lonlat && written["georeferenced"] != true {
        return Err(anyhow!(
            "{}: its wakes are in longitude and latitude but the image has no georeference: give them as \
             \"wakelab\": {{\"coordinates\": \"pixel\"}}, [column, row]",
            image.display()
        ));
    }
    let spacing = written["product"]["pixel_spacing"].clone();
    let spacing = (
        spacing["rows"].as_f64().unwrap_or(f64::NAN),
        spacing["columns"].as_f64().unwrap_or(f64::NAN),
    );
    if !(spacing.0.is_finite() && spacing.1.is_finite()) {
        return Err(anyhow!(
            "{}: the image states no pixel spacing: give it as \"wakelab\": {{\"pixel_spacing_m\": M}} in its GeoJSON",
            image.display()
        ));
    }
    let distance = |p: &Value| place(p, lonlat).map_or(f64::INFINITY, |q| to_wakes(q, annotation, spacing));
    let on_wake: Vec<bool> = written["detections"]
        .as_array()
        .into_iter()
        .flatten()
        .map(|d| distance(d) <= FOUND_WITHIN_M)
        .collect();
    let detection = &found.detection;
    let pixel_m2 = scanned_pixel_m2(&written, spacing);
    let factor = (
        written["resampled"][0].as_f64().unwrap_or(1.0),
        written["resampled"][1].as_f64().unwrap_or(1.0),
    );
    let mut notes = found.notes;
    // the scan is scored whatever becomes of this measure: a second read that fails leaves the
    // wakes unmeasured and says why
    let wake_visibility = if lonlat {
        Vec::new()
    } else {
        wake_visibilities(annotation, &read, factor, detection.window, spacing.0 * factor.0).unwrap_or_else(|e| {
            notes.push(format!("wake visibility not measured: {e:#}"));
            vec![None; annotation.wakes.len()]
        })
    };
    // the scanned grid's pixels in the image's (for wakes drawn in pixels; lonlat needs the frame)
    let scanned_on_wake =
        |row: f64, col: f64| to_wakes((col * factor.1, row * factor.0), annotation, spacing) <= FOUND_WITHIN_M;
    let by_chance = (!lonlat).then(|| peak_by_chance(&detection.tiles, detection.window, scanned_on_wake));
    let by_line = (!lonlat)
        .then(|| peak_by_line(&detection.tiles, detection.window).is_some_and(|(row, col)| scanned_on_wake(row, col)));
    let name: String = image.file_name().unwrap_or_default().to_string_lossy().into();
    let km2 = scored_pixels(detection) as f64 * pixel_m2 / 1e6;
    // the search runs on the averaged grid: a centre may lie a scanned pixel from a drawn box
    let within = SHIP_WITHIN_M.max(spacing.0 * factor.0).max(spacing.1 * factor.1);
    let searched = search.then(|| SearchScore {
        image: name.clone(),
        drawn_ships: annotation
            .ships
            .as_ref()
            .map(|drawn| score_ships(drawn, lonlat, &written, spacing, within)),
        km2,
        ..score_search(&annotation.wakes, lonlat, &written, spacing)
    });
    let score = RealScore {
        image: name,
        footprint,
        wakes: annotation.wakes.len(),
        detections: on_wake.len(),
        false_alarms: on_wake.iter().filter(|on| !**on).count(),
        peak_on_wake: distance(&written["peak"]) <= FOUND_WITHIN_M,
        peak_by_chance: by_chance,
        peak_by_line: by_line,
        strongest_on_wake: on_wake.first() == Some(&true),
        first_on_wake: on_wake.iter().position(|on| *on).map(|i| i + 1),
        km2,
        wake_visibility,
        notes,
        skipped: None,
    };
    Ok((score, searched))
}

/// The visibility ([`visibility::along`]) of each of `annotation`'s wakes (drawn in pixels) in
/// its image as the detector sees it: read as `detect` reads it (`read`), averaged by `factor`
/// (rows, columns) to pixels of `spacing` m, in windows of `n` of them; a wake drawn as a
/// polyline is taken along its first and last points.
fn wake_visibilities(
    annotation: &Annotation,
    read: &ReadOptions,
    factor: (f64, f64),
    n: usize,
    spacing: f64,
) -> Result<Vec<Option<f64>>> {
    let opened = open_product(&annotation.image, read, Band::C, true, &mut |_, _| {})?;
    let product = match opened.source {
        Source::Whole(product) => *product,
        Source::Rows(rows) => rows.read_all(&mut |_, _| {})?,
    };
    let image = if factor == (1.0, 1.0) {
        product.image
    } else {
        wakelab_products::resample::area_average(&product.image, factor.0, factor.1)
    };
    let at = |(x, y): (f64, f64)| (y / factor.0, x / factor.1);
    Ok(annotation
        .wakes
        .iter()
        .map(|wake| match (wake.first(), wake.last()) {
            (Some(&a), Some(&b)) => visibility::along(&image, n, (at(a), at(b)), spacing),
            _ => None,
        })
        .collect())
}

/// Scanned pixels in the map's scored cells, the last row and column of cells cut at the
/// windows' extent (the image's edge).
fn scored_pixels(detection: &wakelab_learn::detect::Detection) -> usize {
    let (w, s) = (detection.window, detection.stride);
    let extent = detection
        .tiles
        .iter()
        .fold((0, 0), |(r, c), t| (r.max(t.row + w), c.max(t.col + w)));
    let span = |i: usize, end: usize| ((i + 1) * s).min(end).saturating_sub(i * s);
    detection
        .map
        .indexed_iter()
        .filter(|(_, v)| v.is_finite())
        .map(|((i, j), _)| span(i, extent.0) * span(j, extent.1))
        .sum()
}

/// The ground area of a scanned pixel (m^2): the product's spacings (rows, columns) times the
/// averaging factors.
fn scanned_pixel_m2(written: &Value, product: (f64, f64)) -> f64 {
    let factor = |i: usize| written["resampled"][i].as_f64().unwrap_or(1.0);
    factor(0) * product.0 * factor(1) * product.1
}

/// `transfer/real.json`: the images of `--real DIR` scored by the detectors of the transfer
/// results whose key this holds.
#[derive(Debug, Serialize, Deserialize)]
pub struct RealResults {
    pub key: String,
    pub dir: PathBuf,
    pub scores: Vec<RealScore>,
    pub summaries: Vec<RealSummary>,
    /// The classic ship and wake search on the same images, once per image (at the first
    /// detector's spacing, as `detect` with it searches), and its summary.
    #[serde(default)]
    pub search: Vec<SearchScore>,
    #[serde(default)]
    pub search_summary: Option<SearchSummary>,
}

/// Where the real images' scores are kept.
pub fn real_file(run_dir: &Path) -> PathBuf {
    run_dir.join("transfer").join("real.json")
}

/// Score every annotated image of `real_dir` with each of `detectors` (footprint, file) of the
/// transfer results keyed `key`; `detect`'s files go to `RUN/real/<footprint>m/<image>/`.
/// Reports progress (images scored, total).
pub fn score_real(
    real_dir: &Path,
    run_dir: &Path,
    key: &str,
    detectors: &[(f64, PathBuf)],
    progress: &mut dyn FnMut(usize, usize),
) -> Result<RealResults> {
    let images = annotations(real_dir)?;
    let total = images.len() * detectors.len();
    let (mut scores, mut search) = (Vec::new(), Vec::new());
    for (k, (footprint, model)) in detectors.iter().enumerate() {
        for annotation in &images {
            let stem = annotation.image.file_stem().unwrap_or_default();
            let name: String = annotation
                .image
                .file_name()
                .unwrap_or_default()
                .to_string_lossy()
                .into();
            let out = run_dir.join("real").join(format!("{footprint:.0}m")).join(stem);
            // the classic search does not depend on the detector: it runs with the first
            match score_image(annotation, model, *footprint, &out, k == 0) {
                Ok((score, searched)) => {
                    scores.push(score);
                    search.extend(searched);
                }
                Err(e) => {
                    let why = format!("{e:#}");
                    scores.push(RealScore {
                        image: name.clone(),
                        footprint: *footprint,
                        wakes: annotation.wakes.len(),
                        detections: 0,
                        false_alarms: 0,
                        peak_on_wake: false,
                        peak_by_chance: None,
                        peak_by_line: None,
                        strongest_on_wake: false,
                        first_on_wake: None,
                        km2: 0.0,
                        wake_visibility: Vec::new(),
                        notes: vec![],
                        skipped: Some(why.clone()),
                    });
                    if k == 0 {
                        search.push(SearchScore {
                            image: name,
                            wakes: annotation.wakes.len(),
                            ships: 0,
                            search_wakes: 0,
                            found: 0,
                            false_wakes: 0,
                            axis_errors_deg: Vec::new(),
                            drawn_ships: None,
                            km2: 0.0,
                            seen_by_both: 0,
                            seen_by_both_found: 0,
                            faint_lines: 0,
                            faint_on_wake: 0,
                            missed_under_faint: 0,
                            promoted: 0,
                            promoted_found: 0,
                            skipped: Some(why),
                        });
                    }
                }
            }
            progress(scores.len(), total);
        }
    }
    let summaries = detectors
        .iter()
        .map(|(f, _)| summarise(*f, &scores.iter().filter(|s| s.footprint == *f).collect::<Vec<_>>()))
        .collect();
    let search_summary = (!search.is_empty()).then(|| summarise_search(&search));
    Ok(RealResults {
        key: key.into(),
        dir: real_dir.to_path_buf(),
        scores,
        summaries,
        search,
        search_summary,
    })
}

/// What the scores of one detector add up to.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct RealSummary {
    pub footprint: f64,
    pub wake_images: usize,
    pub found: usize,
    /// Wake images whose peak lies within 500 m of a wake, and how many would by chance (the sum
    /// of their [`RealScore::peak_by_chance`]; None where no image has one).
    #[serde(default)]
    pub peak_on_wake: usize,
    #[serde(default)]
    pub peak_on_wake_by_chance: Option<f64>,
    /// Wake images whose peak a detector of lines alone would place on a wake (of those with a
    /// [`RealScore::peak_by_line`]; None where none has one).
    #[serde(default)]
    pub peak_on_wake_by_line: Option<usize>,
    pub strongest_on_wake: usize,
    pub false_alarms_per_wake_image: f64,
    pub no_wake_images: usize,
    pub no_wake_images_without_alarm: usize,
    /// None where no image was scanned (no area; null in `real.json`).
    pub false_alarms_per_100_km2: Option<f64>,
    /// The visibility of the wakes of the images scanned.
    #[serde(default)]
    pub wake_visibility: Option<Spread>,
    /// Images this detector could not scan.
    pub skipped: usize,
}

/// The summary of `scores` (one detector's).
pub fn summarise(footprint: f64, scores: &[&RealScore]) -> RealSummary {
    let skipped_count = scores.iter().filter(|s| s.skipped.is_some()).count();
    let scores: Vec<&RealScore> = scores.iter().filter(|s| s.skipped.is_none()).copied().collect();
    let with: Vec<&&RealScore> = scores.iter().filter(|s| s.wakes > 0).collect();
    let without: Vec<&&RealScore> = scores.iter().filter(|s| s.wakes == 0).collect();
    let alarms: usize = scores.iter().map(|s| s.false_alarms).sum();
    let km2: f64 = scores.iter().map(|s| s.km2).sum();
    RealSummary {
        footprint,
        wake_images: with.len(),
        found: with.iter().filter(|s| s.found()).count(),
        peak_on_wake: with.iter().filter(|s| s.peak_on_wake).count(),
        peak_on_wake_by_chance: with.iter().filter_map(|s| s.peak_by_chance).reduce(|a, b| a + b),
        peak_on_wake_by_line: with
            .iter()
            .filter_map(|s| s.peak_by_line)
            .map(usize::from)
            .reduce(|a, b| a + b),
        strongest_on_wake: with.iter().filter(|s| s.strongest_on_wake).count(),
        false_alarms_per_wake_image: with.iter().map(|s| s.false_alarms as f64).sum::<f64>() / with.len().max(1) as f64,
        no_wake_images: without.len(),
        no_wake_images_without_alarm: without.iter().filter(|s| s.detections == 0).count(),
        false_alarms_per_100_km2: (km2 > 0.0).then(|| 100.0 * alarms as f64 / km2),
        wake_visibility: Spread::of(
            &scores
                .iter()
                .flat_map(|s| s.wake_visibility.iter().flatten().copied())
                .collect::<Vec<_>>(),
        ),
        skipped: skipped_count,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn annotation(lonlat: bool, wakes: Vec<Vec<(f64, f64)>>) -> Annotation {
        Annotation {
            image: "a.tif".into(),
            wakes,
            lonlat,
            pixel_spacing: None,
            scale: None,
            exclude: None,
            ships: None,
        }
    }

    /// Distances to a wake: in pixels scaled by each axis' spacing, and in longitude and
    /// latitude by the tangent plane (0.01 degrees of latitude: 1,112 km / 100).
    #[test]
    fn distances_to_a_wake_are_in_metres() {
        let pixels = annotation(false, vec![vec![(0.0, 0.0), (100.0, 0.0)]]);
        // 30 rows below the wake at 10 m rows: 300 m; past its end by 40 columns of 5 m: 200 m
        assert!((to_wakes((50.0, 30.0), &pixels, (10.0, 5.0)) - 300.0).abs() < 1e-9);
        assert!((to_wakes((140.0, 0.0), &pixels, (10.0, 5.0)) - 200.0).abs() < 1e-9);
        let lonlat = annotation(true, vec![vec![(10.0, 55.0), (10.1, 55.0)]]);
        let d = to_wakes((10.05, 55.01), &lonlat, (f64::NAN, f64::NAN));
        assert!((d - 1111.95).abs() < 0.5, "{d}");
    }

    /// An annotation file: pixel wakes, drawn ships, the reading hints, a no-wake image, and
    /// clear errors.
    #[test]
    fn annotations_read_their_wakes_and_hints() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::write(d.join("wake.jpg"), b"").unwrap();
        std::fs::write(
            d.join("wake.geojson"),
            r#"{"type": "FeatureCollection", "wakelab": {"coordinates": "pixel", "pixel_spacing_m": 10, "scale": "display"},
                "features": [{"type": "Feature", "properties": {}, "geometry": {"type": "LineString", "coordinates": [[1, 2], [30, 40]]}},
                             {"type": "Feature", "properties": {"kind": "ship"}, "geometry": {"type": "Point", "coordinates": [1, 2]}}]}"#,
        )
        .unwrap();
        std::fs::write(d.join("sea.tif"), b"").unwrap();
        std::fs::write(
            d.join("sea.geojson"),
            r#"{"type": "FeatureCollection", "features": []}"#,
        )
        .unwrap();
        let read = annotations(d).unwrap();
        assert_eq!(read.len(), 2);
        assert_eq!(
            (read[0].image.file_name().unwrap(), read[0].wakes.len(), read[0].lonlat),
            ("sea.tif".as_ref(), 0, true)
        );
        let wake = &read[1];
        assert_eq!(wake.wakes, vec![vec![(1.0, 2.0), (30.0, 40.0)]]);
        assert_eq!(
            (wake.lonlat, wake.pixel_spacing, wake.scale),
            (false, Some(10.0), Some(InputScale::Display))
        );
        // the image draws a ship, so its ships are scored; the sea's are not drawn
        let ship = DrawnShip {
            min: (1.0, 2.0),
            max: (1.0, 2.0),
        };
        assert_eq!(
            (wake.ships.as_deref(), read[0].ships.as_deref()),
            (Some(&[ship][..]), None)
        );

        // the sea's file rewritten: what annotations() then reads, or why it refuses it
        let sea_reads = |text: &str| {
            std::fs::write(d.join("sea.geojson"), text).unwrap();
            annotations(d)
        };
        // a sea whose ships are drawn and that holds none: ships scored, none there
        let drawn = sea_reads(r#"{"type": "FeatureCollection", "wakelab": {"ships_drawn": true}, "features": []}"#);
        assert_eq!(drawn.unwrap()[0].ships, Some(vec![]));
        let refusals = [
            (
                r#"{"type": "FeatureCollection", "wakelab": {"ships_drawn": "yes"}, "features": []}"#,
                "sea.geojson: wakelab.ships_drawn \"yes\": true or false",
            ),
            (
                r#"{"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {"kind": "ship"}, "geometry": {"type": "LineString", "coordinates": [[1, 2], [3, 4]]}}]}"#,
                "sea.geojson: features[0]: a ship is a Point or a Polygon",
            ),
            (
                r#"{"type": "FeatureCollection", "wakelab": {"pixel_spacing_m": -3}, "features": []}"#,
                "sea.geojson: wakelab.pixel_spacing_m -3",
            ),
        ];
        for (text, why) in refusals {
            let e = sea_reads(text).unwrap_err().to_string();
            assert!(e.contains(why), "{e}");
        }
        std::fs::remove_file(d.join("sea.tif")).unwrap();
        let e = annotations(d).unwrap_err().to_string();
        assert!(e.contains("sea.geojson: no image of that name"), "{e}");
    }

    /// The summary counts wakes found by either rule and alarms over the area scanned.
    #[test]
    fn the_summary_adds_up() {
        let score = |wakes, detections, false_alarms, peak, first| RealScore {
            image: "x".into(),
            footprint: 1280.0,
            wakes,
            detections,
            false_alarms,
            peak_on_wake: peak,
            peak_by_chance: Some(0.25),
            // the line's peak on the wake where the network's is not
            peak_by_line: Some(!peak),
            strongest_on_wake: first == Some(1),
            first_on_wake: first,
            km2: 10.0,
            wake_visibility: vec![Some(wakes as f64), None],
            notes: vec![],
            skipped: None,
        };
        let scores = [
            score(1, 3, 2, false, Some(2)),
            score(1, 1, 0, true, Some(1)),
            score(1, 2, 2, false, None),
            score(0, 0, 0, false, None),
            score(0, 2, 2, false, None),
            RealScore {
                skipped: Some("smaller than the window".into()),
                ..score(1, 0, 0, false, None)
            },
        ];
        let s = summarise(1280.0, &scores.iter().collect::<Vec<_>>());
        assert_eq!((s.wake_images, s.found, s.strongest_on_wake, s.skipped), (3, 2, 1, 1));
        // peaks on a wake, and by chance a quarter for each of the three scanned wake images
        assert_eq!((s.peak_on_wake, s.peak_on_wake_by_chance), (1, Some(0.75)));
        assert_eq!(s.peak_on_wake_by_line, Some(2));
        assert!((s.false_alarms_per_wake_image - 4.0 / 3.0).abs() < 1e-12);
        assert_eq!((s.no_wake_images, s.no_wake_images_without_alarm), (2, 1));
        assert!((s.false_alarms_per_100_km2.unwrap() - 12.0).abs() < 1e-9);
        // the visibilities of the scanned images' wakes: three 1s and two 0s
        let v = s.wake_visibility.unwrap();
        assert_eq!((v.count, v.quartiles), (5, [0.0, 1.0, 1.0]));
        // every image skipped: no area, no rate, and the summary reads back from real.json
        let s = summarise(1280.0, &[&scores[5]]);
        assert_eq!(s.false_alarms_per_100_km2, None);
        let text = serde_json::to_string(&s).unwrap();
        assert_eq!(serde_json::from_str::<RealSummary>(&text).unwrap(), s);
    }
}

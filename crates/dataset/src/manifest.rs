//! The dataset's index: every finished scene of a study gathered into `manifest.json`,
//! `manifest.csv` (one row a scene, the study's axes as columns) and `splits.json`.

use crate::study::Study;
use crate::{fnv, render_key, scene_dir};
use std::collections::BTreeMap;
use std::path::Path;
use wakelab_core::io::{csv_of_records, write_atomically};
use wakelab_core::WakelabError;
use wakelab_schema::axes::AXES;
use wakelab_schema::band::Band;
use wakelab_schema::dataset::SceneRecord;
use wakelab_schema::split::Split;

/// Gather every finished scene of `study` in `dir` into the manifest (JSON and CSV) and the
/// train/test split; returns the records. Pairs go wholly to one side, so both sides are 50/50
/// wake and no-wake; with `grouped_split` whole environments go to one side.
pub fn write_manifest(study: &Study, dir: &Path) -> Result<Vec<SceneRecord>, WakelabError> {
    let pairs = study.pairs()?;
    let mut records = Vec::new();
    for pair in &pairs {
        let (w, n) = pair.ids();
        let key = render_key(study, pair);
        for id in [w, n] {
            let path = scene_dir(dir, &id).join("scene.json");
            if let Ok(text) = std::fs::read_to_string(&path) {
                let r: SceneRecord = serde_json::from_str(&text).map_err(|e| WakelabError::Parse {
                    path: path.display().to_string(),
                    message: e.to_string(),
                })?;
                // a scene of another configuration is not this study's (render_dataset re-renders it)
                if r.render_key == key {
                    records.push(r);
                }
            }
        }
    }
    if records.is_empty() {
        return Err(WakelabError::Dataset {
            path: dir.display().to_string(),
            message: format!(
                "no finished scene of study \"{}\" ({} expected): render them first (wakelab dataset, or its Slurm shards), then merge",
                study.study.name,
                2 * pairs.len()
            ),
        });
    }
    // split by group: hash-ordered groups fill the test side up to test_fraction of the pairs
    let group_of = |r: &SceneRecord| {
        if study.study.grouped_split {
            r.environment.clone()
        } else {
            format!("pair {}", r.pair)
        }
    };
    let mut groups: BTreeMap<String, usize> = BTreeMap::new();
    for r in records.iter().filter(|r| r.label == 1) {
        *groups.entry(group_of(r)).or_default() += 1;
    }
    let mut order: Vec<(u64, String, usize)> = groups
        .into_iter()
        .map(|(g, n)| (fnv(format!("{}:{g}", pairs.len())), g, n))
        .collect();
    order.sort();
    let total: usize = order.iter().map(|o| o.2).sum();
    let target = (study.study.test_fraction * total as f64).round() as usize;
    let mut test_groups = std::collections::BTreeSet::new();
    let mut in_test = 0;
    for (_, g, n) in &order {
        if in_test >= target {
            break;
        }
        test_groups.insert(g.clone());
        in_test += n;
    }
    for r in &mut records {
        r.split = Some(if test_groups.contains(&group_of(r)) {
            Split::Test
        } else {
            Split::Train
        });
    }
    write_atomically(
        dir.join("manifest.json"),
        serde_json::to_string_pretty(&records).expect("serialisable").as_bytes(),
    )?;
    write_atomically(
        dir.join("manifest.csv"),
        manifest_csv(&records, &study.study.bands).as_bytes(),
    )?;
    let split: BTreeMap<String, Vec<&str>> = [Split::Train, Split::Test]
        .into_iter()
        .map(|s| {
            let ids = records
                .iter()
                .filter(|r| r.split.as_ref() == Some(&s))
                .map(|r| r.id.as_str());
            (s.to_string(), ids.collect())
        })
        .collect();
    write_atomically(
        dir.join("splits.json"),
        serde_json::to_string_pretty(&split).expect("serialisable").as_bytes(),
    )?;
    Ok(records)
}

/// The wake's pixel-space geometry as the manifest's CSV writes it (empty for no-wake scenes).
fn geometry_columns(g: Option<&wakelab_schema::dataset::WakeGeometry>) -> [String; 5] {
    let Some(g) = g else { return Default::default() };
    let num = |v: Option<f64>| v.map(|v| format!("{v:.2}")).unwrap_or_default();
    [
        u8::from(g.ship_in_scene).to_string(),
        num(g.stern_pixel.map(|p| p[0])),
        num(g.stern_pixel.map(|p| p[1])),
        num(g.along_track_covered_m.map(|a| a[0])),
        num(g.along_track_covered_m.map(|a| a[1])),
    ]
}

/// The manifest as CSV, one row per scene.
fn manifest_csv(records: &[SceneRecord], bands: &[Band]) -> String {
    let mut header: Vec<String> = ["id", "pair", "label", "split", "seed"].map(String::from).to_vec();
    header.extend(AXES.iter().map(|a| a.name.to_string()));
    header.extend(
        [
            "ship_in_scene",
            "stern_row",
            "stern_col",
            "along_track_from",
            "along_track_to",
            "kelvin_hull",
            "kelvin_mask",
        ]
        .map(String::from),
    );
    for b in bands {
        header.push(format!("visibility_{b}"));
        header.push(format!("label_{b}"));
        header.push(format!("image_{b}"));
        header.push(format!("mask_{b}"));
    }
    let mut rows = vec![header];
    for r in records {
        let mut row: Vec<String> = vec![
            r.id.clone(),
            r.pair.to_string(),
            r.label.to_string(),
            r.split.as_ref().map(Split::to_string).unwrap_or_default(),
            r.seed.to_string(),
        ];
        row.extend(AXES.iter().map(|a| r.parameters.value_text(a.name).unwrap_or_default()));
        row.extend(geometry_columns(r.geometry.as_ref()));
        let kelvin = r.kelvin.as_ref();
        row.push(kelvin.map(|k| k.hull.name().to_string()).unwrap_or_default());
        row.push(kelvin.map(|k| k.mask.clone()).unwrap_or_default());
        for b in bands {
            row.push(format!("{:.6}", r.visibility.get(b).copied().unwrap_or(0.0)));
            row.push(r.label_by_band.get(b).copied().unwrap_or(0).to_string());
            row.push(r.images.get(b).cloned().unwrap_or_default());
            row.push(r.masks.get(b).cloned().unwrap_or_default());
        }
        rows.push(row);
    }
    csv_of_records(rows)
}

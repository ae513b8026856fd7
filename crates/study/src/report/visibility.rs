//! How visible the study's wakes are per band, and whether the detectors' scores follow it: the
//! share of wake scenes whose wake stands out of the clutter (the detection ceiling), the
//! distribution of their contrast to clutter, and the rank correlation between a wake scene's
//! visibility and the score a detector gave it on the test images.

use super::table::{Cell, Table};
use wakelab_core::io::geotiff::quantile;
use wakelab_learn::evaluate::Output;
use wakelab_learn::models::Architecture;
use wakelab_schema::band::Band;
use wakelab_schema::dataset::SceneRecord;
use wakelab_schema::metrics::spearman;
use wakelab_schema::split::Split;

/// One row per single band: wake scenes, their visibility's quartiles, the share at or above 1,
/// and per architecture Spearman's rho between visibility and test score over the wake scenes'
/// test outputs of every repetition.
pub fn visibility_rows(records: &[SceneRecord], outputs: &[Output], bands: &[Band]) -> Vec<Vec<Cell>> {
    let visibility_of = |id: &str, band: Band| {
        records
            .iter()
            .find(|r| r.id == id)
            .and_then(|r| r.visibility.get(&band).copied())
    };
    bands
        .iter()
        .map(|&band| {
            let wakes: Vec<f32> = records
                .iter()
                .filter(|r| r.label == 1)
                .filter_map(|r| r.visibility.get(&band).map(|&v| v as f32))
                .collect();
            let mut row = vec![band.to_string().into(), Cell::count(wakes.len())];
            if wakes.is_empty() {
                row.extend(std::iter::repeat_n(Cell::Missing, 2 + Architecture::ALL.len()));
                return row;
            }
            let [median, lower, upper] = [0.5, 0.25, 0.75].map(|q| quantile(&wakes, q) as f64);
            row.push(Cell::Value {
                shown: format!("{median:.2} [{lower:.2}, {upper:.2}]"),
                parts: vec![
                    ("median", format!("{median:.2}")),
                    ("q25", format!("{lower:.2}")),
                    ("q75", format!("{upper:.2}")),
                ],
            });
            let visible = wakes.iter().filter(|&&v| v >= 1.0).count();
            row.push(Cell::percent(visible as f64 / wakes.len() as f64, 0));
            for a in Architecture::ALL {
                let (x, y): (Vec<f64>, Vec<f64>) = outputs
                    .iter()
                    .filter(|o| {
                        o.architecture == a
                            && o.split == Split::Test
                            && o.label == 1
                            && o.bands.as_single() == Some(band)
                    })
                    .filter_map(|o| visibility_of(&o.scene, band).map(|v| (v, o.output)))
                    .unzip();
                row.push(match spearman(&x, &y) {
                    Some(rho) => {
                        Cell::number(rho, 2).and("n", x.len().to_string(), format!("{rho:.2} (n = {})", x.len()))
                    }
                    None => Cell::Missing,
                });
            }
            row
        })
        .collect()
}

/// The table of [`visibility_rows`] for the report.
pub fn visibility_table(records: &[SceneRecord], outputs: &[Output], bands: &[Band]) -> Table {
    let mut header: Vec<String> = ["band", "wake scenes", "visibility", "visible (>= 1)"]
        .map(String::from)
        .to_vec();
    header.extend(Architecture::ALL.iter().map(|a| format!("{a}: rho(visibility, score)")));
    Table {
        id: "visibility".into(),
        title: "Wake visibility and the detectors' scores".into(),
        caption: "Visibility (median [quartiles] over the band's wake scenes): a wake scene's contrast to clutter, |mean over the wake mask - mean outside| / \
                  standard deviation outside, per pixel, in the band's image (speckle and noise included). \
                  The share at or above 1 is the share of wakes a single pixel shows; a detector integrates \
                  along the wake and can find fainter ones. rho: Spearman's rank correlation between a wake \
                  scene's visibility and the score a detector gave it on the test images (every repetition, \
                  wake scenes only): positive when the detectors see the wakes that stand out more."
            .into(),
        header,
        rows: visibility_rows(records, outputs, bands),
    }
}

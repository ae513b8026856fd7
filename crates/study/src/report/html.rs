//! The report page: one self-contained HTML file (styles inline, pictures as base64 PNG, plots
//! as inline SVG), so it opens in a browser with no network and can be mailed as one file.

use super::learning_tables::confusion_rows;
use super::pictures::{display_values, field_svg, stretch};
use super::svg::{escape, roc_points, LinePlot, Series};
use super::table::Table;
use crate::steps::StudyRun;
use crate::Result;
use ndarray::Array2;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use wakelab_dataset::learning::LearningPlan;
use wakelab_dataset::study::Study;
use wakelab_learn::models::Architecture;
use wakelab_schema::band::{Band, Input};
use wakelab_schema::fusion_row::Source;
use wakelab_schema::split::{Network, Split};

const STYLE: &str = "body{font-family:sans-serif;max-width:1200px;margin:2em auto;padding:0 1em;color:#222}\
table{border-collapse:collapse;margin:0.5em 0 1.5em}th,td{border:1px solid #ccc;padding:3px 8px;text-align:right}\
th{background:#f0f0f0}td:first-child,th:first-child{text-align:left}caption{text-align:left;font-size:0.9em;\
color:#444;caption-side:top;padding-bottom:4px;max-width:900px}.grid{display:flex;flex-wrap:wrap;gap:12px}\
.grid figure{margin:0;max-width:100%}.grid figure:has(>svg:not(.field)){flex:1 1 420px;max-width:580px}.grid figure>svg:not(.field){width:100%;height:auto}figcaption{font-size:0.85em;color:#444}.note{background:#fff8e0;border:1px solid #e8d080;\
padding:0.6em 1em}pre{background:#f6f6f6;padding:0.8em;overflow-x:auto}.cm td{width:3.5em;text-align:center}";

fn table_html(t: &Table) -> String {
    let mut s = format!(
        "<h3 id=\"{}\">{}</h3><table><caption>{}</caption><tr>",
        t.id,
        escape(&t.title),
        escape(&t.caption)
    );
    for h in &t.header {
        let _ = write!(s, "<th>{}</th>", escape(h));
    }
    s.push_str("</tr>");
    for r in &t.rows {
        s.push_str("<tr>");
        for c in r {
            let _ = write!(s, "<td>{}</td>", escape(c.shown()));
        }
        s.push_str("</tr>");
    }
    s.push_str("</table>");
    s
}

/// "wind_speed=5 wind_direction=353.52617587488226" as a person writes it:
/// "wind_speed=5, wind_direction=353.5".
fn readable(environment: &str) -> String {
    environment
        .split_whitespace()
        .map(|pair| match pair.split_once('=') {
            Some((name, value)) => match value.parse::<f64>() {
                Ok(x) => format!("{name}={}", wakelab_core::io::text::number((x * 10.0).round() / 10.0)),
                Err(_) => pair.to_string(),
            },
            None => pair.to_string(),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// Example scenes: one wake/no-wake pair in every band, on a shared colour range per band, and
/// the wake mask.
fn example_scenes(run: &StudyRun) -> Result<String> {
    let dataset = &run.dataset;
    let Some(wake) = dataset.records.iter().find(|r| r.label == 1) else {
        return Ok("<p>No wake scene in the dataset.</p>".into());
    };
    let Some(no_wake) = dataset.records.iter().find(|r| r.pair == wake.pair && r.label == 0) else {
        return Ok("<p>The first wake scene has no partner.</p>".into());
    };
    let mut s = format!(
        "<p>Scene pair {} ({}; the same sea with and without the ship). SAR in dB of the normalised radar \
         cross-section, IR as brightness temperature; both scenes of a band share one colour range \
         (2nd-98th percentile of the wake scene).</p>",
        wake.pair,
        escape(&readable(&wake.environment))
    );
    for band in dataset.bands() {
        let radar = band.is_radar();
        let read = |rel: &str| -> Result<Array2<f32>> { Ok(ndarray_npy::read_npy(dataset.dir.join(rel))?) };
        let w = read(&wake.images[&band])?;
        let n = read(&no_wake.images[&band])?;
        let mask: Array2<u8> = ndarray_npy::read_npy(dataset.dir.join(&wake.masks[&band]))?;
        let (rows, cols) = w.dim();
        let (wv, nv) = (display_values(&w, radar), display_values(&n, radar));
        let mv: Vec<f32> = mask.iter().map(|&m| m as f32).collect();
        let range = stretch(&wv);
        let units = if radar { "dB" } else { "K" };
        let spacing = wake.parameters.pixel_spacing;
        let caption = format!("{cols} x {rows} px of {spacing} m");
        let picture = |values: &[f32], title: String, units: &str, range| {
            field_svg(
                values,
                (rows, cols),
                title,
                units,
                (192.0, &caption),
                range,
                Some(spacing),
            )
        };
        let _ = write!(s, "<h4>{band}</h4><div class=\"grid\">");
        for (values, title) in [(&wv, format!("{band} wake")), (&nv, format!("{band} no wake"))] {
            let _ = write!(s, "<figure>{}</figure>", picture(values, title, units, range)?);
        }
        let mask = picture(&mv, format!("{band} wake mask"), "mask", (0.0, 1.0))?;
        let _ = write!(s, "<figure>{mask}</figure></div>");
    }
    Ok(s)
}

/// 2 x 2 confusion matrices of every row.
fn confusion_matrices(run: &StudyRun) -> String {
    let mut s = String::from("<div class=\"grid\">");
    for r in confusion_rows(run) {
        let _ = write!(
            s,
            "<figure><table class=\"cm\"><tr><th></th><th>wake</th><th>no wake</th></tr>\
             <tr><th>said wake</th><td>{}</td><td>{}</td></tr><tr><th>said none</th><td>{}</td><td>{}</td></tr>\
             </table><figcaption>{} · {}</figcaption></figure>",
            r.tp,
            r.fp,
            r.fn_,
            r.tn,
            r.architecture,
            escape(&r.bands.to_string())
        );
    }
    s.push_str("</div>");
    s
}

/// ROC curves of the pooled test outputs, one plot per architecture.
fn roc_plots(run: &StudyRun) -> String {
    let mut s = String::from("<div class=\"grid\">");
    for a in Architecture::ALL {
        let mut groups: BTreeMap<Source, (Vec<f64>, Vec<u8>)> = BTreeMap::new();
        for o in run
            .outputs
            .iter()
            .filter(|o| o.architecture == a && o.split == Split::Test)
        {
            let g = groups.entry(Source::Input(o.bands.clone())).or_default();
            g.0.push(o.output);
            g.1.push(o.label);
        }
        let s_and_x = [Input::single(Band::S), Input::single(Band::X)];
        for f in run
            .fused
            .iter()
            .filter(|f| f.architecture == a && f.fusion.sources == s_and_x)
        {
            let g = groups.entry(Source::Fusion(f.fusion.clone())).or_default();
            g.0.push(f.output);
            g.1.push(f.label);
        }
        let order: Vec<Source> = run
            .inputs
            .iter()
            .cloned()
            .map(Source::Input)
            .chain(groups.keys().filter(|k| k.fusion().is_some()).cloned())
            .collect();
        let series = order
            .iter()
            .filter_map(|k| groups.get(k).map(|(sc, l)| (k, sc, l)))
            .map(|(k, sc, l)| Series {
                name: k
                    .to_string()
                    .replace("Bayes classifier", "Bayes")
                    .replace("Dempster-Shafer", "DS"),
                points: roc_points(sc, l),
            })
            .collect();
        let plot = LinePlot {
            title: format!("ROC, \"{a}\""),
            x_label: "false positive rate".into(),
            y_label: "true positive rate".into(),
            x_range: Some((0.0, 1.0)),
            y_range: Some((0.0, 1.0)),
            series,
            diagonal: true,
            paired: false,
        };
        let _ = write!(s, "<figure>{}</figure>", plot.to_svg());
    }
    s.push_str("</div>");
    s
}

/// Training loss per epoch (mean over repetitions), one plot per network.
fn training_plots(run: &StudyRun) -> String {
    let mut s = String::from("<div class=\"grid\">");
    let networks = Architecture::ALL
        .map(Network::Classifier)
        .into_iter()
        .chain([Network::Segmenter]);
    for network in networks {
        let mut by_input: BTreeMap<Input, BTreeMap<usize, (f64, usize)>> = BTreeMap::new();
        for c in run.curves.iter().filter(|c| c.network == network) {
            let e = by_input
                .entry(c.bands.clone())
                .or_default()
                .entry(c.epoch.epoch)
                .or_default();
            e.0 += c.epoch.loss;
            e.1 += 1;
        }
        if by_input.is_empty() {
            continue;
        }
        let series = run
            .inputs
            .iter()
            .filter_map(|i| by_input.get(i).map(|m| (i, m)))
            .map(|(i, m)| Series {
                name: i.to_string(),
                points: m.iter().map(|(&e, &(sum, n))| (e as f64, sum / n as f64)).collect(),
            })
            .collect();
        let title = match network {
            Network::Segmenter => "U-Net (0.7 BCE + 0.3 Dice loss)".to_string(),
            Network::Classifier(a) => format!("\"{a}\" classifier (BCE)"),
        };
        let plot = LinePlot {
            title,
            x_label: "epoch".into(),
            y_label: "training loss".into(),
            x_range: None,
            y_range: None,
            series,
            diagonal: false,
            paired: false,
        };
        let _ = write!(s, "<figure>{}</figure>", plot.to_svg());
    }
    s.push_str("</div>");
    s
}

/// How the study's recipe departs from the spec's (4.1-4.2).
fn recipe_note(plan: &LearningPlan) -> String {
    let spec = LearningPlan::default();
    // (name, the study's value, the spec's value) of each setting of the recipe
    let settings = |p: &LearningPlan| -> [(&'static str, String); 10] {
        [
            ("repetitions", p.repetitions.to_string()),
            ("classifier epochs", p.epochs.to_string()),
            ("augmentation", p.augmentation.name().to_string()),
            ("classifier optimiser", p.optimiser.name().to_string()),
            ("classifier learning rate", p.learning_rate.to_string()),
            ("classifier weight decay", p.weight_decay.to_string()),
            ("U-Net epochs", p.unet_epochs.to_string()),
            ("U-Net Adam learning rate", p.unet_learning_rate.to_string()),
            ("U-Net batch size", p.unet_batch_size.to_string()),
            ("U-Net width", p.unet_width.to_string()),
        ]
    };
    let changes: Vec<String> = (settings(plan).into_iter().zip(settings(&spec)))
        .filter(|((_, ours), (_, theirs))| ours != theirs)
        .map(|((name, ours), (_, theirs))| format!("{name} {ours} (spec: {theirs})"))
        .collect();
    if changes.is_empty() {
        "<p>Training follows the spec's recipe (4.1): SGD lr 1e-3 with L2 0.1 for 60 epochs; the U-Net by \
         Adam lr 1e-4 for 60 epochs; 5 repetitions.</p>"
            .into()
    } else {
        format!(
            "<p class=\"note\"><b>A shortened recipe, not the paper's:</b> {}. This keeps the whole study \
             within minutes on a laptop; numbers beside the paper's are therefore indicative. \
             <code>wakelab run --preset paper</code> runs the spec's scale and recipe.</p>",
            escape(&changes.join("; "))
        )
    }
}

/// The whole page.
pub fn report_page(
    study: &Study,
    run: &StudyRun,
    tables: &[Table],
    timing: &Table,
    radar_figures: &[String],
    whole_scene: &str,
    reliability: Option<&str>,
) -> Result<String> {
    let mut s = String::new();
    let title = format!("wakelab study \"{}\"", study.study.name);
    let _ = write!(
        s,
        "<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\"><title>{}</title><style>{STYLE}</style></head><body>",
        escape(&title)
    );
    let records = &run.dataset.records;
    let wakes = records.iter().filter(|r| r.label == 1).count();
    let _ = write!(
        s,
        "<h1>{}</h1><p>wakelab {} · run {} on {} · {} scenes ({} with a wake, {} without) in bands {} · \
         {} inputs × 3 architectures × {} repetitions · seed {}</p>",
        escape(&title),
        env!("CARGO_PKG_VERSION"),
        escape(&run.started),
        escape(&run.device),
        records.len(),
        wakes,
        records.len() - wakes,
        run.dataset
            .bands()
            .iter()
            .map(|b| b.name())
            .collect::<Vec<_>>()
            .join(", "),
        run.inputs.len(),
        run.plan.repetitions,
        run.plan.seed
    );
    s.push_str(&recipe_note(&run.plan));
    s.push_str(
        "<p class=\"note\">In every recipe the U-Net's BCE is class-balanced (Xie &amp; Tu 2015: wake and \
         background pixels weigh half each), not erratum 9's plain BCE, under which no mask pixel reached 0.5.</p>",
    );
    s.push_str(
        "<h2>Contents</h2><ul><li><a href=\"#scenes\">Example scenes</a></li>\
         <li><a href=\"#radar\">Radar physics</a></li>",
    );
    for t in tables {
        let _ = write!(s, "<li><a href=\"#{}\">{}</a></li>", t.id, escape(&t.title));
    }
    if reliability.is_some() {
        s.push_str("<li><a href=\"#reliability\">Reliability</a></li>");
    }
    s.push_str(
        "<li><a href=\"#test-scenes\">Test scenes</a></li>\
         <li><a href=\"#whole-scene\">Whole-scene maps</a></li>\
         <li><a href=\"#matrices\">Confusion matrices</a></li><li><a href=\"#roc\">ROC curves</a></li>\
         <li><a href=\"#training\">Training curves</a></li><li><a href=\"#timing\">Wall time</a></li>\
         <li><a href=\"#config\">Configuration</a></li></ul>",
    );
    s.push_str("<h2 id=\"scenes\">Example scenes</h2>");
    s.push_str(&example_scenes(run)?);
    s.push_str(
        "<h2 id=\"radar\">Radar physics</h2><p>The open sea's C-band VV sigma0 (two-scale Bragg, specular \
         and breaking waves; the study's base sea without swell) against the geophysical model function \
         CMOD5.N (Hersbach 2010), and the example pair's across-wake contrast per radar band (each row's \
         mean along the image, wake scene over no-wake scene). Observed turbulent-wake contrasts are a \
         few dB, weaker at higher wind and in older wakes. The table \"The spec's environments\" says \
         whether the wake is bright or dark in each band without and with swell, beside the spec's Figs. \
         3.1-3.2, with the rates that decide it.</p><div class=\"grid\">",
    );
    for svg in radar_figures {
        let _ = write!(s, "<figure>{svg}</figure>");
    }
    s.push_str("</div>");
    s.push_str("<h2>Results</h2>");
    for t in tables {
        s.push_str(&table_html(t));
    }
    if let Some(svg) = reliability {
        let _ = write!(
            s,
            "<h2 id=\"reliability\">Reliability</h2><p>The C-band detectors' test chips of all repetitions: the \
             share of wake chips against the mean wake probability in each tenth of [0, 1], raw (dashed) and \
             calibrated (solid, each chip by a temperature fitted on the other half of its repetition's chips); \
             a calibrated detector lies on the diagonal (table \"Calibrated probabilities\").</p><figure>{svg}</figure>"
        );
    }
    s.push_str(
        "<h2 id=\"test-scenes\">Test scenes</h2><p>Per band and wind speed, the first repetition's test scenes \
         \"base\" scored highest and lowest, with and without a wake, and every detector's verdict (SAR in \
         dB, IR in K, each image stretched over its 2nd-98th percentile).</p>",
    );
    s.push_str(&super::test_scenes::test_scene_grid(run)?);
    s.push_str(
        "<h2 id=\"whole-scene\">Whole-scene maps</h2><p>Each band's \"base\" detector scanned over one \
         scene eight chips wide, as <code>wakelab detect</code> does (table \"Detection on a whole scene\", with the \
         false alarms at the threshold that flags 5 % of the detector's no-wake test chips): the image, the map \
         of window probabilities, and the band's physics mask of the wake; boxes mark the cells at or above that \
         threshold.</p>",
    );
    s.push_str(whole_scene);
    s.push_str("<h2 id=\"matrices\">Confusion matrices</h2><p>Test images summed over the repetitions.</p>");
    s.push_str(&confusion_matrices(run));
    s.push_str(
        "<h2 id=\"roc\">ROC curves</h2><p>Test outputs of all repetitions pooled; the dashed line is chance.</p>",
    );
    s.push_str(&roc_plots(run));
    s.push_str("<h2 id=\"training\">Training curves</h2><p>Mean training loss per epoch over the repetitions.</p>");
    s.push_str(&training_plots(run));
    s.push_str(&table_html(timing));
    let _ = write!(
        s,
        "<h2 id=\"config\">Configuration</h2><p>The study file this run used (its <code>[base]</code> table \
         is the wakelab configuration every scene starts from; <code>wakelab config show</code> prints all \
         of it).</p><pre>{}</pre></body></html>",
        escape(&toml::to_string(study)?)
    );
    Ok(s)
}

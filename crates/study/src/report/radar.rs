//! The report's radar-physics figures: wakelab's C-band VV sigma0 of the open sea against
//! CMOD5.N (Hersbach 2010), and the across-wake contrast of the example scene pair in S, C and
//! X band.

use super::svg::{LinePlot, Series};
use crate::steps::environments::Sigma0Curve;
use crate::steps::StudyRun;
use anyhow::Result;
use ndarray::Array2;

/// Two plots (looking up-wind, cross-wind) of the environments step's sigma0 curves: wakelab's
/// C-band VV sigma0 (solid) and CMOD5.N's over incidence for winds of 5, 10 and 15 m/s.
pub fn sigma0_against_cmod5n(curves: &[Sigma0Curve]) -> Vec<LinePlot> {
    let mut looks: Vec<&str> = Vec::new();
    for c in curves {
        if !looks.contains(&c.look.as_str()) {
            looks.push(&c.look);
        }
    }
    looks
        .into_iter()
        .map(|name| {
            let mut series = Vec::new();
            for c in curves.iter().filter(|c| c.look == name) {
                let wind = c.wind;
                series.push(Series {
                    name: format!("wakelab {wind}"),
                    points: c.incidence.iter().copied().zip(c.wakelab_db.iter().copied()).collect(),
                });
                series.push(Series {
                    name: format!("CMOD5.N {wind}"),
                    points: c
                        .incidence
                        .iter()
                        .zip(&c.cmod5n_db)
                        .map(|(&inc, db)| (inc, db.unwrap_or(f64::NAN)))
                        .collect(),
                });
            }
            LinePlot {
                title: format!("C-band VV sigma0, {name}, wind in m/s"),
                x_label: "incidence (deg)".into(),
                y_label: "sigma0 (dB)".into(),
                x_range: Some((20.0, 50.0)),
                y_range: None,
                series,
                diagonal: false,
                paired: true,
            }
        })
        .collect()
}

/// The across-wake contrast of the dataset's first wake scene against its no-wake partner, for
/// every radar band: the pixels astern of the ship binned by their distance across the track
/// (one pixel wide, at the scene's heading and placement), each bin's mean in dB.
pub fn across_wake_contrast(run: &StudyRun) -> Result<Option<LinePlot>> {
    let dataset = &run.dataset;
    let Some(wake) = dataset.records.iter().find(|r| r.label == 1) else {
        return Ok(None);
    };
    let Some(no_wake) = dataset.records.iter().find(|r| r.pair == wake.pair && r.label == 0) else {
        return Ok(None);
    };
    let p = &wake.parameters;
    let spacing = p.pixel_spacing;
    let grid = wakelab_surface::scene::SceneGrid::new(&wakelab_core::config::SceneConfig {
        pixel_spacing: spacing,
        size: p.image_size,
        along_track: p.along_track,
        cross_track: p.cross_track,
        heading: p.heading,
        other_wakes: Vec::new(),
        centre: None,
    });
    // each pixel's bin across the track, none ahead of the stern
    let n = p.image_size;
    let bins: Vec<Option<i64>> = (0..n * n)
        .map(|i| {
            let (behind, port) = grid.track_position(i / n, i % n);
            (behind >= 0.0).then(|| (port / spacing).round() as i64)
        })
        .collect();
    let mut series = Vec::new();
    for band in dataset.bands().into_iter().filter(|b| b.is_radar()) {
        let read = |rel: &str| -> Result<Array2<f32>> { Ok(ndarray_npy::read_npy(dataset.dir.join(rel))?) };
        let (w, nw) = (read(&wake.images[&band])?, read(&no_wake.images[&band])?);
        let mut sums: std::collections::BTreeMap<i64, (f64, f64)> = Default::default();
        for ((bin, a), b) in bins.iter().zip(w.iter()).zip(nw.iter()) {
            if let Some(bin) = bin {
                let e = sums.entry(*bin).or_default();
                e.0 += *a as f64;
                e.1 += *b as f64;
            }
        }
        let points = sums
            .into_iter()
            .filter(|(_, (a, b))| *a > 0.0 && *b > 0.0)
            .map(|(bin, (a, b))| (bin as f64 * spacing, 10.0 * (a / b).log10()))
            .collect();
        series.push(Series {
            name: band.to_string(),
            points,
        });
    }
    if series.is_empty() {
        return Ok(None);
    }
    // the wake's own width, twice over (at least +-200 m): where any band departs by 0.05 dB
    let reach = series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|p| p.1.abs() > 0.05)
        .map(|p| p.0.abs())
        .fold(100.0f64, f64::max);
    let half = (2.0 * reach).min(rows_extent(&series));
    Ok(Some(LinePlot {
        title: format!("Across-wake contrast, scene pair {}", wake.pair),
        x_label: "across-track distance (m)".into(),
        y_label: "wake / no wake (dB)".into(),
        x_range: Some((-half, half)),
        y_range: None,
        series,
        diagonal: false,
        paired: false,
    }))
}

/// The largest |y| of any series' points.
fn rows_extent(series: &[Series]) -> f64 {
    series
        .iter()
        .flat_map(|s| s.points.iter())
        .map(|p| p.0.abs())
        .fold(0.0, f64::max)
}

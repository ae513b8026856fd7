//! Free wakes: dark lines of the whole image whose ship is gone or not seen, by the Radon
//! transform of the whole image read on a coarse grid (the field's classic baseline: Rey et al.
//! 1990, Eldhuset 1996, Graziano et al. 2017). A line counts when it is significant among the lines
//! of its own direction (a swell's troughs are many parallel lines, a wake one), long enough, and
//! not the wake of a ship already found ([`crate::wake::ship_wake`]).

use crate::lines::{line, span, Signature, WakeOptions};
use crate::radon::{robust_spread, Normalised, SearchImage};
use crate::wake::Wake;
use crate::{line_difference, Geometry};
use rayon::prelude::*;

/// Free wakes: dark lines of the whole image, significant among the lines of their direction
/// (robust z of the trough contrast over the offsets: a swell's troughs are many), at least `free_min_length_m` long, and not
/// the wake of a ship already found (`known`). The image is read every `cell` metres.
pub fn free_wakes(search: &SearchImage, known: &[Wake], o: &WakeOptions) -> Vec<Wake> {
    let fine = &search.fine;
    let (h, w) = fine.values.dim();
    let g = fine.geometry;
    let diagonal = (h as f64 * g.spacing.0).hypot(w as f64 * g.spacing.1);
    // read on a grid of at least 20 m and at most ~2000 cells along the diagonal
    let pixel = g.spacing.0.max(g.spacing.1);
    let factor = ((diagonal / 2000.0).max(20.0) / pixel).ceil().max(1.0) as usize;
    let coarse = fine.coarsened(factor);
    let to_fine = |(r, c): (f64, f64)| ((r + 0.5) * factor as f64 - 0.5, (c + 0.5) * factor as f64 - 0.5);
    let to_coarse = |(r, c): (f64, f64)| ((r + 0.5) / factor as f64 - 0.5, (c + 0.5) / factor as f64 - 0.5);
    let image = &coarse;
    let g = image.geometry;
    let (h, w) = image.values.dim();
    let cell = g.spacing.0.max(g.spacing.1);
    let o = &WakeOptions {
        trough_half_width_m: o.trough_half_width_m.max(0.5 * cell),
        side_half_width_m: o.side_half_width_m.max(cell),
        side_offset_m: o.side_offset_m.max(3.0 * cell),
        ..*o
    };
    let known: Vec<Wake> = known
        .iter()
        .map(|k| Wake {
            start: to_coarse(k.start),
            ..k.clone()
        })
        .collect();
    let centre = (0.5 * (h - 1) as f64, 0.5 * (w - 1) as f64);
    let lines = radon_lines(image, o, diagonal);
    if lines.is_empty() {
        return Vec::new();
    }
    // each line's z among the lines of its own direction: a swell darkens many parallel lines
    // (its troughs), a wake one
    let mut by_heading: std::collections::BTreeMap<i64, Vec<f64>> = Default::default();
    for l in &lines {
        by_heading.entry((l.1 * 4.0).round() as i64).or_default().push(l.0);
    }
    let spread: std::collections::BTreeMap<i64, (f64, f64)> =
        by_heading.into_iter().map(|(k, v)| (k, robust_spread(&v))).collect();
    let z_of = |l: &(f64, f64, f64)| {
        let (m, s) = spread[&((l.1 * 4.0).round() as i64)];
        (l.0 - m) / s
    };
    let mut order: Vec<usize> = (0..lines.len()).collect();
    order.sort_by(|&a, &b| z_of(&lines[b]).total_cmp(&z_of(&lines[a])));
    let mut found: Vec<Wake> = Vec::new();
    for i in order {
        let (c, hd, off) = lines[i];
        let z = z_of(&lines[i]);
        if z < o.free_min_z || found.len() >= 10 {
            break;
        }
        // not beside a stronger one (5 degrees, 5 cells)
        if found.iter().any(|f| {
            line_difference(f.axis_deg, hd) < 5.0
                && line_distance(&g, to_coarse(f.start), f.axis_deg, centre_offset(&g, centre, hd, off)) < 5.0 * cell
        }) {
            continue;
        }
        let through = centre_offset(&g, centre, hd, off);
        let Some((start, end, length)) = dark_extent(image, through, hd, diagonal, o) else {
            continue;
        };
        if length < o.free_min_length_m {
            continue;
        }
        // a ship's wake already found: same direction, its apex near the line
        if known
            .iter()
            .any(|k| line_difference(k.axis_deg, hd) < 5.0 && line_distance(&g, through, hd, k.start) < 300.0)
        {
            continue;
        }
        found.push(Wake {
            ship: None,
            signature: Signature::Trough,
            start: to_fine(start),
            end: to_fine(end),
            axis_deg: hd,
            course_deg: None,
            course_sigma_deg: None,
            length_m: length,
            contrast: c,
            z,
            along_hull: false,
            arms: None,
            offset_m: None,
            speed: None,
            promoted: false,
        });
    }
    found
}

/// Every line's trough contrast (contrast, heading, offset across from the centre in metres),
/// headings every degree over [0, 180) and offsets every cell: the Radon transform by
/// projection (each pixel binned by its distance across the heading, its bin's mean the line's
/// mean), the trough one bin wide, the sides the bins `side_offset_m` +- `side_half_width_m`
/// away, the darker side counted (a trough is darker than both; a line without sea on both
/// sides is left out). Lines shorter than a third of the diagonal are left out.
fn radon_lines(image: &Normalised, o: &WakeOptions, diagonal: f64) -> Vec<(f64, f64, f64)> {
    let g = image.geometry;
    let (h, w) = image.values.dim();
    let cell = g.spacing.0.max(g.spacing.1);
    let (rc, cc) = (0.5 * (h - 1) as f64, 0.5 * (w - 1) as f64);
    let bins = (diagonal / cell).ceil() as usize + 2;
    let half = bins as f64 / 2.0;
    let side = (
        ((o.side_offset_m - o.side_half_width_m) / cell).round().max(1.0) as usize,
        ((o.side_offset_m + o.side_half_width_m) / cell).round().max(1.0) as usize,
    );
    let min_count = diagonal / 3.0 / cell;
    span(0.0, 179.0, 1.0)
        .par_iter()
        .flat_map_iter(|&hd| {
            let (s, c) = hd.to_radians().sin_cos();
            let (mut sum, mut count) = (vec![0f64; bins], vec![0f64; bins]);
            for ((r, col), &v) in image.values.indexed_iter() {
                if !v.is_finite() {
                    continue;
                }
                let (north, east) = (-(r as f64 - rc) * g.spacing.0, (col as f64 - cc) * g.spacing.1);
                let across = east * c - north * s;
                let bin = (across / cell + half).floor();
                if bin >= 0.0 && (bin as usize) < bins {
                    sum[bin as usize] += v as f64;
                    count[bin as usize] += 1.0;
                }
            }
            let mean = |b: usize| (count[b] >= 0.5 * min_count).then(|| sum[b] / count[b]);
            (0..bins)
                .filter_map(|b| {
                    if count[b] < min_count {
                        return None;
                    }
                    let trough = sum[b] / count[b];
                    let side_mean = |bins: Vec<usize>| {
                        let v: Vec<f64> = bins.into_iter().filter_map(mean).collect();
                        (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
                    };
                    let left = side_mean((side.0..=side.1).filter_map(|k| b.checked_sub(k)).collect());
                    let right = side_mean((side.0..=side.1).map(|k| b + k).filter(|&k| k < bins).collect());
                    // darker than both sides: a trough, not an edge; a line without sea on
                    // one side (the image's edge, a display's frame) is not one
                    let (Some(l), Some(r)) = (left, right) else {
                        return None;
                    };
                    let sides = l.min(r);
                    let offset = (b as f64 + 0.5 - half) * cell;
                    Some((sides - trough, hd, offset))
                })
                .collect::<Vec<_>>()
        })
        .collect()
}

/// A point on the line through `centre` offset `off` metres across heading `hd`.
fn centre_offset(g: &Geometry, centre: (f64, f64), hd: f64, off: f64) -> (f64, f64) {
    let (vr, vc) = g.step(hd + 90.0);
    (centre.0 + vr * off, centre.1 + vc * off)
}

/// The ground distance (m) of `point` from the line through `through` along `heading`.
fn line_distance(g: &Geometry, through: (f64, f64), heading: f64, point: (f64, f64)) -> f64 {
    let (dr, dc) = (point.0 - through.0, point.1 - through.1);
    let (north, east) = (-dr * g.spacing.0, dc * g.spacing.1);
    let (s, c) = heading.to_radians().sin_cos();
    // the component across the heading (east, north) = (sin, cos)
    (east * c - north * s).abs()
}

/// A line's dark stretch: its ends (fractional pixels) and its length (m).
type Extent = ((f64, f64), (f64, f64), f64);

/// The longest run of 250 m segments along the line where the trough is darker than its sides
/// (one weak segment allowed): its ends and length.
fn dark_extent(
    image: &Normalised,
    through: (f64, f64),
    heading: f64,
    diagonal: f64,
    o: &WakeOptions,
) -> Option<Extent> {
    let segment = 250.0;
    let g = image.geometry;
    let starts = span(-0.5 * diagonal, 0.5 * diagonal - segment, segment);
    let dark: Vec<Option<bool>> = starts
        .iter()
        .map(|&d| {
            let c = line(image, through, heading, d, o, d + segment, Signature::Trough).contrast;
            c.is_finite().then_some(c >= 0.5 * o.min_contrast)
        })
        .collect();
    let (mut best, mut run_start, mut misses) = (None::<(usize, usize)>, None::<usize>, 0);
    let mut last_good = 0;
    for (i, d) in dark.iter().enumerate() {
        match d {
            Some(true) => {
                run_start.get_or_insert(i);
                last_good = i;
                misses = 0;
            }
            _ => {
                misses += 1;
                if misses >= 2 || d.is_none() {
                    if let Some(s) = run_start.take() {
                        if best.is_none_or(|(a, b)| last_good - s > b - a) {
                            best = Some((s, last_good));
                        }
                    }
                    misses = 0;
                }
            }
        }
    }
    if let Some(s) = run_start {
        if best.is_none_or(|(a, b)| last_good - s > b - a) {
            best = Some((s, last_good));
        }
    }
    let (a, b) = best?;
    let (d0, d1) = (starts[a], starts[b] + segment);
    let (ur, uc) = g.step(heading);
    Some((
        (through.0 + ur * d0, through.1 + uc * d0),
        (through.0 + ur * d1, through.1 + uc * d1),
        d1 - d0,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A display's dark frame (the top 40 m of a 3 km image 3 dB dark) has sea on one side
    /// only: it is an edge, not a wake, and the free search reports nothing.
    #[test]
    fn an_images_dark_edge_is_no_free_wake() {
        let g = Geometry::along_rows(10.0, 35.0, None);
        let mut image = crate::speckle(300, 300, 4, 0.01, 11);
        image.slice_mut(ndarray::s![..4, ..]).mapv_inplace(|v| v * 0.5);
        let search = SearchImage::new(image.view(), &g, crate::BACKGROUND_M);
        let found = free_wakes(&search, &[], &WakeOptions::default());
        assert!(found.is_empty(), "{found:?}");
    }

    /// Speckle alone holds no free wake; a dark line 4 km long through an empty scene is one.
    #[test]
    fn free_wakes_are_long_dark_lines() {
        let g = Geometry::along_rows(10.0, 35.0, None);
        let mut image = crate::speckle(600, 600, 4, 0.01, 5);
        let empty = free_wakes(
            &SearchImage::new(image.view(), &g, 2000.0),
            &[],
            &WakeOptions::default(),
        );
        assert!(empty.is_empty(), "{empty:?}");
        // a line at 60 degrees through (300, 300), 4 km long, 3 dB dark and 60 m wide
        let (ur, uc) = g.step(60.0);
        let (vr, vc) = g.step(150.0);
        for i in -200..=200 {
            for j in -3..=3 {
                let (r, c) = (
                    300.0 + ur * 10.0 * i as f64 + vr * 10.0 * j as f64,
                    300.0 + uc * 10.0 * i as f64 + vc * 10.0 * j as f64,
                );
                if (0.0..600.0).contains(&r) && (0.0..600.0).contains(&c) {
                    image[[r.round() as usize, c.round() as usize]] *= 0.5;
                }
            }
        }
        let found = free_wakes(
            &SearchImage::new(image.view(), &g, 2000.0),
            &[],
            &WakeOptions::default(),
        );
        assert_eq!(found.len(), 1, "{found:?}");
        let wake = &found[0];
        assert!(line_difference(wake.axis_deg, 60.0) < 2.0, "{wake:?}");
        assert!(wake.length_m > 3000.0, "{wake:?}");
        assert!(wake.course_deg.is_none());
    }
}

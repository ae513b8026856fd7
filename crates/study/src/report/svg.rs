//! Line plots written directly as SVG (ROC and training curves of the report): axes with ticks,
//! one coloured polyline per series and a legend. No external tool, no fonts beyond the
//! browser's sans-serif.

use std::fmt::Write as _;

/// One named line.
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

/// A plot: title, axis labels and fixed or data-driven ranges.
pub struct LinePlot {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub x_range: Option<(f64, f64)>,
    pub y_range: Option<(f64, f64)>,
    pub series: Vec<Series>,
    /// Draw the diagonal y = x (chance line of a ROC plot).
    pub diagonal: bool,
    /// Series come in pairs (a model, then its reference): the second of each pair is drawn
    /// dashed in the first's colour.
    pub paired: bool,
}

/// Colour-blind-safe qualitative palette (Okabe & Ito 2008; its yellow, too faint on white,
/// replaced by Tol's wine), then greys.
const PALETTE: [&str; 10] = [
    "#0072B2", "#E69F00", "#009E73", "#CC79A7", "#56B4E9", "#D55E00", "#882255", "#000000", "#777777", "#BBBBBB",
];

const W: f64 = 420.0;
const H: f64 = 300.0;
const LEFT: f64 = 52.0;
const RIGHT: f64 = 120.0;
const TOP: f64 = 28.0;
const BOTTOM: f64 = 40.0;
/// Share of each axis range left between the data and the frame.
const FRAME_MARGIN: f64 = 0.02;

/// Text as HTML/SVG character data or a double-quoted attribute value.
pub fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// About five round tick values covering [lo, hi].
pub(crate) fn ticks(lo: f64, hi: f64) -> Vec<f64> {
    let span = (hi - lo).max(1e-12);
    let raw = span / 5.0;
    let magnitude = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 2.5, 5.0, 10.0]
        .iter()
        .map(|m| m * magnitude)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * magnitude);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|i| i as f64 * step).collect()
}

pub(crate) fn tick_label(v: f64) -> String {
    if v == 0.0 || (v.abs() >= 0.01 && v.abs() < 1e5) {
        let s = format!("{v:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.1e}")
    }
}

impl LinePlot {
    fn range(&self, fixed: Option<(f64, f64)>, pick: impl Fn(&(f64, f64)) -> f64) -> (f64, f64) {
        if let Some(r) = fixed {
            return r;
        }
        let values: Vec<f64> = self
            .series
            .iter()
            .flat_map(|s| s.points.iter().map(&pick))
            .filter(|v| v.is_finite())
            .collect();
        let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        if !lo.is_finite() {
            (0.0, 1.0)
        } else if hi > lo {
            (lo, hi)
        } else {
            (lo - 0.5, lo + 0.5)
        }
    }

    /// The plot as an `<svg>` element. The frame lies 2 % of each range outside the data, so
    /// a line along an edge (a perfect ROC curve runs up x = 0 and along y = 1) is not hidden
    /// under the frame.
    pub fn to_svg(&self) -> String {
        let padded = |(lo, hi): (f64, f64)| (lo - FRAME_MARGIN * (hi - lo), hi + FRAME_MARGIN * (hi - lo));
        let (x0, x1) = padded(self.range(self.x_range, |p| p.0));
        let (y0, y1) = padded(self.range(self.y_range, |p| p.1));
        let (pw, ph) = (W - LEFT - RIGHT, H - TOP - BOTTOM);
        let sx = |x: f64| LEFT + (x - x0) / (x1 - x0) * pw;
        let sy = |y: f64| TOP + ph - (y - y0) / (y1 - y0) * ph;
        let mut s = String::new();
        let _ = write!(
            s,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" viewBox="0 0 {W} {H}" font-family="sans-serif" font-size="11">"#
        );
        let _ = write!(
            s,
            r#"<rect x="{LEFT}" y="{TOP}" width="{pw}" height="{ph}" fill="white" stroke="black"/>"#
        );
        let _ = write!(
            s,
            r#"<text x="{}" y="16" text-anchor="middle" font-size="13">{}</text>"#,
            LEFT + pw / 2.0,
            escape(&self.title)
        );
        for t in ticks(x0, x1) {
            let x = sx(t);
            let _ = write!(
                s,
                r##"<line x1="{x:.1}" y1="{TOP}" x2="{x:.1}" y2="{:.1}" stroke="#e0e0e0"/><text x="{x:.1}" y="{:.1}" text-anchor="middle">{}</text>"##,
                TOP + ph,
                TOP + ph + 14.0,
                tick_label(t)
            );
        }
        for t in ticks(y0, y1) {
            let y = sy(t);
            let _ = write!(
                s,
                r##"<line x1="{LEFT}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#e0e0e0"/><text x="{:.1}" y="{:.1}" text-anchor="end">{}</text>"##,
                LEFT + pw,
                LEFT - 4.0,
                y + 4.0,
                tick_label(t)
            );
        }
        let _ = write!(
            s,
            r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
            LEFT + pw / 2.0,
            H - 6.0,
            escape(&self.x_label)
        );
        let _ = write!(
            s,
            r#"<text x="14" y="{:.1}" text-anchor="middle" transform="rotate(-90 14 {:.1})">{}</text>"#,
            TOP + ph / 2.0,
            TOP + ph / 2.0,
            escape(&self.y_label)
        );
        if self.diagonal {
            let _ = write!(
                s,
                r##"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="#999" stroke-dasharray="4 3"/>"##,
                sx(x0.max(y0)),
                sy(x0.max(y0)),
                sx(x1.min(y1)),
                sy(x1.min(y1))
            );
        }
        for (i, series) in self.series.iter().enumerate() {
            let colour = PALETTE[if self.paired { i / 2 } else { i } % PALETTE.len()];
            let dash = if self.paired && i % 2 == 1 {
                r#" stroke-dasharray="5 3""#
            } else {
                ""
            };
            let points: Vec<String> = series
                .points
                .iter()
                .filter(|p| p.0.is_finite() && p.1.is_finite() && p.0 >= x0 && p.0 <= x1)
                .map(|&(x, y)| format!("{:.1},{:.1}", sx(x), sy(y.clamp(y0, y1))))
                .collect();
            let _ = write!(
                s,
                r#"<polyline fill="none" stroke="{colour}" stroke-width="1.6"{dash} points="{}"/>"#,
                points.join(" ")
            );
            let ly = TOP + 8.0 + 15.0 * i as f64;
            let lx = LEFT + pw + 10.0;
            let _ = write!(
                s,
                r#"<line x1="{lx:.1}" y1="{ly:.1}" x2="{:.1}" y2="{ly:.1}" stroke="{colour}" stroke-width="2"{dash}/><text x="{:.1}" y="{:.1}">{}</text>"#,
                lx + 16.0,
                lx + 20.0,
                ly + 4.0,
                escape(&series.name)
            );
        }
        s.push_str("</svg>");
        s
    }
}

/// ROC curve points (false positive rate, true positive rate) of scores against labels,
/// thresholds from high to low; tied scores form one step.
pub fn roc_points(scores: &[f64], labels: &[u8]) -> Vec<(f64, f64)> {
    let positives = labels.iter().filter(|&&l| l == 1).count() as f64;
    let negatives = labels.len() as f64 - positives;
    if positives == 0.0 || negatives == 0.0 {
        return Vec::new();
    }
    let mut order: Vec<usize> = (0..scores.len()).collect();
    order.sort_by(|&a, &b| scores[b].total_cmp(&scores[a]));
    let mut points = vec![(0.0, 0.0)];
    let (mut tp, mut fp) = (0.0, 0.0);
    for (k, &i) in order.iter().enumerate() {
        if labels[i] == 1 {
            tp += 1.0;
        } else {
            fp += 1.0;
        }
        let last_of_tie = order.get(k + 1).is_none_or(|&j| scores[j] != scores[i]);
        if last_of_tie {
            points.push((fp / negatives, tp / positives));
        }
    }
    points
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roc_of_a_perfect_and_a_reversed_score() {
        let labels = [1, 1, 0, 0];
        assert_eq!(
            roc_points(&[0.9, 0.8, 0.2, 0.1], &labels),
            vec![(0.0, 0.0), (0.0, 0.5), (0.0, 1.0), (0.5, 1.0), (1.0, 1.0)]
        );
        let reversed = roc_points(&[0.1, 0.2, 0.8, 0.9], &labels);
        assert_eq!(reversed[2], (1.0, 0.0));
        // ties make one diagonal step
        assert_eq!(roc_points(&[0.5; 4], &labels), vec![(0.0, 0.0), (1.0, 1.0)]);
    }

    #[test]
    fn ticks_are_round_and_inside() {
        let unit = ticks(0.0, 1.0);
        let expected = [0.0, 0.2, 0.4, 0.6, 0.8, 1.0];
        assert_eq!(unit.len(), expected.len());
        assert!(
            unit.iter().zip(expected).all(|(a, b)| (a - b).abs() < 1e-12),
            "{unit:?}"
        );
        assert_eq!(tick_label(unit[3]), "0.6");
        let t = ticks(3.0, 47.0);
        assert!(t.iter().all(|&v| (3.0..=47.0).contains(&v)) && t.len() >= 4, "{t:?}");
    }

    #[test]
    fn a_plot_is_one_svg_with_a_line_per_series_and_escaped_text() {
        let plot = LinePlot {
            title: "loss <base>".into(),
            x_label: "epoch".into(),
            y_label: "loss".into(),
            x_range: None,
            y_range: None,
            series: vec![
                Series {
                    name: "S".into(),
                    points: vec![(1.0, 0.7), (2.0, 0.5)],
                },
                Series {
                    name: "S+X".into(),
                    points: vec![(1.0, 0.6), (2.0, 0.3)],
                },
            ],
            diagonal: false,
            paired: false,
        };
        let svg = plot.to_svg();
        assert!(svg.starts_with("<svg") && svg.ends_with("</svg>"));
        assert_eq!(svg.matches("<polyline").count(), 2);
        assert!(svg.contains("loss &lt;base&gt;"));
    }

    /// A perfect ROC curve runs along the left and top edges of the unit square; drawn on the
    /// frame it would vanish. Every vertex lies strictly inside the frame.
    #[test]
    fn a_roc_curve_on_the_edges_is_drawn_inside_the_frame() {
        let plot = LinePlot {
            title: "ROC".into(),
            x_label: "FPR".into(),
            y_label: "TPR".into(),
            x_range: Some((0.0, 1.0)),
            y_range: Some((0.0, 1.0)),
            series: vec![Series {
                name: "perfect".into(),
                points: roc_points(&[0.9, 0.8, 0.2, 0.1], &[1, 1, 0, 0]),
            }],
            diagonal: true,
            paired: false,
        };
        let svg = plot.to_svg();
        let points = svg.split("points=\"").nth(1).unwrap().split('"').next().unwrap();
        let (pw, ph) = (W - LEFT - RIGHT, H - TOP - BOTTOM);
        for p in points.split(' ') {
            let (x, y) = p.split_once(',').unwrap();
            let (x, y): (f64, f64) = (x.parse().unwrap(), y.parse().unwrap());
            assert!(x > LEFT + 1.0 && x < LEFT + pw - 1.0, "{p}");
            assert!(y > TOP + 1.0 && y < TOP + ph - 1.0, "{p}");
        }
    }
}

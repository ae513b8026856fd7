//! A table of the report, as Markdown and CSV.

use std::fmt::Write as _;
use wakelab_core::io::csv_record;

/// A table of the report.
pub struct Table {
    /// File stem of its CSV (`table_4_4_base`).
    pub id: String,
    pub title: String,
    pub caption: String,
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

impl Table {
    pub fn markdown(&self) -> String {
        let mut s = format!("### {}\n\n{}\n\n", self.title, self.caption);
        let _ = writeln!(s, "| {} |", self.header.join(" | "));
        let _ = writeln!(s, "|{}", " --- |".repeat(self.header.len()));
        for r in &self.rows {
            let _ = writeln!(s, "| {} |", r.join(" | "));
        }
        s.push('\n');
        s
    }

    pub fn csv(&self) -> String {
        std::iter::once(&self.header)
            .chain(&self.rows)
            .map(|r| csv_record(r))
            .collect()
    }
}

/// "0.29 ± 0.07", or "63.2% ± 3.2" for a share.
pub(crate) fn plus_minus(mean: f64, spread: f64, percent: bool) -> String {
    if percent {
        format!("{:.1}% ± {:.1}", 100.0 * mean, 100.0 * spread)
    } else {
        format!("{mean:.2} ± {spread:.2}")
    }
}

//! A table of the report, as Markdown and HTML for reading and as a tidy CSV for pandas or R.
//!
//! A cell is shown as a person writes it ("0.29 ± 0.07", "12/12 (100%)"), while its CSV holds one
//! number per cell (Wickham 2014, "Tidy data"): a cell of several numbers gets a column for each
//! (`MCC mean`, `MCC std`, `MCC n`), shares are fractions, and a missing value is an empty field.

use std::fmt::Write as _;
use wakelab_core::io::csv_of_records;

/// One cell: what a reader sees and, for the CSV, its numbers or words by column suffix.
#[derive(Clone, Debug, PartialEq)]
pub enum Cell {
    /// Nothing to show ("-" for a reader, an empty CSV field).
    Missing,
    Text(String),
    Value {
        shown: String,
        /// `("", x)` is the column itself; `("std", s)` becomes the column "<header> std".
        parts: Vec<(&'static str, String)>,
    },
}

/// A number as CSV writes it: rounded as shown, without a leading plus.
fn datum(x: f64, decimals: usize) -> String {
    let text = format!("{x:.decimals$}");
    // "-0.00" is zero
    if text.parse::<f64>() == Ok(0.0) {
        format!("{:.decimals$}", 0.0)
    } else {
        text
    }
}

impl Cell {
    /// A number with `decimals` after the point.
    pub fn number(x: f64, decimals: usize) -> Cell {
        Cell::Value {
            shown: format!("{x:.decimals$}"),
            parts: vec![("", datum(x, decimals))],
        }
    }

    /// A number as a person writes it (35, 5.3): for configured values, not results.
    pub fn plain(x: f64) -> Cell {
        let text = wakelab_core::io::text::number(x);
        Cell::Value {
            shown: text.clone(),
            parts: vec![("", text)],
        }
    }

    /// A number shown with its sign ("+0.6"), as differences are.
    pub fn signed(x: f64, decimals: usize) -> Cell {
        Cell::Value {
            shown: format!("{x:+.decimals$}"),
            parts: vec![("", datum(x, decimals))],
        }
    }

    /// A number in scientific notation ("1.3e-3").
    pub fn scientific(x: f64, decimals: usize) -> Cell {
        let shown = format!("{x:.decimals$e}");
        Cell::Value {
            parts: vec![("", shown.clone())],
            shown,
        }
    }

    /// A count.
    pub fn count(n: usize) -> Cell {
        Cell::Value {
            shown: n.to_string(),
            parts: vec![("", n.to_string())],
        }
    }

    /// A share shown in percent ("27%"), a fraction in the CSV.
    pub fn percent(share: f64, decimals: usize) -> Cell {
        Cell::Value {
            shown: format!("{:.decimals$}%", 100.0 * share),
            parts: vec![("", datum(share, decimals + 2))],
        }
    }

    /// `k` of `n` with its share: "12/12 (100%)"; CSV columns "<h>" (k) and "<h> of" (n).
    pub fn count_of(k: usize, n: usize) -> Cell {
        let share = if n > 0 {
            format!(" ({:.0}%)", 100.0 * k as f64 / n as f64)
        } else {
            String::new()
        };
        Cell::Value {
            shown: format!("{k}/{n}{share}"),
            parts: vec![("", k.to_string()), ("of", n.to_string())],
        }
    }

    /// A mean and its sample standard deviation over `n` repetitions: "0.29 ± 0.07", or
    /// "63.2% ± 3.2" for a share.
    pub fn mean_std(mean: f64, std: f64, n: usize, percent: bool) -> Cell {
        let (shown, d) = if percent {
            (format!("{:.1}% ± {:.1}", 100.0 * mean, 100.0 * std), 3)
        } else {
            (format!("{mean:.2} ± {std:.2}"), 2)
        };
        Cell::Value {
            shown,
            parts: vec![("mean", datum(mean, d)), ("std", datum(std, d)), ("n", n.to_string())],
        }
    }

    /// This cell with one more number or word in a column of its own, the shown text replaced.
    pub fn and(self, suffix: &'static str, csv_value: String, shown: String) -> Cell {
        match self {
            Cell::Value { mut parts, .. } => {
                parts.push((suffix, csv_value));
                Cell::Value { shown, parts }
            }
            other => other,
        }
    }

    /// What a reader sees.
    pub fn shown(&self) -> &str {
        match self {
            Cell::Missing => "-",
            Cell::Text(t) => t,
            Cell::Value { shown, .. } => shown,
        }
    }

    fn parts(&self) -> Vec<(&'static str, &str)> {
        match self {
            Cell::Missing => Vec::new(),
            Cell::Text(t) => vec![("", t.as_str())],
            Cell::Value { parts, .. } => parts.iter().map(|(k, v)| (*k, v.as_str())).collect(),
        }
    }
}

impl From<String> for Cell {
    fn from(text: String) -> Cell {
        Cell::Text(text)
    }
}

impl From<&str> for Cell {
    fn from(text: &str) -> Cell {
        Cell::Text(text.to_string())
    }
}

/// A table of the report.
pub struct Table {
    /// File stem of its CSV (`table_4_4_base`).
    pub id: String,
    pub title: String,
    pub caption: String,
    pub header: Vec<String>,
    pub rows: Vec<Vec<Cell>>,
}

impl Table {
    pub fn markdown(&self) -> String {
        let mut s = format!("### {}\n\n{}\n\n", self.title, self.caption);
        let _ = writeln!(s, "| {} |", self.header.join(" | "));
        let _ = writeln!(s, "|{}", " --- |".repeat(self.header.len()));
        for r in &self.rows {
            let shown: Vec<&str> = r.iter().map(Cell::shown).collect();
            let _ = writeln!(s, "| {} |", shown.join(" | "));
        }
        s.push('\n');
        s
    }

    /// The CSV's columns: for each column of the table, the suffixes its cells use, in the order
    /// they first appear.
    fn csv_columns(&self) -> Vec<Vec<&'static str>> {
        (0..self.header.len())
            .map(|c| {
                let mut suffixes: Vec<&'static str> = Vec::new();
                for row in &self.rows {
                    for (suffix, _) in row.get(c).map(Cell::parts).unwrap_or_default() {
                        if !suffixes.contains(&suffix) {
                            suffixes.push(suffix);
                        }
                    }
                }
                if suffixes.is_empty() {
                    suffixes.push("");
                }
                suffixes
            })
            .collect()
    }

    /// The tidy CSV: one number or word per field.
    pub fn csv(&self) -> String {
        let columns = self.csv_columns();
        let header: Vec<String> = self
            .header
            .iter()
            .zip(&columns)
            .flat_map(|(h, suffixes)| {
                suffixes
                    .iter()
                    .map(move |s| if s.is_empty() { h.clone() } else { format!("{h} {s}") })
            })
            .collect();
        let rows = self.rows.iter().map(|row| {
            let mut fields = Vec::new();
            for (c, suffixes) in columns.iter().enumerate() {
                let parts = row.get(c).map(Cell::parts).unwrap_or_default();
                for s in suffixes {
                    let field = parts.iter().find(|(k, _)| k == s).map_or("", |(_, v)| *v);
                    fields.push(field.to_string());
                }
            }
            fields
        });
        csv_of_records(std::iter::once(header).chain(rows))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(rows: Vec<Vec<Cell>>) -> Table {
        Table {
            id: "t".into(),
            title: "T".into(),
            caption: "c".into(),
            header: vec!["input".into(), "MCC".into(), "mean conflict k".into()],
            rows,
        }
    }

    #[test]
    fn a_mean_and_its_spread_read_as_one_cell_and_parse_as_numbers() {
        let t = table(vec![
            vec!["S, X".into(), Cell::mean_std(0.2941, 0.0712, 5, false), Cell::Missing],
            vec!["C".into(), Cell::mean_std(0.2, 0.03, 5, false), Cell::number(0.4861, 3)],
        ]);
        assert!(t.markdown().contains("| S, X | 0.29 ± 0.07 | - |"));
        let text = t.csv();
        let mut reader = csv::Reader::from_reader(text.as_bytes());
        let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
        assert_eq!(header, ["input", "MCC mean", "MCC std", "MCC n", "mean conflict k"]);
        let rows: Vec<csv::StringRecord> = reader.records().map(Result::unwrap).collect();
        assert_eq!(&rows[0].iter().collect::<Vec<_>>(), &["S, X", "0.29", "0.07", "5", ""]);
        for row in &rows {
            for field in row.iter().skip(1).filter(|f| !f.is_empty()) {
                field
                    .parse::<f64>()
                    .unwrap_or_else(|_| panic!("{field} is not a number"));
            }
        }
    }

    #[test]
    fn shares_are_fractions_in_the_csv_and_percent_for_reading() {
        let c = Cell::mean_std(0.632, 0.032, 3, true);
        assert_eq!(c.shown(), "63.2% ± 3.2");
        assert_eq!(c.parts(), [("mean", "0.632"), ("std", "0.032"), ("n", "3")]);
        assert_eq!(Cell::percent(0.27, 0).parts(), [("", "0.27")]);
        assert_eq!(Cell::count_of(7, 12).shown(), "7/12 (58%)");
        assert_eq!(Cell::signed(-0.001, 2).parts(), [("", "0.00")]);
        assert_eq!(Cell::signed(0.6, 1).shown(), "+0.6");
    }
}

//! CSV as RFC 4180 writes it: a field holding a comma, a double quote or a line break is quoted,
//! its quotes doubled. Records end in LF rather than RFC 4180's CRLF, which every reader of CSV
//! (pandas, R, spreadsheets) accepts.

use std::borrow::Cow;

/// One field, quoted when RFC 4180 (section 2, rules 6-7) asks.
pub fn csv_field(text: &str) -> Cow<'_, str> {
    if text.contains([',', '"', '\n', '\r']) {
        Cow::Owned(format!("\"{}\"", text.replace('"', "\"\"")))
    } else {
        Cow::Borrowed(text)
    }
}

/// One record: the fields joined by commas, ending in a line feed.
pub fn csv_record<S: AsRef<str>>(fields: &[S]) -> String {
    let mut line = fields
        .iter()
        .map(|f| csv_field(f.as_ref()))
        .collect::<Vec<_>>()
        .join(",");
    line.push('\n');
    line
}

/// Rows of a serialisable type as CSV, one column per field of the first row in its order:
/// strings as they are, null as an empty field, other values as JSON writes them.
pub fn csv_of_rows<T: serde::Serialize>(rows: &[T]) -> Result<String, serde_json::Error> {
    let values: Vec<serde_json::Value> = rows.iter().map(serde_json::to_value).collect::<Result<_, _>>()?;
    let Some(first) = values.first().and_then(|v| v.as_object()) else {
        return Ok(String::new());
    };
    let keys: Vec<&String> = first.keys().collect();
    let mut out = csv_record(&keys);
    for v in &values {
        let cells: Vec<String> = keys
            .iter()
            .map(|k| match &v[k.as_str()] {
                serde_json::Value::String(s) => s.clone(),
                serde_json::Value::Null => String::new(),
                other => other.to_string(),
            })
            .collect();
        out += &csv_record(&cells);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Split one RFC 4180 record (no line breaks inside fields) back into its fields.
    fn parse_record(line: &str) -> Vec<String> {
        let mut fields = vec![String::new()];
        let mut quoted = false;
        let mut chars = line.trim_end_matches('\n').chars().peekable();
        while let Some(c) = chars.next() {
            match (c, quoted) {
                ('"', true) if chars.peek() == Some(&'"') => {
                    chars.next();
                    fields.last_mut().unwrap().push('"');
                }
                ('"', _) => quoted = !quoted,
                (',', false) => fields.push(String::new()),
                (c, _) => fields.last_mut().unwrap().push(c),
            }
        }
        fields
    }

    #[test]
    fn fields_with_commas_and_quotes_survive_a_round_trip() {
        let fields = ["Bayes classifier (S, X)", "say \"wake\"", "plain", ""];
        let line = csv_record(&fields);
        assert_eq!(line, "\"Bayes classifier (S, X)\",\"say \"\"wake\"\"\",plain,\n");
        assert_eq!(parse_record(&line), fields);
    }

    #[test]
    fn rows_keep_their_columns() {
        #[derive(serde::Serialize)]
        struct Row {
            name: &'static str,
            value: f64,
            missing: Option<f64>,
        }
        let csv = csv_of_rows(&[Row {
            name: "S, X",
            value: 0.5,
            missing: None,
        }])
        .unwrap();
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(parse_record(lines[0]), ["name", "value", "missing"]);
        assert_eq!(parse_record(lines[1]), ["S, X", "0.5", ""]);
    }
}

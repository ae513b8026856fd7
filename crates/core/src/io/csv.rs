//! Rows of serialisable records as CSV, written by the `csv` crate (RFC 4180 quoting; records
//! end in LF, which every reader of CSV accepts).

/// Records of fields (the header first) as CSV.
pub fn csv_of_records<R, F>(records: impl IntoIterator<Item = R>) -> String
where
    R: IntoIterator<Item = F>,
    F: AsRef<[u8]>,
{
    let mut out = csv::WriterBuilder::new()
        .terminator(csv::Terminator::Any(b'\n'))
        .flexible(true)
        .from_writer(Vec::new());
    let into_memory = "a CSV written into memory cannot fail";
    for record in records {
        out.write_record(record).expect(into_memory);
    }
    String::from_utf8(out.into_inner().expect(into_memory)).expect("UTF-8 fields")
}

/// Rows of a serialisable type as CSV, one column per field of the first row in its order:
/// strings as they are, null as an empty field, other values as JSON writes them.
pub fn csv_of_rows<T: serde::Serialize>(rows: &[T]) -> Result<String, serde_json::Error> {
    let values: Vec<serde_json::Value> = rows.iter().map(serde_json::to_value).collect::<Result<_, _>>()?;
    let Some(first) = values.first().and_then(|v| v.as_object()) else {
        return Ok(String::new());
    };
    let keys: Vec<String> = first.keys().cloned().collect();
    let rows = values.iter().map(|v| {
        keys.iter()
            .map(|k| match &v[k.as_str()] {
                serde_json::Value::String(s) => s.clone(),
                serde_json::Value::Null => String::new(),
                other => other.to_string(),
            })
            .collect::<Vec<_>>()
    });
    Ok(csv_of_records(std::iter::once(keys.clone()).chain(rows)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_keep_their_columns_and_fields_with_commas_survive() {
        #[derive(serde::Serialize)]
        struct Row {
            name: &'static str,
            value: f64,
            missing: Option<f64>,
        }
        let csv = csv_of_rows(&[Row {
            name: "Bayes classifier (S, X) \"say\"",
            value: 0.5,
            missing: None,
        }])
        .unwrap();
        let mut reader = csv::Reader::from_reader(csv.as_bytes());
        assert_eq!(reader.headers().unwrap(), vec!["name", "value", "missing"]);
        let row = reader.records().next().unwrap().unwrap();
        assert_eq!(row, vec!["Bayes classifier (S, X) \"say\"", "0.5", ""]);
    }
}

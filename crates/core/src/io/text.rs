//! Reports as text for a terminal: a JSON object as aligned `key = value` lines.

use std::fmt::Write;

/// A serialisable report as JSON (pretty) or as aligned `key = value` lines; numbers in the
/// lines are printed with seven significant digits, arrays of objects one after another.
pub fn report_text(report: &impl serde::Serialize, json: bool) -> serde_json::Result<String> {
    if json {
        return serde_json::to_string_pretty(report).map(|s| s + "\n");
    }
    let mut out = String::new();
    key_value_lines(&serde_json::to_value(report)?, &mut out);
    Ok(out)
}

fn key_value_lines(value: &serde_json::Value, out: &mut String) {
    if let serde_json::Value::Object(map) = value {
        for (k, v) in map {
            match v {
                serde_json::Value::Array(items) => {
                    for item in items {
                        writeln!(out, "{k}:").expect("writing to a string");
                        key_value_lines(item, out);
                    }
                }
                _ => {
                    let text = v.as_f64().map_or(v.to_string(), |x| format!("{x:.6e}"));
                    writeln!(out, "{k:>26} = {text}").expect("writing to a string");
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn objects_become_aligned_lines_and_arrays_repeat_their_key() {
        let value = serde_json::json!({"a": 1.5, "band": "C", "parts": [{"x": 2.0}]});
        let text = report_text(&value, false).unwrap();
        assert_eq!(
            text,
            format!(
                "{:>26} = 1.500000e0\n{:>26} = \"C\"\nparts:\n{:>26} = 2.000000e0\n",
                "a", "band", "x"
            )
        );
        assert!(report_text(&value, true).unwrap().starts_with("{\n"));
    }
}

//! Reports as text for a terminal: a JSON object as aligned `key = value` lines.

use std::fmt::Write;

/// A serialisable report as JSON (pretty) or as aligned `key = value` lines; numbers in the
/// lines are printed as [`number`] writes them, arrays of objects one after another.
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
                    let text = v.as_f64().map_or(v.to_string(), number);
                    writeln!(out, "{k:>26} = {text}").expect("writing to a string");
                }
            }
        }
    }
}

/// A duration as a person says it: "45 s", "3 min 20 s", "2 h 05 min".
pub fn duration(seconds: f64) -> String {
    let s = seconds.max(0.0).round() as u64;
    match s {
        0..60 => format!("{s} s"),
        60..3600 => format!("{} min {:02} s", s / 60, s % 60),
        _ => format!("{} h {:02} min", s / 3600, (s % 3600) / 60),
    }
}

/// A number as a reader expects it: whole numbers whole (35), others to seven significant
/// digits without trailing zeros (0.01234567, 5.3), and beyond 1e-3..1e7 in scientific
/// notation (5.3e9, 1.234567e-5).
pub fn number(x: f64) -> String {
    let magnitude = x.abs();
    if !x.is_finite() {
        return x.to_string();
    }
    if x == x.trunc() && magnitude < 1e7 {
        return format!("{x:.0}");
    }
    let trim = |s: String| {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    if (1e-3..1e7).contains(&magnitude) {
        let decimals = (6 - magnitude.log10().floor() as i64).max(0) as usize;
        trim(format!("{x:.decimals$}"))
    } else {
        let text = format!("{x:.6e}");
        let (mantissa, exponent) = text.split_once('e').expect("scientific notation");
        format!("{}e{exponent}", trim(mantissa.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations_read_as_people_say_them() {
        assert_eq!(duration(44.6), "45 s");
        assert_eq!(duration(200.0), "3 min 20 s");
        assert_eq!(duration(7500.0), "2 h 05 min");
    }

    #[test]
    fn objects_become_aligned_lines_and_arrays_repeat_their_key() {
        let value = serde_json::json!({"a": 1.5, "band": "C", "parts": [{"x": 2.0}]});
        let text = report_text(&value, false).unwrap();
        assert_eq!(
            text,
            format!("{:>26} = 1.5\n{:>26} = \"C\"\nparts:\n{:>26} = 2\n", "a", "band", "x")
        );
        assert!(report_text(&value, true).unwrap().starts_with("{\n"));
    }

    #[test]
    fn numbers_read_as_a_person_writes_them() {
        for (x, text) in [
            (35.0, "35"),
            (-36.11785, "-36.11785"),
            (66.555094, "66.55509"),
            (0.012345678, "0.01234568"),
            (5.3e9, "5.3e9"),
            (1.2345678e-5, "1.234568e-5"),
            (-0.5, "-0.5"),
            (f64::NAN, "NaN"),
        ] {
            assert_eq!(number(x), text, "{x}");
        }
    }
}

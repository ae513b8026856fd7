//! Findings as GeoJSON (RFC 7946): a FeatureCollection of points in longitude and latitude
//! (WGS 84), one schema for every kind of finding (the `kind` property: window, ship, wake), each
//! with its pixel position in the product, and the properties of the product and detector
//! beside its own. A finding on an image without a place on the Earth has a null geometry
//! (RFC 7946, section 3.2), its pixel position still in its properties.

use crate::Frame;
use serde::Serialize;
use serde_json::{json, Map, Value};

/// What a finding is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// A detector window above its threshold.
    Window,
    Ship,
    Wake,
}

/// One finding at a pixel position (GDAL's convention: column and row from the image's
/// top-left corner) with its own properties; a finding with a `line` (a wake: its vertices as
/// (row, column)) is a LineString, any other a Point.
#[derive(Debug, Clone)]
pub struct Finding {
    pub kind: Kind,
    pub row: f64,
    pub col: f64,
    pub properties: Map<String, Value>,
    pub line: Option<Vec<(f64, f64)>>,
}

/// Decimal places of a coordinate (1e-7 degrees is 1 cm; RFC 7946 section 11.2 advises
/// against more).
const PLACES: f64 = 1e7;

/// The findings on `frame` as a FeatureCollection; `common` is added to every feature's
/// properties.
pub fn feature_collection(frame: &Frame, findings: &[Finding], common: &Map<String, Value>) -> Value {
    // every point and every line vertex placed at once: GDAL's transformer is built once
    let mut points: Vec<(f64, f64)> = findings.iter().map(|f| (f.col, f.row)).collect();
    let mut vertices = Vec::new();
    for f in findings {
        let first = points.len();
        points.extend(f.line.iter().flatten().map(|&(r, c)| (c, r)));
        vertices.push(first..points.len());
    }
    let lonlat = frame.lonlat(&points);
    let rounded = |p: (f64, f64)| [(p.0 * PLACES).round() / PLACES, (p.1 * PLACES).round() / PLACES];
    let features: Vec<Value> = findings
        .iter()
        .enumerate()
        .map(|(i, f)| {
            let mut properties = Map::new();
            properties.insert("kind".into(), json!(f.kind));
            properties.insert("row".into(), json!(f.row));
            properties.insert("col".into(), json!(f.col));
            properties.extend(f.properties.clone());
            properties.extend(common.clone());
            let geometry = match (&lonlat, &f.line) {
                (Some(p), Some(_)) => json!({
                    "type": "LineString",
                    "coordinates": p[vertices[i].clone()].iter().map(|&q| rounded(q)).collect::<Vec<_>>(),
                }),
                (Some(p), None) => json!({ "type": "Point", "coordinates": rounded(p[i]) }),
                (None, _) => Value::Null,
            };
            if let Some(line) = &f.line {
                properties.insert(
                    "line_rows_cols".into(),
                    json!(line.iter().map(|&(r, c)| [r, c]).collect::<Vec<_>>()),
                );
            }
            json!({ "type": "Feature", "geometry": geometry, "properties": properties })
        })
        .collect();
    json!({ "type": "FeatureCollection", "features": features })
}

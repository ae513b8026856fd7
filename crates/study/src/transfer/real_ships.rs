//! The ships a user drew on the images of `--real DIR`, and the classic ship search (the CFAR of
//! `wakelab detect`; issue 39, items 1 and 6) scored against them.
//!
//! A ship is a GeoJSON feature of `"kind": "ship"`: a Point, or a Polygon (its bounding box, as
//! ship-detection datasets such as SSDD draw them). An image's ships are scored only when they
//! are drawn: where its file holds a ship, or says `"wakelab": {"ships_drawn": true}` (an image
//! without a ship); then every ship in the image is taken as drawn. A drawn ship is found when a
//! reported ship's centre lies within [`SHIP_WITHIN_M`] of it, or within one scanned pixel
//! where that is larger: the search runs on the detector's averaged grid, whose pixel may be
//! coarser than a drawn box's edge. A reported ship that finds no drawn ship is a false ship.

use super::real_search::{metres_from, ShipScore};
use serde_json::Value;

/// A reported ship within this of a drawn one (m; 0 inside its box) finds it: more than a
/// ship's half-beam, so a centre on the hull's edge counts, and less than the berth between
/// ships moored side by side.
pub const SHIP_WITHIN_M: f64 = 50.0;

/// A drawn ship: the box from `min` to `max` ((column, row) pixels, or (longitude, latitude));
/// a point where the two are equal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DrawnShip {
    pub min: (f64, f64),
    pub max: (f64, f64),
}

impl DrawnShip {
    /// The ship of a feature's geometry: a Point, or a Polygon's bounding box. `Err` says what
    /// is wrong with it.
    pub fn from_geometry(geometry: &Value) -> Result<Self, String> {
        let position = |p: &Value| Some((p.get(0)?.as_f64()?, p.get(1)?.as_f64()?));
        match geometry["type"].as_str() {
            Some("Point") => position(&geometry["coordinates"])
                .map(|p| Self { min: p, max: p })
                .ok_or_else(|| "a ship's Point needs [x, y]".into()),
            Some("Polygon") => {
                let ring: Option<Vec<(f64, f64)>> = geometry["coordinates"]
                    .get(0)
                    .and_then(Value::as_array)
                    .map(|r| r.iter().map(position).collect::<Option<_>>())
                    .unwrap_or_default();
                match ring {
                    Some(r) if r.len() >= 3 => Ok(r.iter().fold(
                        Self {
                            min: (f64::INFINITY, f64::INFINITY),
                            max: (f64::NEG_INFINITY, f64::NEG_INFINITY),
                        },
                        |b, p| Self {
                            min: (b.min.0.min(p.0), b.min.1.min(p.1)),
                            max: (b.max.0.max(p.0), b.max.1.max(p.1)),
                        },
                    )),
                    _ => Err("a ship's Polygon needs a ring of three or more [x, y] positions".into()),
                }
            }
            other => Err(format!(
                "a ship is a Point or a Polygon, not {}",
                other.unwrap_or("a feature without a geometry type")
            )),
        }
    }

    /// The ship's nearest point to `p`, in its coordinates.
    fn nearest(&self, p: (f64, f64)) -> (f64, f64) {
        (p.0.clamp(self.min.0, self.max.0), p.1.clamp(self.min.1, self.max.1))
    }
}

/// A reported ship's centre as the drawing places it: (column, row), or (lon, lat).
fn centre(ship: &Value, lonlat: bool) -> Option<(f64, f64)> {
    if lonlat {
        Some((ship["lon"].as_f64()?, ship["lat"].as_f64()?))
    } else {
        Some((ship["product_col"].as_f64()?, ship["product_row"].as_f64()?))
    }
}

/// Score the ships of `detections.json` (`written`) against `drawn`; `spacing` (m; rows,
/// columns) scales the product's pixels, and `within` (m) is how near a reported centre must
/// lie ([`SHIP_WITHIN_M`] or a scanned pixel).
pub fn score_ships(drawn: &[DrawnShip], lonlat: bool, written: &Value, spacing: (f64, f64), within: f64) -> ShipScore {
    let mut found = vec![false; drawn.len()];
    let mut false_ships = 0;
    for p in written["ships"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|s| centre(s, lonlat))
    {
        let mut any = false;
        for (ship, found) in drawn.iter().zip(found.iter_mut()) {
            let (x, y) = metres_from(ship.nearest(p), p, lonlat, spacing);
            if x.hypot(y) <= within {
                *found = true;
                any = true;
            }
        }
        false_ships += usize::from(!any);
    }
    ShipScore {
        drawn: drawn.len(),
        found: found.iter().filter(|f| **f).count(),
        false_ships,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    /// A Polygon gives its bounding box, a Point itself; a LineString and a two-point ring are
    /// refused, naming what a ship may be.
    #[test]
    fn ships_are_points_or_boxes() {
        let b = DrawnShip::from_geometry(
            &json!({"type": "Polygon", "coordinates": [[[10, 5], [30, 5], [30, 9], [10, 9], [10, 5]]]}),
        )
        .unwrap();
        assert_eq!((b.min, b.max), ((10.0, 5.0), (30.0, 9.0)));
        let p = DrawnShip::from_geometry(&json!({"type": "Point", "coordinates": [4, 7]})).unwrap();
        assert_eq!((p.min, p.max), ((4.0, 7.0), (4.0, 7.0)));
        let e = DrawnShip::from_geometry(&json!({"type": "LineString", "coordinates": [[0, 0], [1, 1]]})).unwrap_err();
        assert!(e.contains("a Point or a Polygon, not LineString"), "{e}");
        let e = DrawnShip::from_geometry(&json!({"type": "Polygon", "coordinates": [[[0, 0], [1, 1]]]})).unwrap_err();
        assert!(e.contains("three or more"), "{e}");
    }

    /// At 10 m pixels: a centre inside a box finds it; one 4 px (40 m) off its edge finds it
    /// within 50 m, one 6 px (60 m) off does not and is a false ship; a centre 3 px from a
    /// drawn point finds it. Two reported centres on one ship find it once, neither false.
    #[test]
    fn a_reported_ship_finds_a_drawn_one_near_it() {
        let boxed = DrawnShip {
            min: (100.0, 100.0),
            max: (120.0, 104.0),
        };
        let point = DrawnShip {
            min: (300.0, 300.0),
            max: (300.0, 300.0),
        };
        // product_* are (row, column)
        let ship = |row: f64, col: f64| json!({"product_row": row, "product_col": col});
        let written = json!({"ships": [ship(102.0, 110.0), ship(102.0, 118.0), ship(300.0, 303.0)]});
        let s = score_ships(&[boxed, point], false, &written, (10.0, 10.0), SHIP_WITHIN_M);
        assert_eq!((s.drawn, s.found, s.false_ships), (2, 2, 0));
        let near = json!({"ships": [ship(108.0, 110.0)]});
        assert_eq!(
            score_ships(&[boxed], false, &near, (10.0, 10.0), SHIP_WITHIN_M).found,
            1
        );
        let off = json!({"ships": [ship(110.0, 110.0)]});
        let s = score_ships(&[boxed], false, &off, (10.0, 10.0), SHIP_WITHIN_M);
        assert_eq!((s.found, s.false_ships), (0, 1));
        // a coarser scanned pixel (80 m) widens the reach
        assert_eq!(score_ships(&[boxed], false, &off, (10.0, 10.0), 80.0).found, 1);
    }

    /// In longitude and latitude: 0.0004 degrees of latitude (44 m) from a drawn point finds
    /// it, 0.0006 (67 m) does not.
    #[test]
    fn ships_drawn_in_longitude_and_latitude_are_measured_in_metres() {
        let point = DrawnShip {
            min: (10.0, 50.0),
            max: (10.0, 50.0),
        };
        let at = |lat: f64| json!({"ships": [{"lon": 10.0, "lat": lat}]});
        assert_eq!(
            score_ships(&[point], true, &at(50.0004), (f64::NAN, f64::NAN), SHIP_WITHIN_M).found,
            1
        );
        assert_eq!(
            score_ships(&[point], true, &at(50.0006), (f64::NAN, f64::NAN), SHIP_WITHIN_M).found,
            0
        );
    }
}

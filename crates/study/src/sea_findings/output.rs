//! The findings written out: as JSON entries for `detections.json`, as GeoJSON findings, and
//! drawn on the overlay.

use super::SeaFindings;
use image::{Rgb, RgbImage};
use serde_json::{json, Map, Value};
use wakelab_products::geojson::{Finding, Kind};
use wakelab_ships::wake::{FaintLine, NoWake, Signature, Wake};

impl SeaFindings {
    /// The points to place on the ground: every ship's centre, then every wake's start, end and
    /// a point 100 m along its course from its start (for the bearing), then every faint line's
    /// start and end ([`Self::faint_lines`]), in scanned pixels (row, column).
    pub fn points(&self) -> Vec<(f64, f64)> {
        let g = &self.geometry;
        let mut points: Vec<(f64, f64)> = self.ships.iter().map(|s| (s.row, s.col)).collect();
        for w in &self.wakes {
            let course = w.course_deg.unwrap_or(w.axis_deg);
            let (ur, uc) = g.step(course);
            points.extend([w.start, w.end, (w.start.0 + 100.0 * ur, w.start.1 + 100.0 * uc)]);
        }
        for (_, _, line) in self.faint_lines() {
            points.extend([line.start, line.end]);
        }
        points
    }

    /// The faint lines of the ships without a wake (ship, signature, line), the trough's
    /// before the bright arm's, ship by ship: each best line refused for its significance alone.
    pub fn faint_lines(&self) -> Vec<(usize, Signature, FaintLine)> {
        self.no_wake
            .iter()
            .enumerate()
            .filter_map(|(k, n)| n.as_ref().map(|n| (k, n)))
            .flat_map(|(k, n)| {
                [&n.trough, &n.bright_arm]
                    .into_iter()
                    .filter_map(move |r| r.faint_line.map(|line| (k, r.signature, line)))
            })
            .collect()
    }

    /// The findings as JSON entries for `detections.json` and as GeoJSON findings, given where
    /// each of [`Self::points`] lies in the product's pixels and on the ground (lon, lat). An
    /// input that is not `calibrated` (a display stretch) gives its ships no sigma0 or contrast:
    /// its grey levels read as dB are not dB.
    pub fn entries(
        &self,
        product: &[(f64, f64)],
        lonlat: Option<&[(f64, f64)]>,
        calibrated: bool,
    ) -> (Value, Value, Vec<Finding>) {
        let in_db = |v: f64| if calibrated { json!(v) } else { Value::Null };
        let at = |k: usize| (product[k], lonlat.map(|l| l[k]));
        let mut findings = Vec::new();
        // each faint line as detections.json gives it, by ship and signature
        let faint_first = self.ships.len() + 3 * self.wakes.len();
        let faint: Vec<((usize, Signature), Value)> = self
            .faint_lines()
            .into_iter()
            .enumerate()
            .map(|(j, (k, signature, line))| {
                let (start, ll_start) = at(faint_first + 2 * j);
                let (end, ll_end) = at(faint_first + 2 * j + 1);
                let entry = json!({
                    "product_start": [start.0, start.1],
                    "product_end": [end.0, end.1],
                    "lonlat_start": ll_start.map(|p| [p.0, p.1]),
                    "lonlat_end": ll_end.map(|p| [p.0, p.1]),
                    "length_m": line.length_m,
                });
                ((k, signature), entry)
            })
            .collect();
        let ships: Vec<Value> = self
            .ships
            .iter()
            .enumerate()
            .map(|(k, s)| {
                let ((row, col), ll) = at(k);
                let mut properties = Map::new();
                properties.insert("length_m".into(), json!(s.length_m));
                properties.insert("width_m".into(), json!(s.width_m));
                properties.insert("peak_sigma0_db".into(), in_db(s.peak_db));
                properties.insert("contrast_db".into(), in_db(s.contrast_db));
                properties.insert("ship".into(), json!(k));
                properties.insert("found_in".into(), json!(self.ships_polarisation));
                // the CNN's wake probability of the window centred on its return; null: not
                // scored (no CNN, or the window more than half off the image)
                let cnn = self.ship_cnn.get(k).copied().flatten();
                properties.insert("cnn_probability".into(), json!(cnn));
                // why no wake of it was reported; null for a ship with a wake
                let no_wake = self.no_wake.get(k).and_then(Option::as_ref);
                properties.insert("no_wake".into(), json!(no_wake.map(NoWake::reason)));
                findings.push(Finding {
                    kind: Kind::Ship,
                    row,
                    col,
                    properties: properties.clone(),
                    line: None,
                });
                let mut entry = serde_json::to_value(s).expect("a ship serialises");
                if !calibrated {
                    for key in ["peak_sigma0", "peak_db", "background_db", "contrast_db"] {
                        entry[key] = Value::Null;
                    }
                }
                entry["product_row"] = json!(row);
                // the cross-polarised band the ship was found in; null: the scanned band
                entry["found_in"] = json!(self.ships_polarisation);
                entry["product_col"] = json!(col);
                entry["lon"] = json!(ll.map(|p| p.0));
                entry["lat"] = json!(ll.map(|p| p.1));
                entry["cnn_probability"] = json!(cnn);
                entry["no_wake"] = match no_wake {
                    Some(n) => {
                        let mut v = serde_json::to_value(n).expect("a refusal serialises");
                        v["reason"] = json!(n.reason());
                        // where the best line lies when significance is all it failed; null
                        // when it fails another test too
                        for (key, signature) in [("trough", Signature::Trough), ("bright_arm", Signature::BrightArm)] {
                            v[key]["faint_line"] = faint
                                .iter()
                                .find(|(at, _)| *at == (k, signature))
                                .map_or(Value::Null, |(_, line)| line.clone());
                        }
                        v
                    }
                    None => Value::Null,
                };
                entry
            })
            .collect();
        let first = self.ships.len();
        let wakes: Vec<Value> = self
            .wakes
            .iter()
            .enumerate()
            .map(|(k, w)| {
                let (start, ll_start) = at(first + 3 * k);
                let (end, ll_end) = at(first + 3 * k + 1);
                let (_, ll_ahead) = at(first + 3 * k + 2);
                let bearing = ll_start.zip(ll_ahead).map(|(a, b)| bearing(a, b));
                let entry = wake_entry(w, start, end, ll_start, ll_end, bearing);
                let mut properties = Map::new();
                for key in [
                    "ship",
                    "signature",
                    "course_image_deg",
                    "course_deg",
                    "course_sigma_deg",
                    "along_hull",
                    "promoted",
                    "length_m",
                    "speed_offset_ms",
                    "speed_kelvin_ms",
                ] {
                    properties.insert(key.into(), entry[key].clone());
                }
                findings.push(Finding {
                    kind: Kind::Wake,
                    row: start.0,
                    col: start.1,
                    properties,
                    line: Some(vec![start, end]),
                });
                entry
            })
            .collect();
        (Value::Array(ships), Value::Array(wakes), findings)
    }

    /// Draw the land left out (tinted brown), the ships (cyan squares) and the wakes (yellow
    /// lines from their start, the ship's end marked) on an overlay picture of `scale` scanned pixels per picture pixel.
    pub fn draw(&self, picture: &mut RgbImage, scale: f64) {
        let (w, h) = (picture.width() as i64, picture.height() as i64);
        // land left out: tinted brown, half over the image (each picture row from the first
        // scanned row it holds, so that a row is tinted once)
        for &(row, from, to) in &self.land {
            let r = (row as f64 / scale).floor() as i64;
            if !(0..h).contains(&r) || (r as f64 * scale).ceil() as usize != row {
                continue;
            }
            let (c0, c1) = ((from as f64 / scale).round() as i64, (to as f64 / scale).round() as i64);
            for c in c0.max(0)..c1.min(w) {
                let p = picture.get_pixel_mut(c as u32, r as u32);
                for (k, tint) in [150u16, 90, 40].iter().enumerate() {
                    p.0[k] = ((p.0[k] as u16 + tint) / 2) as u8;
                }
            }
        }
        let mut put = |r: f64, c: f64, colour: Rgb<u8>| {
            let (r, c) = ((r / scale).round() as i64, (c / scale).round() as i64);
            if (0..h).contains(&r) && (0..w).contains(&c) {
                picture.put_pixel(c as u32, r as u32, colour);
            }
        };
        // the wakes whole, a promoted faint line dashed (three picture pixels in four), the
        // faint lines dotted (one in four), each in its signature's colour; a line is stepped
        // every half picture pixel, and `lit` of each 8 steps are drawn
        let wakes = self
            .wakes
            .iter()
            .map(|w| (w.start, w.end, w.signature, if w.promoted { 6 } else { 8 }));
        let faint = self.faint_lines().into_iter().map(|(_, s, l)| (l.start, l.end, s, 2));
        for (start, end, signature, lit) in wakes.chain(faint) {
            let colour = wake_colour(signature);
            let steps = ((end.0 - start.0).hypot(end.1 - start.1) / scale * 2.0).ceil().max(1.0);
            for i in (0..=steps as usize).filter(|i| i % 8 < lit) {
                let t = i as f64 / steps;
                put(start.0 + t * (end.0 - start.0), start.1 + t * (end.1 - start.1), colour);
            }
        }
        let cyan = Rgb([0, 255, 255]);
        for ship in &self.ships {
            for d in -4..=4 {
                let d = d as f64 * scale;
                let side = 4.0 * scale;
                put(ship.row - side, ship.col + d, cyan);
                put(ship.row + side, ship.col + d, cyan);
                put(ship.row + d, ship.col - side, cyan);
                put(ship.row + d, ship.col + side, cyan);
            }
        }
    }
}

/// A wake's line on the overlay: yellow for a dark trough, green for a bright arm.
pub fn wake_colour(signature: Signature) -> Rgb<u8> {
    match signature {
        Signature::Trough => Rgb([255, 230, 0]),
        Signature::BrightArm => Rgb([0, 230, 0]),
    }
}

/// The true bearing (degrees clockwise from north) from `a` to `b`, both (lon, lat) in degrees:
/// the initial course of the great circle.
fn bearing(a: (f64, f64), b: (f64, f64)) -> f64 {
    let (l1, p1, l2, p2) = (a.0.to_radians(), a.1.to_radians(), b.0.to_radians(), b.1.to_radians());
    let y = (l2 - l1).sin() * p2.cos();
    let x = p1.cos() * p2.sin() - p1.sin() * p2.cos() * (l2 - l1).cos();
    y.atan2(x).to_degrees().rem_euclid(360.0)
}

/// A wake as `detections.json` holds it.
fn wake_entry(
    w: &Wake,
    start: (f64, f64),
    end: (f64, f64),
    ll_start: Option<(f64, f64)>,
    ll_end: Option<(f64, f64)>,
    bearing: Option<f64>,
) -> Value {
    let (mut offset, mut kelvin) = (json!({}), json!({}));
    if let Some(s) = &w.speed {
        offset = match &s.offset {
            Ok(v) => json!({ "speed_ms": v.value, "sigma_ms": v.sigma }),
            Err(why) => json!({ "unknown": why }),
        };
        kelvin = match &s.kelvin {
            Ok(k) => json!({ "speed_ms": k.speed.value, "sigma_ms": k.speed.sigma, "wavelength_m": k.wavelength_m }),
            Err(why) => json!({ "unknown": why }),
        };
    }
    json!({
        "ship": w.ship,
        "kind": if w.ship.is_some() { "ship's wake" } else { "free wake (its ship not found: the course is 180 degrees ambiguous)" },
        "signature": w.signature,
        "product_start": [start.0, start.1],
        "product_end": [end.0, end.1],
        "lonlat_start": ll_start.map(|p| [p.0, p.1]),
        "lonlat_end": ll_end.map(|p| [p.0, p.1]),
        "axis_image_deg": w.axis_deg,
        "course_image_deg": w.course_deg,
        "course_deg": if w.course_deg.is_some() { bearing } else { None },
        "course_sigma_deg": w.course_sigma_deg,
        "length_m": w.length_m,
        "contrast": w.contrast,
        "z": w.z,
        "along_hull": w.along_hull,
        "promoted": w.promoted,
        "arms": w.arms,
        "azimuth_offset_m": w.offset_m,
        "speed_offset": offset,
        "speed_kelvin": kelvin,
        "speed_offset_ms": w.speed.as_ref().and_then(|s| s.offset.as_ref().ok()).map(|v| v.value),
        "speed_kelvin_ms": w.speed.as_ref().and_then(|s| s.kelvin.as_ref().ok()).map(|k| k.speed.value),
    })
}

#[cfg(test)]
mod tests {
    use super::super::scenes::{ship_scene, whole_search};
    use super::*;
    use wakelab_ships::cfar::CfarOptions;
    use wakelab_ships::Geometry;

    /// Each wake's `signature` in `detections.json` is written in words: the synthetic ship's
    /// 3 dB trough is a "dark trough", and an arm is a "bright arm". Whether it is a promoted
    /// faint line is written as `promoted`.
    #[test]
    fn a_wakes_signature_is_written_in_words() {
        let image = ship_scene(1600, 300, (700, 150), 0);
        let g = Geometry::along_rows(10.0, 35.0, None);
        let (_, wake) = whole_search(&image, &g);
        let entry = wake_entry(&wake, wake.start, wake.end, None, None, None);
        assert_eq!(entry["signature"], "dark trough");
        assert_eq!(entry["promoted"], false);
        let promoted = Wake {
            promoted: true,
            ..wake.clone()
        };
        assert_eq!(
            wake_entry(&promoted, wake.start, wake.end, None, None, None)["promoted"],
            true
        );
        assert_eq!(json!(Signature::BrightArm), "bright arm");
        assert_ne!(wake_colour(Signature::Trough), wake_colour(Signature::BrightArm));
    }

    /// The synthetic ship with its wake, and a second ship beside it on plain speckle (4 km
    /// up the rows), searched: both found.
    fn two_ships() -> SeaFindings {
        let mut image = ship_scene(1600, 300, (700, 150), 0);
        image.slice_mut(ndarray::s![294..306, 49..52]).fill(3.0);
        let g = Geometry::along_rows(10.0, 35.0, None);
        let found = super::super::search_image(image.view(), None, g, CfarOptions::default(), None);
        assert_eq!(found.ships.len(), 2, "{:?}", found.ships);
        found
    }

    /// A ship without a wake says why, in `detections.json` (its best trough and bright arm,
    /// each with the test it failed) and in the GeoJSON (the reason): a second ship beside the
    /// synthetic one, on plain speckle. The ship with a wake has none.
    #[test]
    fn a_ship_without_a_wake_says_why() {
        let found = two_ships();
        assert!(
            found
                .describe()
                .contains("; 1 ship(s) without a wake (why: each ship's `no_wake` in detections.json)"),
            "{}",
            found.describe()
        );
        assert!(found
            .describe()
            .starts_with("2 ship(s), 1 wake(s) (1 of a ship, 0 free)"));
        let mut promoted = found.clone();
        promoted.wakes[0].promoted = true;
        assert!(
            promoted
                .describe()
                .starts_with("2 ship(s), 1 wake(s) (1 of a ship, 0 free; 1 promoted from a faint line, no other wake found (`promoted`))"),
            "{}",
            promoted.describe()
        );
        let points = found.points();
        let (ships, _, features) = found.entries(&points, None, true);
        let ships = ships.as_array().unwrap();
        let with_wake = found
            .wakes
            .iter()
            .find_map(|w| w.ship)
            .expect("the synthetic ship's wake");
        for (k, ship) in ships.iter().enumerate() {
            let in_geojson = &features[k].properties["no_wake"];
            if k == with_wake {
                assert!(ship["no_wake"].is_null() && in_geojson.is_null(), "{ship}");
                continue;
            }
            let no_wake = &ship["no_wake"];
            let reason = no_wake["reason"].as_str().expect("a reason");
            assert!(reason.starts_with("no dark trough: the best line "), "{reason}");
            assert!(reason.contains("; no bright arm: the best line "), "{reason}");
            assert_eq!(no_wake["trough"]["signature"], "dark trough");
            // plain speckle: the best of 360 directions stands a few deviations up, not 5
            assert_eq!(no_wake["trough"]["test"], "significance", "{no_wake}");
            assert_eq!(no_wake["bright_arm"]["signature"], "bright arm");
            assert!(no_wake["trough"]["z"].as_f64().is_some(), "{no_wake}");
            assert_eq!(in_geojson.as_str(), Some(reason));
        }
    }

    /// A faint line is written where it lies, by its ship and signature: the ship without a
    /// wake beside the synthetic one, given a faint trough and a faint arm by hand, places
    /// each at its own points (here the product's pixels are the scanned ones), and null
    /// stands where a refusal has none; the summary counts them.
    #[test]
    fn faint_lines_are_written_where_they_lie() {
        let mut found = two_ships();
        let k = found
            .no_wake
            .iter()
            .position(Option::is_some)
            .expect("a ship without a wake");
        let lines = [
            FaintLine {
                start: (300.0, 50.0),
                end: (300.0, 200.0),
                length_m: 1500.0,
            },
            FaintLine {
                start: (310.0, 52.0),
                end: (460.0, 52.0),
                length_m: 1510.0,
            },
        ];
        let no_wake = found.no_wake[k].as_mut().unwrap();
        no_wake.trough.faint_line = Some(lines[0]);
        no_wake.bright_arm.faint_line = Some(lines[1]);
        assert!(
            found
                .describe()
                .ends_with("2 faint line(s) below significance among them (`faint_line`)"),
            "{}",
            found.describe()
        );
        let points = found.points();
        let (ships, _, _) = found.entries(&points, None, true);
        let no_wake = &ships[k]["no_wake"];
        for (key, line) in [("trough", lines[0]), ("bright_arm", lines[1])] {
            let entry = &no_wake[key]["faint_line"];
            assert_eq!(entry["product_start"], json!([line.start.0, line.start.1]), "{no_wake}");
            assert_eq!(entry["product_end"], json!([line.end.0, line.end.1]), "{no_wake}");
            assert_eq!(entry["length_m"], json!(line.length_m), "{no_wake}");
            assert!(entry["lonlat_start"].is_null(), "not georeferenced: {no_wake}");
        }
        found.no_wake[k].as_mut().unwrap().trough.faint_line = None;
        let points = found.points();
        let (ships, _, _) = found.entries(&points, None, true);
        assert!(ships[k]["no_wake"]["trough"]["faint_line"].is_null());
        assert_eq!(
            ships[k]["no_wake"]["bright_arm"]["faint_line"]["length_m"],
            json!(1510.0)
        );
    }

    #[test]
    fn bearings_follow_the_compass() {
        assert!((bearing((0.0, 0.0), (0.0, 1.0)) - 0.0).abs() < 1e-9);
        assert!((bearing((0.0, 0.0), (1.0, 0.0)) - 90.0).abs() < 1e-9);
        assert!((bearing((10.0, 50.0), (10.0, 49.0)) - 180.0).abs() < 1e-9);
    }
}

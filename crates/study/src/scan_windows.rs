//! Every window of a scan as `windows.csv`: the window, its wake probability and its strongest
//! line ([`wakelab_learn::window_line`]), one row each, for a user who wants more than the map
//! (which averages the windows over each cell) and the detections (which keep only windows above
//! the threshold that overlap no stronger one): to rank the windows another way, to study what
//! the network and the line each say, or to draw every window's line in a GIS.

use std::path::Path;

use anyhow::Result;
use serde::Serialize;
use wakelab_core::io::atomic::write_atomically;
use wakelab_learn::detect::Detection;

/// One window as `windows.csv` holds it (product pixels, row down, column right).
#[derive(Debug, Serialize)]
struct WindowRow {
    /// The window's centre.
    window_row: f64,
    window_col: f64,
    /// Its wake probability, the network's.
    probability: f64,
    /// Where it places its wake: the middle of its strongest line's stretch of contrast, else
    /// (a flat window) its centre, as the peak and detections are placed.
    place_row: f64,
    place_col: f64,
    /// The strongest line's direction (degrees in [0, 180), anticlockwise from the column
    /// axis), the extent of its contrast (the scanned pixels) and its contrast in robust
    /// deviations over the root of its pixels (negative: dark); empty for a flat window.
    orientation_deg: Option<f64>,
    line_length_px: Option<f64>,
    line_z: Option<f64>,
}

/// `detection`'s windows written to `path` (CSV, a header row then one row a window in the
/// scan's order), each scanned pixel position (row, column) taken into the product's by
/// `in_product` ([`crate::scan::Scanned`]'s).
pub fn write_windows(path: &Path, detection: &Detection, in_product: impl Fn(f64, f64) -> (f64, f64)) -> Result<()> {
    let half = 0.5 * detection.window as f64;
    let mut csv = csv::Writer::from_writer(Vec::new());
    for tile in &detection.tiles {
        let (window_row, window_col) = in_product(tile.row as f64 + half, tile.col as f64 + half);
        let (place_row, place_col) = {
            let (row, col) = tile.place(detection.window);
            in_product(row, col)
        };
        csv.serialize(WindowRow {
            window_row,
            window_col,
            probability: tile.probability,
            place_row,
            place_col,
            orientation_deg: tile.line.map(|l| l.angle),
            line_length_px: tile.line.map(|l| l.length),
            line_z: tile.line.map(|l| l.z),
        })?;
    }
    write_atomically(path, &csv.into_inner().map_err(|e| anyhow::anyhow!("{e}"))?)?;
    Ok(())
}

//! One scanned window's result: where it lies, its wake probability, and the strongest line
//! that places its wake. Its own module so that the scan ([`crate::detect`]) and the choice of
//! its peak ([`crate::peak`]) both read it without importing each other.

use crate::window_line::WindowLine;
use serde::Serialize;

/// One window's result.
#[derive(Debug, Clone, Serialize)]
pub struct Tile {
    pub row: usize,
    pub col: usize,
    pub probability: f64,
    /// The window's strongest line in the image's pixels ([`crate::window_line`]): where the
    /// window places its wake. None for a flat window.
    #[serde(skip)]
    pub line: Option<WindowLine>,
}

impl Tile {
    /// Where the window places its wake (row, column in the scanned pixels): the middle of its
    /// strongest line's contrast, or the window's centre where it has no line.
    pub fn place(&self, n: usize) -> (f64, f64) {
        match self.line {
            Some(line) => (line.row, line.col),
            None => (self.row as f64 + 0.5 * n as f64, self.col as f64 + 0.5 * n as f64),
        }
    }
}

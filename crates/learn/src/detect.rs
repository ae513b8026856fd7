//! Detection on a user's own single-band image (npy, TIFF or PNG) of any size: windows of the
//! detector's input size slide over the image with a stride, each made an input as in training
//! ([`crate::data::detector_input`], radar pixels read in the given [`RadarScale`]) and scored,
//! a batch at a time so that memory holds one batch of windows, not the window set. Each cell of
//! `stride` x `stride` pixels gets the mean probability of the windows that cover it (a cell on a
//! wake is covered only by windows that hold the wake, so the map peaks on it); the U-Net's masks
//! are stitched (overlaps averaged) into one mask of the image; the windows above the threshold
//! that overlap no stronger one are the detections. A window places its wake on its strongest
//! line ([`crate::window_line`]), which also gives its direction and length; the U-Net's mask,
//! where there is one, gives them instead.

use crate::data::{detector_input, RadarScale};
use crate::evaluate::detect_with_masks;
use crate::line_sums::line_sums;
use crate::models::Architecture;
use crate::peak::{most_probable, peak_of};
pub use crate::peak::{Peak, PeakRule};
use crate::store::{Detector, ModelInfo};
pub use crate::tile::Tile;
use crate::train::Example;
use crate::window_line::{strongest_line, strongest_line_of, WindowLine};
use burn::tensor::Device;
use ndarray::{s, Array2, Axis};
use rayon::prelude::*;
use serde::Serialize;

use wakelab_core::{ConfigError, WakelabError};
use wakelab_schema::architecture::InputForm;
use wakelab_schema::band::Band;

pub use crate::image_file::read_single_band;

/// How a scene is scanned.
#[derive(Debug, Clone, Copy)]
pub struct ScanOptions {
    /// Step between windows (pixels); None: half the window.
    pub stride: Option<usize>,
    /// How a radar image's pixels are scaled.
    pub scale: RadarScale,
    /// Windows scored at once (bounds the memory).
    pub batch: usize,
    /// Decision threshold on a window's wake probability; None: the detector's.
    pub threshold: Option<f64>,
    /// Which window is the scan's [`Peak`].
    pub peak: PeakRule,
}

impl Default for ScanOptions {
    fn default() -> Self {
        Self {
            stride: None,
            scale: RadarScale::Linear,
            batch: 256,
            threshold: None,
            peak: PeakRule::default(),
        }
    }
}

/// A window above the threshold that overlaps no stronger one.
#[derive(Debug, Clone, Serialize)]
pub struct Found {
    /// Where the window places its wake (pixels; row down, column right): the middle of the
    /// stretch of its strongest line that carries the contrast ([`Tile::place`]).
    pub row: f64,
    pub col: f64,
    /// The window's probability.
    pub score: f64,
    /// Area of the window's cells (pixels).
    pub area: usize,
    /// The wake's direction: degrees in [0, 180), anticlockwise from the image's column axis
    /// (0 = along a row, 90 = up the image). The U-Net mask's principal axis within the cells
    /// where there is a U-Net (None with fewer than 3 mask pixels), else the window's strongest
    /// line (None for a flat window).
    pub orientation: Option<f64>,
    /// The wake's extent along that direction (pixels): of the mask's pixels, or of the line's
    /// stretch of contrast.
    pub length: Option<f64>,
}

/// Detection on one image.
#[derive(Debug, Clone, Serialize)]
pub struct Detection {
    /// Largest window probability: the chance a wake is somewhere in the image.
    pub probability: f64,
    pub wake: bool,
    pub threshold: f64,
    /// Window side and step (pixels).
    pub window: usize,
    pub stride: usize,
    pub tiles: Vec<Tile>,
    /// Where the strongest window places its wake.
    pub peak: Peak,
    /// Wakes found: the windows above the threshold that overlap no stronger one, strongest
    /// first.
    pub detections: Vec<Found>,
    /// Mean probability of the windows covering each `stride` x `stride` cell.
    #[serde(skip)]
    pub map: Array2<f32>,
    /// The U-Net's stitched wake mask (image size).
    #[serde(skip)]
    pub mask: Option<Array2<f32>>,
}

impl Detection {
    /// "wake probability 0.912 (wake at threshold 0.5), 4 window(s) of 64 x 64 px at stride 32,
    /// 1 detection(s)".
    pub fn describe(&self) -> String {
        format!(
            "wake probability {:.3} ({} at threshold {}), {} window(s) of {n} x {n} px at stride {}, {} detection(s)",
            self.probability,
            if self.wake { "wake" } else { "no wake" },
            self.threshold,
            self.tiles.len(),
            self.stride,
            self.detections.len(),
            n = self.window,
        )
    }
}

/// A window with its no-data (NaN) pixels set to the median of its data, so that they sit at
/// the normalised input's zero and neither darken nor brighten it.
fn filled(mut window: Array2<f32>) -> Array2<f32> {
    if window.iter().any(|v| v.is_nan()) {
        let centre = crate::data::median(&window);
        window.mapv_inplace(|v| if v.is_nan() { centre } else { v });
    }
    window
}

/// A window of `band` (pixels in `scale`) as the detector's example: its no-data filled, then
/// normalised ([`detector_input`]).
pub fn window_example(window: Array2<f32>, band: Band, scale: RadarScale) -> Example {
    Example {
        image: detector_input(filled(window), band, scale).insert_axis(Axis(0)),
        label: 0,
        mask: None,
    }
}

/// A window's example and its strongest line; with `summed`, the example's image replaced by
/// its line sums (channel by channel), which the line is read off, so that they are made once.
fn with_line(example: Example, summed: bool) -> (Example, Option<WindowLine>) {
    if !summed {
        let line = strongest_line(example.image.index_axis(Axis(0), 0));
        return (example, line);
    }
    let sums: Vec<Array2<f32>> = example.image.outer_iter().map(|c| line_sums(&c.to_owned())).collect();
    let line = strongest_line_of(example.image.index_axis(Axis(0), 0), &sums[0]);
    let views: Vec<_> = sums.iter().map(|s| s.view().insert_axis(Axis(0))).collect();
    let image = ndarray::concatenate(Axis(0), &views).expect("channels of one side");
    (Example { image, ..example }, line)
}

/// Batches of windows scored at once, side by side.
const PARALLEL_BATCHES: usize = 2;

/// Whether an image of `size` (rows, columns) fills at least half of an `n` x `n` window: the
/// scan pads a smaller image's window with no-data, as at a product's no-data border, and a
/// window more than half no-data is not scored.
pub fn fills_half_a_window(size: (usize, usize), n: usize) -> bool {
    2 * size.0.min(n) * size.1.min(n) >= n * n
}

/// What an image too small for an `n` x `n` window must be: half the window's pixels in view.
pub fn half_a_window(n: usize) -> String {
    let side = ((n * n) as f64 / 2.0).sqrt().ceil() as usize;
    format!(
        "at least half of the detector's {n} x {n}-pixel input in view ({} x {n}, {side} x {side} or more pixels; the rest of its window is taken as no-data)",
        n.div_ceil(2)
    )
}

/// The rows and columns of an `n` x `n` window at `origin` (row, column; it may lie off the
/// image) that lie on an image of `dim`: as ranges in the image and in the window.
fn on_image((h, w): (usize, usize), (r0, c0): (isize, isize), n: usize) -> [std::ops::Range<usize>; 4] {
    let span = |o: isize, len: usize| {
        let start = o.clamp(0, len as isize) as usize;
        let end = (o + n as isize).clamp(0, len as isize) as usize;
        // a window wholly off the image has no part on it: empty ranges both
        let inside = |i: usize| (i as isize - o).max(0) as usize;
        (start..end, inside(start)..inside(end))
    };
    let ((rows, window_rows), (cols, window_cols)) = (span(r0, h), span(c0, w));
    [rows, cols, window_rows, window_cols]
}

/// The `n` x `n` window of `image` whose top-left pixel is `origin` (row, column; it may lie
/// off the image), no-data (NaN) wherever it runs past the image's edge: how a scan reads an
/// image smaller than its window, and the window cut around a ship by the image's edge.
pub fn window_at(image: ndarray::ArrayView2<f32>, origin: (isize, isize), n: usize) -> Array2<f32> {
    let [rows, cols, window_rows, window_cols] = on_image(image.dim(), origin, n);
    if rows.len() == n && cols.len() == n {
        return image.slice(s![rows, cols]).to_owned();
    }
    let mut window = Array2::from_elem((n, n), f32::NAN);
    if !rows.is_empty() && !cols.is_empty() {
        window
            .slice_mut(s![window_rows, window_cols])
            .assign(&image.slice(s![rows, cols]));
    }
    window
}

/// The no-data pixels of [`window_at`]'s window: the image's NaN in it and its part off the
/// image.
fn window_no_data(image: ndarray::ArrayView2<f32>, origin: (isize, isize), n: usize) -> usize {
    let [rows, cols, ..] = on_image(image.dim(), origin, n);
    let on = rows.len() * cols.len();
    let nan = image.slice(s![rows, cols]).iter().filter(|v| v.is_nan()).count();
    nan + n * n - on
}

/// Window origins along one axis of length `len` for windows of `size` every `stride`; the last
/// window ends at the border.
fn tile_starts(len: usize, size: usize, stride: usize) -> Vec<usize> {
    if len <= size {
        return vec![0];
    }
    let mut starts: Vec<usize> = (0..=len - size).step_by(stride.max(1)).collect();
    if *starts.last().unwrap() != len - size {
        starts.push(len - size);
    }
    starts
}

/// For each origin, the range of `stride`-cells its window of `size` covers.
fn covered_cells(start: usize, size: usize, stride: usize) -> std::ops::Range<usize> {
    start / stride..(start + size - 1) / stride + 1
}

/// Scan a single-band detector over an image of any size that fills at least half of the
/// detector's window ([`Scan::new`]); a radar
/// image's pixels are in `options.scale` (an infrared one's are brightness temperatures, K).
/// `progress(done, total)` follows the windows.
pub fn detect_image(
    detector: &Detector,
    info: &ModelInfo,
    image: &Array2<f32>,
    options: ScanOptions,
    device: &Device,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Detection, WakelabError> {
    let mut scan = Scan::new(detector, info, image.dim(), options)?;
    scan.feed(0, image.view(), device, progress);
    scan.finish()
}

/// The wake probability (as a scan reports it: calibrated where the detector is) of each of
/// `windows`, n x n at the detector's input side and spacing, pixels in `options.scale`, NaN for
/// no data (set to the window's median, as a scan sets them). A window more than half no data,
/// or not of the detector's side, is not scored (None), as a scan scores none.
pub fn score_windows(
    detector: &Detector,
    info: &ModelInfo,
    windows: &[Array2<f32>],
    options: ScanOptions,
    device: &Device,
) -> Result<Vec<Option<f64>>, WakelabError> {
    let (n, band) = (info.input_size, info.single_band()?);
    let scored: Vec<usize> = (0..windows.len())
        .filter(|&i| {
            let w = &windows[i];
            w.dim() == (n, n) && 2 * w.iter().filter(|v| v.is_nan()).count() <= n * n
        })
        .collect();
    let mut out = vec![None; windows.len()];
    // a batch's inputs are made when it is scored, so that memory holds one batch of them
    for chunk in scored.chunks(options.batch.max(1)) {
        let examples: Vec<Example> = chunk
            .par_iter()
            .map(|&i| window_example(windows[i].clone(), band, options.scale))
            .collect();
        let (p, _) = detect_with_masks(
            detector,
            info.architecture,
            info.input_form,
            &examples,
            options.batch.max(1),
            device,
        );
        for (&i, &probability) in chunk.iter().zip(&p) {
            out[i] = Some(info.probability(probability));
        }
    }
    Ok(out)
}

/// A scan fed a band of image rows at a time, so that a whole product need not be held: each
/// band scores the windows whose rows it holds and that no earlier band scored
/// ([`Scan::next_rows`] says which rows the next band must start with). Fed the whole image
/// at once it is [`detect_image`]; fed in bands it scores the same windows with the same
/// inputs, so it gives the same map.
pub struct Scan<'a> {
    detector: &'a Detector,
    info: &'a ModelInfo,
    band: Band,
    options: ScanOptions,
    n: usize,
    stride: usize,
    threshold: f64,
    /// The image's rows and columns.
    size: (usize, usize),
    rows: Vec<usize>,
    cols: Vec<usize>,
    /// Index into `rows` of the first window row not yet scored.
    next_row: usize,
    sum: Array2<f32>,
    count: Array2<f32>,
    mask_sum: Option<Array2<f32>>,
    mask_count: Option<Array2<f32>>,
    tiles: Vec<Tile>,
    considered: usize,
}

impl<'a> Scan<'a> {
    /// A scan of an image of `size` (rows, columns); the detector, stride and threshold are
    /// checked here.
    pub fn new(
        detector: &'a Detector,
        info: &'a ModelInfo,
        size: (usize, usize),
        options: ScanOptions,
    ) -> Result<Self, WakelabError> {
        let n = info.input_size;
        let band = info.single_band()?;
        let (h, w) = size;
        if !fills_half_a_window(size, n) {
            return Err(ConfigError::new("IMAGE", format!("{h} x {w} pixels"), half_a_window(n)).into());
        }
        let stride = options.stride.unwrap_or((n / 2).max(1));
        if stride == 0 || stride > n {
            return Err(
                ConfigError::new("--stride", stride, format!("an integer in [1, {n}] (the window side)")).into(),
            );
        }
        let threshold = options.threshold.unwrap_or(info.threshold);
        if !(0.0..=1.0).contains(&threshold) {
            return Err(ConfigError::new("--threshold", threshold, "in [0, 1]").into());
        }
        let cells = (h.div_ceil(stride), w.div_ceil(stride));
        let with_mask = detector.segmenter.is_some() && info.architecture == Architecture::Unet;
        Ok(Self {
            detector,
            info,
            band,
            options,
            n,
            stride,
            threshold,
            size,
            rows: tile_starts(h, n, stride),
            cols: tile_starts(w, n, stride),
            next_row: 0,
            sum: Array2::zeros(cells),
            count: Array2::zeros(cells),
            mask_sum: with_mask.then(|| Array2::zeros(size)),
            mask_count: with_mask.then(|| Array2::zeros(size)),
            tiles: Vec::new(),
            considered: 0,
        })
    }

    /// The window side and the step between windows (pixels).
    pub fn window_and_stride(&self) -> (usize, usize) {
        (self.n, self.stride)
    }

    /// The image rows the next band must begin with (the first unscored window's rows); None
    /// when every window is scored.
    pub fn next_rows(&self) -> Option<std::ops::Range<usize>> {
        self.rows.get(self.next_row).map(|&r| r..(r + self.n).min(self.size.0))
    }

    /// Score the windows held by `band`, image rows `start..start + band.nrows()` (every column),
    /// that no earlier band scored. Windows more than half no-data (NaN) are not scored; the
    /// rest have their no-data pixels set to their median. `progress(done, total)` follows
    /// the windows considered.
    pub fn feed(
        &mut self,
        start: usize,
        band: ndarray::ArrayView2<f32>,
        device: &Device,
        progress: &mut dyn FnMut(usize, usize),
    ) {
        let n = self.n;
        let end = start + band.nrows();
        let mut origins = Vec::new();
        while let Some(&r) = self.rows.get(self.next_row) {
            if r < start || (r + n).min(self.size.0) > end {
                break;
            }
            origins.extend(self.cols.iter().map(|&c| (r, c)));
            self.next_row += 1;
        }
        let total = self.rows.len() * self.cols.len();
        let considered = origins.len();
        let origins: Vec<(usize, usize)> = origins
            .into_iter()
            .filter(|&(r, c)| 2 * window_no_data(band, ((r - start) as isize, c as isize), n) <= n * n)
            .collect();
        // batches scored side by side, PARALLEL_BATCHES at a time (burn's small convolutions
        // keep about one core busy each), their results gathered in order
        let batch_size = self.options.batch.max(1);
        let (detector, architecture, form, kind, scale) = (
            self.detector,
            self.info.architecture,
            self.info.input_form,
            self.band,
            self.options.scale,
        );
        // a classifier of the plain line sums reads the very sums the window's line is read off:
        // made once, they go to the network as its input read as pixels (the U-Net reads pixels)
        let summed = form == InputForm::LineSums && architecture != Architecture::Unet;
        let (before, mut done) = (self.considered, 0);
        for group in origins.chunks(batch_size * PARALLEL_BATCHES) {
            let scored: Vec<_> = group
                .par_chunks(batch_size)
                .map(|batch| {
                    let (examples, lines): (Vec<Example>, Vec<Option<WindowLine>>) = batch
                        .iter()
                        .map(|&(r, c)| {
                            let example =
                                window_example(window_at(band, ((r - start) as isize, c as isize), n), kind, scale);
                            let (example, line) = with_line(example, summed);
                            (example, line.map(|l| l.shifted((r as f64, c as f64))))
                        })
                        .unzip();
                    let form = if summed { InputForm::Pixels } else { form };
                    (
                        detect_with_masks(detector, architecture, form, &examples, batch_size, device),
                        lines,
                    )
                })
                .collect();
            for (batch, ((p, masks), lines)) in group.chunks(batch_size).zip(scored) {
                for (i, ((&(r, c), &probability), line)) in batch.iter().zip(&p).zip(lines).enumerate() {
                    let probability = self.info.probability(probability);
                    self.add(r, c, probability, line, masks.as_ref().map(|m| &m[i]));
                }
            }
            // progress in windows considered, the unscored no-data ones spread over the band
            done += group.len();
            progress(before + done * considered / origins.len(), total);
        }
        self.considered += considered;
        if origins.is_empty() {
            progress(self.considered, total);
        }
    }

    /// One scored window into the map, the mask and the tiles.
    fn add(&mut self, r: usize, c: usize, probability: f64, line: Option<WindowLine>, mask: Option<&Array2<f32>>) {
        let (n, stride) = (self.n, self.stride);
        // a window past the image's edge (an image smaller than the window) covers only the
        // image's cells and pixels
        let within = |cells: std::ops::Range<usize>, len: usize| cells.start..cells.end.min(len);
        let (cell_rows, cell_cols) = self.sum.dim();
        let region = s![
            within(covered_cells(r, n, stride), cell_rows),
            within(covered_cells(c, n, stride), cell_cols)
        ];
        self.sum.slice_mut(region).mapv_inplace(|v| v + probability as f32);
        self.count.slice_mut(region).mapv_inplace(|v| v + 1.0);
        if let (Some(total), Some(times), Some(m)) = (self.mask_sum.as_mut(), self.mask_count.as_mut(), mask) {
            let (h, w) = ((self.size.0 - r).min(n), (self.size.1 - c).min(n));
            let window = s![r..r + h, c..c + w];
            total
                .slice_mut(window)
                .zip_mut_with(&m.slice(s![..h, ..w]), |a, b| *a += b);
            times.slice_mut(window).mapv_inplace(|v| v + 1.0);
        }
        self.tiles.push(Tile {
            row: r,
            col: c,
            probability,
            line,
        });
    }

    /// The detection: the map, its peak and the detections. Refused when no window was scored
    /// (every one more than half no-data).
    pub fn finish(self) -> Result<Detection, WakelabError> {
        let Self {
            n,
            stride,
            threshold,
            sum,
            count,
            mask_sum,
            mask_count,
            tiles,
            ..
        } = self;
        if tiles.is_empty() {
            return Err(WakelabError::Image {
                path: "IMAGE".into(),
                message: format!("every {n} x {n} window is more than half no-data: nothing to scan"),
            });
        }
        // a cell no scored window covers is no-data
        let map = mean_map(&sum, &count);
        // each pixel's mask: the mean over the windows that covered it (no-data where none did)
        let mask = mask_sum.zip(mask_count).map(|(mut total, times)| {
            total.zip_mut_with(&times, |v, &t| *v = if t > 0.0 { *v / t } else { f32::NAN });
            total
        });
        Ok(finish_detection(
            map,
            mask,
            tiles,
            n,
            stride,
            threshold,
            self.options.peak,
        ))
    }
}

/// The detection from the scan's map, mask and scored windows.
fn finish_detection(
    map: Array2<f32>,
    mask: Option<Array2<f32>>,
    tiles: Vec<Tile>,
    n: usize,
    stride: usize,
    threshold: f64,
    rule: PeakRule,
) -> Detection {
    let peak = peak_of(&tiles, n, rule);
    // the chance a wake is somewhere in the image, whichever window the peak is
    let probability = most_probable(&tiles).probability.max(0.0);
    let detections = find_wakes(&map, &tiles, n, stride, threshold, mask.as_ref());
    Detection {
        probability,
        wake: probability > threshold,
        threshold,
        window: n,
        stride,
        tiles,
        peak,
        detections,
        map,
        mask,
    }
}

/// The map of a scan: each cell the mean of the `sum` of the window probabilities over it by
/// their `count`, no-data where no window covers it.
pub(crate) fn mean_map(sum: &Array2<f32>, count: &Array2<f32>) -> Array2<f32> {
    ndarray::Zip::from(sum)
        .and(count)
        .map_collect(|&s, &c| if c > 0.0 { s / c } else { f32::NAN })
}

/// The windows above `threshold` after non-maximum suppression: strongest first, a window is
/// kept unless it overlaps one already kept (the usual sliding-window detector's rule). Each is
/// placed on its strongest line ([`Tile::place`]) and measured on the mask where there is one,
/// else by that line.
fn find_wakes(
    map: &Array2<f32>,
    tiles: &[Tile],
    window: usize,
    stride: usize,
    threshold: f64,
    mask: Option<&Array2<f32>>,
) -> Vec<Found> {
    let mut candidates: Vec<&Tile> = tiles.iter().filter(|t| t.probability > threshold).collect();
    candidates.sort_by(|a, b| b.probability.total_cmp(&a.probability));
    // kept windows by the window-sized block of their origin: an overlapping one is in the 3 x 3
    // blocks around
    let mut kept: std::collections::HashMap<(usize, usize), Vec<(usize, usize)>> = Default::default();
    let mut found = Vec::new();
    for t in candidates {
        let block = (t.row / window, t.col / window);
        let overlaps = (block.0.saturating_sub(1)..=block.0 + 1).any(|br| {
            (block.1.saturating_sub(1)..=block.1 + 1).any(|bc| {
                kept.get(&(br, bc)).is_some_and(|list| {
                    list.iter()
                        .any(|&(r, c)| r.abs_diff(t.row) < window && c.abs_diff(t.col) < window)
                })
            })
        });
        if overlaps {
            continue;
        }
        kept.entry(block).or_default().push((t.row, t.col));
        found.push(measure(t, &window_cells(t, map, window, stride), window, stride, mask));
    }
    found
}

/// The map's cells that the window `t` of side `window` covers.
pub(crate) fn window_cells(t: &Tile, map: &Array2<f32>, window: usize, stride: usize) -> Vec<(usize, usize)> {
    covered_cells(t.row, window, stride)
        .flat_map(|r| covered_cells(t.col, window, stride).map(move |c| (r, c)))
        .filter(|&(r, c)| r < map.nrows() && c < map.ncols())
        .collect()
}

/// A window `t` (of side `window`) as a detection: its place, its score, the area of its
/// `cells`, and its direction and length from the mask's principal axis within them where
/// there is a mask, else from its strongest line.
fn measure(t: &Tile, cells: &[(usize, usize)], window: usize, stride: usize, mask: Option<&Array2<f32>>) -> Found {
    let (row, col) = t.place(window);
    let (orientation, length) = match mask {
        Some(m) => principal_axis(m, cells, stride),
        None => (t.line.map(|l| l.angle), t.line.map(|l| l.length)),
    };
    Found {
        row,
        col,
        score: t.probability,
        area: cells.len() * stride * stride,
        orientation,
        length,
    }
}

/// Direction and extent of the mask pixels (> 0.5) inside the cells, from their second moments.
fn principal_axis(mask: &Array2<f32>, cells: &[(usize, usize)], stride: usize) -> (Option<f64>, Option<f64>) {
    let (h, w) = mask.dim();
    let mut points = Vec::new();
    for &(cr, cc) in cells {
        for r in cr * stride..((cr + 1) * stride).min(h) {
            for c in cc * stride..((cc + 1) * stride).min(w) {
                if mask[[r, c]] > 0.5 {
                    // x to the right, y up the image
                    points.push((c as f64, -(r as f64)));
                }
            }
        }
    }
    if points.len() < 3 {
        return (None, None);
    }
    let count = points.len() as f64;
    let (mx, my) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / count, b + y / count));
    let (mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0);
    for (x, y) in &points {
        sxx += (x - mx) * (x - mx);
        syy += (y - my) * (y - my);
        sxy += (x - mx) * (y - my);
    }
    let angle = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    let (s, c) = angle.sin_cos();
    let along = points.iter().map(|(x, y)| (x - mx) * c + (y - my) * s);
    let (lo, hi) = along.fold((f64::MAX, f64::MIN), |(lo, hi), v| (lo.min(v), hi.max(v)));
    (Some(angle.to_degrees().rem_euclid(180.0)), Some(hi - lo + 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn windows_cover_the_image_with_their_stride() {
        assert_eq!(tile_starts(100, 100, 50), vec![0]);
        assert_eq!(tile_starts(64, 100, 50), vec![0]);
        assert_eq!(tile_starts(250, 100, 50), vec![0, 50, 100, 150]);
        assert_eq!(tile_starts(260, 100, 50), vec![0, 50, 100, 150, 160]);
        assert_eq!(tile_starts(260, 100, 100), vec![0, 100, 160]);
        // a window from 160 of 100 px covers the 40 px cells 4, 5, 6 (pixels 160..260)
        assert_eq!(covered_cells(160, 100, 40), 4..7);
        assert_eq!(covered_cells(0, 64, 32), 0..2);
    }

    /// Three windows of 8 px side by side without lines: the peak is the strongest window's
    /// centre; a window scored NaN is passed over, and where every one is, the first is taken.
    /// With a line, the window's line places it, and gives its direction and contrast.
    #[test]
    fn the_peak_is_the_strongest_scored_window() {
        let tile = |col, probability| Tile {
            row: 0,
            col,
            probability,
            line: None,
        };
        let mut tiles = [tile(0, f64::NAN), tile(8, 0.9), tile(16, 0.3)];
        let map = Array2::from_shape_vec((1, 3), vec![f32::NAN, 0.9, 0.3]).unwrap();
        let peak = peak_of(&tiles, 8, PeakRule::Network);
        assert_eq!((peak.row, peak.col, peak.probability), (4.0, 12.0, 0.9));
        assert_eq!((peak.orientation, peak.line_contrast), (None, None));
        let unscored = [tile(0, f64::NAN), tile(8, f64::NAN)];
        let peak = peak_of(&unscored, 8, PeakRule::Network);
        assert_eq!((peak.row, peak.col), (4.0, 4.0));
        let line = WindowLine {
            row: 1.5,
            col: 9.0,
            angle: 30.0,
            length: 6.0,
            z: -5.0,
        };
        tiles[1].line = Some(line);
        let peak = peak_of(&tiles, 8, PeakRule::Network);
        assert_eq!((peak.row, peak.col), (1.5, 9.0));
        assert_eq!((peak.orientation, peak.line_contrast), (Some(30.0), Some(-5.0)));
        // the scene's probability stays a number, and the most probable window's under the
        // line's rule too (the 0.3 window's line is the stronger there)
        tiles[2].line = Some(WindowLine { z: 7.0, ..line });
        for rule in PeakRule::ALL {
            let detection = finish_detection(map.clone(), None, tiles.to_vec(), 8, 8, 0.5, rule);
            assert_eq!((detection.probability, detection.peak.rule), (0.9, rule));
        }
    }

    #[test]
    fn a_line_in_the_mask_gives_its_direction_and_length() {
        // a line 40 px long rising at 45 degrees (up and to the right) in a 64 x 64 mask
        let mut mask = Array2::<f32>::zeros((64, 64));
        for k in 0..40 {
            mask[[50 - k, 10 + k]] = 1.0;
        }
        let cells: Vec<(usize, usize)> = (0..4).flat_map(|r| (0..4).map(move |c| (r, c))).collect();
        let (angle, length) = principal_axis(&mask, &cells, 16);
        assert!((angle.unwrap() - 45.0).abs() < 1e-9, "{angle:?}");
        // 40 pixels on the diagonal span 39 sqrt 2 between centres, plus one pixel
        assert!(
            (length.unwrap() - (39.0 * 2f64.sqrt() + 1.0)).abs() < 1e-9,
            "{length:?}"
        );
        // a row of pixels lies along the column axis
        let mut row = Array2::<f32>::zeros((64, 64));
        row.slice_mut(s![20, 5..25]).fill(1.0);
        let (angle, length) = principal_axis(&row, &cells, 16);
        assert!(angle.unwrap().abs() < 1e-9 || (angle.unwrap() - 180.0).abs() < 1e-9);
        assert_eq!(length, Some(20.0));
    }

    #[test]
    fn overlapping_windows_give_the_strongest_one_detection() {
        let tile = |row, col, probability| Tile {
            row,
            col,
            probability,
            line: None,
        };
        // 20 px windows every 10 px: (0, 0) and (10, 10) overlap, (40, 40) does not
        let tiles = [
            tile(10, 10, 0.7),
            tile(0, 0, 0.9),
            tile(40, 40, 0.6),
            tile(20, 0, 0.5), // at the threshold: not above it
        ];
        let mut map = Array2::<f32>::from_elem((6, 6), 0.1);
        map[[0, 0]] = 0.9;
        map[[1, 1]] = 0.7;
        let found = find_wakes(&map, &tiles, 20, 10, 0.5, None);
        assert_eq!(found.len(), 2);
        assert_eq!((found[0].score, found[0].area), (0.9, 400));
        assert_eq!(found[1].score, 0.6);
        // without a line, each at its window's centre
        assert_eq!((found[0].row, found[0].col), (10.0, 10.0));
        assert_eq!((found[1].row, found[1].col), (50.0, 50.0));
        assert!(found[0].orientation.is_none() && found[0].length.is_none());
        // with one, on the line, with its direction and length
        let mut lined = tiles.to_vec();
        lined[1].line = Some(WindowLine {
            row: 3.0,
            col: 17.0,
            angle: 100.0,
            length: 12.0,
            z: 4.0,
        });
        let found = find_wakes(&map, &lined, 20, 10, 0.5, None);
        assert_eq!((found[0].row, found[0].col), (3.0, 17.0));
        assert_eq!((found[0].orientation, found[0].length), (Some(100.0), Some(12.0)));
    }
}

//! 3 x 3 convolution (stride 1, zero padding p) of NCHW f32 images on the CPU, forward and
//! backward, as im2col + GEMM with the GEMM shapes chosen for the training step.
//!
//! Why not burn-flex's own convolution: its weight gradient is a convolution with the batch and
//! channel axes swapped, a GEMM of C_out x 9 outputs that the `gemm` crate runs 16 lanes wide with
//! 9 of them used (a quarter of a U-Net training step in `perf`, see `conv`). Here the weight
//! gradient is one GEMM per tile of output rows, dW[C_out, 9 C_in] += dY[C_out, P] cols[9 C_in, P]^T,
//! and the input gradient is the forward kernel applied to dY with the flipped, transposed weights
//! (the adjoint of a stride-1 correlation is the full correlation with the flipped kernel).
//! The arithmetic is the `gemm` crate's; this file only lays the data out.
//!
//! Determinism: every output element of the forward pass is one GEMM call with a fixed k order,
//! and the weight gradient sums fixed chunks of tiles in a fixed order, so the result does not
//! depend on the number of threads or on scheduling.

use rayon::prelude::*;

/// Shape of a convolution's input, [batch, channels, height, width], and its padding.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ConvShape {
    pub batch: usize,
    pub channels_in: usize,
    pub channels_out: usize,
    pub height: usize,
    pub width: usize,
    /// Zero padding on every side (the output is (h + 2p - 2) x (w + 2p - 2)).
    pub padding: usize,
}

impl ConvShape {
    pub fn new(
        batch: usize,
        channels_in: usize,
        channels_out: usize,
        height: usize,
        width: usize,
        padding: usize,
    ) -> Self {
        Self {
            batch,
            channels_in,
            channels_out,
            height,
            width,
            padding,
        }
    }

    pub fn out_height(&self) -> usize {
        self.height + 2 * self.padding - 2
    }

    pub fn out_width(&self) -> usize {
        self.width + 2 * self.padding - 2
    }

    /// Rows of the im2col matrix: 9 C_in, in the (c_in, k_y, k_x) order of a [C_out, C_in, 3, 3]
    /// weight tensor, so the weights are a row-major [C_out, 9 C_in] matrix as they are stored.
    fn taps(&self) -> usize {
        9 * self.channels_in
    }

    /// Output rows per tile: about 512 output pixels, as many as keep a tile's columns in cache.
    fn rows_per_tile(&self) -> usize {
        (512 / self.out_width().max(1)).clamp(1, self.out_height().max(1))
    }

    /// Every (batch item, first output row) of the tiles, in order.
    fn tiles(&self) -> Vec<(usize, usize)> {
        let rows = self.rows_per_tile();
        (0..self.batch)
            .flat_map(|b| (0..self.out_height()).step_by(rows).map(move |r| (b, r)))
            .collect()
    }
}

/// A raw pointer that rayon tasks may share: each task writes a region no other task touches.
#[derive(Clone, Copy)]
struct SharedMut(*mut f32);
unsafe impl Send for SharedMut {}
unsafe impl Sync for SharedMut {}

impl SharedMut {
    /// The pointer (a method, so that closures capture the whole `Send` wrapper).
    fn get(self) -> *mut f32 {
        self.0
    }
}

/// The im2col columns of output rows [row, row + rows) of batch item `b`: a row-major
/// [9 C_in, rows x W_out] matrix, column (y, x) of row (c, k_y, k_x) holding
/// x[b, c, y + k_y - p, x + k_x - p] (0 outside the image).
fn im2col(x: &[f32], s: &ConvShape, b: usize, row: usize, rows: usize, cols: &mut Vec<f32>) {
    let (h, w, wo, p) = (s.height, s.width, s.out_width(), s.padding);
    let n = rows * wo;
    cols.clear();
    cols.resize(s.taps() * n, 0.0);
    for c in 0..s.channels_in {
        let plane = &x[(b * s.channels_in + c) * h * w..][..h * w];
        for ky in 0..3 {
            for kx in 0..3 {
                let dst = &mut cols[((c * 3 + ky) * 3 + kx) * n..][..n];
                // output columns whose input column x + kx - p lies inside [0, w)
                let x0 = p.saturating_sub(kx);
                let x1 = (w + p).saturating_sub(kx).min(wo);
                if x1 <= x0 {
                    continue;
                }
                for (i, y) in (row..row + rows).enumerate() {
                    let yy = y + ky;
                    if yy < p || yy - p >= h {
                        continue;
                    }
                    let src = &plane[(yy - p) * w..][..w];
                    let start = x0 + kx - p;
                    dst[i * wo + x0..i * wo + x1].copy_from_slice(&src[start..start + (x1 - x0)]);
                }
            }
        }
    }
}

/// A matrix in memory: element (i, j) at `at + i * row_stride + j * column_stride`.
struct Matrix<P> {
    at: P,
    column_stride: isize,
    row_stride: isize,
}

impl<P> Matrix<P> {
    fn new(at: P, column_stride: usize, row_stride: usize) -> Self {
        Self {
            at,
            column_stride: column_stride as isize,
            row_stride: row_stride as isize,
        }
    }
}

/// dst (m x n) = lhs (m x k) rhs (k x n), plus dst's old values if `accumulate`: the `gemm`
/// crate's product on this thread (the callers parallelise over tiles).
///
/// # Safety
/// The three matrices must lie inside their allocations for the given sizes and strides, and no
/// other thread may access `dst`'s elements meanwhile.
unsafe fn product(
    [m, n, k]: [usize; 3],
    dst: Matrix<*mut f32>,
    accumulate: bool,
    lhs: Matrix<*const f32>,
    rhs: Matrix<*const f32>,
) {
    gemm::gemm(
        m,
        n,
        k,
        dst.at,
        dst.column_stride,
        dst.row_stride,
        accumulate,
        lhs.at,
        lhs.column_stride,
        lhs.row_stride,
        rhs.at,
        rhs.column_stride,
        rhs.row_stride,
        1.0,
        1.0,
        false,
        false,
        false,
        gemm::Parallelism::None,
    )
}

/// y = conv3x3(x, weight) + bias, NCHW, `weight` [C_out, C_in, 3, 3] row-major.
pub fn forward(x: &[f32], weight: &[f32], bias: Option<&[f32]>, s: &ConvShape) -> Vec<f32> {
    let (ho, wo, co) = (s.out_height(), s.out_width(), s.channels_out);
    assert_eq!(x.len(), s.batch * s.channels_in * s.height * s.width, "input size");
    assert_eq!(weight.len(), co * s.taps(), "weight size");
    let mut y = vec![0.0f32; s.batch * co * ho * wo];
    if let Some(bias) = bias {
        for (i, plane) in y.chunks_mut(ho * wo).enumerate() {
            plane.fill(bias[i % co]);
        }
    }
    let out = SharedMut(y.as_mut_ptr());
    let rows_per_tile = s.rows_per_tile();
    s.tiles().par_iter().for_each_init(Vec::new, |cols, &(b, row)| {
        let rows = rows_per_tile.min(ho - row);
        im2col(x, s, b, row, rows, cols);
        let n = rows * wo;
        // SAFETY: the tile writes rows [row, row + rows) of batch item b's C_out planes, which no
        // other tile writes; the strides describe that region of `y` (row stride ho * wo per
        // output channel, unit stride along the tile's pixels).
        unsafe {
            product(
                [co, n, s.taps()],
                Matrix::new(out.get().add(b * co * ho * wo + row * wo), 1, ho * wo),
                bias.is_some(),
                Matrix::new(weight.as_ptr(), 1, s.taps()),
                Matrix::new(cols.as_ptr(), 1, n),
            );
        }
    });
    y
}

/// Gradients (dx, dweight, dbias) of `forward` for the output gradient `dy`.
pub fn backward(x: &[f32], weight: &[f32], dy: &[f32], s: &ConvShape) -> (Vec<f32>, Vec<f32>, Vec<f32>) {
    (
        input_gradient(weight, dy, s),
        weight_gradient(x, dy, s),
        bias_gradient(dy, s),
    )
}

/// dx: the full correlation of dy with the weights flipped in space and transposed to
/// [C_in, C_out, 3, 3]; its padding 2 - p restores the input size.
pub fn input_gradient(weight: &[f32], dy: &[f32], s: &ConvShape) -> Vec<f32> {
    let (ci, co) = (s.channels_in, s.channels_out);
    let mut flipped = vec![0.0f32; weight.len()];
    for o in 0..co {
        for i in 0..ci {
            for k in 0..9 {
                flipped[(i * co + o) * 9 + (8 - k)] = weight[(o * ci + i) * 9 + k];
            }
        }
    }
    let adjoint = ConvShape {
        batch: s.batch,
        channels_in: co,
        channels_out: ci,
        height: s.out_height(),
        width: s.out_width(),
        padding: 2 - s.padding,
    };
    forward(dy, &flipped, None, &adjoint)
}

/// Chunks of tiles whose weight-gradient partial sums are added in order: fixed, so that the sum
/// does not depend on the threads.
const GRADIENT_CHUNKS: usize = 8;

/// dW[C_out, 9 C_in] = sum over tiles of dy_tile[C_out, P] cols_tile[9 C_in, P]^T.
pub fn weight_gradient(x: &[f32], dy: &[f32], s: &ConvShape) -> Vec<f32> {
    let (ho, wo, co, taps) = (s.out_height(), s.out_width(), s.channels_out, s.taps());
    let tiles = s.tiles();
    let rows_per_tile = s.rows_per_tile();
    let chunk = tiles.len().div_ceil(GRADIENT_CHUNKS).max(1);
    let partials: Vec<Vec<f32>> = tiles
        .par_chunks(chunk)
        .map(|part| {
            let mut dw = vec![0.0f32; co * taps];
            let mut cols = Vec::new();
            for &(b, row) in part {
                let rows = rows_per_tile.min(ho - row);
                im2col(x, s, b, row, rows, &mut cols);
                let n = rows * wo;
                // SAFETY: dw is this task's own [C_out, 9 C_in] buffer; dy's tile is read with
                // its plane stride, cols as its transpose (unit row stride, column stride n).
                unsafe {
                    product(
                        [co, taps, n],
                        Matrix::new(dw.as_mut_ptr(), 1, taps),
                        true,
                        Matrix::new(dy.as_ptr().add(b * co * ho * wo + row * wo), 1, ho * wo),
                        Matrix::new(cols.as_ptr(), n, 1),
                    );
                }
            }
            dw
        })
        .collect();
    let mut dw = vec![0.0f32; co * taps];
    for part in &partials {
        for (d, p) in dw.iter_mut().zip(part) {
            *d += p;
        }
    }
    dw
}

/// dbias[c] = sum of dy over the batch and the output plane of channel c: the channels in
/// parallel, each plane summed in 16 interleaved partial sums (vectorised; a fixed order).
pub fn bias_gradient(dy: &[f32], s: &ConvShape) -> Vec<f32> {
    let plane = s.out_height() * s.out_width();
    let co = s.channels_out;
    (0..co)
        .into_par_iter()
        .map(|c| {
            (0..s.batch)
                .map(|b| plane_sum(&dy[(b * co + c) * plane..][..plane]))
                .sum::<f32>()
        })
        .collect()
}

fn plane_sum(values: &[f32]) -> f32 {
    let mut lanes = [0.0f32; 16];
    let chunks = values.chunks_exact(16);
    let rest: f32 = chunks.remainder().iter().sum();
    for chunk in chunks {
        for (l, v) in lanes.iter_mut().zip(chunk) {
            *l += v;
        }
    }
    lanes.iter().sum::<f32>() + rest
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every product of the definition: (output index, input index, weight index) for each
    /// output pixel and each of its taps that falls inside the image.
    fn for_each_tap(s: &ConvShape, mut visit: impl FnMut(usize, usize, usize)) {
        let (ho, wo) = (s.out_height(), s.out_width());
        for b in 0..s.batch {
            for o in 0..s.channels_out {
                for yy in 0..ho {
                    for xx in 0..wo {
                        let out = ((b * s.channels_out + o) * ho + yy) * wo + xx;
                        for c in 0..s.channels_in {
                            for ky in 0..3 {
                                for kx in 0..3 {
                                    let (iy, ix) =
                                        ((yy + ky).wrapping_sub(s.padding), (xx + kx).wrapping_sub(s.padding));
                                    if iy >= s.height || ix >= s.width {
                                        continue;
                                    }
                                    let xi = ((b * s.channels_in + c) * s.height + iy) * s.width + ix;
                                    visit(out, xi, ((o * s.channels_in + c) * 3 + ky) * 3 + kx);
                                }
                            }
                        }
                    }
                }
            }
        }
    }

    /// The definition, one product at a time, in f64.
    fn direct(x: &[f32], w: &[f32], bias: &[f32], s: &ConvShape) -> Vec<f64> {
        let plane = s.out_height() * s.out_width();
        let mut y: Vec<f64> = (0..s.batch * s.channels_out * plane)
            .map(|i| bias[(i / plane) % s.channels_out] as f64)
            .collect();
        for_each_tap(s, |out, xi, wi| y[out] += x[xi] as f64 * w[wi] as f64);
        y
    }

    fn values(n: usize, seed: f32) -> Vec<f32> {
        (0..n)
            .map(|i| ((i as f32 * 0.7548 + seed).sin() * 1.3).fract())
            .collect()
    }

    fn shapes() -> Vec<ConvShape> {
        let shape = ConvShape::new;
        // odd sizes, a tile boundary inside the image (width 40: 12 rows per tile), both paddings
        vec![
            shape(2, 3, 5, 7, 9, 1),
            shape(1, 2, 4, 30, 40, 1),
            shape(3, 4, 3, 11, 6, 0),
            shape(1, 1, 2, 3, 3, 1),
        ]
    }

    #[test]
    fn forward_is_the_definition() {
        for s in shapes() {
            let x = values(s.batch * s.channels_in * s.height * s.width, 0.1);
            let w = values(s.channels_out * s.channels_in * 9, 0.5);
            let bias = values(s.channels_out, 0.9);
            let want = direct(&x, &w, &bias, &s);
            let got = forward(&x, &w, Some(&bias), &s);
            assert_eq!(got.len(), want.len());
            for (g, w) in got.iter().zip(&want) {
                assert!((*g as f64 - w).abs() < 1e-4, "{s:?}: {g} vs {w}");
            }
        }
    }

    /// The gradients against the definition: for the scalar L = sum(dy * y), dL/dx, dL/dw and
    /// dL/db are sums of products of dy with the inputs, computed here term by term in f64.
    #[test]
    fn backward_is_the_gradient_of_the_definition() {
        for s in shapes() {
            let (ho, wo) = (s.out_height(), s.out_width());
            let x = values(s.batch * s.channels_in * s.height * s.width, 0.2);
            let w = values(s.channels_out * s.channels_in * 9, 0.4);
            let dy = values(s.batch * s.channels_out * ho * wo, 0.8);
            let (dx, dw, db) = backward(&x, &w, &dy, &s);
            let mut want_dx = vec![0.0f64; x.len()];
            let mut want_dw = vec![0.0f64; w.len()];
            for_each_tap(&s, |out, xi, wi| {
                want_dx[xi] += dy[out] as f64 * w[wi] as f64;
                want_dw[wi] += dy[out] as f64 * x[xi] as f64;
            });
            let plane = ho * wo;
            let mut want_db = vec![0.0f64; s.channels_out];
            for (i, g) in dy.iter().enumerate() {
                want_db[(i / plane) % s.channels_out] += *g as f64;
            }
            for (got, want) in [(&dx, &want_dx), (&dw, &want_dw), (&db, &want_db)] {
                assert_eq!(got.len(), want.len());
                for (g, w) in got.iter().zip(want.iter()) {
                    assert!((*g as f64 - w).abs() < 1e-3 * (1.0 + w.abs()), "{s:?}: {g} vs {w}");
                }
            }
        }
    }

    #[test]
    fn results_do_not_depend_on_the_threads() {
        let s = ConvShape::new(3, 5, 7, 33, 20, 1);
        let x = values(s.batch * s.channels_in * s.height * s.width, 0.3);
        let w = values(s.channels_out * s.channels_in * 9, 0.6);
        let dy = values(s.batch * s.channels_out * s.out_height() * s.out_width(), 0.7);
        let run = |threads| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| (forward(&x, &w, None, &s), backward(&x, &w, &dy, &s)))
        };
        assert!(run(1) == run(3), "one thread and three give other bits");
    }
}

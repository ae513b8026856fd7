//! The U-Net's upsampling (Table 4.2: bilinear, scale 2, aligned corners, as PyTorch's
//! `nn.Upsample(scale_factor=2, mode="bilinear", align_corners=True)`) on every backend.
//!
//! Why not burn's `interpolate` everywhere: its backward pass for bilinear modes exists on the
//! CPU backend only; on wgpu and CUDA (cubecl) it fails with "Bilinear interpolation backward is
//! not supported by JIT backend", so the U-Net could not train on a GPU
//! (`tests/gpu_parity.rs` found it). Off the CPU the same interpolation is built here from
//! `select` and element-wise products, one axis at a time, whose gradients every backend has.
//! On the CPU burn's `interpolate` stays, so CPU results are unchanged bit for bit.

use crate::kernels::conv::on_flex;
use burn::tensor::module::interpolate;
use burn::tensor::ops::{InterpolateMode, InterpolateOptions};
use burn::tensor::{Int, Tensor, TensorData};

/// Doubles a [batch, channels, h, w] feature map's height and width by bilinear interpolation
/// with aligned corners: output pixel o of an axis of n samples sits at o (n - 1) / (2n - 1) in
/// the input's pixel coordinates, so the first and last outputs equal the first and last inputs.
pub fn upsample2x(x: Tensor<4>) -> Tensor<4> {
    let [_, _, h, w] = x.dims();
    if on_flex(&x) {
        interpolate(
            x,
            InterpolateOptions::new(InterpolateMode::Bilinear)
                .with_align_corners(true)
                .with_output_size([2 * h, 2 * w]),
        )
    } else {
        let x = linear_along(x, 2, h);
        linear_along(x, 3, w)
    }
}

/// For each of the 2n outputs of an axis of n inputs: the input below, the one above and the
/// weight of the one above.
fn stencil(n: usize) -> (Vec<i64>, Vec<i64>, Vec<f32>) {
    let scale = if n > 1 {
        (n - 1) as f64 / (2 * n - 1) as f64
    } else {
        0.0
    };
    let mut below = Vec::with_capacity(2 * n);
    let mut above = Vec::with_capacity(2 * n);
    let mut weight = Vec::with_capacity(2 * n);
    for o in 0..2 * n {
        let at = o as f64 * scale;
        let i = (at.floor() as usize).min(n - 1);
        below.push(i as i64);
        above.push((i + 1).min(n - 1) as i64);
        weight.push((at - i as f64) as f32);
    }
    (below, above, weight)
}

/// Linear interpolation of `x` along `axis` (of length n) to 2n samples.
fn linear_along(x: Tensor<4>, axis: usize, n: usize) -> Tensor<4> {
    let device = x.device();
    let (below, above, weight) = stencil(n);
    let index = |v: Vec<i64>| Tensor::<1, Int>::from_data(TensorData::new(v, [2 * n]), &device);
    let mut shape = [1; 4];
    shape[axis] = 2 * n;
    let weight = Tensor::<1>::from_data(TensorData::new(weight, [2 * n]), &device).reshape(shape);
    let low = x.clone().select(axis, index(below));
    let high = x.select(axis, index(above));
    low.clone() + (high - low) * weight
}

#[cfg(test)]
mod tests {
    use super::*;
    use burn::tensor::{Device, Distribution};

    /// The aligned-corners stencil from its definition: ends map to ends, and a 2-sample axis
    /// gives 0, 1/3, 2/3, 1.
    #[test]
    fn the_stencil_aligns_the_corners() {
        let (below, above, weight) = stencil(2);
        let at: Vec<f32> = below.iter().zip(&weight).map(|(&i, &w)| i as f32 + w).collect();
        for (a, e) in at.iter().zip([0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0]) {
            assert!((a - e).abs() < 1e-6, "{at:?}");
        }
        assert_eq!(above, vec![1, 1, 1, 1]);
        let (below, _, weight) = stencil(5);
        assert_eq!((below[0], weight[0]), (0, 0.0));
        assert_eq!(*below.last().unwrap() as f32 + weight.last().unwrap(), 4.0);
    }

    /// The portable form (what wgpu and CUDA run) equals burn's CPU `interpolate` in values
    /// and in the input's gradient.
    #[test]
    fn the_portable_form_matches_burns_interpolate_and_its_gradient() {
        let device = Device::flex().autodiff();
        for dims in [[2, 3, 5, 7], [1, 2, 1, 4], [1, 1, 8, 8]] {
            let [_, _, h, w] = dims;
            let x = Tensor::<4>::random(dims, Distribution::Normal(0.0, 1.0), &device).require_grad();
            let ours = linear_along(linear_along(x.clone(), 2, h), 3, w);
            let theirs = upsample2x(x.clone());
            assert_eq!(ours.dims(), [dims[0], dims[1], 2 * h, 2 * w]);
            let weights = Tensor::<4>::random(ours.dims(), Distribution::Normal(0.0, 1.0), &device);
            let g_ours = (ours.clone() * weights.clone()).sum().backward();
            let g_theirs = (theirs.clone() * weights).sum().backward();
            let data = |t: Tensor<4>| t.into_data().try_to_vec::<f32>().unwrap();
            for (what, a, b) in [
                ("values", data(ours), data(theirs)),
                (
                    "gradient",
                    data(x.grad(&g_ours).unwrap()),
                    data(x.grad(&g_theirs).unwrap()),
                ),
            ] {
                for (p, q) in a.iter().zip(&b) {
                    assert!((p - q).abs() <= 1e-5 * (1.0 + q.abs()), "{dims:?} {what}: {p} vs {q}");
                }
            }
        }
    }
}

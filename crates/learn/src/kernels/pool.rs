//! The networks' 2 x 2 max pooling (stride 2, no padding, floor mode) on the CPU backend with its
//! own backward pass; burn's `max_pool2d` on every other backend. Same values and gradients
//! (tests below against burn's).
//!
//! Why: `perf` of `wakelab detect` over an 8192 x 8192 scene put half of its time in burn-flex's
//! general 3-D max pooling (window bounds worked out with divisions for every output value).
//! Here each output row reads two input rows.

use crate::kernels::conv::{contiguous, flex, on_flex, values};
use burn::backend::autodiff::checkpoint::base::Checkpointer;
use burn::backend::autodiff::checkpoint::strategy::CheckpointStrategy;
use burn::backend::autodiff::grads::Gradients;
use burn::backend::autodiff::ops::{Backward, Ops, OpsKind};
use burn::backend::flex::FlexTensor;
use burn::backend::tensor::FloatTensor;
use burn::backend::{backend_extension, Autodiff, Backend, Dispatch, Flex};
use burn::tensor::module::max_pool2d;
use burn::tensor::ops::MaxPoolOptions;
use burn::tensor::Tensor;
use rayon::prelude::*;
use std::sync::Arc;

#[backend_extension(Flex, Autodiff)]
pub trait MaxPoolBackend: Backend {
    /// 2 x 2 max pooling, stride 2: [n, c, h, w] -> [n, c, h / 2, w / 2].
    fn max_pool2x2(x: FloatTensor<Self>) -> FloatTensor<Self>;
}

/// Max over each 2 x 2 block of every plane, and where in the input plane it was (the first of
/// equal values in row order; a NaN wins, as in burn and PyTorch).
fn pool_planes(x: &[f32], [n, c, h, w]: [usize; 4]) -> (Vec<f32>, Vec<u32>) {
    let (ho, wo) = (h / 2, w / 2);
    let mut values = vec![0.0f32; n * c * ho * wo];
    let mut at = vec![0u32; n * c * ho * wo];
    values
        .par_chunks_mut((ho * wo).max(1))
        .zip(at.par_chunks_mut((ho * wo).max(1)))
        .enumerate()
        .for_each(|(plane, (out, index))| {
            let src = &x[plane * h * w..][..h * w];
            for oy in 0..ho {
                for ox in 0..wo {
                    let mut best = (2 * oy * w + 2 * ox) as u32;
                    for (dy, dx) in [(0, 1), (1, 0), (1, 1)] {
                        let i = ((2 * oy + dy) * w + 2 * ox + dx) as u32;
                        let (v, m) = (src[i as usize], src[best as usize]);
                        if v > m || v.is_nan() {
                            best = i;
                        }
                    }
                    out[oy * wo + ox] = src[best as usize];
                    index[oy * wo + ox] = best;
                }
            }
        });
    (values, at)
}

fn input(x: &FlexTensor) -> (FlexTensor, [usize; 4]) {
    let x = contiguous(x);
    let dims = x.layout().shape().dims::<4>();
    (x, dims)
}

fn pooled_shape([n, c, h, w]: [usize; 4]) -> [usize; 4] {
    [n, c, h / 2, w / 2]
}

impl MaxPoolBackend for Flex {
    fn max_pool2x2(x: FlexTensor) -> FlexTensor {
        let (x, dims) = input(&x);
        let (pooled, _) = pool_planes(values(&x), dims);
        flex(pooled, &pooled_shape(dims))
    }
}

#[derive(Debug)]
struct MaxPoolBackward;

impl Backward<Flex, 1> for MaxPoolBackward {
    /// Where each output came from in its input plane, and the input's shape.
    type State = (Arc<Vec<u32>>, [usize; 4]);

    fn backward(self, ops: Ops<Self::State, 1>, grads: &mut Gradients, _: &mut Checkpointer) {
        let [node] = ops.parents;
        let dy = contiguous(&grads.consume::<Flex>(&ops.node));
        let (at, [n, c, h, w]) = ops.state;
        let Some(node) = node else { return };
        let dy = values(&dy);
        let (ho, wo) = (h / 2, w / 2);
        let mut dx = vec![0.0f32; n * c * h * w];
        // every input is in at most one window: each gradient lands on its own element
        dx.par_chunks_mut(h * w).enumerate().for_each(|(plane, dst)| {
            let range = plane * ho * wo..(plane + 1) * ho * wo;
            for (g, &i) in dy[range.clone()].iter().zip(&at[range]) {
                dst[i as usize] = *g;
            }
        });
        grads.register::<Flex>(node.id, flex(dx, &[n, c, h, w]));
    }
}

impl<C: CheckpointStrategy> MaxPoolBackend for Autodiff<Flex, C> {
    fn max_pool2x2(x: FloatTensor<Self>) -> FloatTensor<Self> {
        let (primitive, dims) = input(x.primitive());
        let (pooled, at) = pool_planes(values(&primitive), dims);
        let y = flex(pooled, &pooled_shape(dims));
        match MaxPoolBackward.prepare::<C>([x.node()]).compute_bound().stateful() {
            OpsKind::Tracked(prep) => prep.finish((Arc::new(at), dims), y),
            OpsKind::UnTracked(prep) => prep.finish(y),
        }
    }
}

/// 2 x 2 max pooling with stride 2 (`MaxPool2d` of kernel [2, 2], Tables 4.1-4.3): the kernel above
/// on the CPU backend (with or without autodiff), burn's `max_pool2d` elsewhere.
pub fn max_pool2x2(x: Tensor<4>) -> Tensor<4> {
    if on_flex(&x) {
        Tensor::from_dispatch(<Dispatch as MaxPoolBackend>::max_pool2x2(x.into_dispatch()))
    } else {
        max_pool2d(x, MaxPoolOptions::new([2, 2]).with_stride([2, 2]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use burn::tensor::{Device, Distribution};

    /// Values and gradients equal burn's max_pool2d's, odd sizes (the last row and column
    /// dropped) and ties (a coarse grid of values) included.
    #[test]
    fn matches_burns_max_pool_and_its_gradient() {
        let device = Device::flex().autodiff();
        for dims in [[2, 3, 8, 10], [1, 2, 7, 5]] {
            let x = Tensor::<4>::random(dims, Distribution::Normal(0.0, 1.0), &device);
            let x = (x * 2.0).round().require_grad(); // ties
            let ours = max_pool2x2(x.clone());
            let theirs = max_pool2d(x.clone(), MaxPoolOptions::new([2, 2]).with_stride([2, 2]));
            assert_eq!(ours.dims(), theirs.dims());
            let weights = Tensor::<4>::random(ours.dims(), Distribution::Normal(0.0, 1.0), &device);
            let g_ours = (ours.clone() * weights.clone()).sum().backward();
            let g_theirs = (theirs.clone() * weights).sum().backward();
            let data = |t: Tensor<4>| t.into_data().try_to_vec::<f32>().unwrap();
            assert_eq!(data(ours), data(theirs), "{dims:?} values");
            assert_eq!(
                data(x.grad(&g_ours).unwrap()),
                data(x.grad(&g_theirs).unwrap()),
                "{dims:?} gradient"
            );
        }
    }
}

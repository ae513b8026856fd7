//! The networks' 3 x 3 convolutions on the CPU backend through [`crate::kernels::gemm_conv`], with their
//! own backward pass; burn's `conv2d` on every other backend. Same parameters, same result up to
//! float rounding (tests below against burn's conv2d and its gradients).
//!
//! Why: `perf` of a U-Net training step (128 x 128, batch 4, 2 threads) on burn-flex's conv put
//! 23 % of the time in one GEMM micro-kernel running at 9 of its 16 lanes: burn computes the
//! weight gradient as a convolution with batch and channels swapped, whose GEMM has 9 outputs
//! per row. `bench/learning_vs_pytorch.sh` measures the training step beside PyTorch's.

use crate::kernels::gemm_conv::{self, ConvShape};
use burn::backend::autodiff::checkpoint::base::Checkpointer;
use burn::backend::autodiff::checkpoint::strategy::CheckpointStrategy;
use burn::backend::autodiff::grads::Gradients;
use burn::backend::autodiff::ops::{Backward, Ops, OpsKind};
use burn::backend::flex::{FlexTensor, Layout};
use burn::backend::tensor::FloatTensor;
use burn::backend::{backend_extension, Autodiff, Backend, Dispatch, DispatchDevice, Flex};
use burn::nn::conv::Conv2d;
use burn::tensor::module::conv2d;
use burn::tensor::ops::ConvOptions;
use burn::tensor::{Bytes, DType, Shape, Tensor};

#[backend_extension(Flex, Autodiff)]
pub trait Conv3x3Backend: Backend {
    /// 3 x 3 convolution, stride 1, zero padding `padding` on every side, with bias.
    fn conv3x3(
        x: FloatTensor<Self>,
        weight: FloatTensor<Self>,
        bias: FloatTensor<Self>,
        padding: usize,
    ) -> FloatTensor<Self>;
}

/// A contiguous copy (or the tensor itself) of an f32 CPU tensor; the kernels here are f32 only.
pub(crate) fn contiguous(t: &FlexTensor) -> FlexTensor {
    assert_eq!(t.dtype(), DType::F32, "wakelab's CPU kernels run in f32");
    t.to_contiguous()
}

pub(crate) fn values(t: &FlexTensor) -> &[f32] {
    t.as_slice::<f32>().expect("a contiguous f32 tensor")
}

/// A contiguous f32 CPU tensor of `shape` holding `values`.
pub(crate) fn flex(values: Vec<f32>, shape: &[usize]) -> FlexTensor {
    FlexTensor::new(
        Bytes::from_elems(values),
        Layout::contiguous(Shape::from(shape.to_vec())),
        DType::F32,
    )
}

fn conv_shape(x: &FlexTensor, weight: &FlexTensor, padding: usize) -> ConvShape {
    let [batch, channels_in, height, width] = x.layout().shape().dims::<4>();
    let [channels_out, weight_in, kh, kw] = weight.layout().shape().dims::<4>();
    assert_eq!(
        (weight_in, kh, kw),
        (channels_in, 3, 3),
        "a 3 x 3 kernel over the input's channels"
    );
    ConvShape::new(batch, channels_in, channels_out, height, width, padding)
}

fn forward_flex(x: &FlexTensor, weight: &FlexTensor, bias: &FlexTensor, padding: usize) -> FlexTensor {
    let (x, weight, bias) = (contiguous(x), contiguous(weight), contiguous(bias));
    let s = conv_shape(&x, &weight, padding);
    let y = gemm_conv::forward(values(&x), values(&weight), Some(values(&bias)), &s);
    flex(y, &[s.batch, s.channels_out, s.out_height(), s.out_width()])
}

impl Conv3x3Backend for Flex {
    fn conv3x3(x: FlexTensor, weight: FlexTensor, bias: FlexTensor, padding: usize) -> FlexTensor {
        forward_flex(&x, &weight, &bias, padding)
    }
}

#[derive(Debug)]
struct Conv3x3Backward;

impl Backward<Flex, 3> for Conv3x3Backward {
    /// The input, the weights and the padding.
    type State = (FlexTensor, FlexTensor, usize);

    fn backward(self, ops: Ops<Self::State, 3>, grads: &mut Gradients, _: &mut Checkpointer) {
        let [node_x, node_weight, node_bias] = ops.parents;
        let dy = contiguous(&grads.consume::<Flex>(&ops.node));
        let (x, weight, padding) = ops.state;
        let (x, weight) = (contiguous(&x), contiguous(&weight));
        let s = conv_shape(&x, &weight, padding);
        if let Some(node) = node_x {
            let dx = gemm_conv::input_gradient(values(&weight), values(&dy), &s);
            grads.register::<Flex>(node.id, flex(dx, &[s.batch, s.channels_in, s.height, s.width]));
        }
        if let Some(node) = node_weight {
            let dw = gemm_conv::weight_gradient(values(&x), values(&dy), &s);
            grads.register::<Flex>(node.id, flex(dw, &[s.channels_out, s.channels_in, 3, 3]));
        }
        if let Some(node) = node_bias {
            let db = gemm_conv::bias_gradient(values(&dy), &s);
            grads.register::<Flex>(node.id, flex(db, &[s.channels_out]));
        }
    }
}

impl<C: CheckpointStrategy> Conv3x3Backend for Autodiff<Flex, C> {
    fn conv3x3(
        x: FloatTensor<Self>,
        weight: FloatTensor<Self>,
        bias: FloatTensor<Self>,
        padding: usize,
    ) -> FloatTensor<Self> {
        match Conv3x3Backward
            .prepare::<C>([x.node(), weight.node(), bias.node()])
            .compute_bound()
            .stateful()
        {
            OpsKind::Tracked(prep) => {
                let (x, weight) = (x.primitive().clone(), weight.primitive().clone());
                let y = forward_flex(&x, &weight, bias.primitive(), padding);
                prep.finish((x, weight, padding), y)
            }
            OpsKind::UnTracked(prep) => prep.finish(forward_flex(
                x.primitive(),
                weight.primitive(),
                bias.primitive(),
                padding,
            )),
        }
    }
}

/// `conv`'s forward pass for a 3 x 3, stride-1, undilated, ungrouped convolution with bias and
/// symmetric padding `padding`: [`crate::kernels::gemm_conv`] on the CPU backend (with or without
/// autodiff), burn's `conv2d` elsewhere.
pub fn conv3x3(conv: &Conv2d, x: Tensor<4>, padding: usize) -> Tensor<4> {
    let weight = conv.weight.val();
    let bias = conv
        .bias
        .as_ref()
        .expect("the networks' convolutions have a bias")
        .val();
    if on_flex(&x) {
        Tensor::from_dispatch(<Dispatch as Conv3x3Backend>::conv3x3(
            x.into_dispatch(),
            weight.into_dispatch(),
            bias.into_dispatch(),
            padding,
        ))
    } else {
        conv2d(
            x,
            weight,
            Some(bias),
            ConvOptions::new([1, 1], [padding, padding], [1, 1], 1),
        )
    }
}

pub(crate) fn on_flex(x: &Tensor<4>) -> bool {
    matches!(x.device().inner().as_dispatch(), DispatchDevice::Flex(_))
}

#[cfg(test)]
mod tests {
    use super::*;
    use burn::module::Param;
    use burn::nn::conv::Conv2dConfig;
    use burn::nn::PaddingConfig2d;
    use burn::tensor::{Device, Distribution};

    fn close(a: Tensor<4>, b: Tensor<4>, what: &str) {
        let (a, b) = (
            a.into_data().try_to_vec::<f32>().unwrap(),
            b.into_data().try_to_vec::<f32>().unwrap(),
        );
        assert_eq!(a.len(), b.len(), "{what}");
        let scale = b.iter().fold(0.0f32, |m, v| m.max(v.abs())).max(1.0);
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() <= 1e-4 * scale, "{what}: {x} vs {y}");
        }
    }

    /// Output and all three gradients equal burn's conv2d's (on the same device, autodiff), for
    /// both paddings the networks use.
    #[test]
    fn matches_burns_conv2d_and_its_gradients() {
        let device = Device::flex().autodiff();
        for padding in [0usize, 1] {
            let conv = Conv2dConfig::new([3, 5], [3, 3])
                .with_padding(PaddingConfig2d::Explicit(padding, padding, padding, padding))
                .init(&device);
            let x = Tensor::<4>::random([2, 3, 13, 17], Distribution::Normal(0.0, 1.0), &device).require_grad();
            let ours = conv3x3(&conv, x.clone(), padding);
            let theirs = conv.forward(x.clone());
            close(ours.clone(), theirs.clone(), "output");
            // a loss whose gradient differs per element
            let target = Tensor::<4>::random(ours.dims(), Distribution::Normal(0.0, 1.0), &device);
            let g_ours = (ours * target.clone()).sum().backward();
            let g_theirs = (theirs * target).sum().backward();
            close(x.grad(&g_ours).unwrap(), x.grad(&g_theirs).unwrap(), "input gradient");
            let weight: &Param<Tensor<4>> = &conv.weight;
            close(
                weight.grad(&g_ours).unwrap(),
                weight.grad(&g_theirs).unwrap(),
                "weight gradient",
            );
            let bias = conv.bias.as_ref().unwrap();
            close(
                bias.grad(&g_ours).unwrap().reshape([1, 1, 1, 5]),
                bias.grad(&g_theirs).unwrap().reshape([1, 1, 1, 5]),
                "bias gradient",
            );
        }
    }
}

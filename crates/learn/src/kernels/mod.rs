//! The CPU backend's hand-tuned kernels behind the networks' 3 x 3 convolutions and 2 x 2 max
//! pooling: [`gemm_conv`] is the packed-GEMM convolution itself, [`conv`] and [`pool`] put it and
//! the pooling into burn's graph (forward and backward), falling back to burn's own operators on
//! other backends.

pub mod conv;
pub mod gemm_conv;
pub mod pool;

//! The Nature CNN of the authors' `agent_dqn.py` as a burn module: channel-first 84x84x3 in
//! [0, 1], conv 32 8x8/4, conv 64 4x4/2, conv 64 3x3/1 (ReLU each), dense 512 (ReLU), 9 Q values.
//! Initialised as PyTorch initialises these layers (every weight and bias uniform in
//! +-1/sqrt(fan_in)), but from the run's own ChaCha stream, so a run is a function of its seed.

use burn::module::Param;
use burn::nn::conv::{Conv2d, Conv2dConfig};
use burn::nn::{Linear, LinearConfig};
use burn::prelude::*;
use burn::tensor::activation::relu;
use burn::tensor::TensorData;
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use sec_playground::memory::ACTIONS;

/// Pixels of a frame per channel.
pub const PIXELS: usize = 84 * 84;
/// The last feature map, flattened: 64 channels of 7x7.
const FLAT: usize = 64 * 7 * 7;
const HIDDEN: usize = 512;

/// The Nature DQN network (Mnih et al. 2015): three convolutions and two dense layers, from an
/// 84x84 frame to one Q value per action.
#[derive(Module, Debug)]
pub struct NatureCnn {
    conv1: Conv2d,
    conv2: Conv2d,
    conv3: Conv2d,
    fc: Linear,
    out: Linear,
}

fn tensor<const D: usize>(data: Vec<f32>, shape: [usize; D], device: &Device) -> Tensor<D> {
    Tensor::from_data(TensorData::new(data, shape), device)
}

/// `n` values uniform in +-1/sqrt(fan_in).
fn uniform(n: usize, fan_in: usize, rng: &mut ChaCha8Rng) -> Vec<f32> {
    let bound = 1.0 / (fan_in as f64).sqrt();
    (0..n).map(|_| rng.gen_range(-bound..bound) as f32).collect()
}

fn conv(ci: usize, co: usize, k: usize, stride: usize, rng: &mut ChaCha8Rng, device: &Device) -> Conv2d {
    let mut c = Conv2dConfig::new([ci, co], [k, k]).with_stride([stride, stride]).init(device);
    let fan_in = ci * k * k;
    c.weight = Param::from_tensor(tensor(uniform(co * fan_in, fan_in, rng), [co, ci, k, k], device));
    c.bias = Some(Param::from_tensor(tensor(uniform(co, fan_in, rng), [co], device)));
    c
}

fn linear(fan_in: usize, fan_out: usize, rng: &mut ChaCha8Rng, device: &Device) -> Linear {
    let mut l = LinearConfig::new(fan_in, fan_out).init(device);
    l.weight = Param::from_tensor(tensor(uniform(fan_in * fan_out, fan_in, rng), [fan_in, fan_out], device));
    l.bias = Some(Param::from_tensor(tensor(uniform(fan_out, fan_in, rng), [fan_out], device)));
    l
}

impl NatureCnn {
    /// A network with PyTorch's default initialisation, drawn from `rng`.
    pub fn new(rng: &mut ChaCha8Rng, device: &Device) -> Self {
        NatureCnn {
            conv1: conv(3, 32, 8, 4, rng, device),
            conv2: conv(32, 64, 4, 2, rng, device),
            conv3: conv(64, 64, 3, 1, rng, device),
            fc: linear(FLAT, HIDDEN, rng, device),
            out: linear(HIDDEN, ACTIONS, rng, device),
        }
    }

    /// Q values [batch, 9] of frames [batch, 3, 84, 84].
    pub fn forward(&self, x: Tensor<4>) -> Tensor<2> {
        let x = relu(self.conv1.forward(x));
        let x = relu(self.conv2.forward(x));
        let x = relu(self.conv3.forward(x));
        let [b, c, h, w] = x.dims();
        self.out.forward(relu(self.fc.forward(x.reshape([b, c * h * w]))))
    }

    /// Trainable numbers in the network.
    pub fn parameters(&self) -> usize {
        self.num_params()
    }
}

/// Frames as a channel-first batch: from channel-last RGB bytes (the replay keeps bytes; the
/// camera's floats are bytes / 255, so nothing is lost).
pub fn batch(frames: &[&[u8]], device: &Device) -> Tensor<4> {
    let mut data = vec![0.0f32; frames.len() * 3 * PIXELS];
    for (b, f) in frames.iter().enumerate() {
        for p in 0..PIXELS {
            for c in 0..3 {
                data[(b * 3 + c) * PIXELS + p] = f[p * 3 + c] as f32 / 255.0;
            }
        }
    }
    tensor(data, [frames.len(), 3, 84, 84], device)
}

/// The values of a tensor.
pub fn values<const D: usize>(t: Tensor<D>) -> Vec<f32> {
    t.into_data().convert::<f32>().try_into_vec::<f32>().expect("f32 tensor")
}

//! The paper's autoencoder, layer for layer (docs/ALGORITHM.md, "Perception"): 196,663 parameters,
//! a Dense(20, ReLU) bottleneck, and a decoder with one `valid` convolution.
//!
//! Tensors use Keras layouts: convolutions HWIO `[3][3][in][out]`, dense `[in][out]`, and the
//! flatten before the bottleneck is channel-last `(y, x, c)` order. A trainer with other layouts
//! transposes when it writes the weights file.

use super::kernels::{
    conv3x3_relu, conv3x3_relu_maxpool2, conv3x3_relu_sparse_maxpool2, conv3x3_up2_relu, conv3x3_up2_relu_planar,
    dense, dense_fixed, pad1, pad1_planar, Repeats, Sparse, Up2,
};
use super::weights::{Tensor, Weights};
use crate::error::FileError;
use crate::render::{HEIGHT, WIDTH};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Embedding size (`prototype_length`).
pub const EMBEDDING: usize = 20;
/// Flattened bottleneck input: 11 x 11 x 32.
pub const FLAT: usize = 11 * 11 * 32;
/// Input and output values: 84 x 84 x 3 in [0, 1].
pub const IMAGE: usize = WIDTH * HEIGHT * 3;
/// Every parameter of the model.
pub const PARAMETERS: usize = 196_663;

/// Names and shapes of the tensors, in file order.
pub const TENSORS: [(&str, &[usize]); 18] = [
    ("enc.conv1.w", &[3, 3, 3, 16]),
    ("enc.conv1.b", &[16]),
    ("enc.conv2.w", &[3, 3, 16, 32]),
    ("enc.conv2.b", &[32]),
    ("enc.conv3.w", &[3, 3, 32, 32]),
    ("enc.conv3.b", &[32]),
    ("enc.dense.w", &[FLAT, EMBEDDING]),
    ("enc.dense.b", &[EMBEDDING]),
    ("dec.dense.w", &[EMBEDDING, FLAT]),
    ("dec.dense.b", &[FLAT]),
    ("dec.conv1.w", &[3, 3, 32, 32]),
    ("dec.conv1.b", &[32]),
    ("dec.conv2.w", &[3, 3, 32, 32]),
    ("dec.conv2.b", &[32]),
    ("dec.conv3.w", &[3, 3, 32, 16]),
    ("dec.conv3.b", &[16]),
    ("dec.conv4.w", &[3, 3, 16, 3]),
    ("dec.conv4.b", &[3]),
];

/// The autoencoder's parameters, in `TENSORS` order.
#[derive(Clone, Debug, PartialEq)]
pub struct Autoencoder {
    params: Vec<Vec<f32>>,
    /// The decoder's last three convolutions' weights folded for reading their input before the
    /// upsampling (`Up2`): derived from `params`, kept so that decoding does not redo it.
    up: [Up2; 3],
    /// The task it was trained on.
    pub task: String,
    /// What its embeddings are multiplied by (calibrated per task).
    pub embedding_scale: f32,
}

/// Reusable activation buffers, so encoding allocates nothing after the first call: one per
/// layer's output, so that no buffer changes size from call to call (growing one writes zeros).
#[derive(Clone, Debug, Default)]
pub struct Scratch {
    /// The encoder's layers' outputs, in order.
    enc: [Vec<f32>; 7],
    /// The decoder's, in order.
    dec: [Vec<f32>; 8],
    rec: Vec<f32>,
    sparse: Sparse,
    repeats: Repeats,
}

impl Autoencoder {
    /// Checks names and shapes against the architecture.
    pub fn from_weights(w: &Weights) -> Result<Self, FileError> {
        let params =
            TENSORS.iter().map(|(name, shape)| w.tensor(name, shape).map(<[f32]>::to_vec)).collect::<Result<_, _>>()?;
        if w.tensors.len() != TENSORS.len() {
            return Err(FileError::new("weights", format!("{} tensors, expected {}", w.tensors.len(), TENSORS.len())));
        }
        Ok(Autoencoder::with(params, w.task.clone(), w.embedding_scale))
    }

    /// Keras' initialisation of every layer: Glorot-uniform kernels, zero biases. For tests and
    /// benchmarks.
    pub fn glorot(seed: u64) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let params = TENSORS.iter().map(|(_, shape)| glorot_uniform(shape, &mut rng)).collect();
        Autoencoder::with(params, String::new(), 1.0)
    }

    /// The encoder as Keras initialises it and the authors' agent embedded with (D20): the
    /// encoder's kernels Glorot-uniform from `rng`, in file order, its biases zero. The decoder
    /// is all zeros: this model embeds, it does not reconstruct.
    pub fn untrained_encoder(rng: &mut ChaCha8Rng) -> Self {
        let params =
            TENSORS
                .iter()
                .map(|(name, shape)| {
                    if name.starts_with("enc.") {
                        glorot_uniform(shape, rng)
                    } else {
                        vec![0.0; shape.iter().product()]
                    }
                })
                .collect();
        Autoencoder::with(params, String::new(), 1.0)
    }

    fn with(params: Vec<Vec<f32>>, task: String, embedding_scale: f32) -> Self {
        // dec.conv2 is `same` (border 1 around the upsampled image), dec.conv3 `valid`, dec.conv4 `same`.
        let up =
            [Up2::fold(&params[12], 32, 32, 1), Up2::fold(&params[14], 32, 16, 0), Up2::fold(&params[16], 16, 3, 1)];
        Autoencoder { params, up, task, embedding_scale }
    }

    /// Its weights as a weights file's tensors.
    pub fn to_weights(&self) -> Weights {
        let tensors = TENSORS
            .iter()
            .zip(&self.params)
            .map(|((name, shape), data)| Tensor { name: name.to_string(), shape: shape.to_vec(), data: data.clone() })
            .collect();
        Weights { task: self.task.clone(), embedding_scale: self.embedding_scale, tensors }
    }

    /// FNV-1a of every parameter's bits and the embedding scale: two models give the same
    /// embeddings exactly when their fingerprints match, so a saved memory names the one it needs.
    pub fn fingerprint(&self) -> u64 {
        let mut bytes = Vec::with_capacity(4 * (self.parameter_count() + 1));
        for v in self.params.iter().flatten().chain([&self.embedding_scale]) {
            bytes.extend_from_slice(&v.to_bits().to_le_bytes());
        }
        crate::util::fnv1a(&bytes)
    }

    /// Trainable parameters.
    pub fn parameter_count(&self) -> usize {
        self.params.iter().map(Vec::len).sum()
    }

    fn p(&self, i: usize) -> &[f32] {
        &self.params[i]
    }

    /// The embedding of an 84x84x3 image (channel-last, values in [0, 1]), times the model's
    /// embedding scale.
    pub fn encode(&self, image: &[f32], s: &mut Scratch, out: &mut [f32; EMBEDDING]) {
        assert_eq!(image.len(), IMAGE, "the image must be 84x84x3");
        let [pad, c1, p1, c2, p2, c3, p3] = &mut s.enc;
        let (h, w) = pad1(image, HEIGHT, WIDTH, 3, pad);
        let (h, w) = conv3x3_relu_maxpool2::<3, 16>(pad, h, w, self.p(0), self.p(1), &mut s.repeats, c1, 1, p1);
        let (h, w) = conv3x3_relu_sparse_maxpool2::<16, 32>(p1, h, w, self.p(2), self.p(3), &mut s.sparse, c2, 1, p2);
        let (h, w) = conv3x3_relu_sparse_maxpool2::<32, 32>(p2, h, w, self.p(4), self.p(5), &mut s.sparse, c3, 0, p3);
        debug_assert_eq!(h * w * 32, FLAT);
        dense_fixed(p3, self.p(6), self.p(7), true, out);
        if self.embedding_scale != 1.0 {
            for v in out.iter_mut() {
                *v *= self.embedding_scale;
            }
        }
    }

    /// The reconstruction (84x84x3, channel-last) of an embedding as `encode` returns it.
    pub fn decode(&self, embedding: &[f32; EMBEDDING], s: &mut Scratch, out: &mut Vec<f32>) {
        let raw: [f32; EMBEDDING] = std::array::from_fn(|i| embedding[i] / self.embedding_scale);
        let [flat, padded0, c1, padded1, c2, padded2, c3, planes] = &mut s.dec;
        flat.resize(FLAT, 0.0);
        dense(&raw, self.p(8), self.p(9), false, flat);
        let (h, w) = pad1(flat, 11, 11, 32, padded0);
        let (h, w) = conv3x3_relu::<32, 32>(padded0, h, w, self.p(10), self.p(11), &mut s.repeats, c1);
        pad1(c1, h, w, 32, padded1);
        let (h, w) = conv3x3_up2_relu::<32, 32>(padded1, h, w, &self.up[0], self.p(13), &mut s.sparse, c2);
        pad1(c2, h, w, 32, padded2);
        let (h, w) = conv3x3_up2_relu::<32, 16>(padded2, h, w, &self.up[1], self.p(15), &mut s.sparse, c3);
        pad1_planar(c3, h, w, 16, planes);
        let (h, w) = conv3x3_up2_relu_planar::<16, 3>(planes, h, w, &self.up[2], self.p(17), out);
        debug_assert_eq!((h, w), (HEIGHT, WIDTH));
    }

    /// Mean squared reconstruction error of an image: the reconstruction gate's measure.
    pub fn reconstruction_mse(&self, image: &[f32], s: &mut Scratch) -> f32 {
        let mut e = [0.0; EMBEDDING];
        self.encode(image, s, &mut e);
        self.reconstruction_mse_of(image, &e, s)
    }

    /// `reconstruction_mse` when the image's embedding (as `encode` gave it) is already known.
    pub fn reconstruction_mse_of(&self, image: &[f32], e: &[f32; EMBEDDING], s: &mut Scratch) -> f32 {
        let mut rec = std::mem::take(&mut s.rec);
        self.decode(e, s, &mut rec);
        let sum: f32 = image.iter().zip(&rec).map(|(a, b)| (a - b) * (a - b)).sum();
        s.rec = rec;
        sum / IMAGE as f32
    }
}

/// Keras' `glorot_uniform` for a kernel of `shape` (HWIO or `[in][out]`): uniform in
/// [-limit, limit) with limit = sqrt(6 / (fan_in + fan_out)), fan = kernel area x channels. A
/// bias (rank 1) is zeros, Keras' default.
pub fn glorot_uniform(shape: &[usize], rng: &mut ChaCha8Rng) -> Vec<f32> {
    let n: usize = shape.iter().product();
    if shape.len() == 1 {
        return vec![0.0; n];
    }
    let (limit, _) = glorot_limit(shape);
    (0..n).map(|_| rng.gen_range(-limit..limit)).collect()
}

/// (limit, (fan_in, fan_out)) of Keras' Glorot initialisers for a kernel of `shape`.
pub fn glorot_limit(shape: &[usize]) -> (f32, (usize, usize)) {
    let receptive: usize = shape[..shape.len() - 2].iter().product();
    let (fan_in, fan_out) = (shape[shape.len() - 2] * receptive, shape[shape.len() - 1] * receptive);
    ((6.0 / (fan_in + fan_out) as f32).sqrt(), (fan_in, fan_out))
}

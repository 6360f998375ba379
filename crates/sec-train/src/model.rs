//! The paper's autoencoder (docs/ENCODER.md) as a burn module, channel-first as burn
//! wants it, with exact conversions to and from the project's weights (Keras layouts: conv kernels
//! HWIO, dense `[in][out]`, flatten in (y, x, c) order).

use burn::module::Param;
use burn::nn::conv::{Conv2d, Conv2dConfig};
use burn::nn::pool::{MaxPool2d, MaxPool2dConfig};
use burn::nn::{Linear, LinearConfig, PaddingConfig2d};
use burn::prelude::*;
use burn::tensor::activation::relu;
use burn::tensor::TensorData;
use sec_playground::encoder::model::FLAT;
use sec_playground::encoder::weights::Tensor as WTensor;
use sec_playground::encoder::{Autoencoder, EMBEDDING};

/// The paper's autoencoder as a burn module (trained here, then written as the project's
/// weights file for its own inference).
#[derive(Module, Debug)]
pub struct BurnAe {
    enc1: Conv2d,
    enc2: Conv2d,
    enc3: Conv2d,
    enc_dense: Linear,
    dec_dense: Linear,
    dec1: Conv2d,
    dec2: Conv2d,
    dec3: Conv2d,
    dec4: Conv2d,
    pool: MaxPool2d,
}

fn conv(ci: usize, co: usize, padding: PaddingConfig2d, device: &Device) -> Conv2d {
    Conv2dConfig::new([ci, co], [3, 3]).with_padding(padding).init(device)
}

/// Nearest-neighbour 2x upsampling, written with expand so that its gradient is exact.
fn up2(x: Tensor<4>) -> Tensor<4> {
    let [b, c, h, w] = x.dims();
    x.reshape([b, c, h, 1, w, 1]).expand([b, c, h, 2, w, 2]).reshape([b, c, 2 * h, 2 * w])
}

impl BurnAe {
    /// The architecture with the given project weights.
    pub fn from_autoencoder(ae: &Autoencoder, device: &Device) -> Self {
        let same = PaddingConfig2d::Same;
        let mut m = BurnAe {
            enc1: conv(3, 16, same.clone(), device),
            enc2: conv(16, 32, same.clone(), device),
            enc3: conv(32, 32, same.clone(), device),
            enc_dense: LinearConfig::new(FLAT, EMBEDDING).init(device),
            dec_dense: LinearConfig::new(EMBEDDING, FLAT).init(device),
            dec1: conv(32, 32, same.clone(), device),
            dec2: conv(32, 32, same.clone(), device),
            dec3: conv(32, 16, PaddingConfig2d::Valid, device),
            dec4: conv(16, 3, same, device),
            // ceil_mode pads bottom/right like TensorFlow's `same` pooling (21 -> 11).
            pool: MaxPool2dConfig::new([2, 2]).with_ceil_mode(true).init(),
        };
        let w = ae.to_weights();
        let t = |i: usize| &w.tensors[i];
        set_conv(&mut m.enc1, t(0), t(1), device);
        set_conv(&mut m.enc2, t(2), t(3), device);
        set_conv(&mut m.enc3, t(4), t(5), device);
        set_linear(&mut m.enc_dense, &permute_flatten(&t(6).data, EMBEDDING, true, Order::ToBurn), &t(7).data, device);
        let dec_b = permute_flatten(&t(9).data, FLAT, false, Order::ToBurn);
        set_linear(&mut m.dec_dense, &permute_flatten(&t(8).data, FLAT, false, Order::ToBurn), &dec_b, device);
        set_conv(&mut m.dec1, t(10), t(11), device);
        set_conv(&mut m.dec2, t(12), t(13), device);
        set_conv(&mut m.dec3, t(14), t(15), device);
        set_conv(&mut m.dec4, t(16), t(17), device);
        m
    }

    /// Back to the project's weights (task name and embedding scale from `like`).
    pub fn to_autoencoder(&self, like: &Autoencoder) -> Autoencoder {
        let mut w = like.to_weights();
        let mut put = |i: usize, data: Vec<f32>| w.tensors[i].data = data;
        put(0, conv_to_hwio(&self.enc1.weight.val()));
        put(1, vec_of(self.enc1.bias.as_ref().unwrap().val()));
        put(2, conv_to_hwio(&self.enc2.weight.val()));
        put(3, vec_of(self.enc2.bias.as_ref().unwrap().val()));
        put(4, conv_to_hwio(&self.enc3.weight.val()));
        put(5, vec_of(self.enc3.bias.as_ref().unwrap().val()));
        put(6, permute_flatten(&vec_of(self.enc_dense.weight.val()), EMBEDDING, true, Order::ToProject));
        put(7, vec_of(self.enc_dense.bias.as_ref().unwrap().val()));
        put(8, permute_flatten(&vec_of(self.dec_dense.weight.val()), FLAT, false, Order::ToProject));
        put(9, permute_flatten(&vec_of(self.dec_dense.bias.as_ref().unwrap().val()), FLAT, false, Order::ToProject));
        put(10, conv_to_hwio(&self.dec1.weight.val()));
        put(11, vec_of(self.dec1.bias.as_ref().unwrap().val()));
        put(12, conv_to_hwio(&self.dec2.weight.val()));
        put(13, vec_of(self.dec2.bias.as_ref().unwrap().val()));
        put(14, conv_to_hwio(&self.dec3.weight.val()));
        put(15, vec_of(self.dec3.bias.as_ref().unwrap().val()));
        put(16, conv_to_hwio(&self.dec4.weight.val()));
        put(17, vec_of(self.dec4.bias.as_ref().unwrap().val()));
        Autoencoder::from_weights(&w).expect("shapes follow TENSORS")
    }

    /// Embeddings [batch, 20] of images [batch, 3, 84, 84] (raw, before any embedding scale).
    pub fn encode(&self, x: Tensor<4>) -> Tensor<2> {
        let x = self.pool.forward(relu(self.enc1.forward(x)));
        let x = self.pool.forward(relu(self.enc2.forward(x)));
        let x = self.pool.forward(relu(self.enc3.forward(x)));
        // Dense rows follow burn's (c, y, x) flatten; the conversions permute them to Keras' order.
        let [b, c, h, w] = x.dims();
        relu(self.enc_dense.forward(x.reshape([b, c * h * w])))
    }

    /// Reconstructions [batch, 3, 84, 84] of embeddings [batch, 20].
    pub fn decode(&self, e: Tensor<2>) -> Tensor<4> {
        let [b, _] = e.dims();
        let x = self.dec_dense.forward(e).reshape([b, 32, 11, 11]);
        let x = up2(relu(self.dec1.forward(x)));
        let x = up2(relu(self.dec2.forward(x)));
        let x = up2(relu(self.dec3.forward(x)));
        relu(self.dec4.forward(x))
    }

    /// The reconstruction of a batch of frames (N, 3, 84, 84).
    pub fn forward(&self, x: Tensor<4>) -> Tensor<4> {
        self.decode(self.encode(x))
    }
}

/// A tensor's values as f32, in row-major order.
pub fn vec_of<const D: usize>(t: Tensor<D>) -> Vec<f32> {
    t.into_data().convert::<f32>().try_into_vec::<f32>().expect("f32 tensor")
}

fn tensor<const D: usize>(data: Vec<f32>, shape: [usize; D], device: &Device) -> Tensor<D> {
    Tensor::from_data(TensorData::new(data, shape), device)
}

/// HWIO (Keras) -> [out, in, kh, kw] (burn).
fn set_conv(c: &mut Conv2d, w: &WTensor, b: &WTensor, device: &Device) {
    let (kh, kw, ci, co) = (w.shape[0], w.shape[1], w.shape[2], w.shape[3]);
    let mut oihw = vec![0.0; w.data.len()];
    for y in 0..kh {
        for x in 0..kw {
            for i in 0..ci {
                for o in 0..co {
                    oihw[((o * ci + i) * kh + y) * kw + x] = w.data[((y * kw + x) * ci + i) * co + o];
                }
            }
        }
    }
    c.weight = Param::from_tensor(tensor(oihw, [co, ci, kh, kw], device));
    c.bias = Some(Param::from_tensor(tensor(b.data.clone(), [co], device)));
}

fn conv_to_hwio(t: &Tensor<4>) -> Vec<f32> {
    let [co, ci, kh, kw] = t.dims();
    let d = vec_of(t.clone());
    let mut hwio = vec![0.0; d.len()];
    for o in 0..co {
        for i in 0..ci {
            for y in 0..kh {
                for x in 0..kw {
                    hwio[((y * kw + x) * ci + i) * co + o] = d[((o * ci + i) * kh + y) * kw + x];
                }
            }
        }
    }
    hwio
}

fn set_linear(l: &mut Linear, w: &[f32], b: &[f32], device: &Device) {
    let (fan_in, fan_out) = (w.len() / b.len(), b.len());
    l.weight = Param::from_tensor(tensor(w.to_vec(), [fan_in, fan_out], device));
    l.bias = Some(Param::from_tensor(tensor(b.to_vec(), [fan_out], device)));
}

/// Index of flatten position (y, x, c) in burn's (c, y, x) order, for the 11x11x32 feature map.
fn cyx_index(yxc: usize) -> usize {
    let (y, x, c) = (yxc / (11 * 32), yxc / 32 % 11, yxc % 32);
    (c * 11 + y) * 11 + x
}

/// Which way a flatten reordering goes: the project's (y, x, c) order to burn's (c, y, x), or back.
#[derive(Clone, Copy, PartialEq)]
enum Order {
    ToBurn,
    ToProject,
}

/// Reorders the flatten axis of a row-major matrix with `cols` columns: the rows when
/// `on_rows` (the encoder's dense weights), else the columns (the decoder's dense weights and
/// bias).
fn permute_flatten(data: &[f32], cols: usize, on_rows: bool, order: Order) -> Vec<f32> {
    let rows = data.len() / cols;
    let mut out = vec![0.0; data.len()];
    for r in 0..rows {
        for c in 0..cols {
            let (pr, pc) = if on_rows { (cyx_index(r), c) } else { (r, cyx_index(c)) };
            let (project, burn) = (r * cols + c, pr * cols + pc);
            match order {
                Order::ToBurn => out[burn] = data[project],
                Order::ToProject => out[project] = data[burn],
            }
        }
    }
    out
}

/// Images as a channel-first batch tensor, from channel-last RGB bytes (values / 255).
pub fn batch_from_rgb(rgb: &[u8], indices: &[usize], device: &Device) -> Tensor<4> {
    const P: usize = 84 * 84;
    let mut data = vec![0.0f32; indices.len() * 3 * P];
    for (bi, &i) in indices.iter().enumerate() {
        let src = &rgb[i * 3 * P..(i + 1) * 3 * P];
        for p in 0..P {
            for c in 0..3 {
                data[(bi * 3 + c) * P + p] = src[p * 3 + c] as f32 / 255.0;
            }
        }
    }
    tensor(data, [indices.len(), 3, 84, 84], device)
}

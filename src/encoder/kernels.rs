//! The inference kernels, channel-last (NHWC, one image). Each output channel sums its terms in
//! one fixed order (bias, then kernel row, column and input channel ascending); loops run across
//! output channels, so vectorising them never reorders a sum and every target gives the same bits.
//! No fused multiply-add: Rust never contracts `a * b + c`.

/// 3x3 convolution with ReLU. `same` pads by one with zeros (output h x w); otherwise `valid`
/// (output (h-2) x (w-2)). Weights are HWIO: `[ky][kx][ci][co]`.
///
/// On x86-64 with AVX2 the same code runs compiled for 8-wide vectors; lanes are output
/// channels, so the result is bit-identical to the SSE2 and wasm builds.
pub fn conv3x3_relu<const CI: usize, const CO: usize>(
    input: &[f32],
    h: usize,
    w: usize,
    weights: &[f32],
    bias: &[f32],
    same: bool,
    out: &mut Vec<f32>,
) -> (usize, usize) {
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU supports AVX2, checked just above.
        return unsafe { conv3x3_relu_avx2::<CI, CO>(input, h, w, weights, bias, same, out) };
    }
    conv3x3_relu_any::<CI, CO>(input, h, w, weights, bias, same, out)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn conv3x3_relu_avx2<const CI: usize, const CO: usize>(
    input: &[f32],
    h: usize,
    w: usize,
    weights: &[f32],
    bias: &[f32],
    same: bool,
    out: &mut Vec<f32>,
) -> (usize, usize) {
    conv3x3_relu_any::<CI, CO>(input, h, w, weights, bias, same, out)
}

#[inline(always)]
fn conv3x3_relu_any<const CI: usize, const CO: usize>(
    input: &[f32],
    h: usize,
    w: usize,
    weights: &[f32],
    bias: &[f32],
    same: bool,
    out: &mut Vec<f32>,
) -> (usize, usize) {
    assert_eq!(input.len(), h * w * CI);
    assert_eq!(weights.len(), 9 * CI * CO);
    assert_eq!(bias.len(), CO);
    let (oh, ow, pad) = if same { (h, w, 1isize) } else { (h - 2, w - 2, 0) };
    out.clear();
    out.resize(oh * ow * CO, 0.0);
    let bias: &[f32; CO] = bias.try_into().unwrap();
    for oy in 0..oh {
        let mut ox = 0;
        // Interior runs of BLOCK pixels, whose 3x3 windows are all inside the image columns,
        // share each weight row: a quarter of the weight loads. Same order of sums as below.
        while ox < ow {
            let x0 = ox as isize - pad;
            if x0 >= 0 && x0 as usize + BLOCK + 2 <= w && ox + BLOCK <= ow {
                let o = &mut out[(oy * ow + ox) * CO..][..BLOCK * CO];
                #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
                if CO % (4 * simd::NV) == 0 {
                    simd::conv_block::<CI, CO>(input, h, w, weights, bias, oy as isize - pad, x0 as usize, o);
                    ox += BLOCK;
                    continue;
                }
                conv_block::<CI, CO>(input, h, w, weights, bias, oy as isize - pad, x0 as usize, o);
                ox += BLOCK;
                continue;
            }
            let mut acc = *bias;
            for ky in 0..3 {
                let iy = oy as isize + ky as isize - pad;
                if iy < 0 || iy >= h as isize {
                    continue;
                }
                for kx in 0..3 {
                    let ix = ox as isize + kx as isize - pad;
                    if ix < 0 || ix >= w as isize {
                        continue;
                    }
                    let px = &input[(iy as usize * w + ix as usize) * CI..][..CI];
                    let wk = &weights[(ky * 3 + kx) * CI * CO..][..CI * CO];
                    for (ci, &v) in px.iter().enumerate() {
                        let wr: &[f32; CO] = wk[ci * CO..][..CO].try_into().unwrap();
                        for co in 0..CO {
                            acc[co] += v * wr[co];
                        }
                    }
                }
            }
            let o = &mut out[(oy * ow + ox) * CO..][..CO];
            for co in 0..CO {
                o[co] = relu(acc[co]);
            }
            ox += 1;
        }
    }
    (oh, ow)
}

/// Output pixels convolved together in the interior.
#[cfg(not(target_arch = "wasm32"))]
const BLOCK: usize = 4;
/// In wasm, the simd128 blocks' width (the scalar fallback build keeps it: same bits either way).
#[cfg(target_arch = "wasm32")]
const BLOCK: usize = 2;

/// BLOCK adjacent output pixels whose windows start at input row `y0` and column `x0`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn conv_block<const CI: usize, const CO: usize>(
    input: &[f32],
    h: usize,
    w: usize,
    weights: &[f32],
    bias: &[f32; CO],
    y0: isize,
    x0: usize,
    out: &mut [f32],
) {
    let mut acc = [*bias; BLOCK];
    for ky in 0..3 {
        let iy = y0 + ky as isize;
        if iy < 0 || iy >= h as isize {
            continue;
        }
        let row = &input[(iy as usize * w + x0) * CI..][..(BLOCK + 2) * CI];
        for kx in 0..3 {
            let wk = &weights[(ky * 3 + kx) * CI * CO..][..CI * CO];
            for ci in 0..CI {
                let wr: &[f32; CO] = wk[ci * CO..][..CO].try_into().unwrap();
                for (p, a) in acc.iter_mut().enumerate() {
                    let v = row[(p + kx) * CI + ci];
                    for co in 0..CO {
                        a[co] += v * wr[co];
                    }
                }
            }
        }
    }
    for (p, a) in acc.iter().enumerate() {
        for co in 0..CO {
            out[p * CO + co] = relu(a[co]);
        }
    }
}

/// The interior blocks written with wasm simd128 instructions: wasm engines have 16 vector
/// registers, so a block accumulates P pixels x NV vectors of 4 output channels at a time and
/// walks the channel groups in turn. Each lane does what the portable loop does, in the same
/// order (multiply, then add; ReLU as max with 0), so the bits are the same.
#[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
mod simd {
    use core::arch::wasm32::*;

    pub const P: usize = super::BLOCK;
    pub const NV: usize = 4;

    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub fn conv_block<const CI: usize, const CO: usize>(
        input: &[f32],
        h: usize,
        w: usize,
        weights: &[f32],
        bias: &[f32; CO],
        y0: isize,
        x0: usize,
        out: &mut [f32],
    ) {
        assert!(out.len() >= P * CO && weights.len() == 9 * CI * CO && CO % (4 * NV) == 0);
        let load = |s: &[f32], i: usize| -> v128 {
            let q = &s[i..i + 4];
            // SAFETY: `q` holds 4 f32s; v128_load has no alignment requirement.
            unsafe { v128_load(q.as_ptr() as *const v128) }
        };
        // The hot loop reads weights without a bounds check per load: every index below is
        // (ky * 3 + kx) * CI * CO + ci * CO + g0 + 4 * j + 3 < 9 * CI * CO = weights.len(),
        // asserted above.
        let wp = weights.as_ptr();
        for g0 in (0..CO).step_by(4 * NV) {
            let mut acc = [[f32x4_splat(0.0); NV]; P];
            for a in acc.iter_mut() {
                for (j, v) in a.iter_mut().enumerate() {
                    *v = load(bias, g0 + 4 * j);
                }
            }
            for ky in 0..3 {
                let iy = y0 + ky as isize;
                if iy < 0 || iy >= h as isize {
                    continue;
                }
                let row = &input[(iy as usize * w + x0) * CI..][..(P + 2) * CI];
                for kx in 0..3 {
                    let base = (ky * 3 + kx) * CI * CO + g0;
                    for ci in 0..CI {
                        // SAFETY: in bounds, see `wp`; v128_load has no alignment requirement.
                        let wr: [v128; NV] = std::array::from_fn(|j| unsafe {
                            v128_load(wp.add(base + ci * CO + 4 * j) as *const v128)
                        });
                        for (p, a) in acc.iter_mut().enumerate() {
                            let v = f32x4_splat(row[(p + kx) * CI + ci]);
                            for j in 0..NV {
                                a[j] = f32x4_add(a[j], f32x4_mul(v, wr[j]));
                            }
                        }
                    }
                }
            }
            let zero = f32x4_splat(0.0);
            for (p, a) in acc.iter().enumerate() {
                for (j, &v) in a.iter().enumerate() {
                    let q = &mut out[p * CO + g0 + 4 * j..][..4];
                    // SAFETY: `q` holds 4 f32s; unaligned stores are allowed.
                    unsafe { v128_store(q.as_mut_ptr() as *mut v128, f32x4_pmax(zero, v)) };
                }
            }
        }
    }
}

/// `b` if `a < b`, else `a`: wasm's `f32x4.pmax`, and a compare and select everywhere. `f32::max`
/// would be IEEE maxNum, which wasm has no instruction for: it became a call per element there.
#[inline(always)]
pub fn pmax(a: f32, b: f32) -> f32 {
    if a < b {
        b
    } else {
        a
    }
}

/// ReLU as the simd128 blocks compute it (`pmax(0, x)`: +0 for zeros of either sign).
#[inline(always)]
pub fn relu(x: f32) -> f32 {
    pmax(0.0, x)
}

/// 2x2 max pooling, stride 2, TensorFlow `same` padding: an odd side gets one extra output that
/// pools over the remaining row or column only (21 -> 11).
pub fn maxpool2(input: &[f32], h: usize, w: usize, c: usize, out: &mut Vec<f32>) -> (usize, usize) {
    let (oh, ow) = (h.div_ceil(2), w.div_ceil(2));
    out.clear();
    out.resize(oh * ow * c, f32::NEG_INFINITY);
    for oy in 0..oh {
        for ox in 0..ow {
            let o = &mut out[(oy * ow + ox) * c..][..c];
            for iy in 2 * oy..(2 * oy + 2).min(h) {
                for ix in 2 * ox..(2 * ox + 2).min(w) {
                    let p = &input[(iy * w + ix) * c..][..c];
                    for k in 0..c {
                        o[k] = pmax(o[k], p[k]);
                    }
                }
            }
        }
    }
    (oh, ow)
}

/// Nearest-neighbour upsampling by 2 into planar form (one `(2h + 2) x (2w + 2)` plane per
/// channel, with a border of zeros) for `conv3x3_relu_planar`.
pub fn upsample2_planar(input: &[f32], h: usize, w: usize, c: usize, out: &mut Vec<f32>) -> (usize, usize) {
    let (oh, ow) = (2 * h, 2 * w);
    let (ph, pw) = (oh + 2, ow + 2);
    out.clear();
    out.resize(c * ph * pw, 0.0);
    for oy in 0..oh {
        for ox in 0..ow {
            let px = &input[((oy / 2) * w + ox / 2) * c..][..c];
            for (k, &v) in px.iter().enumerate() {
                out[(k * ph + oy + 1) * pw + ox + 1] = v;
            }
        }
    }
    (oh, ow)
}

/// Pixels one vector of `conv3x3_relu_planar` covers: 2 AVX2 or 4 simd128 registers per channel.
const LANES: usize = 16;

/// 3x3 `same` convolution with ReLU for layers with few output channels (the decoder's last,
/// 16 -> 3), where vectors across channels would be mostly empty: lanes are adjacent output
/// pixels instead. Input: the zero-bordered planes of `upsample2_planar`; output channel-last.
/// Each output sums bias, then kernel row, column and input channel ascending, like
/// `conv3x3_relu`; the border's zero terms add nothing (at most the sign of a zero).
pub fn conv3x3_relu_planar<const CI: usize, const CO: usize>(
    planes: &[f32],
    h: usize,
    w: usize,
    weights: &[f32],
    bias: &[f32],
    out: &mut Vec<f32>,
) {
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU supports AVX2, checked just above.
        return unsafe { conv3x3_relu_planar_avx2::<CI, CO>(planes, h, w, weights, bias, out) };
    }
    conv3x3_relu_planar_any::<CI, CO>(planes, h, w, weights, bias, out)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn conv3x3_relu_planar_avx2<const CI: usize, const CO: usize>(
    planes: &[f32],
    h: usize,
    w: usize,
    weights: &[f32],
    bias: &[f32],
    out: &mut Vec<f32>,
) {
    conv3x3_relu_planar_any::<CI, CO>(planes, h, w, weights, bias, out)
}

#[inline(always)]
fn conv3x3_relu_planar_any<const CI: usize, const CO: usize>(
    planes: &[f32],
    h: usize,
    w: usize,
    weights: &[f32],
    bias: &[f32],
    out: &mut Vec<f32>,
) {
    let (ph, pw) = (h + 2, w + 2);
    assert_eq!(planes.len(), CI * ph * pw);
    assert_eq!(weights.len(), 9 * CI * CO);
    assert_eq!(bias.len(), CO);
    out.clear();
    out.resize(h * w * CO, 0.0);
    for y in 0..h {
        let mut x = 0;
        while x < w {
            if x + LANES <= w {
                let mut acc = [[0.0f32; LANES]; CO];
                for (a, &b) in acc.iter_mut().zip(bias) {
                    *a = [b; LANES];
                }
                for ky in 0..3 {
                    for kx in 0..3 {
                        for ci in 0..CI {
                            let src: &[f32; LANES] =
                                planes[(ci * ph + y + ky) * pw + x + kx..][..LANES].try_into().unwrap();
                            let wr = &weights[((ky * 3 + kx) * CI + ci) * CO..][..CO];
                            for (a, &wv) in acc.iter_mut().zip(wr) {
                                for l in 0..LANES {
                                    a[l] += src[l] * wv;
                                }
                            }
                        }
                    }
                }
                for l in 0..LANES {
                    for co in 0..CO {
                        out[(y * w + x + l) * CO + co] = relu(acc[co][l]);
                    }
                }
                x += LANES;
            } else {
                for co in 0..CO {
                    let mut a = bias[co];
                    for ky in 0..3 {
                        for kx in 0..3 {
                            for ci in 0..CI {
                                a += planes[(ci * ph + y + ky) * pw + x + kx]
                                    * weights[((ky * 3 + kx) * CI + ci) * CO + co];
                            }
                        }
                    }
                    out[(y * w + x) * CO + co] = relu(a);
                }
                x += 1;
            }
        }
    }
}

/// Nearest-neighbour upsampling by 2.
pub fn upsample2(input: &[f32], h: usize, w: usize, c: usize, out: &mut Vec<f32>) -> (usize, usize) {
    out.clear();
    out.resize(4 * h * w * c, 0.0);
    for oy in 0..2 * h {
        for ox in 0..2 * w {
            out[(oy * 2 * w + ox) * c..][..c].copy_from_slice(&input[((oy / 2) * w + ox / 2) * c..][..c]);
        }
    }
    (2 * h, 2 * w)
}

/// Dense layer `out = b + x W` (W is `[in][out]`), optionally with ReLU.
pub fn dense(x: &[f32], weights: &[f32], bias: &[f32], relu: bool, out: &mut [f32]) {
    let n = bias.len();
    assert_eq!(out.len(), n);
    assert_eq!(weights.len(), x.len() * n);
    out.copy_from_slice(bias);
    for (i, &v) in x.iter().enumerate() {
        let row = &weights[i * n..][..n];
        for (o, &wv) in out.iter_mut().zip(row) {
            *o += v * wv;
        }
    }
    if relu {
        for o in out.iter_mut() {
            *o = self::relu(*o);
        }
    }
}

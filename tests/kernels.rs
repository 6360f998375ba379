//! The inference kernels' shortcuts against the plain computation: skipping zero inputs gives the
//! same bits, and a convolution of a 2x upsampling computed on its input (`Up2`) gives the
//! convolution of the upsampled image up to rounding. Natively (the AVX2 path) and under
//! `wasm-pack test --node` (the simd128 kernels).

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use sec_playground::encoder::kernels::{
    conv3x3_relu, conv3x3_relu_maxpool2, conv3x3_relu_sparse, conv3x3_relu_sparse_maxpool2, conv3x3_up2_relu,
    conv3x3_up2_relu_planar, dense, dense_fixed, maxpool2, pad1, pad1_planar, Repeats, Reused, Sparse, Up2,
};

/// Values in [-1, 1], `zeros` of them exactly zero, some of those -0.0.
fn mostly_zero(n: usize, zeros: f64, rng: &mut ChaCha8Rng) -> Vec<f32> {
    (0..n)
        .map(|_| {
            if rng.gen_bool(zeros) {
                if rng.gen_bool(0.3) {
                    -0.0
                } else {
                    0.0
                }
            } else {
                rng.gen_range(-1.0..1.0)
            }
        })
        .collect()
}

fn bits(v: &[f32]) -> Vec<u32> {
    v.iter().map(|x| x.to_bits()).collect()
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn skipping_zero_inputs_gives_the_dense_bits() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut sparse = Sparse::plain();
    // Odd and even sizes, few and many zeros; a negative bias makes many sums end at or below 0.
    for (h, w, zeros) in [(13, 13, 0.8), (23, 23, 0.7), (44, 44, 0.95), (9, 30, 0.0), (12, 17, 1.0)] {
        let input = mostly_zero(h * w * 16, zeros, &mut rng);
        let weights: Vec<f32> = (0..9 * 16 * 32).map(|_| rng.gen_range(-0.5..0.5)).collect();
        let bias: Vec<f32> = (0..32).map(|_| rng.gen_range(-0.5..0.2)).collect();
        let (mut dense, mut skipped) = (Vec::new(), Vec::new());
        let a = conv3x3_relu::<16, 32>(&input, h, w, &weights, &bias, &mut Repeats::plain(), &mut dense);
        let b = conv3x3_relu_sparse::<16, 32>(&input, h, w, &weights, &bias, &mut sparse, &mut skipped);
        assert_eq!(a, b);
        assert_eq!(bits(&dense), bits(&skipped), "{h}x{w}, {zeros} zeros");
        assert!(dense.iter().any(|&v| v > 0.0) || zeros == 1.0);
    }
}

/// Nearest-neighbour 2x upsampling with a border of `border` zero pixels.
fn upsample(x: &[f32], h: usize, w: usize, c: usize, border: usize) -> (Vec<f32>, usize, usize) {
    let (uh, uw) = (2 * h + 2 * border, 2 * w + 2 * border);
    let mut out = vec![0.0; uh * uw * c];
    for y in 0..2 * h {
        for x0 in 0..2 * w {
            for k in 0..c {
                out[((y + border) * uw + x0 + border) * c + k] = x[((y / 2) * w + x0 / 2) * c + k];
            }
        }
    }
    (out, uh, uw)
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn folded_upsampling_convolutions_match_the_upsampled_image() {
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    for (h, w, border) in [(11, 11, 1), (22, 22, 0), (7, 10, 1), (8, 5, 0)] {
        let input = mostly_zero(h * w * 32, 0.5, &mut rng);
        let weights: Vec<f32> = (0..9 * 32 * 16).map(|_| rng.gen_range(-0.5..0.5)).collect();
        let bias: Vec<f32> = (0..16).map(|_| rng.gen_range(-0.2..0.2)).collect();
        let (up, uh, uw) = upsample(&input, h, w, 32, border);
        let mut expected = Vec::new();
        let size = conv3x3_relu::<32, 16>(&up, uh, uw, &weights, &bias, &mut Repeats::plain(), &mut expected);
        let (mut padded, mut got) = (Vec::new(), Vec::new());
        pad1(&input, h, w, 32, &mut padded);
        let fold = Up2::fold(&weights, 32, 16, border);
        let got_size = conv3x3_up2_relu::<32, 16>(&padded, h, w, &fold, &bias, &mut Sparse::default(), &mut got);
        assert_eq!(size, got_size);
        let worst = expected.iter().zip(&got).map(|(a, b)| (a - b).abs()).fold(0.0f32, f32::max);
        assert!(worst <= 1e-5, "{h}x{w} border {border}: off by {worst}");
        assert!(expected.iter().filter(|&&v| v > 0.0).count() > expected.len() / 4);
    }
}

/// The decoder's last layer: 16 -> 3 channels, lanes across pixels on planar input.
#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn the_planar_folded_convolution_matches_the_upsampled_image() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for (h, w) in [(42, 42), (9, 20)] {
        let input = mostly_zero(h * w * 16, 0.6, &mut rng);
        let weights: Vec<f32> = (0..9 * 16 * 3).map(|_| rng.gen_range(-0.5..0.5)).collect();
        let bias: Vec<f32> = (0..3).map(|_| rng.gen_range(-0.2..0.2)).collect();
        let (up, uh, uw) = upsample(&input, h, w, 16, 1);
        let mut expected = Vec::new();
        let size = conv3x3_relu::<16, 3>(&up, uh, uw, &weights, &bias, &mut Repeats::plain(), &mut expected);
        let (mut planes, mut got) = (Vec::new(), Vec::new());
        pad1_planar(&input, h, w, 16, &mut planes);
        let got_size = conv3x3_up2_relu_planar::<16, 3>(&planes, h, w, &Up2::fold(&weights, 16, 3, 1), &bias, &mut got);
        assert_eq!(size, got_size);
        let worst = expected.iter().zip(&got).map(|(a, b)| (a - b).abs()).fold(0.0f32, f32::max);
        assert!(worst <= 1e-5, "{h}x{w}: off by {worst}");
        assert!(expected.iter().filter(|&&v| v > 0.0).count() > expected.len() / 4);
    }
}

/// An activation with repeated windows: rows of runs of equal pixels (some all zero, some with
/// a -0.0 where the pixel on the left has +0.0, which must not count as equal), most rows
/// repeating the row above, as in a rendered wall.
fn with_runs(h: usize, w: usize, c: usize, zeros: f64, rng: &mut ChaCha8Rng) -> Vec<f32> {
    let mut x = mostly_zero(h * w * c, zeros, rng);
    for y in 0..h {
        if y > 0 && rng.gen_bool(0.7) {
            x.copy_within((y - 1) * w * c..y * w * c, y * w * c);
            continue;
        }
        let mut n = 0;
        while n < w {
            let len = rng.gen_range(1..=w - n);
            for k in n + 1..n + len {
                let (src, dst) = ((y * w + n) * c, (y * w + k) * c);
                x.copy_within(src..src + c, dst);
                if rng.gen_bool(0.02) {
                    let v = &mut x[dst + rng.gen_range(0..c)];
                    *v = if v.to_bits() == 0 { -0.0 } else { *v };
                }
            }
            n += len;
        }
    }
    x
}

/// Output pixels whose input window equals their left neighbour's, or else the one above's, copy
/// its output: the same bits as computing every pixel, in every kernel that reuses windows (the
/// dense first layer, the sparse middle layers and the folded decoder layers), on inputs whose
/// rows are runs of equal pixels, most repeating the row above, with and without a zero border.
#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn reusing_repeated_windows_gives_the_bits_of_computing_them() {
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    let (mut reused, mut plain) = (Repeats::default(), Repeats::plain());
    let (mut sparse, mut sparse_plain) = (Sparse::default(), Sparse::plain());
    // Rows wider than 128 pixels are computed in full.
    for (h, w) in [(86, 86), (13, 9), (5, 40), (4, 140)] {
        let input = with_runs(h, w, 3, 0.1, &mut rng);
        let weights: Vec<f32> = (0..9 * 3 * 16).map(|_| rng.gen_range(-0.5..0.5)).collect();
        let bias: Vec<f32> = (0..16).map(|_| rng.gen_range(-0.5..0.2)).collect();
        let (mut a, mut b) = (Vec::new(), Vec::new());
        conv3x3_relu::<3, 16>(&input, h, w, &weights, &bias, &mut plain, &mut a);
        conv3x3_relu::<3, 16>(&input, h, w, &weights, &bias, &mut reused, &mut b);
        assert_eq!(bits(&a), bits(&b), "first layer, {h}x{w}");
        let (r, none) = (reused.reused(), plain.reused());
        assert!((r.left > (h - 2) * (w - 2) / 4) == (w <= 128) && none == Reused::default());
        // Rows repeating the row above: a window not equal to the left one's comes from above (in
        // the large image certainly; the small ones may, by the draw, have none).
        assert!(r.above > 0 || h < 86, "{h}x{w}: {r:?}");
        assert!(w <= 128 || r == Reused::default(), "{h}x{w}: {r:?}");
        assert!(a.iter().any(|&v| v > 0.0));
    }
    // Up to 128 pixels a row (126, padded to 128 for the folded layer): both halves of the marks.
    for (h, w, zeros) in [(44, 44, 0.7), (23, 23, 0.3), (9, 31, 0.0), (6, 126, 0.5)] {
        let input = with_runs(h, w, 16, zeros, &mut rng);
        let weights: Vec<f32> = (0..9 * 16 * 32).map(|_| rng.gen_range(-0.5..0.5)).collect();
        let bias: Vec<f32> = (0..32).map(|_| rng.gen_range(-0.5..0.2)).collect();
        let (mut a, mut b) = (Vec::new(), Vec::new());
        conv3x3_relu_sparse::<16, 32>(&input, h, w, &weights, &bias, &mut sparse_plain, &mut a);
        conv3x3_relu_sparse::<16, 32>(&input, h, w, &weights, &bias, &mut sparse, &mut b);
        assert_eq!(bits(&a), bits(&b), "sparse layer, {h}x{w}");
        let r = sparse.reused();
        assert!(r.left > (h - 2) * (w - 2) / 4 && sparse_plain.reused() == Reused::default(), "{r:?}");
        assert!(r.above > 0 || h < 44, "{h}x{w}: {r:?}");
        let fold = Up2::fold(&weights[..9 * 16 * 16], 16, 16, 1);
        let mut padded = Vec::new();
        pad1(&input, h, w, 16, &mut padded);
        conv3x3_up2_relu::<16, 16>(&padded, h, w, &fold, &bias[..16], &mut sparse_plain, &mut a);
        conv3x3_up2_relu::<16, 16>(&padded, h, w, &fold, &bias[..16], &mut sparse, &mut b);
        assert_eq!(bits(&a), bits(&b), "folded layer, {h}x{w}");
        assert!(sparse.reused().left + sparse.reused().above > 0);
    }
}

/// The encoder's fused layers (a convolution whose reused pixels are not copied, pooled through
/// the pixels they were computed at) give the bits of computing every pixel and pooling them, for
/// odd and even sizes, with and without the pooling's border, on inputs with repeated windows.
#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn pooling_through_reused_pixels_gives_the_bits_of_pooling_them_all() {
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let (mut repeats, mut sparse, mut sparse_plain) = (Repeats::default(), Sparse::default(), Sparse::plain());
    let (mut conv, mut a, mut b) = (Vec::new(), Vec::new(), Vec::new());
    for (h, w, border) in [(86, 86, 1), (13, 9, 0), (6, 41, 1), (4, 140, 0)] {
        let input = with_runs(h, w, 3, 0.1, &mut rng);
        let weights: Vec<f32> = (0..9 * 3 * 16).map(|_| rng.gen_range(-0.5..0.5)).collect();
        let bias: Vec<f32> = (0..16).map(|_| rng.gen_range(-0.5..0.2)).collect();
        let (ch, cw) = conv3x3_relu::<3, 16>(&input, h, w, &weights, &bias, &mut Repeats::plain(), &mut conv);
        let expected = maxpool2::<16>(&conv, ch, cw, border, &mut a);
        let got =
            conv3x3_relu_maxpool2::<3, 16>(&input, h, w, &weights, &bias, &mut repeats, &mut conv, border, &mut b);
        assert_eq!(expected, got);
        assert_eq!(bits(&a), bits(&b), "first layer, {h}x{w}");
        // Most of the large image's windows are reused (the small ones may, by the draw, have
        // few); none of a row wider than 128 pixels.
        let r = repeats.reused();
        assert!(r.left + r.above > (h - 2) * (w - 2) / 4 || h < 86, "{h}x{w}: {r:?}");
        assert!(w <= 128 || r == Reused::default(), "{h}x{w}: {r:?}");
        assert!(a.iter().any(|&v| v > 0.0));
    }
    for (h, w, border, zeros) in [(44, 44, 1, 0.7), (23, 23, 0, 0.3), (9, 31, 1, 0.0)] {
        let input = with_runs(h, w, 16, zeros, &mut rng);
        let weights: Vec<f32> = (0..9 * 16 * 32).map(|_| rng.gen_range(-0.5..0.5)).collect();
        let bias: Vec<f32> = (0..32).map(|_| rng.gen_range(-0.5..0.2)).collect();
        let (ch, cw) = conv3x3_relu_sparse::<16, 32>(&input, h, w, &weights, &bias, &mut sparse_plain, &mut conv);
        let expected = maxpool2::<32>(&conv, ch, cw, border, &mut a);
        let got = conv3x3_relu_sparse_maxpool2::<16, 32>(
            &input,
            h,
            w,
            &weights,
            &bias,
            &mut sparse,
            &mut conv,
            border,
            &mut b,
        );
        assert_eq!(expected, got);
        assert_eq!(bits(&a), bits(&b), "sparse layer, {h}x{w}");
        assert!(sparse.reused().left > (h - 2) * (w - 2) / 4 || h < 44, "{h}x{w}: {:?}", sparse.reused());
    }
}

/// The bottleneck's dense layer into an array gives the bits of the dense layer into a slice,
/// with ReLU (zero inputs skipped) and without.
#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn the_dense_layer_into_an_array_gives_the_same_bits() {
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    for (inputs, zeros) in [(3872, 0.8), (20, 0.0), (130, 0.5)] {
        let x = mostly_zero(inputs, zeros, &mut rng);
        let weights: Vec<f32> = (0..inputs * 20).map(|_| rng.gen_range(-0.5..0.5)).collect();
        let bias: Vec<f32> = (0..20).map(|_| rng.gen_range(-0.5..0.5)).collect();
        for relu in [true, false] {
            let (mut a, mut b) = (vec![0.0; 20], [0.0; 20]);
            dense(&x, &weights, &bias, relu, &mut a);
            dense_fixed(&x, &weights, &bias, relu, &mut b);
            assert_eq!(bits(&a), bits(&b), "{inputs} inputs, relu {relu}");
            assert!(a.iter().any(|&v| v != 0.0));
        }
    }
}

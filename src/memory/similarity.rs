//! The similarity kernels of retrieval: 1 - MAE of the embedding against every stored couplet
//! (f32, and f64 once the LTM has been through forgetting) and G = similarity times T, summed in
//! numpy's order on every target; the AVX2 and wasm simd128 copies are picked through
//! `crate::dispatch`.

use crate::dispatch::avx2_dispatch;
use crate::encoder::EMBEDDING;

/// 1 - MAE between `e` and every stored couplet: `ltm` holds rows of n couplets transposed
/// (`[k][j]`), `out` gets one value per couplet, row-major. Each couplet sums its 20 terms
/// |e_k - x_k| in numpy's pairwise order (`pairwise20`), whether one couplet at a time or eight
/// (AVX2) or four (wasm simd128) side by side, so every target gives the same bits.
pub(super) fn similarity(e: &[f32; EMBEDDING], ltm: &[f32], n: usize, out: &mut [f32]) {
    #[cfg(target_arch = "x86_64")]
    if crate::dispatch::avx2() && n >= 8 {
        // SAFETY: the CPU supports AVX2, checked just above.
        return unsafe { simd_avx2::similarity(e, ltm, n, out) };
    }
    #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
    if n >= 4 {
        return simd128::similarity(e, ltm, n, out);
    }
    similarity_scalar(e, ltm, n, out)
}

/// `similarity` of the one couplet `i` (row-major over rows of n): the same terms summed in the
/// same order, so the same bits as the full pass.
#[cfg(test)]
pub(super) fn similarity_at(e: &[f32; EMBEDDING], ltm: &[f32], n: usize, i: usize) -> f32 {
    couplet_similarity(e, &couplet_at(ltm, n, i))
}

/// `similarity_f64` of the one couplet `i`.
#[cfg(test)]
pub(super) fn similarity_f64_at(e: &[f32; EMBEDDING], ltm: &[f32], n: usize, i: usize) -> f64 {
    couplet_similarity_f64(e, &couplet_at(ltm, n, i))
}

/// Couplet i's embedding, gathered from the LTM's layout (rows of n couplets, transposed).
#[cfg(test)]
pub(super) fn couplet_at(ltm: &[f32], n: usize, i: usize) -> [f32; EMBEDDING] {
    let (row, j) = (&ltm[i / n * EMBEDDING * n..][..EMBEDDING * n], i % n);
    std::array::from_fn(|k| row[k * n + j])
}

/// `similarity` of one couplet whose embedding is `c`: the full pass's terms in its order.
#[inline]
pub(super) fn couplet_similarity(e: &[f32; EMBEDDING], c: &[f32; EMBEDDING]) -> f32 {
    1.0 - pairwise20(|k| (e[k] - c[k]).abs()) / EMBEDDING as f32
}

/// `similarity_f64` of one couplet whose embedding is `c`.
#[inline]
pub(super) fn couplet_similarity_f64(e: &[f32; EMBEDDING], c: &[f32; EMBEDDING]) -> f64 {
    1.0 - pairwise20(|k| (f64::from(e[k]) - f64::from(c[k])).abs()) / EMBEDDING as f64
}

/// numpy's sum of 20 values (`pairwise_sum` for n <= 128): eight partial sums r_l = a_l + a_{8+l},
/// combined as ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7)), then a_16..a_19 added in turn.
/// `term(k)` gives a_k; generic so the same order serves f32 and f64.
#[inline(always)]
pub fn pairwise20<T: Copy + std::ops::Add<Output = T>>(term: impl Fn(usize) -> T) -> T {
    const _: () = assert!(EMBEDDING == 20, "the order below is numpy's for 20 terms");
    let r: [T; 8] = std::array::from_fn(|l| term(l) + term(8 + l));
    let mut s = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]));
    for k in 16..20 {
        s = s + term(k);
    }
    s
}

/// numpy's sum of 9 values: eight partial sums (the values themselves) combined as a tree, then
/// the ninth added.
#[inline]
pub fn pairwise9(a: &[f64; 9]) -> f64 {
    (((a[0] + a[1]) + (a[2] + a[3])) + ((a[4] + a[5]) + (a[6] + a[7]))) + a[8]
}

fn similarity_scalar(e: &[f32; EMBEDDING], ltm: &[f32], n: usize, out: &mut [f32]) {
    for (row, o) in ltm.chunks_exact(EMBEDDING * n).zip(out.chunks_exact_mut(n)) {
        for (j, o) in o.iter_mut().enumerate() {
            let acc = pairwise20(|k| (e[k] - row[k * n + j]).abs());
            *o = 1.0 - acc / EMBEDDING as f32;
        }
    }
}

/// `similarity` for rows of at least L couplets, L side by side: the last block overlaps the one
/// before when L does not divide n (the same values are written twice). `block(row, j, o)`
/// writes the similarities of couplets j..j + L into `o`.
#[cfg(any(target_arch = "x86_64", all(target_arch = "wasm32", target_feature = "simd128")))]
#[inline(always)]
fn blocks<const L: usize, T>(ltm: &[f32], n: usize, out: &mut [T], mut block: impl FnMut(&[f32], usize, &mut [T])) {
    for (row, o) in ltm.chunks_exact(EMBEDDING * n).zip(out.chunks_exact_mut(n)) {
        let mut j0 = 0;
        loop {
            let j = j0.min(n - L);
            block(row, j, &mut o[j..j + L]);
            if j + L >= n {
                break;
            }
            j0 += L;
        }
    }
}

/// The AVX2 copy: eight couplets per instruction. Written with intrinsics because the compiler
/// kept the pairwise order's eight partial sums in memory and ran at half the speed of a plain
/// sum.
#[cfg(target_arch = "x86_64")]
mod simd_avx2 {
    use super::{blocks, EMBEDDING};
    use std::arch::x86_64::*;

    #[target_feature(enable = "avx2")]
    pub unsafe fn similarity(e: &[f32; EMBEDDING], ltm: &[f32], n: usize, out: &mut [f32]) {
        let abs = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fff_ffff));
        let (one, twenty) = (_mm256_set1_ps(1.0), _mm256_set1_ps(EMBEDDING as f32));
        blocks::<8, f32>(ltm, n, out, |row, j, o| {
            debug_assert!(row.len() >= (EMBEDDING - 1) * n + j + 8 && o.len() == 8);
            // SAFETY: every load reads 8 floats of `row` at k * n + j with j + 8 <= n (blocks),
            // and the store writes the 8 of `o`.
            unsafe {
                let d = |k: usize| {
                    let x = _mm256_loadu_ps(row.as_ptr().add(k * n + j));
                    _mm256_and_ps(_mm256_sub_ps(_mm256_set1_ps(e[k]), x), abs)
                };
                let r = |k: usize| _mm256_add_ps(d(k), d(k + 8));
                let left = _mm256_add_ps(_mm256_add_ps(r(0), r(1)), _mm256_add_ps(r(2), r(3)));
                let right = _mm256_add_ps(_mm256_add_ps(r(4), r(5)), _mm256_add_ps(r(6), r(7)));
                let mut acc = _mm256_add_ps(left, right);
                for k in 16..EMBEDDING {
                    acc = _mm256_add_ps(acc, d(k));
                }
                _mm256_storeu_ps(o.as_mut_ptr(), _mm256_sub_ps(one, _mm256_div_ps(acc, twenty)));
            }
        });
    }

    /// `super::similarity_f64`, four couplets per instruction.
    #[target_feature(enable = "avx2")]
    pub unsafe fn similarity_f64(e: &[f32; EMBEDDING], ltm: &[f32], n: usize, out: &mut [f64]) {
        let abs = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fff_ffff_ffff_ffff));
        let (one, twenty) = (_mm256_set1_pd(1.0), _mm256_set1_pd(EMBEDDING as f64));
        blocks::<4, f64>(ltm, n, out, |row, j, o| {
            debug_assert!(row.len() >= (EMBEDDING - 1) * n + j + 4 && o.len() == 4);
            // SAFETY: every load reads 4 floats of `row` at k * n + j with j + 4 <= n (blocks),
            // and the store writes the 4 of `o`.
            unsafe {
                let d = |k: usize| {
                    let x = _mm256_cvtps_pd(_mm_loadu_ps(row.as_ptr().add(k * n + j)));
                    _mm256_and_pd(_mm256_sub_pd(_mm256_set1_pd(e[k] as f64), x), abs)
                };
                let r = |k: usize| _mm256_add_pd(d(k), d(k + 8));
                let left = _mm256_add_pd(_mm256_add_pd(r(0), r(1)), _mm256_add_pd(r(2), r(3)));
                let right = _mm256_add_pd(_mm256_add_pd(r(4), r(5)), _mm256_add_pd(r(6), r(7)));
                let mut acc = _mm256_add_pd(left, right);
                for k in 16..EMBEDDING {
                    acc = _mm256_add_pd(acc, d(k));
                }
                _mm256_storeu_pd(o.as_mut_ptr(), _mm256_sub_pd(one, _mm256_div_pd(acc, twenty)));
            }
        });
    }
}

/// The wasm simd128 copy: four couplets per instruction.
#[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
mod simd128 {
    use super::{blocks, EMBEDDING};
    use std::arch::wasm32::*;

    pub fn similarity(e: &[f32; EMBEDDING], ltm: &[f32], n: usize, out: &mut [f32]) {
        let (one, twenty) = (f32x4_splat(1.0), f32x4_splat(EMBEDDING as f32));
        blocks::<4, f32>(ltm, n, out, |row, j, o| {
            assert!(row.len() >= (EMBEDDING - 1) * n + j + 4);
            let d = |k: usize| {
                // SAFETY: k * n + j + 4 <= row.len() (asserted above; blocks keep j + 4 <= n), and
                // wasm loads need no alignment.
                let x = unsafe { v128_load(row.as_ptr().add(k * n + j) as *const v128) };
                f32x4_abs(f32x4_sub(f32x4_splat(e[k]), x))
            };
            let r = |k: usize| f32x4_add(d(k), d(k + 8));
            let left = f32x4_add(f32x4_add(r(0), r(1)), f32x4_add(r(2), r(3)));
            let right = f32x4_add(f32x4_add(r(4), r(5)), f32x4_add(r(6), r(7)));
            let mut acc = f32x4_add(left, right);
            for k in 16..EMBEDDING {
                acc = f32x4_add(acc, d(k));
            }
            let v = f32x4_sub(one, f32x4_div(acc, twenty));
            assert_eq!(o.len(), 4);
            // SAFETY: `o` holds the block's 4 floats (asserted above).
            unsafe { v128_store(o.as_mut_ptr() as *mut v128, v) };
        });
    }
}

/// `similarity` in f64, as numpy computes it once the LTM holds Python floats: each couplet
/// sums |e_k - x_k| in f64 in `pairwise20`'s order, then 1 - sum / 20.
pub(super) fn similarity_f64(e: &[f32; EMBEDDING], ltm: &[f32], n: usize, out: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    if crate::dispatch::avx2() && n >= 4 {
        // SAFETY: the CPU supports AVX2, checked just above.
        return unsafe { simd_avx2::similarity_f64(e, ltm, n, out) };
    }
    let e = e.map(f64::from);
    for (row, o) in ltm.chunks_exact(EMBEDDING * n).zip(out.chunks_exact_mut(n)) {
        for (j, o) in o.iter_mut().enumerate() {
            let acc = pairwise20(|k| (e[k] - row[k * n + j] as f64).abs());
            *o = 1.0 - acc / EMBEDDING as f64;
        }
    }
}

avx2_dispatch! {
    /// The largest similarity (as f64); a NaN is passed over.
    pub(super) fn max32(v: &[f32]) -> f64 => max_any
}

avx2_dispatch! {
    /// `max32` of f64 similarities.
    pub(super) fn max64(v: &[f64]) -> f64 => max_any
}

/// Eight running maxima so that the loop vectorises (a maximum does not depend on the order).
#[inline(always)]
fn max_any<T: Copy + Into<f64>>(v: &[T]) -> f64 {
    let mut m = [f64::NEG_INFINITY; 8];
    let chunks = v.chunks_exact(8);
    let tail = chunks.remainder();
    for c in chunks {
        for l in 0..8 {
            let x: f64 = c[l].into();
            m[l] = if x > m[l] { x } else { m[l] };
        }
    }
    tail.iter().map(|&x| x.into()).chain(m).fold(f64::NEG_INFINITY, |a, b| if b > a { b } else { a })
}

avx2_dispatch! {
    /// Appends the index of every similarity above `thr` (compared as f64), ascending. Few pass,
    /// so eight are tested at once without a branch and only a block with one is walked.
    pub(super) fn above32(v: &[f32], thr: f64, out: &mut Vec<u32>) => above_any
}

avx2_dispatch! {
    /// `above32` of f64 similarities.
    pub(super) fn above64(v: &[f64], thr: f64, out: &mut Vec<u32>) => above_any
}

#[inline(always)]
fn above_any<T: Copy + Into<f64>>(v: &[T], thr: f64, out: &mut Vec<u32>) {
    let chunks = v.chunks_exact(8);
    let tail = chunks.remainder();
    for (w, c) in chunks.enumerate() {
        let mut any = false;
        for &x in c {
            any |= x.into() > thr;
        }
        if any {
            out.extend((0..8).filter(|&l| c[l].into() > thr).map(|l| (w * 8 + l) as u32));
        }
    }
    let base = v.len() - tail.len();
    out.extend((0..tail.len()).filter(|&l| tail[l].into() > thr).map(|l| (base + l) as u32));
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// One couplet's similarity has the bits of the full pass's, in f32 and f64, for rows of
    /// every block shape.
    #[test]
    fn one_couplet_gives_the_bits_of_the_full_pass() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for n in 1..40 {
            let ltm: Vec<f32> = (0..3 * n * EMBEDDING).map(|_| rng.gen_range(-1.0..1.0)).collect();
            let e: [f32; EMBEDDING] = std::array::from_fn(|_| rng.gen_range(-1.0..1.0));
            let (mut sim, mut sim64) = (vec![0.0; 3 * n], vec![0.0; 3 * n]);
            similarity(&e, &ltm, n, &mut sim);
            similarity_f64(&e, &ltm, n, &mut sim64);
            for i in 0..3 * n {
                assert_eq!(similarity_at(&e, &ltm, n, i).to_bits(), sim[i].to_bits(), "n {n}, couplet {i}");
                assert_eq!(similarity_f64_at(&e, &ltm, n, i).to_bits(), sim64[i].to_bits(), "n {n}, couplet {i}");
            }
        }
    }
}

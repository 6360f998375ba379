//! A coarse copy of the LTM that bounds every couplet's similarity, so that retrieval computes
//! exactly only the couplets that can matter (docs/ALGORITHM.md, "Retrieval").
//!
//! Each stored value is kept as one of 256 levels (`lo + step * level`, off by at most step / 2)
//! and the embedding is put on the same levels (its own error summed exactly). The L1 distance
//! in levels is an integer, the same on every target, and from it each couplet's similarity lies
//! within a known interval. Retrieval needs only the largest similarity (among the couplets whose
//! interval reaches the closest couplet's exact similarity) and the similarities above a
//! threshold (among the couplets whose interval reaches above it), so it computes those exactly,
//! in the full pass's order: the bits are the full pass's. With the double T-maze's embeddings
//! that is about 300 of a full LTM's 25,000 couplets per decision, and the copy is a quarter of
//! the LTM's bytes, which is what a full pass is bound by.

use crate::encoder::EMBEDDING;

/// The highest level.
const TOP: f64 = 255.0;
/// Room above and below the values present when the levels are laid out, so that new sequences
/// of the same encoder usually fit without laying them out again.
const HEADROOM: f64 = 1.0 / 32.0;
/// A bound on the exact kernels' rounding, relative to 1 plus the largest mean distance possible
/// (the 20 differences, the pairwise sum, the division and 1 - x round by at most 2^-24 each
/// step, under 1e-6 in all; f64 rounds less).
const ROUNDING: f64 = 4e-6;

/// The coarse copy and, for the embedding of the last `pass`, each couplet's distance in levels
/// and which couplets' similarities have been computed exactly since.
#[derive(Clone, Debug, Default)]
pub(super) struct Coarse {
    /// The LTM's values as levels, in the LTM's layout; out of date when `step` is 0.
    levels: Vec<u8>,
    /// The LTM's values again, couplet by couplet (each one's 20 adjacent), for the couplets
    /// computed exactly one at a time: in the LTM's layout a couplet's values lie n apart, a
    /// cache line each. Kept with `levels`; the LTM's rows of n couplets (`n`).
    couplets: Vec<f32>,
    n: usize,
    lo: f64,
    step: f64,
    /// Per couplet, the L1 distance in levels to the embedding of the last pass.
    distance: Vec<u16>,
    /// The couplet at the smallest distance (the first of them).
    closest: u32,
    /// How far the true L1 distance may be from `step * distance` (the embedding's own errors
    /// summed, plus step / 2 per stored value).
    slack: f64,
    /// How far an exactly computed similarity may be from 1 - (true distance) / 20.
    rounding: f64,
    /// The bounds of a couplet at distance d are `lowest - per_level * d` and
    /// `highest - per_level * d` (`bounds`).
    per_level: f64,
    lowest: f64,
    highest: f64,
    /// Bit i: couplet i's similarity is exact (when not `all`).
    known: Vec<u64>,
    /// Every similarity of the last pass's embedding is exact (it was a full pass).
    pub all: bool,
}

impl Coarse {
    /// The copy is laid out again at the next pass (after the LTM was replaced).
    pub fn clear(&mut self) {
        self.step = 0.0;
        self.levels.clear();
        self.couplets.clear();
    }

    /// A sequence appended to the LTM (its values in the LTM's layout).
    pub fn append(&mut self, values: &[f32]) {
        if self.step == 0.0 {
            return;
        }
        for &v in values {
            match self.level(v) {
                Some(l) => self.levels.push(l),
                // Outside the levels: laid out again for the new range at the next pass.
                None => return self.clear(),
            }
        }
        push_couplets(values, self.n, &mut self.couplets);
    }

    /// The LTM's values `range` removed.
    pub fn remove(&mut self, range: std::ops::Range<usize>) {
        if self.step != 0.0 {
            // Both copies hold rows of 20 x n values, so a row's values have the same range.
            self.couplets.drain(range.clone());
            self.levels.drain(range);
        }
    }

    /// The level of a stored value, `None` outside the levels.
    fn level(&self, v: f32) -> Option<u8> {
        let l = ((f64::from(v) - self.lo) / self.step).round();
        (0.0..=TOP).contains(&l).then_some(l as u8)
    }

    /// Lays the levels out over the values of `ltm` (with headroom) and quantises them. False
    /// when the values span no finite range (then only full passes are made).
    fn lay_out(&mut self, ltm: &[f32], n: usize) -> bool {
        let (lo, hi) = ltm.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            let v = f64::from(v);
            (a.min(v), b.max(v))
        });
        let span = hi - lo;
        let room = if span > 0.0 { span * HEADROOM } else { lo.abs().max(1.0) };
        self.lo = lo - room;
        self.step = (span + 2.0 * room) / TOP;
        if !(self.lo.is_finite() && self.step.is_finite() && self.step > 0.0) {
            self.clear();
            return false;
        }
        self.levels.clear();
        self.levels.reserve(ltm.len());
        for &v in ltm {
            let Some(l) = self.level(v) else {
                self.clear();
                return false;
            };
            self.levels.push(l);
        }
        self.n = n;
        self.couplets.clear();
        push_couplets(ltm, n, &mut self.couplets);
        true
    }

    /// Each couplet's distance in levels to `e` over the LTM `ltm` (rows of n couplets): false
    /// when no bound can be given (a value that is not finite), and then nothing is changed but
    /// `all`, which the caller then makes true by a full pass.
    pub fn pass(&mut self, e: &[f32; EMBEDDING], ltm: &[f32], n: usize) -> bool {
        self.all = false;
        if !e.iter().all(|v| v.is_finite()) {
            return false;
        }
        if (self.step == 0.0 || self.levels.len() != ltm.len() || self.n != n) && !self.lay_out(ltm, n) {
            return false;
        }
        let mut qe = [0u8; EMBEDDING];
        let mut off = 0.0;
        for (q, &v) in qe.iter_mut().zip(e) {
            let v = f64::from(v);
            let l = ((v - self.lo) / self.step).round().clamp(0.0, TOP);
            *q = l as u8;
            off += (v - (self.lo + self.step * l)).abs();
        }
        // Half a step per stored value; a little more for the rounding of these f64 sums.
        self.slack = (off + EMBEDDING as f64 * self.step / 2.0) * (1.0 + 1e-9);
        let largest = self.lo.abs().max((self.lo + TOP * self.step).abs());
        let far = e.iter().map(|&v| f64::from(v).abs()).sum::<f64>() + EMBEDDING as f64 * largest;
        self.rounding = ROUNDING * (1.0 + far / EMBEDDING as f64);
        if !(self.slack.is_finite() && self.rounding.is_finite()) {
            return false;
        }
        // Rearranged, these differ from the formulas in `bounds`' comment by f64 rounding only,
        // far below `rounding`.
        self.per_level = self.step / EMBEDDING as f64;
        self.lowest = 1.0 - self.slack / EMBEDDING as f64 - self.rounding;
        self.highest = 1.0 + self.slack / EMBEDDING as f64 + self.rounding;
        let cells = ltm.len() / EMBEDDING;
        self.distance.resize(cells, 0);
        distances(&qe, &self.levels, n, &mut self.distance);
        // The smallest value (a reduction that vectorises), then its first place.
        let min = self.distance.iter().copied().min().unwrap_or(0);
        self.closest = self.distance.iter().position(|&d| d == min).unwrap_or(0) as u32;
        self.known.clear();
        self.known.resize(cells.div_ceil(64), 0);
        true
    }

    /// The couplet at the smallest distance in levels: its similarity is a floor for the
    /// largest, and the couplets whose upper bound is below it cannot be the largest.
    pub fn closest(&self) -> u32 {
        self.closest
    }

    /// The largest distance in levels whose similarity may be above `floor`, `None` when no
    /// couplet's can: similarity <= 1 - (step * distance - slack) / 20 + rounding.
    pub fn cut_above(&self, floor: f64) -> Option<u32> {
        let d = (EMBEDDING as f64 * (1.0 + self.rounding - floor) + self.slack) / self.step;
        (d >= 0.0).then(|| clamp_cut(d))
    }

    /// The interval couplet i's exact similarity lies in: 1 - (step * distance -+ slack) / 20
    /// -+ rounding.
    #[inline]
    pub fn bounds(&self, i: usize) -> (f64, f64) {
        let d = self.per_level * f64::from(self.distance[i]);
        (self.lowest - d, self.highest - d)
    }

    /// Appends the couplets within `cut` levels, ascending.
    pub fn within(&self, cut: u32, out: &mut Vec<u32>) {
        out.clear();
        let cut = cut.min(u32::from(u16::MAX)) as u16;
        within_any(&self.distance, cut, out);
    }

    /// Gives each couplet of `idx` its exact similarity in `sim` (`exact` of its embedding),
    /// computing only those not computed since the last pass.
    pub fn fill<T>(
        &mut self,
        idx: impl IntoIterator<Item = u32>,
        sim: &mut [T],
        exact: impl Fn(&[f32; EMBEDDING]) -> T,
    ) {
        for i in idx {
            let (w, b) = (i as usize / 64, 1u64 << (i % 64));
            if self.known[w] & b == 0 {
                self.known[w] |= b;
                let c = &self.couplets[i as usize * EMBEDDING..][..EMBEDDING];
                sim[i as usize] = exact(c.try_into().expect("20 values a couplet"));
            }
        }
    }
}

/// Appends the couplets of `rows` (rows of n couplets in the LTM's layout) couplet by couplet.
fn push_couplets(rows: &[f32], n: usize, out: &mut Vec<f32>) {
    for row in rows.chunks_exact(EMBEDDING * n) {
        for j in 0..n {
            out.extend((0..EMBEDDING).map(|k| row[k * n + j]));
        }
    }
}

/// A distance bound as an integer cut, one level wider for the rounding of `d` itself.
fn clamp_cut(d: f64) -> u32 {
    if d >= f64::from(u16::MAX) {
        u32::from(u16::MAX)
    } else {
        d as u32 + 1
    }
}

/// The L1 distance in levels between `qe` and every couplet of `levels` (rows of n couplets,
/// transposed like the LTM): at most 20 x 255, so a u16 holds it. Integers: every copy gives
/// the same values.
fn distances(qe: &[u8; EMBEDDING], levels: &[u8], n: usize, out: &mut [u16]) {
    #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
    if n >= 16 {
        return simd128::distances(qe, levels, n, out);
    }
    #[cfg(target_arch = "x86_64")]
    if n >= 16 {
        return sse2::distances(qe, levels, n, out);
    }
    distances_scalar(qe, levels, n, out)
}

fn distances_scalar(qe: &[u8; EMBEDDING], levels: &[u8], n: usize, out: &mut [u16]) {
    for (row, o) in levels.chunks_exact(EMBEDDING * n).zip(out.chunks_exact_mut(n)) {
        o.fill(0);
        // Component by component across the row's couplets: a loop over contiguous bytes
        // that vectorises.
        for (k, &q) in qe.iter().enumerate() {
            for (o, &x) in o.iter_mut().zip(&row[k * n..(k + 1) * n]) {
                *o += u16::from(q.abs_diff(x));
            }
        }
    }
}

/// The wasm simd128 copy: 16 couplets at a time, their 20 components summed in registers.
#[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
mod simd128 {
    use super::EMBEDDING;
    use std::arch::wasm32::*;

    pub fn distances(qe: &[u8; EMBEDDING], levels: &[u8], n: usize, out: &mut [u16]) {
        assert!(n >= 16);
        let q: [v128; EMBEDDING] = std::array::from_fn(|k| u8x16_splat(qe[k]));
        for (row, o) in levels.chunks_exact(EMBEDDING * n).zip(out.chunks_exact_mut(n)) {
            // Blocks of 16 couplets; the last one overlaps the one before when 16 does not
            // divide n (the same values are written twice).
            let mut j0 = 0;
            loop {
                let j = j0.min(n - 16);
                let (mut lo, mut hi) = (u16x8_splat(0), u16x8_splat(0));
                for (k, &qk) in q.iter().enumerate() {
                    // SAFETY: k * n + j + 16 <= 20 * n = row.len() (j + 16 <= n); wasm loads need
                    // no alignment.
                    let x = unsafe { v128_load(row.as_ptr().add(k * n + j) as *const v128) };
                    let d = v128_or(u8x16_sub_sat(x, qk), u8x16_sub_sat(qk, x));
                    lo = u16x8_add(lo, u16x8_extend_low_u8x16(d));
                    hi = u16x8_add(hi, u16x8_extend_high_u8x16(d));
                }
                assert!(j + 16 <= o.len());
                // SAFETY: the 16 values j..j + 16 of `o` (asserted just above).
                unsafe {
                    v128_store(o.as_mut_ptr().add(j) as *mut v128, lo);
                    v128_store(o.as_mut_ptr().add(j + 8) as *mut v128, hi);
                }
                if j + 16 >= n {
                    break;
                }
                j0 += 16;
            }
        }
    }
}

/// The x86-64 copy (SSE2, which every x86-64 CPU has): as the simd128 one.
#[cfg(target_arch = "x86_64")]
mod sse2 {
    use super::EMBEDDING;
    use std::arch::x86_64::*;

    pub fn distances(qe: &[u8; EMBEDDING], levels: &[u8], n: usize, out: &mut [u16]) {
        assert!(n >= 16);
        // SAFETY: SSE2 is part of x86-64; every load reads 16 bytes at k * n + j <= 20 * n - 16
        // of `row` and every store writes the 16 values j..j + 16 of `o` (j + 16 <= n).
        unsafe {
            let q: [__m128i; EMBEDDING] = std::array::from_fn(|k| _mm_set1_epi8(qe[k] as i8));
            let zero = _mm_setzero_si128();
            for (row, o) in levels.chunks_exact(EMBEDDING * n).zip(out.chunks_exact_mut(n)) {
                let mut j0 = 0;
                loop {
                    let j = j0.min(n - 16);
                    let (mut lo, mut hi) = (zero, zero);
                    for (k, &qk) in q.iter().enumerate() {
                        let x = _mm_loadu_si128(row.as_ptr().add(k * n + j) as *const __m128i);
                        let d = _mm_or_si128(_mm_subs_epu8(x, qk), _mm_subs_epu8(qk, x));
                        lo = _mm_add_epi16(lo, _mm_unpacklo_epi8(d, zero));
                        hi = _mm_add_epi16(hi, _mm_unpackhi_epi8(d, zero));
                    }
                    _mm_storeu_si128(o.as_mut_ptr().add(j) as *mut __m128i, lo);
                    _mm_storeu_si128(o.as_mut_ptr().add(j + 8) as *mut __m128i, hi);
                    if j + 16 >= n {
                        break;
                    }
                    j0 += 16;
                }
            }
        }
    }
}

/// `Coarse::within`: few couplets are within the cut, so sixteen are tested at once without a
/// branch and only a block with one is walked.
fn within_any(v: &[u16], cut: u16, out: &mut Vec<u32>) {
    let chunks = v.chunks_exact(16);
    let tail = chunks.remainder();
    for (w, c) in chunks.enumerate() {
        if c.iter().fold(false, |any, &d| any | (d <= cut)) {
            out.extend((0..16).filter(|&l| c[l] <= cut).map(|l| (w * 16 + l) as u32));
        }
    }
    let base = v.len() - tail.len();
    out.extend((0..tail.len()).filter(|&l| tail[l] <= cut).map(|l| (base + l) as u32));
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The exact similarity lies within the bounds the levels give, for values spread widely,
    /// embeddings outside the stored range and rows of every length.
    #[test]
    fn every_similarity_lies_within_its_bounds() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for case in 0..200 {
            let n = rng.gen_range(1..40);
            let rows = rng.gen_range(1..6);
            let scale: f32 = [1e-3, 0.3, 1.0, 50.0][case % 4];
            let shift: f32 = if case % 3 == 0 { -scale } else { 0.0 };
            let ltm: Vec<f32> = (0..rows * n * EMBEDDING).map(|_| shift + scale * rng.gen::<f32>()).collect();
            let e: [f32; EMBEDDING] = std::array::from_fn(|_| shift + 1.5 * scale * rng.gen::<f32>() - 0.2 * scale);
            let mut c = Coarse::default();
            assert!(c.pass(&e, &ltm, n));
            for i in 0..rows * n {
                let (row, j) = (i / n, i % n);
                let r = &ltm[row * EMBEDDING * n..];
                let sim = 1.0 - super::super::pairwise20(|k| (e[k] - r[k * n + j]).abs()) / EMBEDDING as f32;
                let (lo, hi) = c.bounds(i);
                assert!((lo..=hi).contains(&f64::from(sim)), "case {case}, couplet {i}: {sim} outside [{lo}, {hi}]");
                assert!(c.cut_above(f64::from(sim) - 1e-12).is_some_and(|cut| u32::from(c.distance[i]) <= cut));
            }
        }
    }

    /// A value outside the levels lays them out again; removing keeps the copy in step, and so
    /// does the couplet-by-couplet copy.
    #[test]
    fn the_copy_follows_appends_and_removals() {
        let n = 2;
        // Every value of a row different, so that a couplet read from the wrong place shows.
        let row = |v: f32| (0..EMBEDDING * n).map(|x| v + 1e-3 * x as f32).collect::<Vec<_>>();
        let in_step = |c: &Coarse, ltm: &[f32]| {
            assert_eq!(c.levels.len(), ltm.len());
            let gathered: Vec<f32> =
                (0..ltm.len() / EMBEDDING).flat_map(|i| super::super::similarity::couplet_at(ltm, n, i)).collect();
            assert_eq!(c.couplets, gathered);
        };
        let mut ltm = row(0.1);
        ltm.extend(row(0.2));
        let mut c = Coarse::default();
        let e = [0.15; EMBEDDING];
        assert!(c.pass(&e, &ltm, n));
        in_step(&c, &ltm);
        c.append(&row(0.12));
        ltm.extend(row(0.12));
        in_step(&c, &ltm);
        c.remove(0..EMBEDDING * n);
        ltm.drain(0..EMBEDDING * n);
        in_step(&c, &ltm);
        c.append(&row(9.0));
        ltm.extend(row(9.0));
        assert_eq!(c.step, 0.0, "a value far outside the range clears the copy");
        assert!(c.pass(&e, &ltm, n));
        in_step(&c, &ltm);
        assert!(!c.pass(&[f32::NAN; EMBEDDING], &ltm, n), "no bound for an embedding that is not finite");
        // The same values read as rows of another length are laid out again.
        assert!(c.pass(&e, &ltm, 1));
        assert_eq!(c.n, 1);
    }

    /// The vector copies give the scalar loop's distances, for rows of every block shape.
    #[test]
    fn every_copy_gives_the_same_distances() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        for n in 1..70 {
            let levels: Vec<u8> = (0..3 * n * EMBEDDING).map(|_| rng.gen()).collect();
            let qe: [u8; EMBEDDING] = std::array::from_fn(|_| rng.gen());
            let (mut a, mut b) = (vec![0; 3 * n], vec![0; 3 * n]);
            distances(&qe, &levels, n, &mut a);
            distances_scalar(&qe, &levels, n, &mut b);
            assert_eq!(a, b, "n = {n}");
            let want: Vec<u16> = (0..3 * n)
                .map(|i| {
                    (0..EMBEDDING).map(|k| u16::from(qe[k].abs_diff(levels[(i / n * EMBEDDING + k) * n + i % n]))).sum()
                })
                .collect();
            assert_eq!(b, want, "n = {n}");
        }
    }

    #[test]
    fn within_lists_the_couplets_at_or_under_the_cut_in_order() {
        let v: Vec<u16> = (0..100).map(|i| (i * 37 % 101) as u16).collect();
        let mut out = Vec::new();
        within_any(&v, 20, &mut out);
        let want: Vec<u32> = (0..100).filter(|&i| v[i as usize] <= 20).collect();
        assert_eq!(out, want);
    }
}

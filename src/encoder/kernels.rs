//! The inference kernels, channel-last (NHWC, one image). Each output channel sums its terms in
//! one fixed order (bias, then kernel row, column and input channel ascending); loops run across
//! output channels (or, in `planar`, across pixels), so vectorising them never reorders a sum and
//! every target gives the same bits. No fused multiply-add: Rust never contracts `a * b + c`.
//!
//! Convolutions are `valid` over their input; a `same` one reads an input with a border of zeros
//! (`pad1`, or `maxpool2` asked for a border), so every output pixel takes the same vectorised
//! path. The border's terms add zeros, which change at most the sign of a zero sum, and ReLU maps
//! both zeros to +0: the bits are those of skipping them.
//!
//! Most activations after a ReLU are exactly zero (70-84 % in the bundled models), so the
//! convolutions that read them (`conv3x3_relu_sparse`, `conv3x3_up2_relu`) first list each pixel's
//! nonzero values (`Sparse`) and sum only those terms, in the same order. A skipped term is a
//! product with zero: it could only change the sign of a zero sum, which ReLU maps to +0, so the
//! bits are those of the dense sum.
//!
//! The decoder's convolutions of a nearest-neighbour 2x upsampling never build it: each output
//! pixel's 3x3 window covers only 2x2 distinct input pixels, so the layer is four 2x2
//! convolutions of the input, one per output-pixel parity, with weights summed ahead (`Up2`):
//! 4/9 of the multiply-adds. The sums are then those of the folded weights, in the same fixed
//! order on every target.
//!
//! Work not done: where an output pixel's whole input window equals its left neighbour's, bit for
//! bit (a wall, the sky, a zero region: 58-93 % of the encoder's windows in a run), or else the
//! window of the pixel above (a wall's columns), the pixel takes that pixel's output instead of
//! summing again (`Repeats`). Equal inputs summed in the same order give equal bits, so this
//! changes nothing but the time.

use crate::dispatch::avx2_dispatch;

/// Where one convolution pass reads and writes: output pixel (i, j), for i < rows and j < cols,
/// is the K x K window of the input at row i + r0 and column j + c0, and goes to pixel
/// (sy * i + oy, sx * j + ox) of an output `ow` pixels wide.
#[derive(Clone, Copy, Debug)]
struct Pass {
    rows: usize,
    cols: usize,
    r0: usize,
    c0: usize,
    sy: usize,
    oy: usize,
    sx: usize,
    ox: usize,
    ow: usize,
}

impl Pass {
    /// The whole output of a plain `valid` convolution of an h x w input.
    fn plain(h: usize, w: usize) -> Pass {
        Pass { rows: h - 2, cols: w - 2, r0: 0, c0: 0, sy: 1, oy: 0, sx: 1, ox: 0, ow: w - 2 }
    }

    /// Output pixel (i, j) of the pass, as an index into the output's pixels.
    fn pixel(&self, i: usize, j: usize) -> usize {
        (self.sy * i + self.oy) * self.ow + self.sx * j + self.ox
    }
}

/// 3x3 `valid` convolution with ReLU: output (h-2) x (w-2). Weights are HWIO:
/// `[ky][kx][ci][co]`.
///
/// On x86-64 with AVX2 the same code runs compiled for 8-wide vectors; lanes are output
/// channels, so the result is bit-identical to the SSE2 and wasm builds.
#[allow(clippy::too_many_arguments)]
pub fn conv3x3_relu<const CI: usize, const CO: usize>(
    input: &[f32],
    h: usize,
    w: usize,
    weights: &[f32],
    bias: &[f32],
    repeats: &mut Repeats,
    out: &mut Vec<f32>,
) -> (usize, usize) {
    let pass = conv3x3_relu_computed::<CI, CO>(input, h, w, weights, bias, repeats, out);
    repeats.fill::<CO>(&pass, out);
    (pass.rows, pass.cols)
}

/// `conv3x3_relu` without the reused pixels' copies: only the pixels `repeats.todo` lists are
/// written (the others hold stale values until `Repeats::fill`, or are read through
/// `Repeats::sources`).
#[allow(clippy::too_many_arguments)]
fn conv3x3_relu_computed<const CI: usize, const CO: usize>(
    input: &[f32],
    h: usize,
    w: usize,
    weights: &[f32],
    bias: &[f32],
    repeats: &mut Repeats,
    out: &mut Vec<f32>,
) -> Pass {
    assert_eq!(input.len(), h * w * CI);
    let pass = Pass::plain(h, w);
    out.resize(pass.rows * pass.cols * CO, 0.0); // every value read is written: no need to clear
    repeats.mark::<CI>(input, h, w);
    repeats.plan(&pass, 3);
    conv_pass::<CI, CO, 3>(input, w, weights, bias, pass, &repeats.todo, out);
    pass
}

/// `conv3x3_relu` then `maxpool2`: the same bits, but a reused pixel is not copied; the pooling
/// reads the pixel whose output it took (most of the first layer's pixels are reused, and their
/// copies cost more than the pooling). `conv` holds the convolution's computed pixels; returns
/// the pooled size, border included.
#[allow(clippy::too_many_arguments)]
pub fn conv3x3_relu_maxpool2<const CI: usize, const CO: usize>(
    input: &[f32],
    h: usize,
    w: usize,
    weights: &[f32],
    bias: &[f32],
    repeats: &mut Repeats,
    conv: &mut Vec<f32>,
    border: usize,
    out: &mut Vec<f32>,
) -> (usize, usize) {
    let pass = conv3x3_relu_computed::<CI, CO>(input, h, w, weights, bias, repeats, conv);
    repeats.sources(&pass);
    maxpool2_via::<CO>(conv, &repeats.src, pass.rows, pass.cols, border, out)
}

/// Which pixels of an activation equal their left neighbour, and which the pixel above, in every
/// channel, bit for bit; and from that, which output pixels of a pass must be computed (`todo`)
/// and which take an output already there: the left neighbour's, where the K x K input window
/// equals the left neighbour's window (its K columns each equal the column to their left in all
/// K rows), else the one above's, where the window equals the window above (its K rows each
/// equal the row above in all K columns: a wall's columns, the sky). Rows are bit sets, so
/// activations wider than 128 pixels are computed in full.
#[derive(Clone, Debug)]
pub struct Repeats {
    /// Per input row, bit c: pixel c equals pixel c - 1 (bit 0 is never set).
    same: Vec<u128>,
    /// Per input row, bit c: pixel c equals the pixel above it (never set in row 0).
    above: Vec<u128>,
    /// Output pixels (i, j) of the pass to compute, row by row.
    todo: Vec<(u32, u32)>,
    /// Per output row of the pass, bit j: pixel (i, j) takes the output of (i, j - 1).
    left: Vec<u128>,
    /// Per output row of the pass, bit j: pixel (i, j) takes the output of (i - 1, j).
    up: Vec<u128>,
    /// The (rows, cols) of the pass `todo`, `left` and `up` were planned for.
    planned: (usize, usize),
    /// Per output pixel of a plain pass, the pixel whose output it has (`sources`).
    src: Vec<u32>,
    /// Whether windows are compared at all (`plain` computes every pixel).
    reuse: bool,
}

impl Default for Repeats {
    fn default() -> Self {
        Repeats {
            same: Vec::new(),
            above: Vec::new(),
            todo: Vec::new(),
            left: Vec::new(),
            up: Vec::new(),
            planned: (0, 0),
            src: Vec::new(),
            reuse: true,
        }
    }
}

/// Output pixels of a pass that took an output already computed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Reused {
    /// Those whose window equals their left neighbour's.
    pub left: usize,
    /// Those whose window equals the window above (and not the left one).
    pub above: usize,
}

impl Repeats {
    /// Scratch space that computes every output pixel: the reference the reuse is tested against.
    pub fn plain() -> Self {
        Repeats { reuse: false, ..Repeats::default() }
    }

    fn mark<const C: usize>(&mut self, input: &[f32], h: usize, w: usize) {
        assert_eq!(input.len(), h * w * C);
        self.same.clear();
        self.above.clear();
        if !(self.reuse && crate::reuse::on()) || w > 128 {
            return;
        }
        mark_rows::<C>(input, w, &mut self.same, &mut self.above);
    }

    /// Splits the pass's output pixels into those to compute and those to copy (after `mark` of
    /// its input). Without marks (reuse off, or a wide input), every pixel is computed.
    fn plan(&mut self, pass: &Pass, k: usize) {
        let (rows, cols) = (pass.rows, pass.cols);
        self.planned = (rows, cols);
        self.todo.clear();
        self.left.clear();
        self.left.resize(rows, 0);
        self.up.clear();
        self.up.resize(rows, 0);
        if self.same.is_empty() {
            self.todo.extend((0..rows).flat_map(|i| (0..cols).map(move |j| (i as u32, j as u32))));
            return;
        }
        assert!(pass.r0 + rows + k - 1 <= self.same.len() && pass.c0 + cols + k - 1 <= 128);
        assert!((2..=3).contains(&k) && pass.c0 <= 1, "a 2x2 or 3x3 window at column 0 or 1");
        let columns = if cols == 128 { u128::MAX } else { (1u128 << cols) - 1 };
        // Bit j: the marks of input columns c0 + j .. c0 + j + k are set in all k rows under
        // output row i's windows. (Shifts by constants: a variable one is a call in wasm.)
        let windows = |marks: &[u128], i: usize| {
            let column = marks[pass.r0 + i..][..k].iter().fold(u128::MAX, |m, &r| m & r);
            let all = column & column >> 1 & if k == 3 { column >> 2 } else { u128::MAX };
            (if pass.c0 == 1 { all >> 1 } else { all }) & columns
        };
        for i in 0..rows {
            // The window at j equals the one at j - 1 (each of its columns equals the column to
            // its left), else the one a row up (each of its rows equals the row above; the
            // pass's row above reads the input rows one higher).
            let left = windows(&self.same, i) & !1;
            let up = if i == 0 { 0 } else { windows(&self.above, i) & !left };
            (self.left[i], self.up[i]) = (left, up);
            let mut todo = !(left | up) & columns;
            while todo != 0 {
                self.todo.push((i as u32, todo.trailing_zeros()));
                todo &= todo - 1;
            }
        }
    }

    /// Output pixels of the last planned pass that took an output already computed.
    pub fn reused(&self) -> Reused {
        let count = |m: &[u128]| m.iter().map(|c| c.count_ones() as usize).sum();
        Reused { left: count(&self.left), above: count(&self.up) }
    }

    /// Gives each copied pixel its output, row by row: first those from the row above (complete
    /// by then), then runs from the left (whose source, computed or copied from above, is there).
    fn fill<const CO: usize>(&self, pass: &Pass, out: &mut [f32]) {
        for (i, (&left, &up)) in self.left.iter().zip(&self.up).enumerate() {
            let mut bits = up;
            while bits != 0 {
                let j = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                let (src, dst) = (pass.pixel(i - 1, j) * CO, pass.pixel(i, j) * CO);
                out.copy_within(src..src + CO, dst);
            }
            for (j, len) in runs_of(left) {
                // A run of copies j..j + len all take pixel j - 1's output.
                let v: [f32; CO] = out[pass.pixel(i, j - 1) * CO..][..CO].try_into().unwrap();
                for jj in j..j + len {
                    out[pass.pixel(i, jj) * CO..][..CO].copy_from_slice(&v);
                }
            }
        }
    }

    /// `fill` without copying: per output pixel of the (plain) pass just planned, row by row, the
    /// pixel whose output it has: itself where computed, else its source's (a copy of the pixel
    /// above takes that one's source, a run from the left its left neighbour's).
    fn sources(&mut self, pass: &Pass) {
        assert!(pass.sx == 1 && pass.sy == 1 && pass.ox == 0 && pass.oy == 0 && pass.ow == pass.cols);
        assert_eq!(self.planned, (pass.rows, pass.cols), "the pass was not planned");
        let (rows, cols) = (pass.rows, pass.cols);
        self.src.clear();
        self.src.extend(0..(rows * cols) as u32);
        for (i, (&left, &up)) in self.left.iter().zip(&self.up).enumerate() {
            if left | up == 0 {
                continue;
            }
            let (above, row) =
                self.src[i.saturating_sub(1) * cols..(i + 1) * cols].split_at_mut(if i == 0 { 0 } else { cols });
            // Whole runs at a time, without a branch per pixel: first the copies from above (that
            // row is complete), then the runs from the left, each of which takes the source of
            // the pixel before it (computed or copied from above: a run is maximal).
            for (j, len) in runs_of(up) {
                row[j..j + len].copy_from_slice(&above[j..j + len]);
            }
            for (j, len) in runs_of(left) {
                let s = row[j - 1];
                row[j..j + len].fill(s);
            }
        }
    }
}

/// The runs of set bits of `bits`, lowest first, each as (first bit, length). Without shifts by
/// a variable count (each one a call in wasm): adding its lowest bit carries through a run,
/// leaving the bit after it set.
#[inline(always)]
fn runs_of(mut bits: u128) -> impl Iterator<Item = (usize, usize)> {
    std::iter::from_fn(move || {
        if bits == 0 {
            return None;
        }
        let j = bits.trailing_zeros() as usize;
        let carried = bits.wrapping_add(bits & bits.wrapping_neg());
        // The bit after the run (128 when the run reaches the top bit).
        let end = (carried & !bits).trailing_zeros() as usize;
        bits &= carried;
        Some((j, end - j))
    })
}

avx2_dispatch! {
    /// `Repeats::mark`'s bits of each row of an activation `w` pixels wide (at most 128).
    fn mark_rows<const C: usize>(input: &[f32], w: usize, same: &mut Vec<u128>, above: &mut Vec<u128>) => mark_rows_any
}

#[inline(always)]
fn mark_rows_any<const C: usize>(input: &[f32], w: usize, same: &mut Vec<u128>, above: &mut Vec<u128>) {
    assert!(w <= 128);
    let mut prev: Option<&[f32]> = None;
    for row in input.chunks_exact(w * C) {
        same.push(row_bits(1..w, |c| equal_pixels::<C>(&row[c * C..], &row[(c - 1) * C..])));
        above.push(match prev {
            Some(prev) => row_bits(0..w, |c| equal_pixels::<C>(&row[c * C..], &prev[c * C..])),
            None => 0,
        });
        prev = Some(row);
    }
}

/// The bits of the pixels in `columns` (all below 128) where `equal` holds: made in two 64-bit
/// halves (a u128 shifted by a variable count is a call in wasm), without a branch per pixel.
#[inline(always)]
fn row_bits(columns: std::ops::Range<usize>, equal: impl Fn(usize) -> bool) -> u128 {
    let mut half = [0u64; 2];
    for c in columns {
        half[(c >> 6) & 1] |= u64::from(equal(c)) << (c & 63);
    }
    u128::from(half[1]) << 64 | u128::from(half[0])
}

/// Whether the first C values of `a` and `b` are the same bits: the OR of their XORed bits is
/// zero (a loop across the channels, then one test: no branch per value).
#[inline(always)]
fn equal_pixels<const C: usize>(a: &[f32], b: &[f32]) -> bool {
    let (a, b): (&[f32; C], &[f32; C]) = (a[..C].try_into().unwrap(), b[..C].try_into().unwrap());
    #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
    if C % 4 == 0 {
        return simd::equal_pixels::<C>(a, b);
    }
    let mut m = 0;
    for k in 0..C {
        m |= a[k].to_bits() ^ b[k].to_bits();
    }
    m == 0
}

/// The 3x3 weights of a convolution that reads a 2x nearest-neighbour upsampling, folded for
/// reading the input itself (see the module's comment). `border` is the zero border around the
/// upsampled image (1: a `same` convolution, 0: `valid`).
#[derive(Clone, Debug, PartialEq)]
pub struct Up2 {
    /// Per parity (py, px) in row-major order, a 2x2 kernel `[ty][tx][ci][co]`.
    weights: [Vec<f32>; 4],
    /// Per parity, the first of the two input rows (or columns) read, relative to the output
    /// pixel's half and counting the input's one-pixel border.
    first: [usize; 2],
    border: usize,
}

impl Up2 {
    /// Output pixel 2i + p of the upsampled image (border b) reads upsampled rows 2i + p + k - b,
    /// k = 0..3, i.e. input rows i + floor((p + k - b) / 2): two neighbours. Each 2x2 weight is
    /// the sum, in kernel row then column order, of the 3x3 weights that land on it.
    pub fn fold(weights: &[f32], ci: usize, co: usize, border: usize) -> Up2 {
        assert_eq!(weights.len(), 9 * ci * co);
        assert!(border <= 1);
        // floor((p + k - b) / 2) for p + k - b >= -1, as an offset from -1.
        let row = |p: usize, k: usize| (p + k + 2 - border) / 2;
        let first = [row(0, 0), row(1, 0)];
        let weights = std::array::from_fn(|parity| {
            let (py, px) = (parity / 2, parity % 2);
            let mut f = vec![0.0f32; 4 * ci * co];
            for ky in 0..3 {
                for kx in 0..3 {
                    let (ty, tx) = (row(py, ky) - first[py], row(px, kx) - first[px]);
                    let src = &weights[(ky * 3 + kx) * ci * co..][..ci * co];
                    for (d, &s) in f[(ty * 2 + tx) * ci * co..][..ci * co].iter_mut().zip(src) {
                        *d += s;
                    }
                }
            }
            f
        });
        Up2 { weights, first, border }
    }

    /// Output size for an h x w input (before its border).
    fn output(&self, h: usize, w: usize) -> (usize, usize) {
        (2 * h + 2 * self.border - 2, 2 * w + 2 * self.border - 2)
    }

    /// The four passes over an input of h x w pixels plus a one-pixel border.
    fn passes(&self, h: usize, w: usize) -> impl Iterator<Item = (Pass, &[f32])> + '_ {
        let (oh, ow) = self.output(h, w);
        assert!(oh % 2 == 0 && ow % 2 == 0);
        (0..4).map(move |parity| {
            let (py, px) = (parity / 2, parity % 2);
            let pass = Pass {
                rows: oh / 2,
                cols: ow / 2,
                r0: self.first[py],
                c0: self.first[px],
                sy: 2,
                oy: py,
                sx: 2,
                ox: px,
                ow,
            };
            (pass, &self.weights[parity][..])
        })
    }
}

/// 3x3 `valid` convolution with ReLU (as `conv3x3_relu`) of a mostly-zero input, through its
/// nonzero values: `sparse` is scratch space.
#[allow(clippy::too_many_arguments)]
pub fn conv3x3_relu_sparse<const CI: usize, const CO: usize>(
    input: &[f32],
    h: usize,
    w: usize,
    weights: &[f32],
    bias: &[f32],
    sparse: &mut Sparse,
    out: &mut Vec<f32>,
) -> (usize, usize) {
    let pass = conv3x3_relu_sparse_computed::<CI, CO>(input, h, w, weights, bias, sparse, out);
    sparse.repeats.fill::<CO>(&pass, out);
    (pass.rows, pass.cols)
}

/// `conv3x3_relu_sparse` without the reused pixels' copies (as `conv3x3_relu_computed`).
#[allow(clippy::too_many_arguments)]
fn conv3x3_relu_sparse_computed<const CI: usize, const CO: usize>(
    input: &[f32],
    h: usize,
    w: usize,
    weights: &[f32],
    bias: &[f32],
    sparse: &mut Sparse,
    out: &mut Vec<f32>,
) -> Pass {
    sparse.build::<CI>(input, h, w);
    let pass = Pass::plain(h, w);
    out.resize(pass.rows * pass.cols * CO, 0.0);
    sparse.repeats.plan(&pass, 3);
    sparse_pass::<CI, CO, 3>(sparse, weights, bias, pass, out);
    pass
}

/// `conv3x3_relu_sparse` then `maxpool2`, reading reused pixels where they were computed (as
/// `conv3x3_relu_maxpool2`).
#[allow(clippy::too_many_arguments)]
pub fn conv3x3_relu_sparse_maxpool2<const CI: usize, const CO: usize>(
    input: &[f32],
    h: usize,
    w: usize,
    weights: &[f32],
    bias: &[f32],
    sparse: &mut Sparse,
    conv: &mut Vec<f32>,
    border: usize,
    out: &mut Vec<f32>,
) -> (usize, usize) {
    let pass = conv3x3_relu_sparse_computed::<CI, CO>(input, h, w, weights, bias, sparse, conv);
    sparse.repeats.sources(&pass);
    maxpool2_via::<CO>(conv, &sparse.repeats.src, pass.rows, pass.cols, border, out)
}

/// 3x3 convolution with ReLU of the 2x nearest-neighbour upsampling of an h x w input, read
/// from the input (with a one-pixel zero border: (h + 2) x (w + 2)) through `Up2` weights and
/// the input's nonzero values (`sparse` is scratch space).
#[allow(clippy::too_many_arguments)]
pub fn conv3x3_up2_relu<const CI: usize, const CO: usize>(
    input: &[f32],
    h: usize,
    w: usize,
    up: &Up2,
    bias: &[f32],
    sparse: &mut Sparse,
    out: &mut Vec<f32>,
) -> (usize, usize) {
    sparse.build::<CI>(input, h + 2, w + 2);
    let (oh, ow) = up.output(h, w);
    out.resize(oh * ow * CO, 0.0);
    for (pass, weights) in up.passes(h, w) {
        sparse.repeats.plan(&pass, 2);
        sparse_pass::<CI, CO, 2>(sparse, weights, bias, pass, out);
        sparse.repeats.fill::<CO>(&pass, out);
    }
    (oh, ow)
}

/// The nonzero values of an activation of h x w pixels of CI channels, pixel by pixel: those of
/// pixel p are entries `start[p]..start[p + 1]`, each a value and its index within its row of
/// the activation (x * CI + ci), in channel order; and its `Repeats`.
#[derive(Clone, Debug, Default)]
pub struct Sparse {
    start: Vec<u32>,
    pos: Vec<u32>,
    val: Vec<f32>,
    repeats: Repeats,
    /// The activation's width and channels, checked by `sparse_pass`.
    w: usize,
    ci: usize,
}

/// For a mask of `lanes` bits (at most 8), the lanes whose bit is set, in order, then the others:
/// the order that packs a vector's nonzero lanes to its front (`Sparse::build`'s vector copies).
#[cfg(any(target_arch = "x86_64", all(target_arch = "wasm32", target_feature = "simd128")))]
const fn packed_lanes(m: usize, lanes: usize) -> [usize; 8] {
    let (mut order, mut k, mut set) = ([0; 8], 0, 0);
    while set < 2 {
        let mut lane = 0;
        while lane < lanes {
            if (m & (1 << lane) != 0) == (set == 0) {
                order[k] = lane;
                k += 1;
            }
            lane += 1;
        }
        set += 1;
    }
    order
}

/// `packed_lanes` of each 8-bit mask: the AVX2 permutation.
#[cfg(target_arch = "x86_64")]
static PACK: [[u32; 8]; 256] = {
    let mut t = [[0u32; 8]; 256];
    let mut m = 0;
    while m < 256 {
        let (order, mut k) = (packed_lanes(m, 8), 0);
        while k < 8 {
            t[m][k] = order[k] as u32;
            k += 1;
        }
        m += 1;
    }
    t
};

/// `Sparse::build`'s packing eight values at a time: each vector's nonzero values (and their
/// positions in the row) are permuted to its front and stored whole at the next free entry, which
/// then advances by their count. The entries up to the count are the scalar loop's; the ones
/// written past it are overwritten or never read. Returns the count.
///
/// # Safety
/// The CPU must support AVX2; `input`, `val` and `pos` hold the same number of values, a multiple
/// of `w * CI`, and `start` one per pixel; CI is a multiple of 8.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn pack_avx2<const CI: usize>(
    input: &[f32],
    w: usize,
    val: &mut [f32],
    pos: &mut [u32],
    start: &mut [u32],
) -> usize {
    use std::arch::x86_64::*;
    assert!(CI % 8 == 0 && input.len() == val.len() && val.len() == pos.len() && start.len() * CI == input.len());
    let (zero, lanes) = (_mm256_setzero_ps(), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
    let mut k = 0;
    for (p, px) in input.chunks_exact(CI).enumerate() {
        start[p] = k as u32;
        let x = p % w;
        for g in 0..CI / 8 {
            // SAFETY: k counts the nonzeros before this vector, so k + 8 <= its end <= the
            // length; the load reads the vector's 8 values, PACK's row is 8 indices.
            unsafe {
                let v = _mm256_loadu_ps(px.as_ptr().add(8 * g));
                let m = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_NEQ_UQ>(v, zero)) as usize;
                let perm = _mm256_loadu_si256(PACK[m].as_ptr() as *const __m256i);
                let at = _mm256_add_epi32(_mm256_set1_epi32((x * CI + 8 * g) as i32), lanes);
                _mm256_storeu_ps(val.as_mut_ptr().add(k), _mm256_permutevar8x32_ps(v, perm));
                _mm256_storeu_si256(pos.as_mut_ptr().add(k) as *mut __m256i, _mm256_permutevar8x32_epi32(at, perm));
                k += m.count_ones() as usize;
            }
        }
    }
    k
}

impl Sparse {
    fn build<const CI: usize>(&mut self, input: &[f32], h: usize, w: usize) {
        assert_eq!(input.len(), h * w * CI);
        assert!(h * w * CI <= u32::MAX as usize);
        (self.w, self.ci) = (w, CI);
        self.start.resize(h * w + 1, 0);
        // Every value is written at the next free entry, which advances only past nonzeros: no
        // branch per value. Entries past the last nonzero are never read, so these only grow
        // (growing writes zeros, and the layers alternate in size).
        if self.val.len() < h * w * CI {
            self.pos.resize(h * w * CI, 0);
            self.val.resize(h * w * CI, 0.0);
        }
        let n = h * w * CI;
        let (val, pos, start) = (&mut self.val[..n], &mut self.pos[..n], &mut self.start[..h * w]);
        #[cfg(target_arch = "x86_64")]
        if CI % 8 == 0 && crate::dispatch::avx2() {
            // SAFETY: the CPU supports AVX2, checked just above; the lengths are as `pack_avx2` asks.
            self.start[h * w] = unsafe { pack_avx2::<CI>(input, w, val, pos, start) } as u32;
            self.repeats.mark::<CI>(input, h, w);
            return;
        }
        #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
        if CI % 4 == 0 {
            self.start[h * w] = simd::pack::<CI>(input, w, val, pos, start) as u32;
            self.repeats.mark::<CI>(input, h, w);
            return;
        }
        let mut k = 0;
        for (y, row) in input.chunks_exact(w * CI).enumerate() {
            for (x, px) in row.chunks_exact(CI).enumerate() {
                start[y * w + x] = k as u32;
                for (ci, &v) in px.iter().enumerate() {
                    // SAFETY: k counts the nonzeros before this value, so k <= its index < n.
                    unsafe {
                        *val.get_unchecked_mut(k) = v;
                        *pos.get_unchecked_mut(k) = (x * CI + ci) as u32;
                    }
                    k += (v != 0.0) as usize;
                }
            }
        }
        self.start[h * w] = k as u32;
        self.repeats.mark::<CI>(input, h, w);
    }

    /// Output pixels of the last pass that took an output already computed.
    pub fn reused(&self) -> Reused {
        self.repeats.reused()
    }

    /// Scratch space whose convolutions compute every output pixel (see `Repeats::plain`).
    pub fn plain() -> Self {
        Sparse { repeats: Repeats::plain(), ..Sparse::default() }
    }
}

/// One pass of a K x K convolution with ReLU through the input's nonzero values: for output
/// pixel (i, j) and kernel row ky, the entries of the K input pixels under the window are
/// adjacent in `sparse`, in kernel column then channel order, so one loop sums them.
fn sparse_pass<const CI: usize, const CO: usize, const K: usize>(
    sparse: &Sparse,
    weights: &[f32],
    bias: &[f32],
    pass: Pass,
    out: &mut [f32],
) {
    #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
    match CO {
        32 => return simd::sparse_pass::<CI, CO, K, 8>(sparse, weights, bias, pass, out),
        16 => return simd::sparse_pass::<CI, CO, K, 4>(sparse, weights, bias, pass, out),
        _ => {}
    }
    #[allow(unreachable_code)]
    sparse_pass_native::<CI, CO, K>(sparse, weights, bias, pass, out)
}

avx2_dispatch! {
    fn sparse_pass_native<const CI: usize, const CO: usize, const K: usize>(
        sparse: &Sparse, weights: &[f32], bias: &[f32], pass: Pass, out: &mut [f32]
    ) => sparse_pass_any
}

/// The checks every version of `sparse_pass` relies on: the activation's geometry, the window
/// inside it, the weights' and the output's sizes.
fn check_sparse_pass<const CI: usize, const CO: usize, const K: usize>(
    sparse: &Sparse,
    weights: &[f32],
    bias: &[f32],
    pass: &Pass,
    out: &[f32],
) {
    let w = sparse.w;
    assert!(sparse.ci == CI && w > 0 && sparse.start.len() % w == 1);
    assert!(pass.r0 + pass.rows + K - 1 <= sparse.start.len() / w && pass.c0 + pass.cols + K - 1 <= w);
    assert!(weights.len() == K * K * CI * CO && bias.len() == CO);
    assert!(pass.pixel(pass.rows - 1, pass.cols - 1) * CO + CO <= out.len());
    // `todo` lists pixels (i, j) with i < rows and j < cols of the pass it was planned for.
    assert_eq!(sparse.repeats.planned, (pass.rows, pass.cols), "the pass was not planned");
}

#[inline(always)]
fn sparse_pass_any<const CI: usize, const CO: usize, const K: usize>(
    sparse: &Sparse,
    weights: &[f32],
    bias: &[f32],
    pass: Pass,
    out: &mut [f32],
) {
    check_sparse_pass::<CI, CO, K>(sparse, weights, bias, &pass, out);
    let (w, bias) = (sparse.w, <&[f32; CO]>::try_from(bias).unwrap());
    for &(i, j) in &sparse.repeats.todo {
        let (i, j) = (i as usize, j as usize);
        {
            let mut acc = *bias;
            for ky in 0..K {
                let p0 = (pass.r0 + i + ky) * w + pass.c0 + j;
                let (a, b) = (sparse.start[p0] as usize, sparse.start[p0 + K] as usize);
                // Entry (x, ci) meets weight [ky][x - c0 - j][ci].
                let skip = (pass.c0 + j) * CI;
                let wk = &weights[ky * K * CI * CO..][..K * CI * CO];
                for (&v, &pos) in sparse.val[a..b].iter().zip(&sparse.pos[a..b]) {
                    let wr: &[f32; CO] = wk[(pos as usize - skip) * CO..][..CO].try_into().unwrap();
                    for co in 0..CO {
                        acc[co] += v * wr[co];
                    }
                }
            }
            let o = &mut out[pass.pixel(i, j) * CO..][..CO];
            for co in 0..CO {
                o[co] = relu(acc[co]);
            }
        }
    }
}

avx2_dispatch! {
    /// One pass of a K x K convolution with ReLU over an input `w` pixels wide: the output pixels
    /// `todo` lists (`Repeats::plan` of this pass).
    fn conv_pass<const CI: usize, const CO: usize, const K: usize>(
        input: &[f32], w: usize, weights: &[f32], bias: &[f32], pass: Pass, todo: &[(u32, u32)], out: &mut [f32]
    ) => conv_pass_any
}

#[inline(always)]
fn conv_pass_any<const CI: usize, const CO: usize, const K: usize>(
    input: &[f32],
    w: usize,
    weights: &[f32],
    bias: &[f32],
    pass: Pass,
    todo: &[(u32, u32)],
    out: &mut [f32],
) {
    assert_eq!(weights.len(), K * K * CI * CO);
    assert!(pass.r0 + pass.rows + K - 1 <= input.len() / (w * CI) && pass.c0 + pass.cols + K - 1 <= w);
    assert!(pass.pixel(pass.rows - 1, pass.cols - 1) * CO + CO <= out.len());
    let bias: &[f32; CO] = bias.try_into().expect("one bias per output channel");
    #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
    if CO % 16 == 0 {
        // Few input channels (the first layer) leave time for more pixels per weight load.
        if CI <= 4 {
            for block in blocks::<4>(pass, todo) {
                simd::conv_block::<CI, CO, K, 4, 2>(input, w, weights, bias, pass, block, out);
            }
        } else {
            for block in blocks::<2>(pass, todo) {
                simd::conv_block::<CI, CO, K, 2, 4>(input, w, weights, bias, pass, block, out);
            }
        }
        return;
    }
    for block in blocks::<BLOCK>(pass, todo) {
        conv_block::<CI, CO, K>(input, w, weights, bias, pass, block, out);
    }
}

/// The output pixels `todo` lists, B at a time, each as (i, j) of the pass. Blocks of pixels
/// share each weight load. The last block repeats its last pixel when B does not divide the
/// count; a repeated pixel is computed again the same way. (An iterator, not a callback: a
/// closure holding a kernel was not inlined into the AVX2 copies and ran without AVX2, ten times
/// slower.)
#[inline(always)]
fn blocks<const B: usize>(pass: Pass, todo: &[(u32, u32)]) -> impl Iterator<Item = [(usize, usize); B]> + '_ {
    todo.chunks(B).map(move |c| {
        std::array::from_fn(|p| {
            let (i, j) = c[p.min(c.len() - 1)];
            let (i, j) = (i as usize, j as usize);
            assert!(i < pass.rows && j < pass.cols, "a pixel outside the pass");
            (i, j)
        })
    })
}

/// The runs of B pixels (i, j..j + B) of the pass, row by row. The last run of a row overlaps
/// the one before when B does not divide the width; its pixels are computed again the same way.
#[inline(always)]
fn runs<const B: usize>(pass: Pass) -> impl Iterator<Item = (usize, usize)> {
    assert!(pass.cols >= B, "the output must be at least {B} pixels wide");
    let (cols, per_row) = (pass.cols, pass.cols.div_ceil(B));
    (0..pass.rows).flat_map(move |i| (0..per_row).map(move |k| (i, (k * B).min(cols - B))))
}

/// Output pixels convolved together.
#[cfg(not(target_arch = "wasm32"))]
const BLOCK: usize = 4;
/// In wasm without simd128 (the fallback build): same bits either way.
#[cfg(target_arch = "wasm32")]
const BLOCK: usize = 2;

/// The output pixels of one block (each inside the pass, checked by `blocks`).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn conv_block<const CI: usize, const CO: usize, const K: usize>(
    input: &[f32],
    w: usize,
    weights: &[f32],
    bias: &[f32; CO],
    pass: Pass,
    block: [(usize, usize); BLOCK],
    out: &mut [f32],
) {
    let mut acc = [*bias; BLOCK];
    for ky in 0..K {
        let rows: [&[f32]; BLOCK] = std::array::from_fn(|p| {
            let (i, j) = block[p];
            &input[((pass.r0 + i + ky) * w + pass.c0 + j) * CI..][..K * CI]
        });
        for kx in 0..K {
            let wk = &weights[(ky * K + kx) * CI * CO..][..CI * CO];
            for ci in 0..CI {
                let wr: &[f32; CO] = wk[ci * CO..][..CO].try_into().unwrap();
                for (a, row) in acc.iter_mut().zip(&rows) {
                    let v = row[kx * CI + ci];
                    for co in 0..CO {
                        a[co] += v * wr[co];
                    }
                }
            }
        }
    }
    for (a, &(i, j)) in acc.iter().zip(&block) {
        let o = &mut out[pass.pixel(i, j) * CO..][..CO];
        for co in 0..CO {
            o[co] = relu(a[co]);
        }
    }
}

/// The kernels written with wasm simd128 instructions. Each lane does what the portable loops
/// do, in the same order (multiply, then add; ReLU as max with 0), so the bits are the same.
#[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
mod simd {
    use super::Pass;
    use core::arch::wasm32::*;

    /// The output pixels of one block (each inside the pass, checked by `blocks`). Wasm engines
    /// have 16 vector registers, so a block accumulates P pixels x NV vectors of 4 output
    /// channels at a time and walks the channel groups in turn.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub fn conv_block<const CI: usize, const CO: usize, const K: usize, const P: usize, const NV: usize>(
        input: &[f32],
        w: usize,
        weights: &[f32],
        bias: &[f32; CO],
        pass: Pass,
        block: [(usize, usize); P],
        out: &mut [f32],
    ) {
        let first: [usize; P] = std::array::from_fn(|p| ((pass.r0 + block[p].0) * w + pass.c0 + block[p].1) * CI);
        let to: [usize; P] = std::array::from_fn(|p| pass.pixel(block[p].0, block[p].1) * CO);
        assert!(weights.len() == K * K * CI * CO && CO % (4 * NV) == 0);
        for p in 0..P {
            assert!(first[p] + ((K - 1) * w + K) * CI <= input.len());
            assert!(to[p] + CO <= out.len());
        }
        // The hot loop reads without a bounds check per load. Weights: every index is
        // (ky * K + kx) * CI * CO + ci * CO + g0 + 4 * v + 3 < K * K * CI * CO = weights.len().
        // Inputs: first[p] + (ky * w + kx) * CI + ci < first[p] + ((K - 1) * w + K) * CI.
        // Outputs: to[p] + g0 + 4 * v + 3 < to[p] + CO. All asserted above.
        let (wp, ip, op) = (weights.as_ptr(), input.as_ptr(), out.as_mut_ptr());
        let zero = f32x4_splat(0.0);
        // A short channel loop (the first layer's 3) hidden from the optimiser: unrolled, its
        // loads and products are all live at once and V8 spills them (0.24 -> 0.17 ms).
        let channels = if CI <= 4 { core::hint::black_box(CI) } else { CI };
        for g0 in (0..CO).step_by(4 * NV) {
            // SAFETY (all loads and stores below): in bounds, see above; v128 loads and stores
            // have no alignment requirement.
            let mut acc = [[zero; NV]; P];
            for a in acc.iter_mut() {
                for (v, x) in a.iter_mut().enumerate() {
                    *x = unsafe { v128_load(bias.as_ptr().add(g0 + 4 * v) as *const v128) };
                }
            }
            for ky in 0..K {
                for kx in 0..K {
                    let base = (ky * K + kx) * CI * CO + g0;
                    let shift = (ky * w + kx) * CI;
                    for ci in 0..channels {
                        let wr: [v128; NV] = std::array::from_fn(|v| unsafe {
                            v128_load(wp.add(base + ci * CO + 4 * v) as *const v128)
                        });
                        for (p, a) in acc.iter_mut().enumerate() {
                            // One load that fills the four lanes, no shuffle.
                            let x = unsafe { v128_load32_splat(ip.add(first[p] + shift + ci) as *const u32) };
                            for v in 0..NV {
                                a[v] = f32x4_add(a[v], f32x4_mul(x, wr[v]));
                            }
                        }
                    }
                }
            }
            for (p, a) in acc.iter().enumerate() {
                let o = to[p] + g0;
                for (v, &x) in a.iter().enumerate() {
                    unsafe { v128_store(op.add(o + 4 * v) as *mut v128, f32x4_pmax(zero, x)) };
                }
            }
        }
    }

    /// `super::equal_pixels` for C a multiple of 4: the OR of the XORed vectors has no bit set.
    #[inline(always)]
    pub fn equal_pixels<const C: usize>(a: &[f32; C], b: &[f32; C]) -> bool {
        let mut m = i32x4_splat(0);
        for g in 0..C / 4 {
            // SAFETY: 4 * g + 3 < C, inside both arrays; v128 loads need no alignment.
            let (x, y) = unsafe {
                (v128_load(a.as_ptr().add(4 * g) as *const v128), v128_load(b.as_ptr().add(4 * g) as *const v128))
            };
            m = v128_or(m, v128_xor(x, y));
        }
        !v128_any_true(m)
    }

    /// `packed_lanes` of each 4-bit mask, as the bytes of those lanes: the `i8x16.swizzle`.
    static PACK: [[u8; 16]; 16] = {
        let mut t = [[0u8; 16]; 16];
        let mut m = 0;
        while m < 16 {
            let order = super::packed_lanes(m, 4);
            let mut b = 0;
            while b < 16 {
                t[m][b] = (4 * order[b / 4] + b % 4) as u8;
                b += 1;
            }
            m += 1;
        }
        t
    };

    /// `Sparse::build`'s packing four values at a time (as `pack_avx2` does eight): each
    /// vector's nonzero values and their positions are swizzled to its front and stored whole at
    /// the next free entry, which then advances by their count. The entries up to the count are
    /// the scalar loop's; those written past it are overwritten or never read. Returns the count.
    pub fn pack<const CI: usize>(
        input: &[f32],
        w: usize,
        val: &mut [f32],
        pos: &mut [u32],
        start: &mut [u32],
    ) -> usize {
        assert!(CI % 4 == 0 && w > 0 && input.len() == val.len() && val.len() == pos.len());
        assert!(start.len() * CI == input.len());
        let (zero, lanes) = (f32x4_splat(0.0), u32x4(0, 1, 2, 3));
        let (mut k, mut x) = (0, 0);
        for (p, px) in input.chunks_exact(CI).enumerate() {
            start[p] = k as u32;
            for g in 0..CI / 4 {
                // SAFETY: k counts the nonzeros before this vector, so k + 4 <= its end <= the
                // length of `val` and `pos`; the load reads the vector's 4 values of `px`.
                unsafe {
                    let v = v128_load(px.as_ptr().add(4 * g) as *const v128);
                    let m = i32x4_bitmask(f32x4_ne(v, zero)) as usize;
                    let perm = v128_load(PACK[m].as_ptr() as *const v128);
                    let at = u32x4_add(u32x4_splat((x * CI + 4 * g) as u32), lanes);
                    v128_store(val.as_mut_ptr().add(k) as *mut v128, i8x16_swizzle(v, perm));
                    v128_store(pos.as_mut_ptr().add(k) as *mut v128, i8x16_swizzle(at, perm));
                    k += m.count_ones() as usize;
                }
            }
            x = if x + 1 == w { 0 } else { x + 1 };
        }
        k
    }

    /// `sparse_pass` in simd128: one output pixel's CO channels in NV = CO / 4 accumulators.
    pub fn sparse_pass<const CI: usize, const CO: usize, const K: usize, const NV: usize>(
        sparse: &super::Sparse,
        weights: &[f32],
        bias: &[f32],
        pass: Pass,
        out: &mut [f32],
    ) {
        super::check_sparse_pass::<CI, CO, K>(sparse, weights, bias, &pass, out);
        assert_eq!(4 * NV, CO);
        let w = sparse.w;
        let (wp, vp, pp, op) = (weights.as_ptr(), sparse.val.as_ptr(), sparse.pos.as_ptr(), out.as_mut_ptr());
        let zero = f32x4_splat(0.0);
        // SAFETY (the unchecked loads and stores below): by `check_sparse_pass`, every listed
        // output pixel is inside the pass, the window's K
        // pixels p0..p0 + K lie in one row of the activation, so their entries a..b are
        // within `val` and `pos` (`build` writes `start` ascending up to their length), and
        // each entry's pos - skip = (x - c0 - j) * CI + ci with 0 <= x - c0 - j < K and
        // ci < CI, so the weight row read is inside `weights`; the output pixel is inside
        // `out`. v128 loads and stores have no alignment requirement.
        for &(i, j) in &sparse.repeats.todo {
            let (i, j) = (i as usize, j as usize);
            {
                let mut acc: [v128; NV] =
                    std::array::from_fn(|g| unsafe { v128_load(bias.as_ptr().add(4 * g) as *const v128) });
                for ky in 0..K {
                    let p0 = (pass.r0 + i + ky) * w + pass.c0 + j;
                    let (a, b) = (sparse.start[p0] as usize, sparse.start[p0 + K] as usize);
                    let skip = (pass.c0 + j) * CI;
                    let wk = ky * K * CI * CO;
                    for e in a..b {
                        let (v, pos) = unsafe { (v128_load32_splat(vp.add(e) as *const u32), *pp.add(e) as usize) };
                        let row = wk + (pos - skip) * CO;
                        for (g, x) in acc.iter_mut().enumerate() {
                            let wv = unsafe { v128_load(wp.add(row + 4 * g) as *const v128) };
                            *x = f32x4_add(*x, f32x4_mul(v, wv));
                        }
                    }
                }
                let o = pass.pixel(i, j) * CO;
                for (g, &x) in acc.iter().enumerate() {
                    unsafe { v128_store(op.add(o + 4 * g) as *mut v128, f32x4_pmax(zero, x)) };
                }
            }
        }
    }

    /// `planar_pass` in simd128: LANES pixels x CO channels of accumulators (LANES / 4 vectors
    /// each), the same sums lane by lane.
    #[allow(clippy::too_many_arguments)]
    pub fn planar_pass<const CI: usize, const CO: usize, const K: usize>(
        planes: &[f32],
        ph: usize,
        pw: usize,
        weights: &[f32],
        bias: &[f32],
        pass: Pass,
        out: &mut [f32],
    ) {
        const V: usize = super::LANES / 4;
        assert!(planes.len() == CI * ph * pw && weights.len() == K * K * CI * CO && bias.len() == CO);
        assert!(pass.r0 + pass.rows + K - 1 <= ph && pass.c0 + pass.cols + K - 1 <= pw);
        // Unchecked reads: input indices are at most ((CI - 1) * ph + r0 + rows + K - 2) * pw +
        // c0 + cols + K - 2 < CI * ph * pw, weights at most K * K * CI * CO - 1; both asserted
        // above.
        let (pp, wp) = (planes.as_ptr(), weights.as_ptr());
        let zero = f32x4_splat(0.0);
        for (i, j) in super::runs::<{ super::LANES }>(pass) {
            let mut acc: [[v128; V]; CO] = std::array::from_fn(|co| [f32x4_splat(bias[co]); V]);
            for ky in 0..K {
                for kx in 0..K {
                    for ci in 0..CI {
                        let src = (ci * ph + pass.r0 + i + ky) * pw + pass.c0 + j + kx;
                        // SAFETY: in bounds, see `pp`; no alignment requirement.
                        let x: [v128; V] =
                            std::array::from_fn(|l| unsafe { v128_load(pp.add(src + 4 * l) as *const v128) });
                        let wr = ((ky * K + kx) * CI + ci) * CO;
                        for (co, a) in acc.iter_mut().enumerate() {
                            // SAFETY: in bounds, see `wp`.
                            let wv = unsafe { v128_load32_splat(wp.add(wr + co) as *const u32) };
                            for l in 0..V {
                                a[l] = f32x4_add(a[l], f32x4_mul(x[l], wv));
                            }
                        }
                    }
                }
            }
            for (co, a) in acc.iter().enumerate() {
                for (l, &v) in a.iter().enumerate() {
                    let r = f32x4_pmax(zero, v);
                    let lanes = [
                        f32x4_extract_lane::<0>(r),
                        f32x4_extract_lane::<1>(r),
                        f32x4_extract_lane::<2>(r),
                        f32x4_extract_lane::<3>(r),
                    ];
                    for (k, &x) in lanes.iter().enumerate() {
                        out[pass.pixel(i, j + 4 * l + k) * CO + co] = x;
                    }
                }
            }
        }
    }
}

/// The input with a border of one zero pixel: (h + 2) x (w + 2), for a `same` convolution.
pub fn pad1(input: &[f32], h: usize, w: usize, c: usize, out: &mut Vec<f32>) -> (usize, usize) {
    assert_eq!(input.len(), h * w * c);
    let (ph, pw) = (h + 2, w + 2);
    out.resize(ph * pw * c, 0.0);
    zero_border(out, ph, pw, c, 1);
    for y in 0..h {
        out[((y + 1) * pw + 1) * c..][..w * c].copy_from_slice(&input[y * w * c..][..w * c]);
    }
    (ph, pw)
}

/// Zeros the outer `border` pixels of an h x w image of c channels, channel-last: the callers
/// write every other value, so the buffer is not cleared first (it is reused, call after call).
fn zero_border(out: &mut [f32], h: usize, w: usize, c: usize, border: usize) {
    if border == 0 {
        return;
    }
    assert!(out.len() == h * w * c && h >= 2 * border && w >= 2 * border);
    out[..border * w * c].fill(0.0);
    out[(h - border) * w * c..].fill(0.0);
    for y in border..h - border {
        out[y * w * c..][..border * c].fill(0.0);
        out[((y + 1) * w - border) * c..][..border * c].fill(0.0);
    }
}

/// `pad1` into planar form: one (h + 2) x (w + 2) plane per channel, for `conv3x3_up2_relu_planar`.
pub fn pad1_planar(input: &[f32], h: usize, w: usize, c: usize, out: &mut Vec<f32>) -> (usize, usize) {
    assert_eq!(input.len(), h * w * c);
    let (ph, pw) = (h + 2, w + 2);
    out.resize(c * ph * pw, 0.0);
    // Each plane's border is zeroed, the rest written below (the buffer is reused, not cleared).
    for plane in out.chunks_exact_mut(ph * pw) {
        zero_border(plane, ph, pw, 1, 1);
    }
    for y in 0..h {
        for x in 0..w {
            for (k, &v) in input[(y * w + x) * c..][..c].iter().enumerate() {
                out[(k * ph + y + 1) * pw + x + 1] = v;
            }
        }
    }
    (ph, pw)
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
/// pools over the remaining row or column only (21 -> 11). With `border` 1 the output gets a
/// border of zeros for the next `same` convolution. Returns the output's size, border included.
pub fn maxpool2<const C: usize>(
    input: &[f32],
    h: usize,
    w: usize,
    border: usize,
    out: &mut Vec<f32>,
) -> (usize, usize) {
    assert_eq!(input.len(), h * w * C);
    pool2::<C>(input, h, w, border, out, |p| p)
}

/// `maxpool2` of an h x w activation whose pixel p is stored at pixel `src[p]` of `input`.
fn maxpool2_via<const C: usize>(
    input: &[f32],
    src: &[u32],
    h: usize,
    w: usize,
    border: usize,
    out: &mut Vec<f32>,
) -> (usize, usize) {
    assert!(input.len() == h * w * C && src.len() == h * w);
    pool2::<C>(input, h, w, border, out, |p| src[p] as usize)
}

/// `maxpool2` reading pixel p at `at(p)`. All inputs are ReLU outputs (no NaN, no -0), so the
/// maximum does not depend on the order its values come in.
#[inline(always)]
fn pool2<const C: usize>(
    input: &[f32],
    h: usize,
    w: usize,
    border: usize,
    out: &mut Vec<f32>,
    at: impl Fn(usize) -> usize,
) -> (usize, usize) {
    let (oh, ow) = (h.div_ceil(2), w.div_ceil(2));
    let (bh, bw) = (oh + 2 * border, ow + 2 * border);
    out.resize(bh * bw * C, 0.0);
    zero_border(out, bh, bw, C, border);
    for oy in 0..oh {
        for ox in 0..ow {
            let o: &mut [f32; C] = (&mut out[((oy + border) * bw + ox + border) * C..][..C]).try_into().unwrap();
            *o = [f32::NEG_INFINITY; C];
            for iy in 2 * oy..(2 * oy + 2).min(h) {
                for ix in 2 * ox..(2 * ox + 2).min(w) {
                    let p: &[f32; C] = input[at(iy * w + ix) * C..][..C].try_into().unwrap();
                    for k in 0..C {
                        o[k] = pmax(o[k], p[k]);
                    }
                }
            }
        }
    }
    (bh, bw)
}

/// Pixels one run of `planar_pass` covers: 2 AVX2 registers per channel.
#[cfg(not(target_arch = "wasm32"))]
const LANES: usize = 16;
/// In wasm 3 simd128 registers per channel, so that 3 channels' accumulators and a row of inputs
/// fit the engines' 16 vector registers.
#[cfg(target_arch = "wasm32")]
const LANES: usize = 12;

/// `conv3x3_up2_relu` for layers with few output channels (the decoder's last, 16 -> 3), where
/// vectors across channels would be mostly empty: lanes are adjacent output pixels of a pass
/// instead. Input: the planes of `pad1_planar` (h x w before the border); output channel-last.
pub fn conv3x3_up2_relu_planar<const CI: usize, const CO: usize>(
    planes: &[f32],
    h: usize,
    w: usize,
    up: &Up2,
    bias: &[f32],
    out: &mut Vec<f32>,
) -> (usize, usize) {
    let (oh, ow) = up.output(h, w);
    out.resize(oh * ow * CO, 0.0);
    for (pass, weights) in up.passes(h, w) {
        planar_pass::<CI, CO, 2>(planes, h + 2, w + 2, weights, bias, pass, out);
    }
    (oh, ow)
}

fn planar_pass<const CI: usize, const CO: usize, const K: usize>(
    planes: &[f32],
    ph: usize,
    pw: usize,
    weights: &[f32],
    bias: &[f32],
    pass: Pass,
    out: &mut [f32],
) {
    #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
    return simd::planar_pass::<CI, CO, K>(planes, ph, pw, weights, bias, pass, out);
    #[allow(unreachable_code)]
    planar_pass_native::<CI, CO, K>(planes, ph, pw, weights, bias, pass, out)
}

avx2_dispatch! {
    fn planar_pass_native<const CI: usize, const CO: usize, const K: usize>(
        planes: &[f32], ph: usize, pw: usize, weights: &[f32], bias: &[f32], pass: Pass, out: &mut [f32]
    ) => planar_pass_any
}

/// Each output sums bias, then kernel row, column and input channel ascending, like `conv_pass`.
#[inline(always)]
fn planar_pass_any<const CI: usize, const CO: usize, const K: usize>(
    planes: &[f32],
    ph: usize,
    pw: usize,
    weights: &[f32],
    bias: &[f32],
    pass: Pass,
    out: &mut [f32],
) {
    assert_eq!(planes.len(), CI * ph * pw);
    assert_eq!(weights.len(), K * K * CI * CO);
    assert_eq!(bias.len(), CO);
    for (i, j) in runs::<LANES>(pass) {
        let mut acc = [[0.0f32; LANES]; CO];
        for (a, &b) in acc.iter_mut().zip(bias) {
            *a = [b; LANES];
        }
        for ky in 0..K {
            for kx in 0..K {
                for ci in 0..CI {
                    let src: &[f32; LANES] =
                        planes[(ci * ph + pass.r0 + i + ky) * pw + pass.c0 + j + kx..][..LANES].try_into().unwrap();
                    let wr = &weights[((ky * K + kx) * CI + ci) * CO..][..CO];
                    for (a, &wv) in acc.iter_mut().zip(wr) {
                        for l in 0..LANES {
                            a[l] += src[l] * wv;
                        }
                    }
                }
            }
        }
        for l in 0..LANES {
            let o = &mut out[pass.pixel(i, j + l) * CO..][..CO];
            for co in 0..CO {
                o[co] = relu(acc[co][l]);
            }
        }
    }
}

/// Dense layer `out = b + x W` (W is `[in][out]`), optionally with ReLU. With ReLU, zero inputs
/// (most of the encoder's, after its last ReLU and pooling) are skipped: a skipped term could only
/// change the sign of a zero sum, which ReLU maps to +0.
pub fn dense(x: &[f32], weights: &[f32], bias: &[f32], relu: bool, out: &mut [f32]) {
    let n = bias.len();
    assert_eq!(out.len(), n);
    assert_eq!(weights.len(), x.len() * n);
    dense_native(x, weights, bias, relu, out);
}

/// `dense` into an array: a few sums (the encoder's bottleneck) kept in registers rather than
/// in memory, the same terms in the same order.
pub fn dense_fixed<const N: usize>(x: &[f32], weights: &[f32], bias: &[f32], relu: bool, out: &mut [f32; N]) {
    assert_eq!(bias.len(), N);
    assert_eq!(weights.len(), x.len() * N);
    dense_fixed_native::<N>(x, weights, bias, relu, out);
}

avx2_dispatch! {
    fn dense_native(x: &[f32], weights: &[f32], bias: &[f32], relu: bool, out: &mut [f32]) => dense_any
}

avx2_dispatch! {
    fn dense_fixed_native<const N: usize>(x: &[f32], weights: &[f32], bias: &[f32], relu: bool, out: &mut [f32; N])
        => dense_fixed_any
}

#[inline(always)]
fn dense_any(x: &[f32], weights: &[f32], bias: &[f32], relu: bool, out: &mut [f32]) {
    out.copy_from_slice(bias);
    dense_terms(x, weights, relu, out);
    if relu {
        for o in out.iter_mut() {
            *o = self::relu(*o);
        }
    }
}

#[inline(always)]
fn dense_fixed_any<const N: usize>(x: &[f32], weights: &[f32], bias: &[f32], relu: bool, out: &mut [f32; N]) {
    let mut acc: [f32; N] = bias.try_into().expect("one bias per output");
    dense_terms(x, weights, relu, &mut acc);
    *out = if relu { acc.map(self::relu) } else { acc };
}

/// Adds each input's term to `out` (`dense`'s sums after their bias), inputs ascending.
#[inline(always)]
fn dense_terms(x: &[f32], weights: &[f32], relu: bool, out: &mut [f32]) {
    let n = out.len();
    let mut term = |i: usize| {
        let (v, row) = (x[i], &weights[i * n..][..n]);
        for (o, &wv) in out.iter_mut().zip(row) {
            *o += v * wv;
        }
    };
    for (k, chunk) in x.chunks(64).enumerate() {
        // The terms of this chunk's inputs, ascending; with ReLU only the nonzero ones, found
        // without a branch per input (most are zero: a branch would mispredict).
        let mut todo = chunk.iter().enumerate().fold(0u64, |m, (b, &v)| m | (((v != 0.0) | !relu) as u64) << b);
        while todo != 0 {
            term(k * 64 + todo.trailing_zeros() as usize);
            todo &= todo - 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::runs_of;

    /// The runs of set bits, one bit at a time.
    fn runs_bit_by_bit(bits: u128) -> Vec<(usize, usize)> {
        let mut runs: Vec<(usize, usize)> = Vec::new();
        for b in 0..128 {
            if bits >> b & 1 == 1 {
                match runs.last_mut() {
                    Some((j, len)) if *j + *len == b => *len += 1,
                    _ => runs.push((b, 1)),
                }
            }
        }
        runs
    }

    #[test]
    fn runs_of_finds_every_run_of_set_bits() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let edges = [0, 1, u128::MAX, 1 << 127, u128::MAX << 1, u128::MAX >> 1, 3 << 63, u128::MAX << 64];
        // Random words, and words of long runs (each bit repeating the one below, mostly).
        let random = (0..2000).map(|k| {
            if k % 2 == 0 {
                rng.gen::<u128>()
            } else {
                (1..128).fold(rng.gen::<u128>() & 1, |w, b| w | (w >> (b - 1) & 1 ^ u128::from(rng.gen_bool(0.1))) << b)
            }
        });
        for bits in edges.into_iter().chain(random) {
            assert_eq!(runs_of(bits).collect::<Vec<_>>(), runs_bit_by_bit(bits), "{bits:#x}");
        }
    }
}

//! Retrieval (docs/ALGORITHM.md, "Retrieval"): T's update after each decision, the selection of
//! couplets by both thresholds, Q over the actions of the selected and the proportional draw.

use super::similarity::{biased, biased_f64, pairwise9, similarity, similarity_f64};
use super::{Memory, Selected, ACTIONS};
use crate::arena::Action;
use crate::encoder::EMBEDDING;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

impl Memory {
    /// The T half of `update`.
    pub fn update_bias(&mut self) {
        self.sel_prev.copy_from_slice(&self.sel);
        if self.is_empty() || !self.cfg.sequential_bias {
            return;
        }
        let (beta, alpha, n) = (self.cfg.beta, self.cfg.alpha, self.cfg.n);
        decay(&mut self.t, &self.sel_prev, beta);
        // Then the successors' boost (each T gets at most one, so their order does not matter).
        let t = &mut self.t;
        each_set(&self.sel_prev, |idx| {
            if idx % n != n - 1 {
                t[idx + 1] += alpha;
            }
        });
    }

    /// Retrieval: similarity to every stored couplet, selection by both thresholds, Q over the
    /// actions of the selected, and an action drawn in proportion to Q. `None` when nothing
    /// passes (the authors' [-1, -1]); the entropy is then left as it was.
    ///
    /// The similarity and the comparisons are in the precision the authors' numpy computed them
    /// in: 1 - MAE in f32 (their embeddings are f32) until the LTM has been through forgetting,
    /// in f64 after (their LTM is then a list of Python floats); times T in f64 with the bias,
    /// while without it G stays f32 and is compared with theta_abs and G / Gmax with theta_prop
    /// as f32 (numpy casts a Python float to the array's type).
    pub fn retrieve(&mut self, e: &[f32; EMBEDDING], rng: &mut ChaCha8Rng) -> Option<Action> {
        self.selected.clear();
        let (n, rows) = (self.cfg.n, self.len());
        if rows == 0 {
            return None;
        }
        self.g.resize(rows * n, 0.0);
        let t: &[f64] = if self.cfg.sequential_bias { &self.t } else { &[] };
        // The similarities of the same embedding to the same LTM are those computed last time.
        let key = (e.map(f32::to_bits), self.forgot);
        let fresh = !(crate::reuse::on() && self.sim_for == Some(key));
        let gmax = if self.forgot {
            if fresh {
                self.sim64.resize(rows * n, 0.0);
                similarity_f64(e, &self.ltm, n, &mut self.sim64);
            }
            biased_f64(&self.sim64, t, &mut self.g)
        } else {
            if fresh {
                self.sim.resize(rows * n, 0.0);
                similarity(e, &self.ltm, n, &mut self.sim);
            }
            biased(&self.sim, t, &mut self.g)
        };
        self.sim_for = Some(key);
        // D16: with Gmax <= 0 nothing can pass (every G <= Gmax <= 0 < theta_abs or G / Gmax
        // undefined); otherwise G > theta_abs and G / Gmax > theta_prop, the ratio rounded as
        // numpy rounds it.
        let (ta, tp) = (self.cfg.theta_abs, self.cfg.theta_prop);
        // A vectorised pass marks a superset: G > theta_abs and G above theta_prop * Gmax lowered
        // by far more than the division's and the product's rounding (1e-12 in f64, 1e-6 in
        // f32), so every couplet with G / Gmax > theta_prop is in it; the few marked ones are
        // then checked with the division itself.
        let (g, selected) = (&self.g, &mut self.selected);
        if gmax <= 0.0 {
            self.sel.fill(false);
        } else if t.is_empty() && !self.forgot {
            let (ta, tp, gmax) = (ta as f32, tp as f32, gmax as f32);
            let lo = tp * gmax * (1.0 - 1e-6);
            for (s, &g) in self.sel.iter_mut().zip(&self.sim) {
                *s = (g > ta) & (g > lo);
            }
            let sim = &self.sim;
            refine(&mut self.sel, |idx| sim[idx] / gmax > tp, |idx| push(selected, n, idx, g[idx]));
        } else {
            let lo = tp * gmax * (1.0 - 1e-12);
            for (s, &g) in self.sel.iter_mut().zip(g) {
                *s = (g > ta) & (g > lo);
            }
            refine(&mut self.sel, |idx| g[idx] / gmax > tp, |idx| push(selected, n, idx, g[idx]));
        }
        if self.selected.is_empty() {
            return None;
        }
        let rmax = self.selected.iter().map(|s| self.rewards[s.row as usize]).fold(f64::NEG_INFINITY, f64::max);
        self.q = [0.0; ACTIONS];
        for s in &mut self.selected {
            let idx = s.row as usize * n + s.col as usize;
            s.t = t.get(idx).copied().unwrap_or(1.0);
            s.rr = self.rewards[s.row as usize] / rmax;
            s.d = (n - s.col as usize) as f64 / n as f64;
            let dist = libm::exp(-s.d / self.cfg.tau);
            s.action = self.actions[idx];
            s.value = self.cfg.value_function.value(s.g, s.rr, dist);
            self.q[s.action.index()] += s.value;
        }
        // numpy's sums of 9 (pairwise); a p of 0 adds nothing (the authors' nan_to_num term is -0).
        let total = pairwise9(&self.q);
        // Values that all underflowed (or a sum that overflowed) give no distribution: no
        // contextual action rather than a p of NaN.
        if !(total.is_finite() && total > 0.0) {
            return None;
        }
        let mut terms = [0.0; ACTIONS];
        for ((p, &q), t) in self.p.iter_mut().zip(&self.q).zip(&mut terms) {
            *p = q / total;
            if *p > 0.0 {
                *t = *p * libm::log2(*p);
            }
        }
        self.entropy = 0.0 - pairwise9(&terms);
        Some(Action::ALL[sample(&self.p, rng)])
    }
}

crate::dispatch::avx2_dispatch! {
    /// T's decay, its clamp at 1 and the reset of the selected in one pass (the same values as
    /// three), branch-free with compare and select so that it vectorises (`f64::max` is a call
    /// per element in wasm).
    fn decay(t: &mut [f64], sel_prev: &[bool], beta: f64) => decay_any
}

#[inline(always)]
fn decay_any(t: &mut [f64], sel_prev: &[bool], beta: f64) {
    assert_eq!(t.len(), sel_prev.len());
    for (t, &s) in t.iter_mut().zip(sel_prev) {
        let v = *t * (1.0 - beta) + beta;
        *t = if s | (v < 1.0) { 1.0 } else { v };
    }
}

/// Keeps a true of `mask` only where `keep(index)` holds, calling `kept` with each kept index in
/// ascending order. Few are true, so it skips eight at a time.
fn refine(mask: &mut [bool], keep: impl Fn(usize) -> bool, mut kept: impl FnMut(usize)) {
    for (w, chunk) in mask.chunks_mut(8).enumerate() {
        if chunk.iter().any(|&s| s) {
            for (l, s) in chunk.iter_mut().enumerate() {
                if *s {
                    *s = keep(w * 8 + l);
                    if *s {
                        kept(w * 8 + l);
                    }
                }
            }
        }
    }
}

fn push(selected: &mut Vec<Selected>, n: usize, idx: usize, g: f64) {
    let (row, col) = ((idx / n) as u32, (idx % n) as u32);
    selected.push(Selected { row, col, g, t: 1.0, rr: 0.0, d: 0.0, action: Action::NOOP, value: 0.0 });
}

/// Calls `f` with the index of every true in `mask`, ascending. Few couplets are selected, so
/// it skips eight at a time.
fn each_set(mask: &[bool], mut f: impl FnMut(usize)) {
    for (w, chunk) in mask.chunks(8).enumerate() {
        if chunk.iter().any(|&s| s) {
            for (l, &s) in chunk.iter().enumerate() {
                if s {
                    f(w * 8 + l);
                }
            }
        }
    }
}

/// Draws an index with probabilities `p` (summing to 1): the first index whose cumulative sum
/// exceeds a uniform draw; never an index of probability 0.
pub(super) fn sample(p: &[f64], rng: &mut ChaCha8Rng) -> usize {
    let u: f64 = rng.gen();
    let mut c = 0.0;
    let mut last = 0;
    for (i, &pi) in p.iter().enumerate() {
        if pi > 0.0 {
            c += pi;
            last = i;
            if u < c {
                return i;
            }
        }
    }
    last
}

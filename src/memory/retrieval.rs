//! Retrieval (docs/ALGORITHM.md, "Retrieval"): T's update after each decision, the selection of
//! couplets by both thresholds, Q over the actions of the selected and the proportional draw.

use super::similarity::{
    above32, above64, couplet_similarity, couplet_similarity_f64, max32, max64, pairwise9, similarity, similarity_f64,
};
use super::{raised_of, LastG, Memory, Selected, ACTIONS};
use crate::arena::Action;
use crate::encoder::EMBEDDING;
use rand_chacha::ChaCha8Rng;

impl Memory {
    /// The T half of `update`.
    pub fn update_bias(&mut self) {
        self.sel_prev.clone_from(&self.sel);
        if self.is_empty() || !self.cfg.sequential_bias {
            return;
        }
        let (beta, alpha, n) = (self.cfg.beta, self.cfg.alpha, self.cfg.n);
        if settle(1.0, false, beta) == 1.0 {
            // A T of 1 decays to 1 at this beta (as at every beta tried), so only the raised change.
            // A selected couplet's T is reset to 1 whatever it was, and then decays to 1: so the
            // selected are set first, and every raised one then decays as if not selected.
            let t = &mut self.t;
            for &s in &self.sel_prev {
                t[s as usize] = 1.0;
            }
            self.raised.retain(|&i| {
                let i = i as usize;
                t[i] = settle(t[i], false, beta);
                t[i] != 1.0
            });
        } else {
            let mut prev = self.sel_prev.iter().peekable();
            for (i, t) in self.t.iter_mut().enumerate() {
                let was_selected = prev.next_if(|&&s| s as usize == i).is_some();
                *t = settle(*t, was_selected, beta);
            }
            self.raised = raised_of(&self.t);
        }
        // Then the successors' boost (each T gets at most one, so their order does not matter).
        let (t, lifted) = (&mut self.t, &mut self.lifted);
        lifted.clear();
        for &idx in &self.sel_prev {
            let idx = idx as usize;
            if idx % n != n - 1 {
                let was = t[idx + 1];
                t[idx + 1] += alpha;
                if was == 1.0 && t[idx + 1] != 1.0 {
                    lifted.push(idx as u32 + 1);
                }
            }
        }
        merge_sorted(&mut self.raised, lifted);
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
    ///
    /// G is the similarity wherever T is 1, so only the raised couplets' G is computed; Gmax is
    /// the larger of the largest similarity and the raised G, and only the couplets whose
    /// similarity or G passes both thresholds' lower bound are tested exactly.
    pub fn retrieve(&mut self, e: &[f32; EMBEDDING], rng: &mut ChaCha8Rng) -> Option<Action> {
        self.selected.clear();
        self.sel.clear();
        let (n, rows) = (self.cfg.n, self.len());
        if rows == 0 {
            return None;
        }
        let cells = rows * n;
        let bias = self.cfg.sequential_bias;
        let forgot = self.forgot;
        // The similarities of the same embedding to the same LTM are those computed last time.
        // Otherwise the coarse copy bounds them all, and only those that can be the largest or
        // pass a threshold are computed (`coarse`); a full pass where it cannot bound them.
        let key = (e.map(f32::to_bits), forgot);
        if !(crate::reuse::on() && self.sim_for == Some(key)) {
            if forgot {
                self.sim64.resize(cells, 0.0);
            } else {
                self.sim.resize(cells, 0.0);
            }
            if !(crate::reuse::on() && self.coarse.pass(e, &self.ltm, n)) {
                self.full_pass(e);
            }
        }
        self.sim_for = Some(key);
        // The largest similarity, from the couplets that can be it.
        if !self.coarse.all {
            let closest = self.coarse.closest();
            self.candidates.clear();
            self.candidates.push(closest);
            self.exact(e, Which::Candidates);
            // (No cut: only the closest can be the largest.)
            if let Some(cut) = self.coarse.cut_above(self.similarity_of(closest)) {
                self.coarse.within(cut, &mut self.candidates);
            }
            if self.candidates.len() > cells / 4 {
                self.full_pass(e);
            } else {
                self.exact(e, Which::Candidates);
            }
        }
        let top = match (self.coarse.all, forgot) {
            (true, true) => max64(&self.sim64[..cells]),
            (true, false) => max32(&self.sim[..cells]),
            (false, _) => self.candidates.iter().fold(f64::NEG_INFINITY, |a, &i| larger(a, self.similarity_of(i))),
        };
        // G is the similarity times T. Gmax is the largest similarity or a raised G above it:
        // the raised couplets whose G may be above every lower bound are computed exactly.
        self.t_raised.clear();
        if bias {
            let t = &self.t;
            self.t_raised.extend(self.raised.iter().map(|&i| (i, t[i as usize])));
        }
        let gmax = if self.coarse.all {
            self.t_raised.iter().fold(top, |a, &(i, t)| larger(a, self.similarity_of(i) * t))
        } else {
            let coarse = &self.coarse;
            let floor = self.t_raised.iter().fold(top, |a, &(i, t)| larger(a, coarse.bounds(i as usize).0 * t));
            self.g_raised.clear();
            self.g_raised.extend(self.t_raised.iter().filter(|&&(i, t)| upper_g(coarse, i, t) >= floor));
            self.exact(e, Which::Raised);
            self.g_raised.iter().fold(top, |a, &(i, t)| larger(a, self.similarity_of(i) * t))
        };
        // Where a G is below its similarity, the similarity is negative: then a positive Gmax is
        // still this one, and when every G is at most 0 this is at most 0 too, and nothing passes
        // either way (D16).
        self.last_g = LastG::Derived { cells, forgot };
        // D16: with Gmax <= 0 nothing can pass (every G <= Gmax <= 0 < theta_abs or G / Gmax
        // undefined); otherwise G > theta_abs and G / Gmax > theta_prop, the ratio rounded as
        // numpy rounds it. A couplet is tested only if G > theta_abs and G > theta_prop * Gmax
        // lowered by far more than the division's and the product's rounding (1e-12 in f64,
        // 1e-6 in f32), which every couplet with G / Gmax > theta_prop passes.
        if gmax <= 0.0 {
            return None;
        }
        let (ta, tp) = (self.cfg.theta_abs, self.cfg.theta_prop);
        if !bias && !forgot {
            let (ta, tp, gmax) = (ta as f32, tp as f32, gmax as f32);
            let lo = tp * gmax * (1.0 - 1e-6);
            self.above(e, f64::from(if ta > lo { ta } else { lo }));
            let (sim, selected) = (&self.sim[..cells], &mut self.selected);
            for &i in self.candidates.iter() {
                let g = sim[i as usize];
                if g > ta && g > lo && g / gmax > tp {
                    push(selected, n, i as usize, g as f64);
                }
            }
        } else {
            let lo = tp * gmax * (1.0 - 1e-12);
            let bound = if ta > lo { ta } else { lo };
            self.above(e, bound);
            // The raised couplets whose G may pass the bound, with their G.
            if !self.coarse.all {
                let coarse = &self.coarse;
                self.g_raised.clear();
                self.g_raised.extend(self.t_raised.iter().filter(|&&(i, t)| upper_g(coarse, i, t) > bound));
                self.exact(e, Which::Raised);
            } else {
                self.g_raised.clone_from(&self.t_raised);
            }
            for k in 0..self.g_raised.len() {
                let (i, t) = self.g_raised[k];
                self.g_raised[k].1 = self.similarity_of(i) * t;
            }
            let (sim, sim64): (&[f32], &[f64]) =
                if forgot { (&[], &self.sim64[..cells]) } else { (&self.sim[..cells], &[]) };
            let s = |i: usize| if forgot { sim64[i] } else { sim[i] as f64 };
            let selected = &mut self.selected;
            let mut pass = |i: u32, g: f64| {
                if g > ta && g > lo && g / gmax > tp {
                    push(selected, n, i as usize, g);
                }
            };
            // The candidates and the raised, in ascending order, each with its G.
            let mut raised = self.g_raised.iter().peekable();
            for &c in self.candidates.iter() {
                while let Some(&(i, g)) = raised.next_if(|&&(i, _)| i < c) {
                    pass(i, g);
                }
                match raised.next_if(|&&(i, _)| i == c) {
                    Some(&(i, g)) => pass(i, g),
                    None => pass(c, s(c as usize)),
                }
            }
            raised.for_each(|&(i, g)| pass(i, g));
        }
        self.sel.extend(self.selected.iter().map(|s| s.row * n as u32 + s.col));
        if self.selected.is_empty() {
            return None;
        }
        let tau = self.cfg.tau;
        if self.dist.0 != tau.to_bits() || self.dist.1.len() != n {
            self.dist = (tau.to_bits(), (0..n).map(|col| libm::exp(-((n - col) as f64 / n as f64) / tau)).collect());
        }
        let rmax = self.selected.iter().map(|s| self.rewards[s.row as usize]).fold(f64::NEG_INFINITY, f64::max);
        self.q = [0.0; ACTIONS];
        for s in &mut self.selected {
            let idx = s.row as usize * n + s.col as usize;
            s.t = if bias { self.t[idx] } else { 1.0 };
            s.rr = self.rewards[s.row as usize] / rmax;
            s.d = (n - s.col as usize) as f64 / n as f64;
            s.action = self.actions[idx];
            s.value = self.cfg.value_function.value(s.g, s.rr, self.dist.1[s.col as usize]);
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
        Some(Action::ALL[crate::seed::sample(&self.p, rng)])
    }
}

/// Which couplets `Memory::exact` computes.
#[derive(Clone, Copy)]
enum Which {
    Candidates,
    /// Those of `g_raised`.
    Raised,
}

/// The most a raised couplet's G may be: its similarity's upper bound times T (T >= 0).
fn upper_g(coarse: &super::coarse::Coarse, i: u32, t: f64) -> f64 {
    coarse.bounds(i as usize).1 * t
}

/// The larger of two values, the first on a tie (the order of the full pass's maximum).
fn larger(a: f64, b: f64) -> f64 {
    if b > a {
        b
    } else {
        a
    }
}

impl Memory {
    /// Every similarity of `e`, in the precision of the last pass's key.
    fn full_pass(&mut self, e: &[f32; EMBEDDING]) {
        let (n, cells) = (self.cfg.n, self.len() * self.cfg.n);
        if self.forgot {
            similarity_f64(e, &self.ltm, n, &mut self.sim64[..cells]);
        } else {
            similarity(e, &self.ltm, n, &mut self.sim[..cells]);
        }
        self.coarse.all = true;
    }

    /// The exact similarities of the candidates or of `g_raised`'s couplets where the coarse
    /// copy left them uncomputed.
    fn exact(&mut self, e: &[f32; EMBEDDING], which: Which) {
        let Memory { coarse, candidates, g_raised, sim, sim64, forgot, .. } = self;
        // In the precision of the last pass.
        let mut fill = |idx: &mut dyn Iterator<Item = u32>| match *forgot {
            true => coarse.fill(idx, sim64, |c| couplet_similarity_f64(e, c)),
            false => coarse.fill(idx, sim, |c| couplet_similarity(e, c)),
        };
        match which {
            Which::Candidates => fill(&mut candidates.iter().copied()),
            Which::Raised => fill(&mut g_raised.iter().map(|&(i, _)| i)),
        }
    }

    /// Couplet i's similarity of the last pass, as f64 (exact where it is read).
    fn similarity_of(&self, i: u32) -> f64 {
        if self.forgot {
            self.sim64[i as usize]
        } else {
            f64::from(self.sim[i as usize])
        }
    }

    /// `candidates`: every couplet whose similarity is above `thr` (compared as f64), ascending,
    /// each with its exact similarity.
    fn above(&mut self, e: &[f32; EMBEDDING], thr: f64) {
        let cells = self.len() * self.cfg.n;
        if !self.coarse.all {
            match self.coarse.cut_above(thr) {
                None => return self.candidates.clear(),
                Some(cut) => {
                    self.coarse.within(cut, &mut self.candidates);
                    if self.candidates.len() <= cells / 4 {
                        self.exact(e, Which::Candidates);
                        let (sim, sim64, forgot) = (&self.sim, &self.sim64, self.forgot);
                        self.candidates.retain(|&i| {
                            let s = if forgot { sim64[i as usize] } else { f64::from(sim[i as usize]) };
                            s > thr
                        });
                        return;
                    }
                    self.full_pass(e);
                }
            }
        }
        self.candidates.clear();
        if self.forgot {
            above64(&self.sim64[..cells], thr, &mut self.candidates);
        } else {
            above32(&self.sim[..cells], thr, &mut self.candidates);
        }
    }
}

/// One T's decay towards 1, its clamp at 1, and its reset when it was selected.
#[inline(always)]
fn settle(t: f64, selected: bool, beta: f64) -> f64 {
    let v = t * (1.0 - beta) + beta;
    if selected | (v < 1.0) {
        1.0
    } else {
        v
    }
}

/// Merges the ascending `add` into the ascending `v` (no value in both).
fn merge_sorted(v: &mut Vec<u32>, add: &[u32]) {
    if add.is_empty() {
        return;
    }
    let (mut i, mut j) = (v.len(), add.len());
    v.resize(i + j, 0);
    while j > 0 {
        if i > 0 && v[i - 1] > add[j - 1] {
            v[i + j - 1] = v[i - 1];
            i -= 1;
        } else {
            v[i + j - 1] = add[j - 1];
            j -= 1;
        }
    }
}

fn push(selected: &mut Vec<Selected>, n: usize, idx: usize, g: f64) {
    let (row, col) = ((idx / n) as u32, (idx % n) as u32);
    selected.push(Selected { row, col, g, t: 1.0, rr: 0.0, d: 0.0, action: Action::NOOP, value: 0.0 });
}

//! SEC's contextual layer (docs/ALGORITHM.md, "The contextual layer"): the short-term memory (STM) of
//! the last n couplets, the long-term memory (LTM) of rewarded sequences, the sequential-bias
//! matrix T, retrieval and action selection.
//!
//! Memory is laid out for retrieval: each LTM row keeps its n embeddings transposed (embedding
//! component major, couplet minor), so the similarity of all couplets of a row is a loop over
//! couplets that vectorises, and each couplet still sums its 20 terms in the same order (numpy's,
//! `pairwise20`) on every target. Nothing is allocated per decision: every buffer is sized for the capacity m up front.

pub mod file;

use crate::arena::ConfigError;
use crate::dispatch::avx2_dispatch;
use crate::encoder::EMBEDDING;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// The number of actions (`Action`'s flat indices 3*a0 + a1).
pub const ACTIONS: usize = crate::arena::Action::COUNT;

/// The option of `table` named `s`, or an error naming `param` and the choices.
fn parse_named<T: Copy>(param: &str, table: &[(&str, T)], s: &str) -> Result<T, ConfigError> {
    table.iter().find(|(n, _)| *n == s).map(|(_, v)| *v).ok_or_else(|| {
        let names: Vec<&str> = table.iter().map(|(n, _)| *n).collect();
        ConfigError::new(param, format!("'{s}' is not one of {}", names.join(", ")))
    })
}

/// How a selected couplet's value combines its similarity g, relative reward rr and distance d
/// (docs/ALGORITHM.md, retrieval). `Default` is the paper's SEC; the others are the ablations of experiment 3.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase")]
pub enum ValueFn {
    /// g * rr * exp(-d / tau)
    Default,
    /// rr * exp(-d / tau)
    NoGi,
    /// g * rr
    NoDist,
    /// g * exp(-d / tau)
    #[serde(rename = "noRR")]
    NoRr,
    /// g
    SoloGi,
    /// exp(-d / tau)
    SoloDist,
    /// rr
    #[serde(rename = "soloRR")]
    SoloRr,
}

impl ValueFn {
    pub const ALL: [(&'static str, ValueFn); 7] = [
        ("default", ValueFn::Default),
        ("noGi", ValueFn::NoGi),
        ("noDist", ValueFn::NoDist),
        ("noRR", ValueFn::NoRr),
        ("soloGi", ValueFn::SoloGi),
        ("soloDist", ValueFn::SoloDist),
        ("soloRR", ValueFn::SoloRr),
    ];

    pub fn parse(s: &str) -> Result<Self, ConfigError> {
        parse_named("valueFunction", &Self::ALL, s)
    }

    /// The value of a couplet with similarity `g`, relative reward `rr` and distance weight
    /// `dist` = exp(-d / tau).
    pub fn value(self, g: f64, rr: f64, dist: f64) -> f64 {
        match self {
            // As numpy evaluates `collectors * (rewards * np.exp(-distances / tau))`.
            ValueFn::Default => g * (rr * dist),
            ValueFn::NoGi => rr * dist,
            ValueFn::NoDist => g * rr,
            ValueFn::NoRr => g * dist,
            ValueFn::SoloGi => g,
            ValueFn::SoloDist => dist,
            ValueFn::SoloRr => rr,
        }
    }
}

/// What happens when a sequence is stored into a full LTM (docs/ALGORITHM.md, storage and forgetting).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Forgetting {
    /// The LTM freezes at m; later sequences are not stored (the paper's main runs, D9).
    None,
    /// The oldest sequence goes.
    Fifo,
    /// A lowest-reward sequence goes (the oldest of equals).
    Rwd,
    /// The floor(10 % of m) lowest-reward sequences go.
    RwdProp,
    /// One sequence goes, drawn with probability proportional to (max reward + 1) - its reward.
    Prior,
}

impl Forgetting {
    pub const ALL: [(&'static str, Forgetting); 5] = [
        ("none", Forgetting::None),
        ("fifo", Forgetting::Fifo),
        ("rwd", Forgetting::Rwd),
        ("rwd-prop", Forgetting::RwdProp),
        ("prior", Forgetting::Prior),
    ];

    pub fn parse(s: &str) -> Result<Self, ConfigError> {
        parse_named("forgetting", &Self::ALL, s)
    }
}

/// The contextual layer's parameters. Defaults are the authors' code (the "code" preset).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase", default, deny_unknown_fields)]
pub struct MemoryConfig {
    /// STM length n: couplets per sequence.
    pub n: usize,
    /// LTM capacity m: sequences.
    pub m: usize,
    /// Absolute threshold on the biased similarity G (strict).
    pub theta_abs: f64,
    /// Threshold on G / Gmax (strict).
    pub theta_prop: f64,
    /// T increment for the successor of a selected couplet.
    pub alpha: f64,
    /// T decay rate towards 1.
    pub beta: f64,
    /// Distance decay tau in exp(-d / tau).
    pub tau: f64,
    /// The sequential bias T; false is NSEC.
    pub sequential_bias: bool,
    pub value_function: ValueFn,
    pub forgetting: Forgetting,
}

impl Default for MemoryConfig {
    fn default() -> Self {
        MemoryConfig {
            n: 50,
            m: 500,
            theta_abs: 0.98,
            theta_prop: 0.995,
            alpha: 0.01,
            beta: 0.05,
            tau: 0.9,
            sequential_bias: true,
            value_function: ValueFn::Default,
            forgetting: Forgetting::None,
        }
    }
}

/// Allowed ranges, also shown by the page's controls.
pub const N_RANGE: (usize, usize) = (1, 1000);
pub const M_RANGE: (usize, usize) = (1, 100_000);
pub const THETA_ABS_RANGE: (f64, f64) = (0.0, 2.0);
pub const THETA_PROP_RANGE: (f64, f64) = (0.0, 1.0);
pub const ALPHA_RANGE: (f64, f64) = (0.0, 1.0);
pub const BETA_RANGE: (f64, f64) = (0.0, 1.0);
/// From 0.01: below it exp(-d / tau) underflows to 0 for distant couplets and every value with
/// it, which made p 0 / 0 (the retrieval also refuses a zero total, see `retrieve`).
pub const TAU_RANGE: (f64, f64) = (0.01, 100.0);
/// The most couplets the LTM may hold, n x m: 80 MB of embeddings (the paper's largest is
/// 50 x 1000). The LTM grows as sequences arrive; nothing of this is reserved up front.
pub const MAX_COUPLETS: usize = 1_000_000;
/// The largest reward a sequence may carry (a memory file's; the tasks pay a few units), so that
/// PRIOR forgetting's sums of rewards stay finite.
pub const MAX_REWARD: f64 = 1e6;

fn check_f(name: &str, v: f64, lo: f64, hi: f64, lo_open: bool) -> Result<(), ConfigError> {
    let ok = v.is_finite() && v <= hi && if lo_open { v > lo } else { v >= lo };
    if ok {
        Ok(())
    } else {
        let open = if lo_open { "(" } else { "[" };
        Err(ConfigError::new(name, format!("{v} is out of range {open}{lo}, {hi}]")))
    }
}

impl MemoryConfig {
    /// Every parameter in its range; the error names the parameter and the range.
    pub fn validate(&self) -> Result<(), ConfigError> {
        if !(N_RANGE.0..=N_RANGE.1).contains(&self.n) {
            return Err(ConfigError::new("n", format!("{} is out of range {}..={}", self.n, N_RANGE.0, N_RANGE.1)));
        }
        if !(M_RANGE.0..=M_RANGE.1).contains(&self.m) {
            return Err(ConfigError::new("m", format!("{} is out of range {}..={}", self.m, M_RANGE.0, M_RANGE.1)));
        }
        check_f("thetaAbs", self.theta_abs, THETA_ABS_RANGE.0, THETA_ABS_RANGE.1, false)?;
        check_f("thetaProp", self.theta_prop, THETA_PROP_RANGE.0, THETA_PROP_RANGE.1, false)?;
        check_f("alpha", self.alpha, ALPHA_RANGE.0, ALPHA_RANGE.1, false)?;
        check_f("beta", self.beta, BETA_RANGE.0, BETA_RANGE.1, false)?;
        check_f("tau", self.tau, TAU_RANGE.0, TAU_RANGE.1, false)?;
        if self.n * self.m > MAX_COUPLETS {
            let message = format!("n x m = {} x {} is over {MAX_COUPLETS} couplets", self.n, self.m);
            return Err(ConfigError::new("m", message));
        }
        Ok(())
    }
}

/// One decision: the embedding the agent saw and the action it then took.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Couplet {
    pub embedding: [f32; EMBEDDING],
    pub action: u8,
}

impl Couplet {
    /// The STM's initial content: a zero embedding with action [0, 0].
    pub const ZERO: Couplet = Couplet { embedding: [0.0; EMBEDDING], action: 0 };
}

/// A selected couplet (docs/ALGORITHM.md, retrieval): LTM row, column, its G (bias included)
/// and the terms of its value, kept so that a decision can be explained term by term.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Selected {
    pub row: u32,
    pub col: u32,
    pub g: f64,
    /// T of the couplet at the retrieval (1 without the bias).
    pub t: f64,
    /// Relative reward: its sequence's reward over the best selected sequence's.
    pub rr: f64,
    /// Distance to the goal, (n - col) / n.
    pub d: f64,
    /// The action it votes for.
    pub action: u8,
    /// Its value, added to Q of `action`.
    pub value: f64,
}

/// STM, LTM, T and the selection masks, with the operations of sections 5-8.
#[derive(Clone, Debug)]
pub struct Memory {
    cfg: MemoryConfig,
    /// Ring of n couplets; `stm_head` is the oldest.
    stm: Vec<Couplet>,
    stm_head: usize,
    /// Per LTM row: n x 20 embeddings transposed (`[k][j]`).
    ltm: Vec<f32>,
    /// Per LTM row: n actions, oldest first.
    actions: Vec<u8>,
    rewards: Vec<f64>,
    /// T, rows x n (f64 like the authors' numpy array).
    t: Vec<f64>,
    /// M (selected by the last `retrieve`) and M_prev, rows x n.
    sel: Vec<bool>,
    sel_prev: Vec<bool>,
    /// G of the last `retrieve`, rows x n, in the precision the authors' numpy used (see
    /// `retrieve`), held as f64.
    g: Vec<f64>,
    /// Whether the LTM has been through forgetting: from then on the authors' LTM is a list of
    /// Python floats, so numpy computes the similarity in f64 (see `retrieve`).
    forgot: bool,
    /// 1 - MAE of every couplet, rows x n.
    sim: Vec<f32>,
    selected: Vec<Selected>,
    q: [f64; ACTIONS],
    p: [f64; ACTIONS],
    entropy: f64,
}

impl Memory {
    pub fn new(cfg: MemoryConfig) -> Result<Self, ConfigError> {
        cfg.validate()?;
        let n = cfg.n;
        // The LTM's buffers grow as sequences arrive (a store may allocate; a decision only
        // when the LTM has grown since the last).
        Ok(Memory {
            stm: vec![Couplet::ZERO; n],
            stm_head: 0,
            ltm: Vec::new(),
            actions: Vec::new(),
            rewards: Vec::new(),
            t: Vec::new(),
            sel: Vec::new(),
            sel_prev: Vec::new(),
            g: Vec::new(),
            forgot: false,
            sim: Vec::new(),
            selected: Vec::new(),
            q: [0.0; ACTIONS],
            p: [0.0; ACTIONS],
            entropy: 0.0,
            cfg,
        })
    }

    pub fn config(&self) -> &MemoryConfig {
        &self.cfg
    }

    /// Number of stored sequences S.
    pub fn len(&self) -> usize {
        self.rewards.len()
    }

    pub fn is_empty(&self) -> bool {
        self.rewards.is_empty()
    }

    /// The last computed entropy in bits: 0 before the first selection, and stale (kept) when
    /// nothing was selected (D14).
    pub fn entropy(&self) -> f64 {
        self.entropy
    }

    pub fn rewards(&self) -> &[f64] {
        &self.rewards
    }

    /// T, row-major (S x n).
    pub fn bias(&self) -> &[f64] {
        &self.t
    }

    /// G of the last `retrieve`, row-major (S x n).
    pub fn biased_similarity(&self) -> &[f64] {
        &self.g
    }

    /// The couplets the last `retrieve` selected, in row-major order.
    pub fn selected(&self) -> &[Selected] {
        &self.selected
    }

    /// Q and p over the 9 actions from the last selection.
    pub fn q(&self) -> &[f64; ACTIONS] {
        &self.q
    }

    pub fn p(&self) -> &[f64; ACTIONS] {
        &self.p
    }

    /// The STM, oldest couplet first.
    pub fn stm(&self) -> impl Iterator<Item = &Couplet> {
        self.stm[self.stm_head..].iter().chain(&self.stm[..self.stm_head])
    }

    /// Embedding k of couplet j of LTM row i.
    pub fn ltm_embedding(&self, i: usize, j: usize) -> [f32; EMBEDDING] {
        let n = self.cfg.n;
        std::array::from_fn(|k| self.ltm[(i * EMBEDDING + k) * n + j])
    }

    pub fn ltm_action(&self, i: usize, j: usize) -> u8 {
        self.actions[i * self.cfg.n + j]
    }

    /// Push the previous decision into the STM, then update T from the mask of the
    /// last `retrieve` (decay, clamp, reset the selected, boost their successors: in this order).
    pub fn update(&mut self, couplet: Couplet) {
        self.push(couplet);
        self.update_bias();
    }

    /// The STM half of `update`: the couplet goes in, the oldest falls out.
    pub fn push(&mut self, couplet: Couplet) {
        self.stm[self.stm_head] = couplet;
        self.stm_head = (self.stm_head + 1) % self.cfg.n;
    }

    /// The T half of `update`.
    pub fn update_bias(&mut self) {
        self.sel_prev.copy_from_slice(&self.sel);
        if self.is_empty() || !self.cfg.sequential_bias {
            return;
        }
        let (beta, alpha, n) = (self.cfg.beta, self.cfg.alpha, self.cfg.n);
        // Decay, clamp at 1 and reset the selected in one pass (the same values as three), with
        // compare and select: `f64::max` is a call per element in wasm.
        for (t, &s) in self.t.iter_mut().zip(&self.sel_prev) {
            let v = *t * (1.0 - beta) + beta;
            *t = if s || v < 1.0 { 1.0 } else { v };
        }
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
    pub fn retrieve(&mut self, e: &[f32; EMBEDDING], rng: &mut ChaCha8Rng) -> Option<u8> {
        self.selected.clear();
        let (n, rows) = (self.cfg.n, self.len());
        if rows == 0 {
            return None;
        }
        self.g.resize(rows * n, 0.0);
        let t: &[f64] = if self.cfg.sequential_bias { &self.t } else { &[] };
        let gmax = if self.forgot {
            similarity_f64(e, &self.ltm, n, &mut self.g);
            biased_in_place(t, &mut self.g)
        } else {
            self.sim.resize(rows * n, 0.0);
            similarity(e, &self.ltm, n, &mut self.sim);
            biased(&self.sim, t, &mut self.g)
        };
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
            self.q[s.action as usize] += s.value;
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
        Some(sample(&self.p, rng) as u8)
    }

    /// Storage: stores the STM as a sequence with reward `r` when r > 0 and there is room, then
    /// forget if the LTM is full. Returns whether the sequence was stored (it may have been
    /// forgotten again at once by RWD or PRIOR).
    pub fn store(&mut self, r: f64, rng: &mut ChaCha8Rng) -> bool {
        let (n, m) = (self.cfg.n, self.cfg.m);
        let stored = r > 0.0 && self.len() < m;
        if stored {
            let row = self.ltm.len();
            self.ltm.resize(row + EMBEDDING * n, 0.0);
            let head = self.stm_head;
            for (j, c) in self.stm[head..].iter().chain(&self.stm[..head]).enumerate() {
                for k in 0..EMBEDDING {
                    self.ltm[row + k * n + j] = c.embedding[k];
                }
                self.actions.push(c.action);
            }
            self.rewards.push(r);
            self.t.resize(self.t.len() + n, 1.0);
            self.sel.resize(self.sel.len() + n, false);
            self.sel_prev.resize(self.sel_prev.len() + n, false);
        }
        if self.len() >= m {
            // Any forgetting, even one that removes nothing, leaves the authors' LTM as Python
            // floats (`np.delete(...).tolist()`).
            self.forgot |= self.cfg.forgetting != Forgetting::None;
            match self.cfg.forgetting {
                Forgetting::None => {}
                Forgetting::Fifo => self.remove(0),
                Forgetting::Rwd => {
                    let i = self.lowest_rewards(1)[0];
                    self.remove(i);
                }
                Forgetting::RwdProp => {
                    let mut rows = self.lowest_rewards((self.len() as f64 * 0.1) as usize);
                    rows.sort_unstable_by(|a, b| b.cmp(a));
                    for i in rows {
                        self.remove(i);
                    }
                }
                Forgetting::Prior => {
                    let i = sample(&self.prior_probabilities(), rng);
                    self.remove(i);
                }
            }
        }
        stored
    }

    /// Probability of each row being forgotten by PRIOR now (for tests and the page).
    pub fn prior_probabilities(&self) -> Vec<f64> {
        let top = self.rewards.iter().copied().fold(f64::NEG_INFINITY, f64::max) + 1.0;
        let sum: f64 = self.rewards.iter().map(|r| top - r).sum();
        self.rewards.iter().map(|r| (top - r) / sum).collect()
    }

    /// End of episode: T back to 1 everywhere. The STM and the masks stay (D5).
    pub fn reset_bias(&mut self) {
        self.t.fill(1.0);
    }

    /// Applies new parameters to the running memory (the page's live controls). Thresholds,
    /// alpha, beta, tau, the value function and the forgetting mode act from the next decision; a
    /// smaller capacity m forgets the oldest sequences down to m; switching the bias off or on
    /// restarts T at 1. The STM length n is fixed for a run. On error nothing changes.
    pub fn reconfigure(&mut self, cfg: MemoryConfig) -> Result<(), ConfigError> {
        cfg.validate()?;
        if cfg.n != self.cfg.n {
            return Err(ConfigError::new(
                "n",
                format!("{} differs from the run's {}: the STM length needs a new run", cfg.n, self.cfg.n),
            ));
        }
        if cfg.sequential_bias != self.cfg.sequential_bias {
            self.reset_bias();
        }
        while self.len() > cfg.m {
            self.remove(0);
            self.forgot = true;
        }
        self.cfg = cfg;
        Ok(())
    }

    /// Empties the STM (the `reset_stm_on_episode` deviation, D5).
    pub fn reset_stm(&mut self) {
        self.stm.fill(Couplet::ZERO);
        self.stm_head = 0;
    }

    /// The `k` rows with the lowest rewards, ties broken towards the older row.
    fn lowest_rewards(&self, k: usize) -> Vec<usize> {
        let mut idx: Vec<usize> = (0..self.len()).collect();
        idx.sort_by(|&a, &b| self.rewards[a].total_cmp(&self.rewards[b]).then(a.cmp(&b)));
        idx.truncate(k);
        idx
    }

    fn remove(&mut self, i: usize) {
        let n = self.cfg.n;
        self.ltm.drain(i * EMBEDDING * n..(i + 1) * EMBEDDING * n);
        self.actions.drain(i * n..(i + 1) * n);
        self.rewards.remove(i);
        self.t.drain(i * n..(i + 1) * n);
        self.sel.drain(i * n..(i + 1) * n);
        self.sel_prev.drain(i * n..(i + 1) * n);
        self.g.truncate(0);
    }
}

/// 1 - MAE between `e` and every stored couplet: `ltm` holds rows of n couplets transposed
/// (`[k][j]`), `out` gets one value per couplet, row-major. Each couplet sums its 20 terms
/// |e_k - x_k| in numpy's pairwise order (`pairwise20`), whether one couplet at a time or eight
/// (AVX2) or four (wasm simd128) side by side, so every target gives the same bits.
fn similarity(e: &[f32; EMBEDDING], ltm: &[f32], n: usize, out: &mut [f32]) {
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") && n >= 8 {
        // SAFETY: the CPU supports AVX2, checked just above.
        return unsafe { simd_avx2::similarity(e, ltm, n, out) };
    }
    #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
    if n >= 4 {
        return simd128::similarity(e, ltm, n, out);
    }
    similarity_scalar(e, ltm, n, out)
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
fn similarity_f64(e: &[f32; EMBEDDING], ltm: &[f32], n: usize, out: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") && n >= 4 {
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

/// G = similarity times T (unchanged when `t` is empty, NSEC), in place; returns Gmax.
fn biased_in_place(t: &[f64], g: &mut [f64]) -> f64 {
    for (g, &t) in g.iter_mut().zip(t) {
        *g *= t;
    }
    g.iter().fold(f64::NEG_INFINITY, |a, &b| if b > a { b } else { a })
}

avx2_dispatch! {
    /// G = (1 - MAE) times T (or 1 when `t` is empty, NSEC) into `g`; returns Gmax. Eight running
    /// maxima so that the loop vectorises; a maximum does not depend on the order.
    fn biased(sim: &[f32], t: &[f64], g: &mut [f64]) -> f64 => biased_any
}

#[inline(always)]
fn biased_any(sim: &[f32], t: &[f64], g: &mut [f64]) -> f64 {
    if t.is_empty() {
        for (g, &s) in g.iter_mut().zip(sim) {
            *g = s as f64;
        }
    } else {
        for ((g, &s), &t) in g.iter_mut().zip(sim).zip(t) {
            *g = s as f64 * t;
        }
    }
    let mut m = [f64::NEG_INFINITY; 8];
    let chunks = g.chunks_exact(8);
    let tail = chunks.remainder();
    for c in chunks {
        for l in 0..8 {
            m[l] = if c[l] > m[l] { c[l] } else { m[l] };
        }
    }
    tail.iter().chain(&m).fold(f64::NEG_INFINITY, |a, &b| if b > a { b } else { a })
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
    selected.push(Selected { row, col, g, t: 1.0, rr: 0.0, d: 0.0, action: 0, value: 0.0 });
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
fn sample(p: &[f64], rng: &mut ChaCha8Rng) -> usize {
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

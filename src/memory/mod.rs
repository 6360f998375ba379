//! SEC's contextual layer (docs/ALGORITHM.md, "The contextual layer"): the short-term memory (STM) of
//! the last n couplets, the long-term memory (LTM) of rewarded sequences, the sequential-bias
//! matrix T, retrieval and action selection. One file per concept: `config` (the parameters and
//! their ranges), this file (the STM and LTM, storage, forgetting, live changes), `retrieval`
//! (T's update, selection, Q and the draw), `similarity` (the kernels), `coarse` (the LTM in
//! levels, whose bounds spare retrieval most similarities), `file` (memory files).
//!
//! Memory is laid out for retrieval: each LTM row keeps its n embeddings transposed (embedding
//! component major, couplet minor), so the similarity of all couplets of a row is a loop over
//! couplets that vectorises, and each couplet still sums its 20 terms in the same order (numpy's,
//! `pairwise20`) on every target. Nothing is allocated per decision: every buffer is sized for the capacity m up front.

mod coarse;
mod config;
pub mod file;
mod retrieval;
mod similarity;

pub use config::*;
pub use similarity::{pairwise20, pairwise9};

use crate::arena::{Action, ConfigError};
use crate::encoder::EMBEDDING;
use rand_chacha::ChaCha8Rng;

/// The number of actions (`Action`'s flat indices 3*a0 + a1).
pub const ACTIONS: usize = crate::arena::Action::COUNT;

/// One decision: the embedding the agent saw and the action it then took.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Couplet {
    /// The frame's embedding.
    pub embedding: [f32; EMBEDDING],
    /// The action taken at it.
    pub action: Action,
}

impl Couplet {
    /// The STM's initial content: a zero embedding with action [0, 0].
    pub const ZERO: Couplet = Couplet { embedding: [0.0; EMBEDDING], action: Action::NOOP };
}

/// A selected couplet (docs/ALGORITHM.md, retrieval): LTM row, column, its G (bias included)
/// and the terms of its value, kept so that a decision can be explained term by term (the
/// explanation's couplets, `session::Explanation`, serialise it as they are).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Selected {
    /// LTM sequence.
    #[serde(rename = "sequence")]
    pub row: u32,
    /// STM position.
    #[serde(rename = "position")]
    pub col: u32,
    /// Biased similarity G = similarity x T.
    pub g: f64,
    /// T of the couplet at the retrieval (1 without the bias).
    pub t: f64,
    /// Relative reward: its sequence's reward over the best selected sequence's.
    pub rr: f64,
    /// Distance to the goal, (n - col) / n.
    pub d: f64,
    /// The action it votes for.
    pub action: Action,
    /// Its value, added to Q of `action`.
    pub value: f64,
}

/// Where G of the last `retrieve` is. G equals the similarity wherever T is 1, so a decision
/// keeps the similarities and the G of the raised couplets, and G is written out only when read.
#[derive(Clone, Copy, Debug)]
enum LastG {
    /// In `g` (loaded from a checkpoint, emptied by a change to the LTM, or computed in full).
    Full,
    /// `sim` (`sim64` when `forgot`) of the first `cells` couplets times `t_raised`.
    Derived { cells: usize, forgot: bool },
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
    actions: Vec<Action>,
    rewards: Vec<f64>,
    /// T, rows x n (f64 like the authors' numpy array).
    t: Vec<f64>,
    /// M (selected by the last `retrieve`) and M_prev, as ascending indices into rows x n: few
    /// couplets are selected, so a decision need not walk two masks of the whole LTM.
    sel: Vec<u32>,
    sel_prev: Vec<u32>,
    /// The indices where T is not 1, ascending: T rises only after the selected couplets and
    /// decays back, so these are few, and T's decay and G need visit only them.
    raised: Vec<u32>,
    /// Scratch for `update_bias`: the couplets its boost raised from 1, ascending.
    lifted: Vec<u32>,
    /// G of the last `retrieve` (rows x n, in the precision the authors' numpy used, held as
    /// f64) when `last_g` is `Full`.
    g: Vec<f64>,
    /// T of the raised couplets at the last `retrieve`, by ascending index: their G is their
    /// similarity times it.
    t_raised: Vec<(u32, f64)>,
    /// Scratch for `retrieve`: the raised couplets whose G may matter (to Gmax, then to the
    /// selection), with their T and then their G.
    g_raised: Vec<(u32, f64)>,
    /// Where G of the last `retrieve` is (see `biased_similarity`).
    last_g: LastG,
    /// Scratch for `retrieve`: the couplets whose similarity passes both thresholds' bound.
    candidates: Vec<u32>,
    /// exp(-d / tau) per STM position (d = (n - col) / n), for the tau (as bits) it was made with.
    dist: (u64, Vec<f64>),
    /// Whether the LTM has been through forgetting: from then on the authors' LTM is a list of
    /// Python floats, so numpy computes the similarity in f64 (see `retrieve`).
    forgot: bool,
    /// 1 - MAE of every couplet, rows x n: in f32, and in f64 once `forgot`.
    sim: Vec<f32>,
    sim64: Vec<f64>,
    /// The embedding (as bits) and the precision `sim` or `sim64` holds the similarities of for
    /// the LTM as it is (`None` after any change to the LTM): the same embedding again, as when
    /// the agent faces a wall, reuses them.
    sim_for: Option<([u32; EMBEDDING], bool)>,
    /// The LTM in levels, and which similarities of the last pass are exact (`coarse`).
    coarse: coarse::Coarse,
    selected: Vec<Selected>,
    q: [f64; ACTIONS],
    p: [f64; ACTIONS],
    entropy: f64,
}

impl Memory {
    /// An empty memory of `cfg`; an invalid `cfg` is refused.
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
            raised: Vec::new(),
            lifted: Vec::new(),
            g: Vec::new(),
            t_raised: Vec::new(),
            g_raised: Vec::new(),
            last_g: LastG::Full,
            candidates: Vec::new(),
            dist: (0, Vec::new()),
            forgot: false,
            sim: Vec::new(),
            sim64: Vec::new(),
            sim_for: None,
            coarse: coarse::Coarse::default(),
            selected: Vec::new(),
            q: [0.0; ACTIONS],
            p: [0.0; ACTIONS],
            entropy: 0.0,
            cfg,
        })
    }

    /// Its parameters.
    pub fn config(&self) -> &MemoryConfig {
        &self.cfg
    }

    /// Number of stored sequences S.
    pub fn len(&self) -> usize {
        self.rewards.len()
    }

    /// Whether the LTM holds no sequence.
    pub fn is_empty(&self) -> bool {
        self.rewards.is_empty()
    }

    /// The last computed entropy in bits: 0 before the first selection, and stale (kept) when
    /// nothing was selected (D14).
    pub fn entropy(&self) -> f64 {
        self.entropy
    }

    /// Each LTM sequence's reward, oldest first.
    pub fn rewards(&self) -> &[f64] {
        &self.rewards
    }

    /// T, row-major (S x n).
    pub fn bias(&self) -> &[f64] {
        &self.t
    }

    /// G of the last `retrieve`, row-major (S x n; empty after a change to the LTM).
    pub fn biased_similarity(&self) -> Vec<f64> {
        match self.last_g {
            LastG::Full => self.g.clone(),
            LastG::Derived { cells, forgot } => {
                let mut g: Vec<f64> = if forgot {
                    self.in_full(&self.sim64, true, similarity::similarity_f64)[..cells].to_vec()
                } else {
                    self.sim_in_full()[..cells].iter().map(|&s| s as f64).collect()
                };
                for &(i, t) in &self.t_raised {
                    g[i as usize] *= t;
                }
                g
            }
        }
    }

    /// The embedding of the last `retrieve` and its precision, while the coarse copy left some
    /// of its similarities uncomputed (the LTM is then as it was at that retrieval).
    fn partial(&self) -> Option<([f32; EMBEDDING], bool)> {
        match self.sim_for {
            Some((bits, forgot)) if !self.coarse.all => Some((bits.map(f32::from_bits), forgot)),
            _ => None,
        }
    }

    /// `sim` (f32) or `sim64` (once `forgot`), the similarities of the last retrieval, in full:
    /// `pass` computes them where the coarse copy left some out.
    fn in_full<'a, T: Copy + Default>(
        &'a self,
        buf: &'a [T],
        forgot: bool,
        pass: fn(&[f32; EMBEDDING], &[f32], usize, &mut [T]),
    ) -> std::borrow::Cow<'a, [T]> {
        match self.partial() {
            Some((e, f)) if f == forgot => {
                let mut sim = vec![T::default(); buf.len()];
                pass(&e, &self.ltm, self.cfg.n, &mut sim);
                sim.into()
            }
            _ => buf.into(),
        }
    }

    /// `sim` in full.
    fn sim_in_full(&self) -> std::borrow::Cow<'_, [f32]> {
        self.in_full(&self.sim, false, similarity::similarity)
    }

    /// Computes the similarities the coarse copy let the last retrieval skip, before the LTM
    /// changes: what a checkpoint or the page reads is then the full pass's, as it would have been.
    fn finish_similarity(&mut self) {
        match self.partial() {
            Some((e, false)) => similarity::similarity(&e, &self.ltm, self.cfg.n, &mut self.sim),
            Some((e, true)) => similarity::similarity_f64(&e, &self.ltm, self.cfg.n, &mut self.sim64),
            None => {}
        }
        self.coarse.all = true;
    }

    /// The couplets the last `retrieve` selected, in row-major order.
    pub fn selected(&self) -> &[Selected] {
        &self.selected
    }

    /// Q and p over the 9 actions from the last selection.
    pub fn q(&self) -> &[f64; ACTIONS] {
        &self.q
    }

    /// The last retrieval's policy p = Q / sum Q.
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

    /// The action of couplet `j` of LTM sequence `i`.
    pub fn ltm_action(&self, i: usize, j: usize) -> Action {
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

    /// Storage: stores the STM as a sequence with reward `r` when r > 0 and there is room, then
    /// forget if the LTM is full. Returns whether the sequence was stored (it may have been
    /// forgotten again at once by RWD or PRIOR).
    pub fn store(&mut self, r: f64, rng: &mut ChaCha8Rng) -> bool {
        let (n, m) = (self.cfg.n, self.cfg.m);
        let stored = r > 0.0 && self.len() < m;
        if stored {
            self.finish_similarity();
            let row = self.ltm.len();
            self.ltm.resize(row + EMBEDDING * n, 0.0);
            let head = self.stm_head;
            for (j, c) in self.stm[head..].iter().chain(&self.stm[..head]).enumerate() {
                for k in 0..EMBEDDING {
                    self.ltm[row + k * n + j] = c.embedding[k];
                }
                self.actions.push(c.action);
            }
            self.coarse.append(&self.ltm[row..]);
            self.rewards.push(r);
            self.t.resize(self.t.len() + n, 1.0);
            self.sim_for = None;
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
                    let i = crate::seed::sample(&self.prior_probabilities(), rng);
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
        for &i in &self.raised {
            self.t[i as usize] = 1.0;
        }
        self.raised.clear();
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
        self.finish_similarity();
        let n = self.cfg.n;
        let values = i * EMBEDDING * n..(i + 1) * EMBEDDING * n;
        self.ltm.drain(values.clone());
        self.coarse.remove(values);
        self.actions.drain(i * n..(i + 1) * n);
        self.rewards.remove(i);
        self.t.drain(i * n..(i + 1) * n);
        let (lo, hi) = ((i * n) as u32, ((i + 1) * n) as u32);
        for list in [&mut self.sel, &mut self.sel_prev, &mut self.raised] {
            list.retain(|&c| c < lo || c >= hi);
            list.iter_mut().filter(|c| **c >= hi).for_each(|c| *c -= n as u32);
        }
        self.g.truncate(0);
        self.last_g = LastG::Full;
        self.sim_for = None;
    }
}

/// The indices where T is not 1, ascending (`Memory::raised` of `t`).
fn raised_of(t: &[f64]) -> Vec<u32> {
    (0..t.len()).filter(|&i| t[i] != 1.0).map(|i| i as u32).collect()
}

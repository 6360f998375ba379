//! The MFEC baseline as the authors ran it (docs/ALGORITHM.md, "MFEC"): nine per-action buffers
//! of (embedding, value), Q by exact match or the mean of the k nearest, argmax, the reactive walk
//! for exploration, and discounted returns written back at episode end.
//!
//! Faithful by default, including the reward bookkeeping handicap of D13: only rewards on decision
//! frames reach the buffers, so a goal between decisions is lost. `sum_rewards` removes it. The
//! transitions are kept as the authors' agent kept them (D21, `Bookkeeping::Authors`): a run
//! starts with a dummy couplet, the terminal frame's decision is taken, and an episode's last
//! couplet is carried into the next.

use super::controller::{Controller, EpisodeEnd, MemoryUse, Observation, Step};
use super::{Decision, Layer, Reactive};
use crate::arena::{Action, ConfigError};
use crate::encoder::{EMBEDDING, IMAGE};
use crate::memory::ACTIONS;
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use std::collections::{HashMap, VecDeque};

/// Where MFEC's state vectors come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Embedding {
    /// The task's autoencoder, as SEC sees it (MFEC-ae).
    Autoencoder,
    /// A seeded Gaussian random projection of the 84x84x3 image to 20 numbers (MFEC-rp).
    RandomProjection,
}

/// How transitions are cut into episodes (D21).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Bookkeeping {
    /// As `agent_mfec.py`: the run starts with a dummy couplet (zero state, no-op), which takes
    /// the first frame's reward and overwrites the no-op buffer's (zeros, -10) entry; every
    /// decision, the terminal frame's included, closes the previous couplet with the current
    /// frame's reward; the couplet open at an episode's end is carried into the next episode and
    /// credited with that episode's return; returns are written newest first; Q is computed
    /// only when MFEC itself acts (its entropy is stale otherwise); a buffer holds at most
    /// capacity - 1 entries (it deletes its oldest as soon as it reaches the capacity).
    #[default]
    Authors,
    /// Each episode's decisions are its own transitions, the terminal frame's decision is not
    /// one, returns are written oldest first, Q and its entropy are computed at every decision
    /// and a buffer holds `capacity` entries (the project's bookkeeping before D21).
    PerEpisode,
}

/// MFEC's parameters; defaults are the authors' (FC buffer cap).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase", default, deny_unknown_fields)]
pub struct MfecConfig {
    /// Where the state vectors come from.
    pub embedding: Embedding,
    /// Neighbours averaged for an unseen state.
    pub k: usize,
    /// Entries per action buffer (FC 100,000; HEAD 25,000; memory-matched runs m * 50 / 9).
    pub capacity: usize,
    /// Discount factor of the returns stored.
    pub gamma: f64,
    /// Probability of a reactive step once the warm-up is over.
    pub epsilon: f64,
    /// Decisions taken by the reactive walk before MFEC's own.
    pub warmup_decisions: u64,
    /// Rewarded episodes needed before MFEC's own decisions.
    pub warmup_rewarded_episodes: u64,
    /// Deviation from D13: every frame's reward reaches the transition of the decision it follows.
    pub sum_rewards: bool,
    /// When returns are written into the buffers.
    pub bookkeeping: Bookkeeping,
}

impl Default for MfecConfig {
    fn default() -> Self {
        MfecConfig {
            embedding: Embedding::Autoencoder,
            k: 50,
            capacity: 100_000,
            gamma: 0.99,
            epsilon: 0.005,
            warmup_decisions: 1250,
            warmup_rewarded_episodes: 5,
            sum_rewards: false,
            bookkeeping: Bookkeeping::Authors,
        }
    }
}

impl MfecConfig {
    /// Every field in its range, the error naming it.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let range = |p: &str, v: String, r: &str| Err(ConfigError::new(p, format!("{v} is out of range {r}")));
        if !(1..=1000).contains(&self.k) {
            return range("mfec.k", self.k.to_string(), "1..=1000");
        }
        // The authors' buffers hold capacity - 1 entries, so 1 would leave them empty.
        if !(2..=1_000_000).contains(&self.capacity) {
            return range("mfec.capacity", self.capacity.to_string(), "2..=1000000");
        }
        if !(self.gamma >= 0.0 && self.gamma <= 1.0) {
            return range("mfec.gamma", self.gamma.to_string(), "[0, 1]");
        }
        if !(self.epsilon >= 0.0 && self.epsilon <= 1.0) {
            return range("mfec.epsilon", self.epsilon.to_string(), "[0, 1]");
        }
        if self.warmup_decisions > 1_000_000_000 {
            return range("mfec.warmupDecisions", self.warmup_decisions.to_string(), "0..=1000000000");
        }
        if self.warmup_rewarded_episodes > 1_000_000 {
            return range("mfec.warmupRewardedEpisodes", self.warmup_rewarded_episodes.to_string(), "0..=1000000");
        }
        Ok(())
    }
}

impl super::section::AgentConfig for MfecConfig {
    const KEY: &'static str = "mfec";
    const TYPESCRIPT: &'static str = r#"
export interface RunConfig {
  mfec?: {
    embedding?: "autoencoder" | "random-projection"; k?: number; capacity?: number; gamma?: number;
    epsilon?: number; warmupDecisions?: number; warmupRewardedEpisodes?: number; sumRewards?: boolean;
    bookkeeping?: "authors" | "per-episode";
  };
}
"#;

    fn validate(&self) -> Result<(), ConfigError> {
        MfecConfig::validate(self)
    }
}

/// One action's buffer: entries in slots, an exact-match index, and FIFO order by stamp.
#[derive(Clone, Debug, Default)]
struct Buffer {
    keys: Vec<[f32; EMBEDDING]>,
    values: Vec<f64>,
    stamps: Vec<u64>,
    index: HashMap<[u32; EMBEDDING], usize>,
    /// (stamp, slot) in insertion order; entries whose slot has a newer stamp are stale.
    order: VecDeque<(u64, usize)>,
}

fn bits(e: &[f32; EMBEDDING]) -> [u32; EMBEDDING] {
    e.map(f32::to_bits)
}

impl Buffer {
    fn len(&self) -> usize {
        self.keys.len()
    }

    /// Q of state `e`: its value if stored, else the mean value of the k nearest (all of them if
    /// fewer), nearest by squared Euclidean distance ties to the lower slot.
    fn q(&self, e: &[f32; EMBEDDING], k: usize, dist: &mut Vec<(f32, u32)>) -> f64 {
        if let Some(&slot) = self.index.get(&bits(e)) {
            return self.values[slot];
        }
        if self.len() <= k {
            return self.values.iter().sum::<f64>() / self.len() as f64;
        }
        dist.clear();
        dist.extend(self.keys.iter().enumerate().map(|(i, key)| {
            let mut s = 0.0f32;
            for c in 0..EMBEDDING {
                let d = key[c] - e[c];
                s += d * d;
            }
            (s, i as u32)
        }));
        let cmp = |a: &(f32, u32), b: &(f32, u32)| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1));
        dist.select_nth_unstable_by(k - 1, cmp);
        let near = &mut dist[..k];
        near.sort_unstable_by_key(|&(_, i)| i);
        near.iter().map(|&(_, i)| self.values[i as usize]).sum::<f64>() / k as f64
    }

    /// Writes a return: a stored state keeps the larger value and moves to the FIFO's end; a new
    /// one is appended, evicting the oldest entry when the buffer is full.
    fn write(&mut self, e: &[f32; EMBEDDING], g: f64, capacity: usize, stamp: u64) {
        let key = bits(e);
        let slot = match self.index.get(&key) {
            Some(&slot) => {
                self.values[slot] = self.values[slot].max(g);
                slot
            }
            None if self.len() < capacity => {
                self.keys.push(*e);
                self.values.push(g);
                self.stamps.push(0);
                self.index.insert(key, self.len() - 1);
                self.len() - 1
            }
            None => {
                let slot = loop {
                    let (s, slot) = self.order.pop_front().expect("a full buffer has a live entry");
                    if self.stamps[slot] == s {
                        break slot;
                    }
                };
                self.index.remove(&bits(&self.keys[slot]));
                self.index.insert(key, slot);
                self.keys[slot] = *e;
                self.values[slot] = g;
                slot
            }
        };
        self.stamps[slot] = stamp;
        self.order.push_back((stamp, slot));
    }
}

/// A transition of the current episode: the state, the action taken there, and the reward that
/// reached it.
#[derive(Clone, Copy, Debug)]
struct Transition {
    e: [f32; EMBEDDING],
    action: Action,
    reward: f64,
}

/// The MFEC agent.
#[derive(Clone, Debug)]
pub struct Mfec {
    cfg: MfecConfig,
    buffers: Vec<Buffer>,
    reactive: Reactive,
    /// The episode's closed transitions, oldest first.
    episode: Vec<Transition>,
    /// The last decision's couplet, whose reward is still coming (`Authors` bookkeeping; the run
    /// starts with the dummy couplet, and a person's driving leaves none).
    open: Option<Transition>,
    decisions: u64,
    rewarded_episodes: u64,
    stamp: u64,
    q: [f64; ACTIONS],
    entropy: f64,
    dist: Vec<(f32, u32)>,
    /// MFEC-rp's projection of the image (`None`: the perception's embedding, MFEC-ae).
    projection: Option<RandomProjection>,
}

impl Mfec {
    /// An agent of `cfg`, its reactive walk drawn from `rng`; an invalid `cfg` is refused.
    pub fn new(cfg: MfecConfig, rng: &mut ChaCha8Rng) -> Result<Self, ConfigError> {
        cfg.validate()?;
        // Each buffer starts with one entry: the zero state, valued -10.
        let mut buffers = vec![Buffer::default(); ACTIONS];
        for b in &mut buffers {
            b.write(&[0.0; EMBEDDING], -10.0, cfg.capacity, 0);
        }
        let open = (cfg.bookkeeping == Bookkeeping::Authors).then_some(Transition {
            e: [0.0; EMBEDDING],
            action: Action::NOOP,
            reward: 0.0,
        });
        Ok(Mfec {
            cfg,
            buffers,
            reactive: Reactive::new(rng),
            episode: Vec::new(),
            open,
            decisions: 0,
            rewarded_episodes: 0,
            stamp: 1,
            q: [0.0; ACTIONS],
            entropy: 0.0,
            dist: Vec::new(),
            projection: None,
        })
    }

    /// MFEC-rp: its states are `projection`'s of the image instead of the perception's.
    pub fn with_projection(self, projection: RandomProjection) -> Self {
        Mfec { projection: Some(projection), ..self }
    }

    /// Its parameters.
    pub fn config(&self) -> &MfecConfig {
        &self.cfg
    }

    /// Q of the last state MFEC valued.
    pub fn q(&self) -> &[f64; ACTIONS] {
        &self.q
    }

    /// Entropy (bits) of the softmax over the last Q.
    pub fn entropy(&self) -> f64 {
        self.entropy
    }

    /// Entries over all buffers.
    pub fn len(&self) -> usize {
        self.buffers.iter().map(Buffer::len).sum()
    }

    /// Whether no buffer holds an entry.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Entries a buffer keeps: the authors' delete their oldest on reaching the capacity.
    fn kept(&self) -> usize {
        match self.cfg.bookkeeping {
            Bookkeeping::Authors => self.cfg.capacity - 1,
            Bookkeeping::PerEpisode => self.cfg.capacity,
        }
    }

    /// The transition a frame's reward goes to: the open couplet (`Authors`) or the episode's
    /// last decision (`PerEpisode`).
    fn receiving(&mut self) -> Option<&mut Transition> {
        match self.cfg.bookkeeping {
            Bookkeeping::Authors => self.open.as_mut(),
            Bookkeeping::PerEpisode => self.episode.last_mut(),
        }
    }

    /// A frame's reward: `reward` of the frame, `r_ep` the episode's so far, `goal` whether the
    /// frame reached a goal, `decision` whether a decision is taken on it. Faithfully only decision
    /// frames count, a goal frame with the cumulative episode reward (D13).
    /// With the authors' bookkeeping a goal counts towards the warm-up on its frame (theirs
    /// counted frames paying >= 1, here the goal event with a positive episode reward, D12), so
    /// a decision on that frame already sees it.
    pub fn frame(&mut self, reward: f64, r_ep: f64, goal: bool, decision: bool) {
        if self.cfg.bookkeeping == Bookkeeping::Authors && goal && r_ep > 0.0 {
            self.rewarded_episodes += 1;
        }
        let sum = self.cfg.sum_rewards;
        let Some(last) = self.receiving() else { return };
        if sum {
            last.reward += reward;
        } else if decision {
            last.reward = if goal { r_ep } else { reward };
        }
    }

    fn value(&mut self, e: &[f32; EMBEDDING]) {
        for (a, b) in self.buffers.iter().enumerate() {
            self.q[a] = b.q(e, self.cfg.k, &mut self.dist);
        }
        self.entropy = softmax_entropy_bits(&self.q);
    }

    /// Chooses the action for state `e` on a frame that `terminal` or not ends the episode.
    pub fn decide(&mut self, e: &[f32; EMBEDDING], terminal: bool, rng: &mut ChaCha8Rng) -> Decision {
        let authors = self.cfg.bookkeeping == Bookkeeping::Authors;
        if !authors {
            self.value(e);
        }
        let explore = rng.gen::<f64>() < self.cfg.epsilon
            || self.decisions < self.cfg.warmup_decisions
            || self.rewarded_episodes < self.cfg.warmup_rewarded_episodes;
        let (action, layer) = if explore {
            (self.reactive.step(rng), Layer::Reactive)
        } else {
            if authors {
                self.value(e);
            }
            let best = (0..ACTIONS).fold(0, |b, a| if self.q[a] > self.q[b] { a } else { b });
            (Action::ALL[best], Layer::Contextual)
        };
        self.decisions += 1;
        let next = Transition { e: *e, action, reward: 0.0 };
        if authors {
            // The couplet this decision closes had its reward set by this frame's `frame`.
            if let Some(closed) = self.open.replace(next) {
                self.episode.push(closed);
            }
        } else if !terminal {
            self.episode.push(next);
        }
        Decision { action, layer, selected: !explore || !authors }
    }

    /// Forgets the episode in progress without learning from it (a person drove it), and the
    /// couplet it would carry.
    pub fn discard_episode(&mut self) {
        self.episode.clear();
        self.open = None;
    }

    /// Episode end: discounted returns backwards, written into the action buffers (newest first
    /// with the authors' bookkeeping, oldest first otherwise). The open couplet, if any, stays
    /// for the next episode. `rewarded`: the episode reached a goal (counted here with the
    /// per-episode bookkeeping, at the goal's frame with the authors').
    pub fn episode_end(&mut self, rewarded: bool) {
        let mut g = 0.0;
        for t in self.episode.iter_mut().rev() {
            g = t.reward + self.cfg.gamma * g;
            t.reward = g;
        }
        let kept = self.kept();
        let mut write = |t: &Transition, stamp: &mut u64| {
            self.buffers[t.action.index()].write(&t.e, t.reward, kept, *stamp);
            *stamp += 1;
        };
        let mut stamp = self.stamp;
        match self.cfg.bookkeeping {
            Bookkeeping::Authors => self.episode.iter().rev().for_each(|t| write(t, &mut stamp)),
            Bookkeeping::PerEpisode => self.episode.iter().for_each(|t| write(t, &mut stamp)),
        }
        self.stamp = stamp;
        self.episode.clear();
        if self.cfg.bookkeeping == Bookkeeping::PerEpisode {
            self.rewarded_episodes += rewarded as u64;
        }
    }
}

impl Controller for Mfec {
    fn on_step(&mut self, step: &Step, _: Option<&[f32]>, _: &mut ChaCha8Rng) -> bool {
        self.frame(step.reward, step.episode_reward, step.good_goal, step.decides);
        false
    }

    fn decide(&mut self, obs: &Observation, _: &mut dyn FnMut() -> f32, rng: &mut ChaCha8Rng) -> Decision {
        match &self.projection {
            Some(p) => {
                let mut e = [0.0; EMBEDDING];
                p.project(obs.image, &mut e);
                Mfec::decide(self, &e, obs.terminal, rng)
            }
            None => Mfec::decide(self, obs.embedding, obs.terminal, rng),
        }
    }

    /// An episode a person drove in part is not MFEC's experience.
    fn on_episode_end(&mut self, end: &EpisodeEnd) {
        if end.driven {
            self.discard_episode();
        } else {
            self.episode_end(end.goal);
        }
    }

    fn entropy(&self) -> f64 {
        self.entropy
    }

    fn memory_use(&self) -> MemoryUse {
        MemoryUse { used: self.len(), capacity: self.cfg.capacity * ACTIONS }
    }
}

/// Entropy in bits of softmax(q).
pub fn softmax_entropy_bits(q: &[f64; ACTIONS]) -> f64 {
    let max = q.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let w = q.map(|v| libm::exp(v - max));
    let z: f64 = w.iter().sum();
    -w.iter().map(|&x| x / z).filter(|&p| p > 0.0).map(|p| p * libm::log2(p)).sum::<f64>()
}

/// A Gaussian random projection of the RGB image to 20 numbers, N(0, 1/inputs) entries drawn
/// with Box-Muller from the run's seed.
#[derive(Clone, Debug)]
pub struct RandomProjection {
    /// 20 rows of `IMAGE` weights.
    w: Vec<f32>,
}

impl RandomProjection {
    /// A projection drawn from `rng`.
    pub fn new(rng: &mut ChaCha8Rng) -> Self {
        let sd = 1.0 / (IMAGE as f64).sqrt();
        let w = (0..EMBEDDING * IMAGE)
            .map(|_| {
                let u1 = 1.0 - rng.gen::<f64>();
                let u2 = rng.gen::<f64>();
                (libm::sqrt(-2.0 * libm::log(u1)) * libm::cos(2.0 * std::f64::consts::PI * u2) * sd) as f32
            })
            .collect();
        RandomProjection { w }
    }

    /// Projects an image (`IMAGE` floats). Eight partial sums in a fixed order, so every target
    /// gets the same bits.
    pub fn project(&self, image: &[f32], out: &mut [f32; EMBEDDING]) {
        for (o, row) in out.iter_mut().zip(self.w.chunks_exact(IMAGE)) {
            let mut acc = [0.0f32; 8];
            for (x, w) in image.chunks_exact(8).zip(row.chunks_exact(8)) {
                for l in 0..8 {
                    acc[l] += x[l] * w[l];
                }
            }
            *o = ((acc[0] + acc[1]) + (acc[2] + acc[3])) + ((acc[4] + acc[5]) + (acc[6] + acc[7]));
        }
    }
}

#[cfg(target_arch = "wasm32")]
#[wasm_bindgen::prelude::wasm_bindgen(typescript_custom_section)]
const MFEC_CONFIG_TYPESCRIPT: &str = <MfecConfig as super::section::AgentConfig>::TYPESCRIPT;

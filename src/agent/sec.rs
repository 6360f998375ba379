//! SEC (docs/ALGORITHM.md, "The contextual layer", arbitration): at every decision the contextual
//! layer of `crate::memory` and the reactive layer both answer, and the contextual action is taken
//! only when it selected something, the LTM holds enough sequences and the reconstruction gate is
//! open.

use super::controller::{AgentView, Controller, EpisodeEnd, MemoryUse, Observation, Step};
use super::section::{own_section, AgentConfig, SectionSetting};
use super::{Decision, Layer, Reactive};
use crate::arena::{Action, ConfigError};
use crate::encoder::EMBEDDING;
use crate::error::Error;
use crate::memory::file::Identity;
use crate::memory::{Couplet, Memory, MemoryConfig};
use crate::memory::{
    Forgetting, ValueFn, ALPHA_RANGE, BETA_RANGE, M_RANGE, N_RANGE, TAU_RANGE, THETA_ABS_RANGE, THETA_PROP_RANGE,
};
use crate::param::{name_of, names, Param};
use rand_chacha::ChaCha8Rng;
use std::any::Any;

/// SEC's parameters beyond the memory's. Defaults follow the authors' code.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase", default, deny_unknown_fields)]
pub struct SecConfig {
    /// The STM and LTM's parameters.
    pub memory: MemoryConfig,
    /// The contextual layer may act once the LTM holds at least this many sequences (code: 5).
    pub min_sequences: usize,
    /// Reconstruction-gate threshold: the contextual layer acts only while the frame's MSE is
    /// below it. `None` turns the gate off (a documented deviation).
    pub gate: Option<f32>,
    /// Deviation D4: also store the couplet whose action reached the goal (the paper's figure).
    pub store_last_couplet: bool,
    /// Deviation D5: empty the STM at every episode end.
    pub reset_stm_on_episode: bool,
}

impl Default for SecConfig {
    fn default() -> Self {
        SecConfig {
            memory: MemoryConfig::default(),
            min_sequences: 5,
            gate: Some(0.01),
            store_last_couplet: false,
            reset_stm_on_episode: false,
        }
    }
}

impl SecConfig {
    /// The authors' code (the default).
    pub fn code() -> Self {
        Self::default()
    }

    /// The paper's text: thresholds the other way round (D2) and a T increment of 0.1 (D3).
    pub fn paper() -> Self {
        let mut c = Self::default();
        c.memory.theta_abs = 0.995;
        c.memory.theta_prop = 0.98;
        c.memory.alpha = 0.1;
        c
    }

    /// Every field in its range, the error naming it.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.memory.validate()?;
        if self.min_sequences > self.memory.m {
            return Err(ConfigError::new(
                "minSequences",
                format!(
                    "{} is out of range 0..={m} (the LTM capacity m): SEC acts from {} stored sequences, which an \
                     LTM of m = {m} cannot hold; raise m to {} or more, or lower minSequences to {m} or less",
                    self.min_sequences,
                    self.min_sequences,
                    self.min_sequences,
                    m = self.memory.m
                ),
            ));
        }
        if let Some(g) = self.gate {
            if !(g.is_finite() && g > 0.0 && g <= 100.0) {
                return Err(ConfigError::new("gate", format!("{g} is out of range (0, 100]")));
            }
        }
        Ok(())
    }
}

impl AgentConfig for SecConfig {
    const KEY: &'static str = "agent";
    const TYPESCRIPT: &'static str = r#"
export interface RunConfig {
  agent?: {
    memory?: {
      n?: number; m?: number; thetaAbs?: number; thetaProp?: number;
      alpha?: number; beta?: number; tau?: number; sequentialBias?: boolean;
      valueFunction?: "default" | "noGi" | "noDist" | "noRR" | "soloGi" | "soloDist" | "soloRR";
      forgetting?: "none" | "fifo" | "rwd" | "rwd-prop" | "prior";
    };
    minSequences?: number; gate?: number | null; storeLastCouplet?: boolean; resetStmOnEpisode?: boolean;
  };
}
"#;

    fn validate(&self) -> Result<(), ConfigError> {
        SecConfig::validate(self)
    }

    /// The settings the page shows of SEC, in its order: the retrieval's, then the memory's.
    #[rustfmt::skip]
    fn settings() -> Vec<SectionSetting> {
        vec![
            SectionSetting::of(
                Param::switch("bias", "T", "Sequential bias: on is SEC, off is NSEC (T restarts at 1).", true).group("retrieval"),
                |c: &SecConfig| (c.memory.sequential_bias as u8).to_string(),
                |c: &mut SecConfig, v| c.memory.sequential_bias = v == 1.0,
            ),
            SectionSetting::of(
                Param::number("alpha", "α", "How much T rises for the successor of a selected couplet.", ALPHA_RANGE, false, 0.001).group("retrieval"),
                |c: &SecConfig| c.memory.alpha.to_string(),
                |c: &mut SecConfig, v| c.memory.alpha = v,
            ),
            SectionSetting::of(
                Param::number("beta", "β", "How fast T decays back towards 1 at every decision.", BETA_RANGE, false, 0.001).group("retrieval"),
                |c: &SecConfig| c.memory.beta.to_string(),
                |c: &mut SecConfig, v| c.memory.beta = v,
            ),
            SectionSetting::of(
                Param::number("tau", "τ", "Distance discount exp(-d/τ): lower favours couplets near the goal.", TAU_RANGE, false, 0.01).group("retrieval"),
                |c: &SecConfig| c.memory.tau.to_string(),
                |c: &mut SecConfig, v| c.memory.tau = v,
            ),
            SectionSetting::of(
                Param::number("thetaAbs", "θ_abs", "A couplet is selected only if its biased similarity G exceeds this...", THETA_ABS_RANGE, false, 0.001).group("retrieval"),
                |c: &SecConfig| c.memory.theta_abs.to_string(),
                |c: &mut SecConfig, v| c.memory.theta_abs = v,
            ),
            SectionSetting::of(
                Param::number("thetaProp", "θ_prop", "...and G / Gmax exceeds this.", THETA_PROP_RANGE, false, 0.001).group("retrieval"),
                |c: &SecConfig| c.memory.theta_prop.to_string(),
                |c: &mut SecConfig, v| c.memory.theta_prop = v,
            ),
            SectionSetting::of(
                Param::integer("n", "n", "STM length: couplets per stored sequence (a new run).", (N_RANGE.0 as u64, N_RANGE.1 as u64), false).group("memory"),
                |c: &SecConfig| c.memory.n.to_string(),
                |c: &mut SecConfig, v| c.memory.n = v as usize,
            ),
            SectionSetting::of(
                Param::integer("m", "m", "LTM capacity in sequences; a smaller m forgets the oldest now.", (M_RANGE.0 as u64, M_RANGE.1 as u64), true).group("memory"),
                |c: &SecConfig| c.memory.m.to_string(),
                |c: &mut SecConfig, v| c.memory.m = v as usize,
            ),
            SectionSetting::of(
                Param::integer("minSequences", "min", "Memory acts only once the LTM holds this many sequences (at most m).", (0, M_RANGE.1 as u64), true).group("memory"),
                |c: &SecConfig| c.min_sequences.to_string(),
                |c: &mut SecConfig, v| c.min_sequences = v as usize,
            ),
            SectionSetting::of(
                Param::choice("forgetting", "forget", "What a full LTM does: nothing, drop the oldest, the lowest reward, the 10% lowest, or one drawn by low reward.", &names(&Forgetting::ALL), true).group("memory"),
                |c: &SecConfig| name_of(&Forgetting::ALL, c.memory.forgetting),
                |c: &mut SecConfig, v| c.memory.forgetting = Forgetting::ALL[v as usize].1,
            ),
            SectionSetting::of(
                Param::choice("value", "value", "How a couplet's similarity g, relative reward rr and distance d make its value.", &names(&ValueFn::ALL), true).group("retrieval"),
                |c: &SecConfig| name_of(&ValueFn::ALL, c.memory.value_function),
                |c: &mut SecConfig, v| c.memory.value_function = ValueFn::ALL[v as usize].1,
            ),
        ]
    }
}

/// The contextual and reactive layers and the arbitration between them.
#[derive(Clone, Debug)]
pub struct Sec {
    cfg: SecConfig,
    memory: Memory,
    reactive: Reactive,
    /// The last decision, pushed into the STM at the next one (zeros and [0, 0] at first).
    previous: Couplet,
    /// Set when `previous` must not be pushed again: `store_last_couplet` already did, or the
    /// STM was reset since.
    previous_pushed: bool,
}

impl Sec {
    /// An agent of `cfg` with an empty memory, its reactive walk drawn from `rng`.
    pub fn new(cfg: SecConfig, rng: &mut ChaCha8Rng) -> Result<Self, ConfigError> {
        cfg.validate()?;
        Ok(Sec {
            memory: Memory::new(cfg.memory.clone())?,
            reactive: Reactive::new(rng),
            previous: Couplet::ZERO,
            previous_pushed: false,
            cfg,
        })
    }

    /// Its parameters.
    pub fn config(&self) -> &SecConfig {
        &self.cfg
    }

    /// The contextual layer's memory, read-only: it changes only through the agent's decisions,
    /// goals, live parameters and memory files.
    pub fn memory(&self) -> &Memory {
        &self.memory
    }

    /// The last decision's couplet: the frame's embedding and the action taken (it enters the
    /// STM at the next decision).
    pub fn last_couplet(&self) -> &Couplet {
        &self.previous
    }

    /// Applies new parameters to the running agent (see `Memory::reconfigure`); on error
    /// nothing changes.
    pub fn reconfigure(&mut self, cfg: SecConfig) -> Result<(), ConfigError> {
        cfg.validate()?;
        self.memory.reconfigure(cfg.memory.clone())?;
        self.cfg = cfg;
        Ok(())
    }

    /// Push the previous couplet (updating T), let both layers answer, arbitrate.
    /// `rec_mse` is the reconstruction gate's last measurement.
    pub fn decide(&mut self, e: &[f32; EMBEDDING], rec_mse: f32, rng: &mut ChaCha8Rng) -> Decision {
        self.decide_with(e, || rec_mse, rng)
    }

    /// `decide`, reading the gate's measurement only if the arbitration needs it (the contextual
    /// layer selected something and the LTM holds enough sequences): the gate can then skip the
    /// autoencoder pass.
    pub fn decide_with(
        &mut self,
        e: &[f32; EMBEDDING],
        rec_mse: impl FnOnce() -> f32,
        rng: &mut ChaCha8Rng,
    ) -> Decision {
        self.act(e, rec_mse, None, rng)
    }

    /// A person chose `action` at this decision (the page's "drive it yourself" with record on):
    /// the memory goes through the same steps as for `decide`, but the couplet holds the
    /// person's action, so a rewarded episode is stored like any other sequence.
    pub fn follow(&mut self, e: &[f32; EMBEDDING], action: Action, rng: &mut ChaCha8Rng) -> Decision {
        self.act(e, || f32::INFINITY, Some(action), rng)
    }

    fn act(
        &mut self,
        e: &[f32; EMBEDDING],
        rec_mse: impl FnOnce() -> f32,
        forced: Option<Action>,
        rng: &mut ChaCha8Rng,
    ) -> Decision {
        if !self.previous_pushed {
            self.memory.push(self.previous);
        }
        self.memory.update_bias();
        self.previous_pushed = false;
        let reactive = self.reactive.step(rng);
        let contextual = self.memory.retrieve(e, rng);
        let gate = self.cfg.gate;
        let (action, layer) = match (forced, contextual) {
            (Some(a), _) => (a, Layer::Human),
            (None, Some(a)) if self.memory.len() >= self.cfg.min_sequences && gate.is_none_or(|g| rec_mse() < g) => {
                (a, Layer::Contextual)
            }
            _ => (reactive, Layer::Reactive),
        };
        self.previous = Couplet { embedding: *e, action };
        Decision { action, layer, selected: contextual.is_some() }
    }

    /// A goal was reached with episode reward `r`: store the STM (docs/ALGORITHM.md, storage). By default the
    /// couplet of the last decision is not part of it (D4).
    pub fn goal(&mut self, r: f64, rng: &mut ChaCha8Rng) -> bool {
        if self.cfg.store_last_couplet && !self.previous_pushed {
            self.memory.push(self.previous);
            self.previous_pushed = true;
        }
        self.memory.store(r, rng)
    }

    /// Episode end: T back to 1; the STM too with `reset_stm_on_episode`.
    pub fn episode_end(&mut self) {
        self.memory.reset_bias();
        if self.cfg.reset_stm_on_episode {
            self.memory.reset_stm();
            self.previous = Couplet::ZERO;
            self.previous_pushed = true;
        }
    }
}

impl Controller for Sec {
    /// Storage on the goal event, before this frame's decision, so the last decision's couplet
    /// is not in the sequence (D4, D12).
    fn on_step(&mut self, step: &Step, _: Option<&[f32]>, rng: &mut ChaCha8Rng) -> bool {
        if step.goal_event {
            self.goal(step.episode_reward, rng);
        }
        step.goal_event
    }

    fn decide(&mut self, obs: &Observation, gate_mse: &mut dyn FnMut() -> f32, rng: &mut ChaCha8Rng) -> Decision {
        match obs.person {
            Some(action) => self.follow(obs.embedding, action, rng),
            None => self.decide_with(obs.embedding, gate_mse, rng),
        }
    }

    fn on_episode_end(&mut self, _: &EpisodeEnd) {
        self.episode_end();
    }

    /// The stale-inclusive value (D14).
    fn entropy(&self) -> f64 {
        self.memory.entropy()
    }

    fn memory_use(&self) -> MemoryUse {
        MemoryUse { used: self.memory.len(), capacity: self.memory.config().m }
    }

    fn checkpoints(&self) -> bool {
        true
    }

    /// The walk, the couplet waiting for the STM, and the whole memory (`Memory::put_state`).
    fn save_state(&self, out: &mut dyn std::io::Write) -> Result<(), String> {
        let mut b = Vec::new();
        for w in self.reactive.words() {
            b.extend_from_slice(&w.to_le_bytes());
        }
        for v in self.previous.embedding {
            b.extend_from_slice(&v.to_le_bytes());
        }
        b.push(self.previous.action.into());
        b.push(self.previous_pushed as u8);
        self.memory.put_state(&mut b);
        out.write_all(&b).map_err(|e| e.to_string())
    }

    fn load_state(&mut self, input: &mut dyn std::io::Read) -> Result<(), String> {
        let mut bytes = Vec::new();
        input.read_to_end(&mut bytes).map_err(|e| e.to_string())?;
        let mut r = crate::util::ByteReader { b: &bytes, at: 0, what: "checkpoint" };
        let mut read = || -> Result<(), crate::error::FileError> {
            let words = [r.u32()?, r.u32()?, r.u32()?, r.u32()?];
            let mut embedding = [0.0f32; crate::encoder::EMBEDDING];
            for v in &mut embedding {
                *v = r.f32()?;
            }
            let action = Action::new(r.take(1)?[0].into())
                .map_err(|_| crate::error::FileError::field("checkpoint", "previous", "not an action"))?;
            if let Some(v) = embedding.iter().find(|v| !v.is_finite()) {
                let rule = format!("holds {v}, not a finite number");
                return Err(crate::error::FileError::field("checkpoint", "previous.embedding", rule));
            }
            let pushed = r.bool()?;
            let walk = Reactive::from_words(words)?;
            self.memory.take_state(&mut r)?;
            self.reactive = walk;
            (self.previous, self.previous_pushed) = (Couplet { embedding, action }, pushed);
            Ok(())
        };
        read().map_err(|e| e.to_string())?;
        if r.at != bytes.len() {
            return Err(format!("{} bytes after the agent's state", bytes.len() - r.at));
        }
        Ok(())
    }

    fn reconfigure(&mut self, section: &dyn Any) -> Result<(), ConfigError> {
        Sec::reconfigure(self, own_section::<SecConfig>(section, "agent")?.clone())
    }

    fn inspect(&self) -> AgentView<'_> {
        AgentView {
            memory: Some(&self.memory),
            last_embedding: Some(&self.previous.embedding),
            min_sequences: Some(self.cfg.min_sequences),
            gate: self.cfg.gate,
        }
    }

    fn traces(&self) -> bool {
        true
    }

    fn save_memory(&self, id: &Identity) -> Result<Vec<u8>, ConfigError> {
        Ok(self.memory.to_file(id))
    }

    fn load_memory(&mut self, bytes: &[u8], id: &Identity) -> Result<usize, Error> {
        Ok(self.memory.load_file(bytes, id)?)
    }
}

#[cfg(target_arch = "wasm32")]
#[wasm_bindgen::prelude::wasm_bindgen(typescript_custom_section)]
const SEC_CONFIG_TYPESCRIPT: &str = <SecConfig as AgentConfig>::TYPESCRIPT;

//! The hooks every agent kind answers. The run loop (`crate::experiment::Run::tick`) is the env
//! loop alone and talks to agents only through them, so a new agent (DQN, ERLAM) is its own
//! module implementing `Controller` plus one arm where runs build their agent.

use super::Decision;
use crate::arena::{Action, ConfigError};
use crate::encoder::EMBEDDING;
use crate::error::Error;
use crate::memory::file::Identity;
use crate::memory::Memory;
use rand_chacha::ChaCha8Rng;
use std::any::Any;
use std::io::{Read, Write};

/// What a controller without checkpoints answers `save_state` and `load_state`.
pub const NO_CHECKPOINT: &str = "this agent does not checkpoint";

/// What an agent's decisions read of each frame (its table row's `reads`: the run renders and
/// embeds only what is read, and the perception settings apply to the agents that read the
/// embedding).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub enum Input {
    /// The perception's embedding (SEC, MFEC-ae).
    Embedding,
    /// The RGB image itself (MFEC-rp projects it).
    Image,
    /// Nothing (the reactive walk).
    Nothing,
}

/// One env step as a controller is told of it, before the decision due at it, if any.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Step {
    /// The step's own reward.
    pub reward: f64,
    /// R_ep so far, this step's reward included.
    pub episode_reward: f64,
    /// The step touched a good goal.
    pub good_goal: bool,
    /// The goal event: a good goal with a positive episode reward (SEC stores its STM on it).
    pub goal_event: bool,
    /// A decision is taken at this step.
    pub decides: bool,
    /// The step ended the episode (a goal, a death or the time limit).
    pub done: bool,
}

/// What a decision sees.
#[derive(Clone, Copy, Debug)]
pub struct Observation<'a> {
    /// The perception's embedding of the frame (all zeros unless `input` is `Embedding`).
    pub embedding: &'a [f32; EMBEDDING],
    /// The frame as RGB floats in [0, 1] (current unless `input` is `Nothing`).
    pub image: &'a [f32],
    /// This step ends the episode.
    pub terminal: bool,
    /// The action a person chose, to be followed and learned from (only for an agent whose row
    /// `can_be_driven`).
    pub person: Option<Action>,
}

/// How an episode ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EpisodeEnd {
    /// A goal event happened in it.
    pub goal: bool,
    /// A person took at least one of its decisions.
    pub driven: bool,
}

/// How full a controller's memory is (the metrics' `ltm`, the page's gauge).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct MemoryUse {
    /// Entries stored: SEC's sequences, MFEC's entries over all action buffers.
    pub used: usize,
    /// The most it keeps.
    pub capacity: usize,
}

/// What a controller's memory holds, logged with an episode now and then so that an explanation
/// of how it learns (ERLAM's: only once its graph filled) can be read off the log.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct MemoryCensus {
    /// Entries held (ERLAM's graph nodes).
    pub nodes: usize,
    /// The share of them with a value other than 0 (ERLAM: the graph's target G for the node's own
    /// action).
    pub valued_share: f64,
    /// The median of their values (0 for no entries).
    pub median_value: f64,
}

/// An agent as the run loop drives it: told of every env step, asked for a decision every
/// `decisionPeriod` steps, told of each episode's end. What it reads, whether it has a gate and
/// whether a person's driving goes through its memory are its table row's (`AgentInfo`), once.
pub trait Controller: Send {
    /// Whether `on_step` needs this step's frame (DQN stores a transition with it on decision and
    /// reward frames); the run then renders it.
    fn wants_frame(&self, _step: &Step) -> bool {
        false
    }

    /// Every env step, before the decision due at it; `frame` is the step's image (RGB floats)
    /// when `wants_frame` asked for it. Returns whether it took the step's goal event (SEC stores
    /// its STM), which the run's event log records.
    fn on_step(&mut self, step: &Step, frame: Option<&[f32]>, rng: &mut ChaCha8Rng) -> bool;

    /// The action for this frame. `gate_mse` measures the reconstruction error of the frame,
    /// on demand (an autoencoder pass).
    fn decide(&mut self, obs: &Observation, gate_mse: &mut dyn FnMut() -> f32, rng: &mut ChaCha8Rng) -> Decision;

    /// After the episode's last step.
    fn on_episode_end(&mut self, end: &EpisodeEnd);

    /// The entropy (bits) the last decision logs.
    fn entropy(&self) -> f64;

    /// How full its memory is.
    fn memory_use(&self) -> MemoryUse;

    /// A census of its memory to log with the episode that just ended, when it keeps one then
    /// (ERLAM every `erlam.censusEvery` episodes); asked after `on_episode_end`.
    fn census(&self) -> Option<MemoryCensus> {
        None
    }

    /// Whether it can write its state to a checkpoint (`experiment::checkpoint`).
    fn checkpoints(&self) -> bool {
        false
    }

    /// Writes, between two episodes, everything it has learned and every counter and draw state
    /// it keeps, so that `load_state` on a controller freshly built from the same configuration
    /// and seed continues exactly as this one would.
    fn save_state(&self, _out: &mut dyn Write) -> Result<(), String> {
        Err(NO_CHECKPOINT.into())
    }

    /// Restores what `save_state` wrote; on an error the controller is to be dropped.
    fn load_state(&mut self, _input: &mut dyn Read) -> Result<(), String> {
        Err(NO_CHECKPOINT.into())
    }

    /// Applies a live change of its parameters (the page's sliders) from the next decision:
    /// `section` is its own configuration section (the one its table row names, read with
    /// `section::own_section`), and the run has checked that nothing else changed
    /// (`RunConfig::needs_restart`). An agent without live parameters keeps this default. On an
    /// error nothing changes.
    fn reconfigure(&mut self, _section: &dyn Any) -> Result<(), ConfigError> {
        Ok(())
    }

    /// What views and explanations may read of it (the page, Python's `Run.view`).
    fn inspect(&self) -> AgentView<'_> {
        AgentView::default()
    }

    /// Whether it records the event trace (`experiment::trace`) that replays its decisions.
    fn traces(&self) -> bool {
        false
    }

    /// Its memory as a file (`memory::file`), for an agent that keeps one.
    fn save_memory(&self, _id: &Identity) -> Result<Vec<u8>, ConfigError> {
        Err(ConfigError::new("agent", NO_MEMORY_FILE))
    }

    /// Replaces its memory with a file's, returning the entries loaded; a refused file leaves
    /// the memory as it was.
    fn load_memory(&mut self, _bytes: &[u8], _id: &Identity) -> Result<usize, Error> {
        Err(ConfigError::new("agent", NO_MEMORY_FILE).into())
    }
}

/// What an agent without memory files answers `save_memory` and `load_memory`.
pub const NO_MEMORY_FILE: &str = "only SEC keeps a memory file (this run's agent does not)";

/// What an agent shows of itself, read-only: the page's views and explanation panel and Python
/// read agents through this alone. An agent shows what it has and leaves the rest `None`.
#[derive(Clone, Copy, Debug, Default)]
pub struct AgentView<'a> {
    /// Its sequential memory (SEC): STM, LTM, the last retrieval's couplets, Q and p.
    pub memory: Option<&'a Memory>,
    /// The embedding of the last decision's frame, as it entered (or will enter) the memory.
    pub last_embedding: Option<&'a [f32; EMBEDDING]>,
    /// The memory acts only once the LTM holds this many sequences.
    pub min_sequences: Option<usize>,
    /// The reconstruction gate's threshold, when it has a gate that is on.
    pub gate: Option<f32>,
}

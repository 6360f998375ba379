//! DQN's and ERLAM's configuration sections (`dqn`, `erlam` in a `RunConfig`), as the authors'
//! `run_agent_dqn.py` and `run_agent_erlam.py` set them (docs/ALGORITHM.md, "DQN"). The core
//! knows these agents only as rows of its table with opaque sections (`SectionSpec::native`);
//! `register` gives the sections their types here, so configurations are checked, filled in
//! and written in full by every tool that links this crate.

use sec_playground::agent::section::{register_section, AgentConfig, SectionSpec};
use sec_playground::arena::ConfigError;
use sec_playground::experiment::RunConfig;

/// DQN's (and ERLAM's network's) parameters. Defaults are the authors'.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase", default, deny_unknown_fields)]
pub struct DqnConfig {
    /// RMSprop's learning rate.
    pub learning_rate: f64,
    /// Discount factor.
    pub gamma: f64,
    /// Transitions per training batch.
    pub batch_size: usize,
    /// Transitions the replay buffer keeps (the authors ran 25,000 and a 5,000 variant).
    pub replay_size: usize,
    /// Decisions taken by the reactive walk before the network's own.
    pub random_decisions: u64,
    /// Decisions over which epsilon falls linearly from `epsilon_start` to `epsilon_end`.
    pub epsilon_decisions: u64,
    /// Exploration rate at the start of the decay.
    pub epsilon_start: f64,
    /// Exploration rate after the decay.
    pub epsilon_end: f64,
    /// A training step every this many decisions.
    pub train_every: u64,
    /// The target network is synced every this many decisions.
    pub target_sync: u64,
    /// Deviation D13 undone: a transition's reward sums the frames since the last one, instead of
    /// the authors' single frame's reward (or the episode's, on a goal frame).
    pub sum_rewards: bool,
}

impl Default for DqnConfig {
    fn default() -> Self {
        DqnConfig {
            learning_rate: 2.5e-4,
            gamma: 0.99,
            batch_size: 32,
            replay_size: 25_000,
            random_decisions: 1250,
            epsilon_decisions: 25_000,
            epsilon_start: 1.0,
            epsilon_end: 0.1,
            train_every: 4,
            target_sync: 2500,
            sum_rewards: false,
        }
    }
}

fn range(field: &str, value: impl std::fmt::Display, allowed: &str) -> Result<(), ConfigError> {
    Err(ConfigError::new(format!("dqn.{field}"), format!("{value} is out of range {allowed}")))
}

impl DqnConfig {
    /// Every field in its range, the error naming it.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let unit = |v: f64| v.is_finite() && (0.0..=1.0).contains(&v);
        if !(self.learning_rate.is_finite() && self.learning_rate > 0.0 && self.learning_rate <= 1.0) {
            return range("learningRate", self.learning_rate, "(0, 1]");
        }
        if !unit(self.gamma) {
            return range("gamma", self.gamma, "[0, 1]");
        }
        if !(1..=4096).contains(&self.batch_size) {
            return range("batchSize", self.batch_size, "1..=4096");
        }
        if !(self.batch_size..=1_000_000).contains(&self.replay_size) {
            return range(
                "replaySize",
                self.replay_size,
                &format!("{}..=1000000 (at least batchSize)", self.batch_size),
            );
        }
        if self.random_decisions > 100_000_000 {
            return range("randomDecisions", self.random_decisions, "0..=100000000");
        }
        if !(1..=100_000_000).contains(&self.epsilon_decisions) {
            return range("epsilonDecisions", self.epsilon_decisions, "1..=100000000");
        }
        if !unit(self.epsilon_start) {
            return range("epsilonStart", self.epsilon_start, "[0, 1]");
        }
        if !unit(self.epsilon_end) || self.epsilon_end > self.epsilon_start {
            return range("epsilonEnd", self.epsilon_end, &format!("[0, epsilonStart = {}]", self.epsilon_start));
        }
        if !(1..=100_000).contains(&self.train_every) {
            return range("trainEvery", self.train_every, "1..=100000");
        }
        if !(1..=100_000_000).contains(&self.target_sync) {
            return range("targetSync", self.target_sync, "1..=100000000");
        }
        Ok(())
    }

    /// Epsilon after one more decision: the authors subtract (start - end) / epsilon_decisions
    /// after every decision and stop at `epsilon_end` (repeated subtraction, as they did).
    pub fn next_epsilon(&self, epsilon: f64) -> f64 {
        let step = (self.epsilon_start - self.epsilon_end) / self.epsilon_decisions as f64;
        (epsilon - step).max(self.epsilon_end)
    }
}

impl AgentConfig for DqnConfig {
    const KEY: &'static str = "dqn";
    fn validate(&self) -> Result<(), ConfigError> {
        DqnConfig::validate(self)
    }
}

/// ERLAM's associative memory (its network and exploration are `DqnConfig`'s), as the authors'
/// `run_agent_erlam.py` sets it.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase", default, deny_unknown_fields)]
pub struct ErlamConfig {
    /// The weight of the graph's target in the loss, mean[(Y - Q)^2 + lambda (G - Q)^2].
    pub lambda: f64,
    /// Graph nodes kept (the authors ran 25,000 and a 5,000 variant).
    pub nodes: usize,
    /// Evict the least recently improved node when the graph is full (the authors': on).
    pub forgetting: bool,
    /// Value propagation every this many episodes.
    pub propagate_every: u64,
    /// A state within this Euclidean distance of a stored node's embedding is that node.
    pub merge_distance: f64,
    /// Propagation stops when a sweep changes the returns by at most this much in total.
    pub converge: f64,
    /// Propagation sets a terminal node to r + gamma max Rt of its successors too, as the
    /// authors' code does (on): a non-terminal view merged into a goal's node links it on, and
    /// the cycles this makes lift values above any reward (REPRODUCTION.md). Off, a deviation: a
    /// terminal node keeps the return it was stored with.
    pub propagate_past_terminals: bool,
    /// Logs the graph's census (nodes, the share with G != 0, the median G) with every this
    /// many episodes (0: never), so the timing of learning can be held against the graph's fill.
    pub census_every: u64,
}

impl Default for ErlamConfig {
    fn default() -> Self {
        ErlamConfig {
            lambda: 0.3,
            nodes: 25_000,
            forgetting: true,
            propagate_every: 50,
            merge_distance: 0.02,
            converge: 1e-6,
            propagate_past_terminals: true,
            census_every: 0,
        }
    }
}

impl ErlamConfig {
    /// Every field in its range, the error naming it.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let bad = |field: &str, value: String, allowed: &str| {
            Err(ConfigError::new(format!("erlam.{field}"), format!("{value} is out of range {allowed}")))
        };
        if !(self.lambda.is_finite() && (0.0..=100.0).contains(&self.lambda)) {
            return bad("lambda", self.lambda.to_string(), "[0, 100]");
        }
        if !(2..=1_000_000).contains(&self.nodes) {
            return bad("nodes", self.nodes.to_string(), "2..=1000000");
        }
        if !(1..=1_000_000).contains(&self.propagate_every) {
            return bad("propagateEvery", self.propagate_every.to_string(), "1..=1000000");
        }
        if !(self.merge_distance.is_finite() && self.merge_distance >= 0.0 && self.merge_distance <= 1e6) {
            return bad("mergeDistance", self.merge_distance.to_string(), "[0, 1e6]");
        }
        if !(self.converge.is_finite() && self.converge > 0.0 && self.converge <= 1e6) {
            return bad("converge", self.converge.to_string(), "(0, 1e6]");
        }
        if self.census_every > 1_000_000 {
            return bad("censusEvery", self.census_every.to_string(), "0..=1000000");
        }
        Ok(())
    }
}

impl AgentConfig for ErlamConfig {
    const KEY: &'static str = "erlam";
    fn validate(&self) -> Result<(), ConfigError> {
        ErlamConfig::validate(self)
    }
}

/// Gives the core's `dqn` and `erlam` sections these types (`register_section`): configurations
/// read or made afterwards hold them checked and filled in. Every tool that runs or writes
/// configurations calls it first (`factory` too); again is harmless.
///
/// ```
/// use sec_playground::experiment::RunConfig;
/// sec_dqn::register();
/// let cfg = RunConfig::from_json(r#"{"kind": "dqn", "dqn": {"gamma": 0.9}}"#).unwrap();
/// assert_eq!(sec_dqn::config::dqn(&cfg).unwrap().batch_size, 32, "filled in from the defaults");
/// assert!(RunConfig::from_json(r#"{"dqn": {"gamma": 2}}"#).is_err(), "checked");
/// ```
pub fn register() {
    register_section(SectionSpec::of::<DqnConfig>());
    register_section(SectionSpec::of::<ErlamConfig>());
}

/// The section of type `T` in `cfg`, whether the configuration was made before `register` (an
/// opaque section, read here) or after; checked.
fn section<T: AgentConfig + serde::de::DeserializeOwned + Default>(cfg: &RunConfig) -> Result<T, ConfigError> {
    let value = cfg.sections.get(T::KEY).map_or(serde_json::Value::Null, |s| s.to_value());
    let section = if value.is_null() {
        T::default()
    } else {
        serde_json::from_value(value).map_err(|e| ConfigError::new(T::KEY, e.to_string()))?
    };
    section.validate()?;
    Ok(section)
}

/// The run's DQN section.
pub fn dqn(cfg: &RunConfig) -> Result<DqnConfig, ConfigError> {
    section(cfg)
}

/// The run's ERLAM section.
pub fn erlam(cfg: &RunConfig) -> Result<ErlamConfig, ConfigError> {
    section(cfg)
}

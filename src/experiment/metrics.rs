//! What an episode counts, as the paper's tables count it: the running totals of the episode in
//! progress (`EpisodeState`) and the line they become at its end (`EpisodeMetrics`).

use crate::agent::controller::MemoryCensus;
use crate::agent::{Decision, Layer};

/// One episode as the paper's tables count it.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct EpisodeMetrics {
    /// Its number, from 0.
    pub episode: u64,
    /// The layout it started in.
    pub layout: String,
    /// R_ep when positive, else 0 (the tables' reward).
    pub reward: f64,
    /// R_ep itself: goal reward plus the per-step penalties.
    pub raw_reward: f64,
    /// A goal event happened.
    pub goal: bool,
    /// Env steps it lasted.
    pub env_steps: u32,
    /// Decisions taken in it.
    pub decisions: u32,
    /// Mean entropy (bits) logged at every decision, stale values included (the authors').
    pub entropy: f64,
    /// Mean over the decisions whose entropy was computed afresh; `None` if none was.
    pub entropy_fresh: Option<f64>,
    /// Sequences in the LTM at the end of the episode.
    pub ltm: usize,
    /// Share of decisions taken by the contextual layer.
    pub contextual_share: f64,
    /// A person drove at least one decision of it (the page's "drive it yourself").
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub human: bool,
    /// The agent's census of its memory after the episode, where it logs one (ERLAM's graph every
    /// `erlam.censusEvery` episodes).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub census: Option<MemoryCensus>,
}

impl EpisodeMetrics {
    /// One JSON line (no newline): the runner's output format.
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).expect("metrics serialise")
    }
}

/// The running totals of the episode in progress.
#[derive(Clone, Debug)]
pub struct EpisodeState {
    /// Its number, from 0.
    pub episode: u64,
    /// The layout it started in.
    pub layout: String,
    /// R_ep so far.
    pub reward: f64,
    /// Decisions so far.
    pub decisions: u32,
    /// Of them, the contextual layer's.
    pub contextual: u32,
    /// Decisions a person took.
    pub human: u32,
    /// A goal event happened.
    pub goal: bool,
    entropy_sum: f64,
    fresh_sum: f64,
    fresh_n: u32,
}

impl EpisodeState {
    /// The totals of a fresh episode.
    pub fn new(episode: u64, layout: String) -> Self {
        EpisodeState {
            episode,
            layout,
            reward: 0.0,
            decisions: 0,
            contextual: 0,
            human: 0,
            goal: false,
            entropy_sum: 0.0,
            fresh_sum: 0.0,
            fresh_n: 0,
        }
    }

    /// Counts a decision and the entropy it logged (fresh when the contextual layer selected).
    pub fn record(&mut self, d: &Decision, entropy: f64) {
        self.decisions += 1;
        self.contextual += (d.layer == Layer::Contextual) as u32;
        self.human += (d.layer == Layer::Human) as u32;
        self.entropy_sum += entropy;
        if d.selected {
            self.fresh_sum += entropy;
            self.fresh_n += 1;
        }
    }

    /// The episode's line: `env_steps` it lasted, `ltm` the memory at its end.
    pub fn finish(self, env_steps: u32, ltm: usize) -> EpisodeMetrics {
        let per_decision = |x: f64| x / self.decisions.max(1) as f64;
        EpisodeMetrics {
            episode: self.episode,
            reward: self.reward.max(0.0),
            raw_reward: self.reward,
            goal: self.goal,
            env_steps,
            decisions: self.decisions,
            entropy: per_decision(self.entropy_sum),
            entropy_fresh: (self.fresh_n > 0).then(|| self.fresh_sum / self.fresh_n as f64),
            ltm,
            contextual_share: per_decision(self.contextual as f64),
            human: self.human > 0,
            layout: self.layout,
            census: None,
        }
    }
}

/// The digest of a log continued by one episode's line (`Run`'s running digest).
pub(crate) fn extend_log(digest: u64, line: &str) -> u64 {
    crate::util::fnv1a_extend(crate::util::fnv1a_extend(digest, line.as_bytes()), b"\n")
}

//! The trace: a recorded stream of events fed through SEC's agent with a given seed, writing its
//! internals after every decision. Anyone with another implementation can feed it the same events
//! and compare, decision by decision.
//!
//! Input, one JSON object per line:
//! `{"event":"decision","embedding":[20 numbers],"recMse":0.002}` (`recMse` optional, default 0),
//! `{"event":"goal","reward":2.7}` and `{"event":"episodeEnd"}`, after an optional first line
//! `{"event":"perception","perception":"untrained","embeddingScale":1.0}` saying which encoder
//! made the embeddings (a recorded run writes it; `trace` refuses a config that says otherwise).
//! Output, one line per decision: the action and the layer that took it, the sequences in the
//! LTM, T (the entries that differ from 1, as [row, column, value], as used by this decision), the
//! selected couplets with their G, Q and p (null when nothing was selected) and the entropy as
//! the authors log it (stale when nothing was selected).

use crate::agent::{Layer, Sec, SecConfig};
use crate::arena::Action;
use crate::encoder::{PerceptionKind, EMBEDDING};
use crate::error::{Error, FileError};
use crate::seed::Stream;
use rand_chacha::ChaCha8Rng;
use std::io::{BufRead, Write};

/// One recorded event.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "event", rename_all = "camelCase", deny_unknown_fields)]
pub enum Event {
    /// Which encoder made the embeddings that follow, and its scale.
    Perception {
        /// Which encoder.
        perception: PerceptionKind,
        #[serde(rename = "embeddingScale")]
        /// Its scale.
        embedding_scale: f32,
    },
    /// A decision: the frame's embedding and the gate's MSE.
    Decision {
        /// The embedding the agent read.
        embedding: Vec<f32>,
        /// The reconstruction gate's last MSE.
        #[serde(rename = "recMse", default)]
        rec_mse: f32,
    },
    /// A goal reached with episode reward `reward`: the STM is stored if it is positive.
    Goal {
        /// R_ep at the goal.
        reward: f64,
    },
    /// The episode ended.
    EpisodeEnd,
}

/// A selected couplet as the trace writes it.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TracedCouplet {
    /// LTM sequence.
    pub row: u32,
    /// STM position.
    pub col: u32,
    /// Its biased similarity G.
    pub g: f64,
}

/// The internals after one decision.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TraceLine {
    /// The decision's number.
    pub decision: u64,
    /// The action taken.
    pub action: Action,
    /// The layer that took it (R, C or H).
    pub layer: String,
    /// Sequences in the LTM.
    pub ltm: usize,
    /// The bias T where it is not 1: (sequence, position, T).
    pub t: Vec<(u32, u32, f64)>,
    /// The couplets the retrieval selected.
    pub selected: Vec<TracedCouplet>,
    /// Q per action, when something was selected.
    pub q: Option<Vec<f64>>,
    /// p per action, when something was selected.
    pub p: Option<Vec<f64>>,
    /// The entropy logged.
    pub entropy: f64,
}

/// Why a trace stopped.
#[derive(Debug)]
pub enum TraceError {
    /// A bad line: 1-based line number and what is wrong.
    Input(Error),
    /// Reading or writing failed.
    Io(std::io::Error),
}

impl std::fmt::Display for TraceError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TraceError::Input(e) => e.fmt(f),
            TraceError::Io(e) => write!(f, "i/o: {e}"),
        }
    }
}

impl std::error::Error for TraceError {}

impl From<std::io::Error> for TraceError {
    fn from(e: std::io::Error) -> Self {
        TraceError::Io(e)
    }
}

/// The agent's random stream for `seed`: the same one a `Run` with that seed gives its agent, so
/// the events a run records trace to the same actions.
pub fn agent_rng(seed: u64) -> ChaCha8Rng {
    crate::seed::rng(seed, Stream::Agent)
}

/// An event log's line `line` is wrong in `field`.
fn bad(line: usize, field: &str, message: impl Into<String>) -> FileError {
    FileError { line: Some(line), ..FileError::field("events", field, message) }
}

/// Parses one event line; `line` is its 1-based number, for the error.
pub fn parse_event(text: &str, line: usize) -> Result<Event, FileError> {
    let event: Event = serde_json::from_str(text).map_err(|e| bad(line, "event", e.to_string()))?;
    if let Event::Decision { embedding, rec_mse } = &event {
        if embedding.len() != EMBEDDING {
            return Err(bad(line, "embedding", format!("has {} numbers, not {EMBEDDING}", embedding.len())));
        }
        if !rec_mse.is_finite() || *rec_mse < 0.0 {
            return Err(bad(line, "recMse", format!("{rec_mse} is out of range [0, inf)")));
        }
    }
    if let Event::Goal { reward } = event {
        if !reward.is_finite() {
            return Err(bad(line, "reward", format!("{reward} is not a finite number")));
        }
    }
    Ok(event)
}

/// The internals of `agent` after decision number `decision`.
pub fn trace_line(agent: &Sec, decision: u64, action: Action, layer: Layer) -> TraceLine {
    let memory = agent.memory();
    let n = memory.config().n;
    let t = memory
        .bias()
        .iter()
        .enumerate()
        .filter(|(_, &v)| v != 1.0)
        .map(|(i, &v)| ((i / n) as u32, (i % n) as u32, v))
        .collect();
    let selected: Vec<TracedCouplet> =
        memory.selected().iter().map(|s| TracedCouplet { row: s.row, col: s.col, g: s.g }).collect();
    let any = !selected.is_empty();
    TraceLine {
        decision,
        action,
        layer: match layer {
            Layer::Contextual => "C",
            Layer::Reactive => "R",
            Layer::Human => "H",
        }
        .into(),
        ltm: memory.len(),
        t,
        selected,
        q: any.then(|| memory.q().to_vec()),
        p: any.then(|| memory.p().to_vec()),
        entropy: memory.entropy(),
    }
}

/// Feeds the events of `input` through a fresh SEC agent with `cfg` and `seed`, writing one
/// [`TraceLine`] per decision to `output`; `perception`, when given, must be the one the events
/// name (if they name one). Returns the number of decisions.
pub fn trace(
    cfg: &SecConfig,
    perception: Option<PerceptionKind>,
    seed: u64,
    input: impl BufRead,
    mut output: impl Write,
) -> Result<u64, TraceError> {
    let mut rng = agent_rng(seed);
    let mut agent = Sec::new(cfg.clone(), &mut rng).map_err(|e| TraceError::Input(e.into()))?;
    let mut decisions = 0;
    for (i, text) in input.lines().enumerate() {
        let text = text?;
        if text.trim().is_empty() {
            continue;
        }
        match parse_event(&text, i + 1).map_err(|e| TraceError::Input(e.into()))? {
            Event::Decision { embedding, rec_mse } => {
                let e: [f32; EMBEDDING] = embedding.try_into().expect("checked by parse_event");
                let d = agent.decide(&e, rec_mse, &mut rng);
                let line = trace_line(&agent, decisions, d.action, d.layer);
                serde_json::to_writer(&mut output, &line).map_err(std::io::Error::from)?;
                output.write_all(b"\n")?;
                decisions += 1;
            }
            Event::Goal { reward } => {
                agent.goal(reward, &mut rng);
            }
            Event::EpisodeEnd => agent.episode_end(),
            Event::Perception { perception: recorded, .. } => {
                if let Some(want) = perception.filter(|&p| p != recorded) {
                    return Err(TraceError::Input(
                        bad(
                            i + 1,
                            "perception",
                            format!("the events were recorded with the {recorded:?} encoder, the config says {want:?}"),
                        )
                        .into(),
                    ));
                }
            }
        }
    }
    output.flush()?;
    Ok(decisions)
}

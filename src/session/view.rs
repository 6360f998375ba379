//! What a front end shows of a run after a decision: the page's views and "explain this
//! decision", Python's `Run.view()` and `Run.explain()`. Built from the agent's `AgentView`, so
//! every front end shows the same numbers under the same names.

use crate::agent::SecConfig;
use crate::agent::{Decision, Layer};
use crate::arena::Action;
use crate::experiment::Run;
use crate::memory::{Selected, ValueFn, ACTIONS};
use serde::Serialize;

/// The last decision and the state the views show.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct DecisionView {
    /// The action taken at the last decision (none before the first).
    pub action: Option<Action>,
    /// The layer that chose it.
    pub layer: Option<Layer>,
    /// Couplets the contextual layer selected at the last decision.
    pub selected: usize,
    /// The entropy (bits) the last decision logs.
    pub entropy: f64,
    /// The memory's policy p = Q / sum Q, while it has one (an agent with a memory that selected
    /// something, or whose entropy is still that of an earlier selection).
    pub p: Option<[f64; ACTIONS]>,
    /// The reconstruction error the gate measured last (none before its first measurement, every
    /// 16 env steps, or for an agent without the gate).
    pub gate_mse: Option<f32>,
    /// Entries in the agent's memory, and the most it keeps.
    pub ltm: usize,
    /// The most entries it keeps.
    pub capacity: usize,
    /// The episode in progress and its env step.
    pub episode: u64,
    /// The env step within the episode.
    pub step: u32,
    /// R_ep so far.
    pub episode_reward: f64,
    /// The body's position on the floor and its heading (radians).
    pub x: f32,
    /// Position z.
    pub z: f32,
    /// Heading, radians.
    pub heading: f32,
    /// Decisions since the run started (a rate is its change over time).
    pub decisions: u64,
    /// The memory acts only once the LTM holds this many sequences (0 for an agent without).
    pub min_sequences: usize,
    /// The reconstruction gate's threshold (none: no gate).
    pub gate: Option<f32>,
    /// The embedding of the last decision's frame (none for an agent that keeps none).
    pub embedding: Option<Vec<f32>>,
}

/// The last decision's contextual layer term by term (no couplets when it selected nothing).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Explanation {
    /// Each selected couplet: its LTM sequence and STM position, G, T, rr, d, the action it votes
    /// for and its value.
    pub couplets: Vec<Selected>,
    /// Q per action (the sum of its couplets' values) and p = Q / sum Q.
    pub q: [f64; ACTIONS],
    /// p = Q / sum Q.
    pub p: [f64; ACTIONS],
    /// The parameters the terms were computed with.
    pub tau: f64,
    /// The value function's name.
    pub value_function: &'static str,
    /// The absolute threshold theta_abs.
    pub theta_abs: f64,
    /// The proportional threshold theta_prop.
    pub theta_prop: f64,
    /// Whether the sequential bias is on (SEC, not NSEC).
    pub sequential_bias: bool,
}

/// The view of `run` after `last` (the last decision, if any) and `decisions` decisions.
pub fn decision_view(run: &mut Run, last: Option<Decision>, decisions: u64) -> DecisionView {
    let gate_mse = run.gate_mse();
    let (entropy, memory_use) = (run.controller().entropy(), run.controller().memory_use());
    let agent = run.inspect();
    let (p, selected) = match agent.memory {
        Some(m) => ((m.entropy() > 0.0 || !m.selected().is_empty()).then(|| *m.p()), m.selected().len()),
        None => (None, 0),
    };
    let body = &run.env().world().agent;
    DecisionView {
        action: last.map(|d| d.action),
        layer: last.map(|d| d.layer),
        selected,
        entropy,
        p,
        gate_mse,
        ltm: memory_use.used,
        capacity: memory_use.capacity,
        episode: run.env().episode(),
        step: run.env().steps(),
        episode_reward: run.current().map_or(0.0, |c| c.reward),
        x: body.pos.x,
        z: body.pos.y,
        heading: body.heading,
        decisions,
        min_sequences: agent.min_sequences.unwrap_or(0),
        gate: agent.gate,
        embedding: agent.last_embedding.map(|e| e.to_vec()),
    }
}

/// The last decision of `run` explained; the parameters are the agent's memory's, or the
/// configuration's for an agent without one.
pub fn explain(run: &Run) -> Explanation {
    let memory = run.inspect().memory;
    let cfg = memory.map_or(&run.config().section::<SecConfig>().memory, |m| m.config());
    let (couplets, q, p) = match memory {
        Some(m) if !m.selected().is_empty() => {
            let couplets = m.selected().to_vec();
            (couplets, *m.q(), *m.p())
        }
        _ => (Vec::new(), [0.0; ACTIONS], [0.0; ACTIONS]),
    };
    let value_function =
        ValueFn::ALL.iter().find(|(_, v)| *v == cfg.value_function).map_or("default", |(name, _)| name);
    Explanation {
        couplets,
        q,
        p,
        tau: cfg.tau,
        value_function,
        theta_abs: cfg.theta_abs,
        theta_prop: cfg.theta_prop,
        sequential_bias: cfg.sequential_bias,
    }
}

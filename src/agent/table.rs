//! Every agent a run can hold, declared once: its key (the page's `agent` setting, the CLI's
//! and Python's name for it), its label, which configuration section it reads and what it can do.
//! The page, the element, the explanation panel, compare, Python and the CLI read this table;
//! the settings that apply to an agent follow from its capabilities. Adding an agent is its
//! module (a `Controller`) and a row here.

use super::controller::{Controller, Input};
use super::mfec::{Embedding, Mfec, MfecConfig, RandomProjection};
use super::section::{own_section, registered, SectionSpec};
use super::{Reactive, Sec, SecConfig};
use crate::arena::ConfigError;
use crate::encoder::Perception;
use crate::seed::{self, Stream};
use rand_chacha::ChaCha8Rng;
use serde::Serialize;
use std::any::Any;

/// Builds an agent for a run with `seed` from its own configuration section (the one its row
/// names; `()` for none), drawing its initial state from the agent stream `rng`; `perception` is
/// the run's (an agent that embeds by itself reads it).
pub type Build = fn(&dyn Any, &Perception, u64, &mut ChaCha8Rng) -> Result<Box<dyn Controller>, ConfigError>;

/// The agents a run can hold (`RunConfig.kind`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum AgentKind {
    /// SEC; NSEC is SEC without `sequentialBias`.
    Sec,
    /// Model-free episodic control, on the autoencoder's embedding or a random projection.
    Mfec,
    /// The reactive layer alone.
    Reactive,
    /// The authors' DQN: a Nature CNN on the camera image, trained with burn (native only).
    Dqn,
    /// DQN with ERLAM's associative memory graph over the trained autoencoder's embeddings.
    Erlam,
}

/// One row of the agent table.
#[derive(Clone, Copy, Debug, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct AgentInfo {
    /// Its name everywhere: the page's `agent` setting, the CLI, Python.
    pub key: &'static str,
    /// As the page writes it.
    pub label: &'static str,
    /// Its label with the sequential bias off, for an agent that has one (SEC: NSEC).
    pub unbiased_label: Option<&'static str>,
    /// One line on what it is.
    pub about: &'static str,
    /// Why its decision was not its memory's, when that is not SEC's arbitration (the page's
    /// "why" line); `None` for an agent whose views explain it (SEC).
    pub explores: Option<&'static str>,
    /// Its configuration section: its key in a `RunConfig`'s JSON, its type's defaults and
    /// parser (`None`: it has no parameters). Rows may share one (MFEC's two).
    pub section: Option<SectionSpec>,
    /// What it reads of each frame.
    pub reads: Input,
    /// A sequential memory the views show (STM, LTM, the couplets of a decision), files of it,
    /// live parameters.
    pub has_memory: bool,
    /// Arbitrates with the reconstruction gate (which then watches every frame).
    pub has_gate: bool,
    /// Runs only natively (its networks are trained with burn, which the wasm build leaves out).
    pub native_only: bool,
    /// A person's driving can go through its memory (the page's "record").
    pub can_be_driven: bool,
    /// The `RunConfig.kind` it runs as.
    pub kind: AgentKind,
    /// Its `RunConfig.mfec.embedding`, for the MFEC rows.
    #[serde(rename = "mfecEmbedding")]
    pub embedding: Option<Embedding>,
    /// How the core builds it (`None`: a native crate does, `experiment::AgentFactory`).
    #[serde(skip)]
    pub build: Option<Build>,
}

fn mfec(section: &dyn Any, seed: u64, rng: &mut ChaCha8Rng) -> Result<Mfec, ConfigError> {
    let cfg: &MfecConfig = own_section(section, "mfec")?;
    Mfec::new(cfg.clone(), rng).map(|m| {
        if cfg.embedding == Embedding::RandomProjection {
            m.with_projection(RandomProjection::new(&mut seed::rng(seed, Stream::Projection)))
        } else {
            m
        }
    })
}

/// The agents, in the order the page offers them: what the page, Python (`agents()`) and the
/// CLI (`sec-experiment agents`) read.
///
/// ```
/// use sec_playground::agent::AGENTS;
/// let sec = AGENTS.iter().find(|a| a.key == "sec").expect("SEC is an agent");
/// assert!(sec.has_memory && !sec.native_only);
/// assert!(AGENTS.iter().filter(|a| a.native_only).all(|a| ["dqn", "erlam"].contains(&a.key)));
/// ```
#[rustfmt::skip]
pub const AGENTS: &[AgentInfo] = &[
    AgentInfo {
        key: "sec", label: "SEC", unbiased_label: Some("NSEC"),
        about: "Sequential episodic control: stores the views and actions that led to a goal as sequences and replays them, with a reactive walk until memory knows the view.",
        explores: None, section: Some(SectionSpec::of::<SecConfig>()), reads: Input::Embedding,
        has_memory: true, has_gate: true, native_only: false, can_be_driven: true,
        kind: AgentKind::Sec, embedding: None,
        build: Some(|section, _, _, rng| Ok(Box::new(Sec::new(own_section::<SecConfig>(section, "agent")?.clone(), rng)?))),
    },
    AgentInfo {
        key: "mfec-ae", label: "MFEC", unbiased_label: None,
        about: "Model-free episodic control on the autoencoder's embedding: the best return seen per view and action, k nearest neighbours elsewhere.",
        explores: Some("MFEC explores with the reactive walk (its warm-up, or an ε step)."),
        section: Some(SectionSpec::of::<MfecConfig>()), reads: Input::Embedding,
        has_memory: false, has_gate: false, native_only: false, can_be_driven: false,
        kind: AgentKind::Mfec, embedding: Some(Embedding::Autoencoder),
        build: Some(|section, _, seed, rng| Ok(Box::new(mfec(section, seed, rng)?))),
    },
    AgentInfo {
        key: "mfec-rp", label: "MFEC on a random projection", unbiased_label: None,
        about: "MFEC on a fixed random projection of the camera image instead of the autoencoder.",
        explores: Some("MFEC explores with the reactive walk (its warm-up, or an ε step)."),
        section: Some(SectionSpec::of::<MfecConfig>()), reads: Input::Image,
        has_memory: false, has_gate: false, native_only: false, can_be_driven: false,
        kind: AgentKind::Mfec, embedding: Some(Embedding::RandomProjection),
        build: Some(|section, _, seed, rng| Ok(Box::new(mfec(section, seed, rng)?))),
    },
    AgentInfo {
        key: "reactive", label: "the reactive walk", unbiased_label: None,
        about: "The reactive layer alone: straight runs and turns, no memory.",
        explores: Some("The reactive walk alone: straight runs and turns, no memory."),
        section: None, reads: Input::Nothing,
        has_memory: false, has_gate: false, native_only: false, can_be_driven: false,
        kind: AgentKind::Reactive, embedding: None,
        build: Some(|_, _, _, rng| Ok(Box::new(Reactive::new(rng)))),
    },
    AgentInfo {
        key: "dqn", label: "DQN", unbiased_label: None,
        about: "The authors' deep Q-network on the camera image (native only: sec-experiment).",
        explores: Some("DQN explores with ε-greedy steps."),
        section: Some(SectionSpec::native("dqn")), reads: Input::Image,
        has_memory: false, has_gate: false, native_only: true, can_be_driven: false,
        kind: AgentKind::Dqn, embedding: None, build: None,
    },
    AgentInfo {
        key: "erlam", label: "ERLAM", unbiased_label: None,
        about: "DQN with ERLAM's associative memory graph over the trained autoencoder's embeddings (native only).",
        explores: Some("ERLAM explores with ε-greedy steps."),
        section: Some(SectionSpec::native("erlam")), reads: Input::Image,
        has_memory: false, has_gate: false, native_only: true, can_be_driven: false,
        kind: AgentKind::Erlam, embedding: None, build: None,
    },
];
impl AgentInfo {
    /// The row of `key`; an unknown key is an error listing the known ones.
    pub fn find(key: &str) -> Result<&'static AgentInfo, crate::arena::ConfigError> {
        AGENTS.iter().find(|a| a.key == key).ok_or_else(|| {
            let keys: Vec<&str> = AGENTS.iter().map(|a| a.key).collect();
            crate::arena::ConfigError::new(
                "agent",
                format!("'{}' is not one of {}", crate::util::shown(key), keys.join(", ")),
            )
        })
    }

    /// The row of a run's kind and MFEC embedding.
    pub fn of(kind: AgentKind, embedding: Embedding) -> &'static AgentInfo {
        AGENTS
            .iter()
            .find(|a| a.kind == kind && a.embedding.is_none_or(|e| e == embedding))
            .expect("every kind has a row")
    }

    /// The agents' configuration sections, one per key (rows may share one), in table order; a
    /// native agent's is the type its crate registered, if it did (`register_section`).
    pub fn sections() -> impl Iterator<Item = SectionSpec> {
        let mut seen: Vec<&str> = Vec::new();
        AGENTS.iter().filter_map(|a| a.section).filter_map(move |s| {
            let new = !seen.contains(&s.key);
            seen.push(s.key);
            new.then(|| registered(s.key).unwrap_or(s))
        })
    }

    /// The section keys of the native agents' rows (`native_only`): what their runs may read
    /// (ERLAM's network is DQN's) and what the other runs neither read nor write.
    pub fn native_section_keys() -> Vec<&'static str> {
        AGENTS.iter().filter(|a| a.native_only).filter_map(|a| a.section.map(|s| s.key)).collect()
    }

    /// The keys of the agents with `capability`, in table order.
    pub fn keys_where(capability: fn(&AgentInfo) -> bool) -> Vec<&'static str> {
        AGENTS.iter().filter(|a| capability(a)).map(|a| a.key).collect()
    }
}

//! The agents: SEC (`sec`: its contextual layer of `crate::memory` arbitrated with the reactive
//! walk), the reactive walk alone and MFEC, all driven by the run loop through the `Controller`
//! hooks. The deep baselines (DQN, ERLAM) are rows of the table whose code and configuration
//! live in the native crate `crates/sec-dqn`, which registers its sections' types at start-up.

pub mod controller;
pub mod mfec;
pub mod reactive;
mod sec;
pub mod section;
pub mod table;

use crate::arena::Action;
pub use reactive::Reactive;
pub use sec::{Sec, SecConfig};
pub use table::{AgentInfo, AgentKind, AGENTS};

/// Which layer's action was taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Layer {
    #[serde(rename = "R")]
    /// The reactive walk.
    Reactive,
    #[serde(rename = "C")]
    /// The contextual layer: memory.
    Contextual,
    /// A person at the controls (the page's "drive it yourself").
    #[serde(rename = "H")]
    Human,
}

/// One decision's outcome.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Decision {
    /// The action taken.
    pub action: Action,
    /// The layer that chose it.
    pub layer: Layer,
    /// Whether the contextual layer selected couplets (so its entropy is fresh).
    pub selected: bool,
}

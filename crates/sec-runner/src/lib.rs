#![warn(missing_docs)]
//! The experiment runner, apart from the tools that report on its output so that it stays light:
//! `sec-experiment run` (crates/sec-tools) and the Python package's Ray driver (crates/sec-py)
//! make the same files through it. The agents the core does not hold (DQN and ERLAM, burn) come
//! in through each job's `AgentFactory`; without one, their runs are refused by name.
//!
//! One concern per module, from the bottom up: `plan` (what a grid is: jobs, the experiment's
//! manifest, shards, seeds), `layout` (where its files go, written atomically), `verify` (what is
//! missing, and whether each finished log is what its configuration makes), `play` (playing the
//! grid, resuming and copying), and `manifest` (one run's record). Their items are re-exported
//! here, the runner's one front door.

pub mod layout;
pub mod manifest;
pub mod plan;
pub mod play;
pub mod verify;

#[cfg(test)]
mod tests;

pub use layout::*;
pub use plan::*;
pub use play::*;
pub use verify::*;

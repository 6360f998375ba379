//! Runs of SEC or of a baseline in a task: what a run is (`config`), the loop that plays it
//! (`run`), its metrics, checkpoints and event traces, the page's settings and their liveness
//! (`settings`), partial changes (`change`) and the experiments' presets.

pub mod change;
pub mod checkpoint;
pub mod config;
#[cfg(feature = "test-hooks")]
pub mod fixtures;
pub mod metrics;
pub mod presets;
pub mod run;
pub mod settings;
pub mod trace;

pub use crate::agent::AgentKind;
pub use config::RunConfig;
pub use metrics::{EpisodeMetrics, EpisodeState};
pub use run::{AgentFactory, Driver, Run, Tick};

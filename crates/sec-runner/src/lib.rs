#![warn(missing_docs)]
//! The experiment runner, apart from the tools that report on its output so that it stays light:
//! `sec-experiment run` (crates/sec-tools) and the Python package's Ray driver (crates/sec-py)
//! make the same files through it. The agents the core does not hold (DQN and ERLAM, burn) come
//! in through each job's `AgentFactory`; without one, their runs are refused by name.

pub mod manifest;
pub mod runner;

//! SEC Playground core: Sequential Episodic Control (Freire, Amil & Verschure) and its baselines
//! in the Animal-AI v1 arenas, seen through the agent's first-person camera: the arenas, the
//! camera, the autoencoders, SEC's memory, the agents, runs and sessions, built for the browser
//! (wasm32) and natively from the same code, deterministically. docs/ARCHITECTURE.md has the
//! layers and where each concept lives; every public item is documented (`missing_docs`).

#![warn(missing_docs)]

pub mod agent;
pub mod arena;
mod dispatch;
pub mod encoder;
pub mod env;
pub mod error;
pub mod experiment;
pub mod memory;
pub mod param;
pub mod render;
pub mod reuse;
pub mod seed;
pub mod session;
pub mod util;

#[cfg(target_arch = "wasm32")]
pub mod web;

pub use arena::{Action, Task};
pub use dispatch::kernel_path;
pub use env::{Env, EnvConfig};
pub use error::{ConfigError, Error, FileError};

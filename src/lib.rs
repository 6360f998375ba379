//! SEC Playground core: the Animal-AI v1 arenas and their first-person camera, and SEC's
//! perceptual layer (the paper's autoencoder), built for the browser (wasm32) and natively from
//! the same code, deterministically.

pub mod agent;
pub mod arena;
mod dispatch;
pub mod encoder;
pub mod error;
pub mod experiment;
pub mod memory;
pub mod render;
pub mod seed;
pub mod session;
pub mod util;

#[cfg(target_arch = "wasm32")]
pub mod web;

pub use arena::{Action, Env, EnvConfig, Task};
pub use dispatch::kernel_path;
pub use error::{ConfigError, Error, FileError};

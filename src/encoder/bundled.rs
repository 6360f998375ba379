//! The trained models, one per task (sec-algorithm.md section 11), compiled into the binary so
//! that the wasm build needs no extra download. `sec-train` writes them; `encoder-report`
//! calibrates their embedding scale (docs/ENCODER.md).

use super::{Autoencoder, Weights};
use crate::arena::{ConfigError, TASK_NAMES};

macro_rules! model_file {
    ($name:literal) => {
        ($name, include_bytes!(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/encoders/", $name, ".secae")) as &[u8])
    };
}

/// (task, weights file) for every task preset.
pub const FILES: [(&str, &[u8]); 6] = [
    model_file!("double-t-maze"),
    model_file!("detour"),
    model_file!("detour-transparent"),
    model_file!("cylinder"),
    model_file!("object-permanence"),
    model_file!("object-permanence-pits"),
];

/// The trained autoencoder of a task preset. A file whose task differs from its name is refused.
pub fn autoencoder(task: &str) -> Result<Autoencoder, ConfigError> {
    let (_, bytes) = FILES.iter().find(|(name, _)| *name == task).ok_or_else(|| {
        ConfigError::new("task", format!("no trained autoencoder for '{task}'; one of {}", TASK_NAMES.join(", ")))
    })?;
    let ae = Autoencoder::from_weights(&Weights::from_bytes(bytes)?)?;
    if ae.task != task {
        return Err(ConfigError::new("weights", format!("the file for '{task}' holds the model of '{}'", ae.task)));
    }
    Ok(ae)
}

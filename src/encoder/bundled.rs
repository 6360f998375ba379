//! The trained models, one per task (docs/ALGORITHM.md, "Perception"). Native builds compile all six
//! in (`sec-train` writes them; `encoder-report` calibrates their embedding scale,
//! docs/ENCODER.md). The wasm build does not: the page fetches the one model its task needs
//! (`assets/encoders/<task>.secae`, about 394 KB) and registers it, which keeps the download
//! for the default page a sixth of what all six would be.

use super::{Autoencoder, Weights};
use crate::arena::{TASKS, TASK_NAMES};
use crate::error::{ConfigError, Error, FileError};
use std::sync::Mutex;

/// (task, weights file) for every task whose model is compiled in: all of them natively
/// (`arena::TASKS`), none in the wasm build (the page registers the one it fetched).
fn files() -> impl Iterator<Item = (&'static str, &'static [u8])> {
    TASKS.iter().filter(|t| !t.model.is_empty()).map(|t| (t.name, t.model))
}

/// Models registered at run time (the page's fetched weights), by task.
static REGISTERED: Mutex<Vec<Autoencoder>> = Mutex::new(Vec::new());

/// Checks a weights file and makes it the model of its task (replacing one registered before);
/// returns the task. A corrupt file or one for an unknown task is refused.
pub fn register(bytes: &[u8]) -> Result<String, FileError> {
    let ae = Autoencoder::from_weights(&Weights::from_bytes(bytes)?)?;
    if !TASK_NAMES.contains(&ae.task.as_str()) {
        return Err(FileError::new(
            "weights",
            format!("the file holds a model of '{}', not one of {}", ae.task, TASK_NAMES.join(", ")),
        ));
    }
    let task = ae.task.clone();
    let mut reg = REGISTERED.lock().unwrap_or_else(|e| e.into_inner());
    reg.retain(|m| m.task != task);
    reg.push(ae);
    Ok(task)
}

/// Whether `task`'s model is available (registered, or compiled in).
pub fn has(task: &str) -> bool {
    REGISTERED.lock().unwrap_or_else(|e| e.into_inner()).iter().any(|m| m.task == task)
        || files().any(|(name, _)| name == task)
}

/// The trained autoencoder of a task preset. A file whose task differs from its name is refused.
pub fn autoencoder(task: &str) -> Result<Autoencoder, Error> {
    if let Some(ae) = REGISTERED.lock().unwrap_or_else(|e| e.into_inner()).iter().find(|m| m.task == task) {
        return Ok(ae.clone());
    }
    let Some((_, bytes)) = files().find(|(name, _)| *name == task) else {
        return Err(Error::Config(if TASK_NAMES.contains(&task) {
            ConfigError::new(
                "weights",
                format!("the model of '{task}' is not loaded: register assets/encoders/{task}.secae first"),
            )
        } else {
            ConfigError::new("task", format!("no trained autoencoder for '{task}'; one of {}", TASK_NAMES.join(", ")))
        }));
    };
    let ae = Autoencoder::from_weights(&Weights::from_bytes(bytes)?)?;
    if ae.task != task {
        return Err(FileError::new("weights", format!("the file for '{task}' holds the model of '{}'", ae.task)).into());
    }
    Ok(ae)
}

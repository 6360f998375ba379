//! The trained models, one per task (docs/ALGORITHM.md, "Perception"). Native builds compile all six
//! in (`sec-train` writes them; `encoder-report` calibrates their embedding scale,
//! docs/ENCODER.md). The wasm build does not: the page fetches the one model its task needs
//! (`assets/encoders/<task>.secae`, about 394 KB) and registers it, which keeps the download
//! for the default page a sixth of what all six would be.

use super::{model_name, Autoencoder, Weights};
use crate::arena::{TASKS, TASK_NAMES};
use crate::error::{ConfigError, Error, FileError};
use crate::render::Surface;
use std::sync::Mutex;

/// (model name, weights file) for every model compiled in: natively every task's flat model and
/// the textured ones trained so far (`arena::TASKS`), none in the wasm build (the page registers
/// the one it fetched).
fn files() -> impl Iterator<Item = (String, &'static [u8])> {
    TASKS.iter().flat_map(|t| {
        [(model_name(t.name, Surface::Flat), t.model), (model_name(t.name, Surface::Textured), t.textured_model)]
            .into_iter()
            .filter(|(_, bytes)| !bytes.is_empty())
    })
}

/// Every model name a task and surface can ask for.
fn model_names() -> Vec<String> {
    TASK_NAMES.iter().flat_map(|t| Surface::ALL.map(|(_, s)| model_name(t, s))).collect()
}

/// Models registered at run time (the page's fetched weights), by task.
static REGISTERED: Mutex<Vec<Autoencoder>> = Mutex::new(Vec::new());

/// Checks a weights file and makes it the model of its task (replacing one registered before);
/// returns the task. A corrupt file or one for an unknown task is refused.
pub fn register(bytes: &[u8]) -> Result<String, FileError> {
    let ae = Autoencoder::from_weights(&Weights::from_bytes(bytes)?)?;
    let names = model_names();
    if !names.contains(&ae.task) {
        return Err(FileError::new(
            "weights",
            format!("the file holds a model of '{}', not one of {}", ae.task, names.join(", ")),
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

/// The trained autoencoder of a task preset, or of a model name (`encoder::model_name`). A file
/// whose task differs from its name is refused.
pub fn autoencoder(task: &str) -> Result<Autoencoder, Error> {
    if let Some(ae) = REGISTERED.lock().unwrap_or_else(|e| e.into_inner()).iter().find(|m| m.task == task) {
        return Ok(ae.clone());
    }
    let Some((_, bytes)) = files().find(|(name, _)| name == task) else {
        return Err(Error::Config(if model_names().iter().any(|m| m == task) {
            ConfigError::new(
                "weights",
                if cfg!(target_arch = "wasm32") {
                    format!("the model of '{task}' is not loaded: register assets/encoders/{task}.secae first")
                } else {
                    format!(
                        "no model '{task}' is trained yet (sec-train train --task TASK --surface textured makes it)"
                    )
                },
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

#![warn(missing_docs)]
//! `sec_playground._core`: the Rust side of the Python package (crates/sec-py/python holds the
//! Gymnasium classes built on it). The arenas, the vector of arenas stepped across cores with the
//! GIL released, the runs of SEC, NSEC, MFEC and the reactive walk, and the bundled encoders.
//! Every value that comes from Python is checked here; a bad one raises `ValueError` naming the
//! parameter and its range, and leaves the object as it was.
//!
//! One module per class: `env` (`Env`), `vec_env` (`VecEnv`), `run` (`Run`), `encoder`
//! (`Encoder`), `grid` (the Ray driver's calls into the runner); `checks` holds the checks they
//! share. This file registers them and the module's functions.

use pyo3::prelude::*;
use sec_playground::arena::TASK_NAMES;
use sec_playground::experiment::{settings, RunConfig};
use sec_playground::seed::MAX_SEED;

mod checks;
mod encoder;
mod env;
mod grid;
mod run;
mod vec_env;

use checks::value_error;
use encoder::{fingerprint, PyEncoder};
use env::PyEnv;
use run::{json, PyRun};
use vec_env::PyVecEnv;

/// A user's text file (an Animal-AI YAML arena): a regular file of at most
/// `MAX_TEXT_FILE_BYTES` of UTF-8, else ValueError naming `what` (a named pipe, a device or a
/// directory is refused before any read).
#[pyfunction]
fn read_text_file(path: std::path::PathBuf, what: &str) -> PyResult<String> {
    sec_playground::util::read_text_file(&path, what).map_err(value_error)
}

/// The settings table the page builds its controls from, for `agent` (a key of the agent table)
/// or every agent, as JSON: key, symbol, help, kind (with its range), live, group, agents.
#[pyfunction]
#[pyo3(signature = (agent=None))]
fn parameters_json(agent: Option<&str>) -> PyResult<String> {
    let params = settings::params_for(agent).map_err(value_error)?;
    Ok(json(&params))
}

/// The configuration (JSON) `config` with the page's settings `pairs` (key, value as the URL hash
/// writes it) applied in order and checked as a whole, as JSON; a bad one raises ValueError
/// naming the key and its range.
#[pyfunction]
fn apply_settings(config: &str, pairs: Vec<(String, String)>) -> PyResult<String> {
    let cfg = RunConfig::from_json(config).map_err(value_error)?;
    let next = settings::with_settings(&cfg, &pairs).map_err(value_error)?;
    Ok(json(&next))
}

/// The configuration (JSON) `config` playing the arena file `yaml` named `name`
/// (`RunConfig::with_arena`: the untrained encoder, SEC's gate off), as JSON; a refused file or
/// field raises ValueError naming it.
#[pyfunction]
fn with_arena(config: &str, name: &str, yaml: &str) -> PyResult<String> {
    let cfg = RunConfig::from_json(config).map_err(value_error)?;
    Ok(json(&cfg.with_arena(name, yaml).map_err(value_error)?))
}

/// The page's settings, every key (what the URL hash shows), after the `changes` (key, value as
/// the hash writes it) are applied to `current` (the defaults where it is empty) as one batch, as
/// JSON: what the notebook widget checks before the page sees a value. A bad change raises
/// ValueError naming each key and its range, `; `-separated, and nothing applies.
#[pyfunction]
fn page_settings(current: Vec<(String, String)>, changes: Vec<(String, String)>) -> PyResult<String> {
    let (cfg, seed, errors) = settings::from_settings(&current.into_iter().collect());
    if let Some(e) = errors.first() {
        return Err(value_error(e));
    }
    match settings::apply_all(&cfg, seed, &changes.into_iter().collect()) {
        Ok((cfg, seed)) => Ok(json(&settings::to_settings(&cfg, seed))),
        Err(errors) => Err(value_error(errors.iter().map(|e| e.to_string()).collect::<Vec<_>>().join("; "))),
    }
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyEnv>()?;
    m.add_class::<PyVecEnv>()?;
    m.add_class::<PyRun>()?;
    m.add_class::<PyEncoder>()?;
    m.add_function(wrap_pyfunction!(fingerprint, m)?)?;
    m.add_function(wrap_pyfunction!(read_text_file, m)?)?;
    m.add_function(wrap_pyfunction!(parameters_json, m)?)?;
    m.add_function(wrap_pyfunction!(apply_settings, m)?)?;
    m.add_function(wrap_pyfunction!(with_arena, m)?)?;
    m.add_function(wrap_pyfunction!(page_settings, m)?)?;
    m.add_function(wrap_pyfunction!(grid::grid_conditions, m)?)?;
    m.add_function(wrap_pyfunction!(grid::grid_seeds, m)?)?;
    m.add_function(wrap_pyfunction!(grid::grid_prepare, m)?)?;
    m.add_function(wrap_pyfunction!(grid::grid_run, m)?)?;
    m.add("TASKS", TASK_NAMES.to_vec())?;
    m.add("EXPERIMENTS", sec_playground::experiment::presets::EXPERIMENTS.iter().map(|(n, _)| *n).collect::<Vec<_>>())?;
    m.add("MAX_SEED", MAX_SEED)?;
    m.add("MAX_TEXT_FILE_BYTES", sec_playground::util::MAX_TEXT_FILE_BYTES)?;
    m.add("TASKS_JSON", serde_json::to_string(&sec_playground::arena::TASKS).expect("the task table serialises"))?;
    m.add("AGENTS_JSON", serde_json::to_string(sec_playground::agent::AGENTS).expect("the agent table serialises"))?;
    Ok(())
}

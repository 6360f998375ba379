//! The experiment grid from Python: an experiment preset's runs, one call per run, made by the
//! same runner as `sec-experiment run` (crates/sec-runner), so the files are the CLI's. The Ray
//! driver (`python -m sec_playground.grid`) schedules these calls; each releases the GIL while it
//! plays. DQN and ERLAM train with burn, which the wheel leaves out: their runs are refused by
//! name (run them with `sec-experiment`).

use crate::checks::{check_seed, value_error};
use pyo3::prelude::*;
use sec_playground::experiment::presets::{self, Condition};
use sec_runner::{self as runner, Job};
use std::path::PathBuf;

/// The preset's conditions `only` names (all without it), refused by name when none is.
fn conditions(experiment: &str, only: Option<&str>) -> PyResult<Vec<Condition>> {
    let all = presets::experiment(experiment).map_err(value_error)?;
    runner::select(experiment, all, only).map_err(value_error)
}

/// The names (`group/model`) of an experiment preset's conditions, as `sec-experiment list` gives
/// them, cut to those `only` names (comma-separated names, or groups ending in `/`).
#[pyfunction]
#[pyo3(signature = (experiment, only=None))]
pub fn grid_conditions(experiment: &str, only: Option<&str>) -> PyResult<Vec<String>> {
    Ok(conditions(experiment, only)?.into_iter().map(|c| c.name).collect())
}

/// The seeds of `seeds` as the CLI's `--seeds` reads them (`N`, `A..B` or `A,B,C`).
#[pyfunction]
pub fn grid_seeds(seeds: &str) -> PyResult<Vec<u64>> {
    runner::parse_seeds(seeds).map_err(value_error)
}

/// Writes `out/EXPERIMENT/experiment.json` for these runs as `sec-experiment run` does; refused
/// when the folder holds another experiment's or other episodes' runs.
#[pyfunction]
#[pyo3(signature = (experiment, seeds, episodes, out, only=None))]
pub fn grid_prepare(experiment: &str, seeds: &str, episodes: usize, out: PathBuf, only: Option<&str>) -> PyResult<()> {
    let seeds = runner::parse_seeds(seeds).map_err(value_error)?;
    runner::check_episodes(episodes).map_err(value_error)?;
    let conditions = conditions(experiment, only)?;
    runner::prepare(&out.join(experiment), &runner::experiment_manifest(experiment, episodes, &seeds, &conditions))
        .map_err(value_error)
}

/// Makes one run of the grid under `out/EXPERIMENT` (what `sec-experiment run` would write for it:
/// the log, its manifest), resuming from the checkpoint an interrupted run left and doing nothing
/// when the run is finished (from one of an earlier format only with `legacy_checkpoint`; else
/// it starts again); returns whether it played. The GIL is released while it plays.
#[pyfunction]
#[pyo3(signature = (experiment, condition, seed, episodes, out, checkpoint_every=runner::CHECKPOINT_EVERY, legacy_checkpoint=false))]
#[allow(clippy::too_many_arguments)] // Python's keyword arguments, one each
pub fn grid_run(
    py: Python<'_>,
    experiment: &str,
    condition: &str,
    seed: u64,
    episodes: usize,
    out: PathBuf,
    checkpoint_every: usize,
    legacy_checkpoint: bool,
) -> PyResult<bool> {
    let c = conditions(experiment, Some(condition))?.into_iter().next().expect("select keeps at least one");
    if c.name != condition {
        return Err(value_error(format!("condition: '{condition}' is not one condition of {experiment}")));
    }
    let seed = check_seed(seed)?;
    if checkpoint_every > runner::MAX_EPISODES {
        return Err(value_error(format!(
            "checkpoint_every: {checkpoint_every} is out of range 0..={}",
            runner::MAX_EPISODES
        )));
    }
    let job = Job { condition: c.name, config: c.config, seed, agents: None, legacy_checkpoint };
    let dir = out.join(experiment);
    py.detach(|| runner::run_one(&job, &dir, episodes, checkpoint_every)).map_err(value_error)
}

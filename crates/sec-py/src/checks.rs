//! The checks every value from Python passes (seeds, actions, frame sizes): a bad one is a
//! `ValueError` naming the parameter and its range.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use sec_playground::arena::Action;
use sec_playground::seed::MAX_SEED;

pub(crate) const SIDE: usize = 84;
/// Env steps an action may be held for.
pub(crate) const MAX_FRAME_SKIP: u32 = 100;

pub(crate) fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

pub(crate) fn check_seed(seed: u64) -> PyResult<u64> {
    if seed > MAX_SEED {
        return Err(value_error(format!("seed: {seed} is out of range 0..={MAX_SEED}")));
    }
    Ok(seed)
}

pub(crate) fn check_action(action: i64) -> PyResult<Action> {
    if !(0..9).contains(&action) {
        return Err(value_error(format!("action: {action} is out of range 0..=8")));
    }
    Action::new(action as u32).map_err(value_error)
}

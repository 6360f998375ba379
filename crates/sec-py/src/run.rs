//! `Run`: a run of any page agent (a `Session`), stepped, viewed, explained, changed live,
//! checkpointed and resumed from Python.

use crate::checks::{check_seed, value_error};
use pyo3::prelude::*;
use sec_playground::experiment::checkpoint::ResumeCheck;
use sec_playground::experiment::RunConfig;
use sec_playground::session::Session;
use std::io::Cursor;
use std::sync::Mutex;

/// A run of SEC (NSEC, MFEC, the reactive walk) with the RunConfig of the CLI and the page, as
/// JSON text (`sec_playground.Run` takes a dict): an adapter over the core's `Session`, so its
/// views and explanations are the page's.
#[pyclass(module = "sec_playground._core", name = "Run")]
pub(crate) struct PyRun {
    /// A class shared with Python must be `Sync`; a run's agent is only `Send`.
    session: Mutex<Session>,
}

impl PyRun {
    fn session(&self) -> std::sync::MutexGuard<'_, Session> {
        self.session.lock().expect("a run's episode does not panic")
    }
}

pub(crate) fn json<T: serde::Serialize>(value: &T) -> String {
    serde_json::to_string(value).expect("views and metrics serialise")
}

#[pymethods]
impl PyRun {
    #[new]
    fn new(config: &str, seed: u64) -> PyResult<Self> {
        check_seed(seed)?;
        Ok(PyRun { session: Mutex::new(Session::from_json(config, seed).map_err(value_error)?) })
    }

    /// Plays one episode (the GIL released) and returns its metrics as a JSON line.
    fn episode(&self, py: Python<'_>) -> String {
        py.detach(|| self.session().step_episode().to_json())
    }

    /// Runs `decisions` decisions (the GIL released); the episodes they finished, as JSON lines.
    fn decisions(&self, py: Python<'_>, decisions: u32) -> PyResult<Vec<String>> {
        py.detach(|| self.session().run_decisions(decisions))
            .map(|done| done.iter().map(|m| m.to_json()).collect())
            .map_err(value_error)
    }

    /// Applies a partial change (JSON naming only the fields to change; `Session::configure_patch`):
    /// `{"applied": "live" | "restart", "changed": [{"field", "from", "to", "live"}]}` as JSON.
    fn configure(&self, config: &str) -> PyResult<String> {
        Ok(json(&self.session().configure_patch(config).map_err(value_error)?))
    }

    /// The last decision and the run's state (the page's `DecisionView`), as JSON.
    fn view(&self) -> String {
        json(&self.session().view())
    }

    /// The last decision's contextual layer term by term (the page's `Explanation`), as JSON.
    fn explain(&self) -> String {
        json(&self.session().explain())
    }

    /// The configuration, every field filled in, as JSON.
    fn config(&self) -> String {
        json(self.session().config())
    }

    /// The run as checkpoint bytes (`Run::save_checkpoint`), its decisions and its episodes so
    /// far; refused in the middle of an episode and for agents that do not checkpoint (MFEC, the
    /// reactive walk).
    fn checkpoint<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, pyo3::types::PyBytes>, u64, u64)> {
        let session = self.session();
        let mut bytes = Vec::new();
        session.run().save_checkpoint(&mut bytes).map_err(value_error)?;
        Ok((pyo3::types::PyBytes::new(py, &bytes), session.decisions(), session.run().env().episode()))
    }

    /// The run of `config` and `seed` brought to `checkpoint` (from `checkpoint`), which may
    /// claim at most `max_episodes` (the caller's count, never the file's); with `log` (the
    /// episodes' JSON lines) the log's head must be the one the checkpoint continues. A checkpoint
    /// of another configuration or seed, a corrupt one, or one of an earlier format unless
    /// `allow_legacy`, is refused.
    #[staticmethod]
    #[pyo3(signature = (config, seed, checkpoint, decisions, max_episodes, log=None, allow_legacy=false))]
    fn resume(
        config: &str,
        seed: u64,
        checkpoint: &[u8],
        decisions: u64,
        max_episodes: u64,
        log: Option<&str>,
        allow_legacy: bool,
    ) -> PyResult<Self> {
        check_seed(seed)?;
        let cfg = RunConfig::from_json(config).map_err(value_error)?;
        let check = ResumeCheck { max_episodes, log, legacy: allow_legacy };
        let session =
            Session::resume(cfg, seed, None, &mut Cursor::new(checkpoint), &check, decisions).map_err(value_error)?;
        Ok(PyRun { session: Mutex::new(session) })
    }
}

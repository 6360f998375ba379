//! `sec_playground._core`: the Rust side of the Python package (crates/sec-py/python holds the
//! Gymnasium classes built on it). The arenas, the vector of arenas stepped across cores with the
//! GIL released, the runs of SEC, NSEC, MFEC and the reactive walk, and the bundled encoders.
//! Every value that comes from Python is checked here; a bad one raises `ValueError` naming the
//! parameter and its range, and leaves the object as it was.

use numpy::ndarray::{Array1, Array3, Array4};
use numpy::{IntoPyArray, PyArray1, PyArray3, PyArray4, PyReadonlyArray1, PyReadonlyArray3};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;
use sec_playground::arena::yaml::load_task;
use sec_playground::arena::{Action, Env, EnvConfig, Task, FRAMES_PER_STEP, FRAME_DT, TASK_NAMES};
use sec_playground::encoder::{Perception, PerceptionKind, Scratch, EMBEDDING, IMAGE};
use sec_playground::experiment::RunConfig;
use sec_playground::render::{Frame, Trail};
use sec_playground::seed::MAX_SEED;
use sec_playground::session::Session;
use std::sync::Mutex;

const SIDE: usize = 84;
/// Env steps an action may be held for.
const MAX_FRAME_SKIP: u32 = 100;

fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

fn check_seed(seed: u64) -> PyResult<u64> {
    if seed > MAX_SEED {
        return Err(value_error(format!("seed: {seed} is out of range 0..={MAX_SEED}")));
    }
    Ok(seed)
}

fn check_action(action: i64) -> PyResult<Action> {
    if !(0..9).contains(&action) {
        return Err(value_error(format!("action: {action} is out of range 0..=8")));
    }
    Action::new(action as u32).map_err(value_error)
}

/// The camera's RGB bytes, channel-last (the alpha dropped).
fn rgb(frame: &Frame, out: &mut [u8]) {
    for (o, p) in out.chunks_exact_mut(3).zip(frame.rgba.chunks_exact(4)) {
        o.copy_from_slice(&p[..3]);
    }
}

fn observation<'py>(py: Python<'py>, env: &mut Env) -> Bound<'py, PyArray3<u8>> {
    let mut out = vec![0u8; IMAGE];
    rgb(env.observation(), &mut out);
    Array3::from_shape_vec((SIDE, SIDE, 3), out).expect("84x84x3").into_pyarray(py)
}

/// The task of a preset name, or of an Animal-AI YAML file's text (named `task`).
fn task_of(task: &str, yaml: Option<&str>) -> PyResult<Task> {
    match yaml {
        Some(src) => load_task(task, src).map_err(value_error),
        None => Task::preset(task).map_err(value_error),
    }
}

/// One arena. The Python class `sec_playground.ArenaEnv` wraps it as a `gymnasium.Env`.
#[pyclass(module = "sec_playground._core", name = "Env")]
struct PyEnv {
    env: Env,
    frame_skip: u32,
    trail: Trail,
}

#[pymethods]
impl PyEnv {
    /// `task`: a preset name (`TASKS`), or the name of the arena whose YAML text is `yaml`;
    /// `t`: the episode limit in env steps (the task's own if None); `frame_skip`: env steps
    /// each action is held for (SEC's 4).
    #[new]
    #[pyo3(signature = (task, t=None, yaml=None, frame_skip=1))]
    fn new(task: &str, t: Option<u32>, yaml: Option<&str>, frame_skip: u32) -> PyResult<Self> {
        if !(1..=MAX_FRAME_SKIP).contains(&frame_skip) {
            return Err(value_error(format!("frame_skip: {frame_skip} is out of range 1..={MAX_FRAME_SKIP}")));
        }
        let env = Env::new(EnvConfig { task: task_of(task, yaml)?, t }, 0).map_err(value_error)?;
        let trail = Trail::new(env.world().agent.pos);
        Ok(PyEnv { env, frame_skip, trail })
    }

    /// Starts an episode: with a seed the run restarts from it, without one the next layout.
    #[pyo3(signature = (seed=None))]
    fn reset<'py>(&mut self, py: Python<'py>, seed: Option<u64>) -> PyResult<Bound<'py, PyArray3<u8>>> {
        if let Some(s) = seed {
            check_seed(s)?;
        }
        self.env.reset(seed);
        self.trail.restart(self.env.world().agent.pos);
        Ok(observation(py, &mut self.env))
    }

    /// Holds `action` (3 * a0 + a1) for `frame_skip` env steps: (observation, reward,
    /// terminated, truncated).
    fn step<'py>(&mut self, py: Python<'py>, action: i64) -> PyResult<(Bound<'py, PyArray3<u8>>, f64, bool, bool)> {
        let a = check_action(action)?;
        let out = self.env.advance(a, self.frame_skip).map_err(value_error)?;
        self.trail.push(self.env.world().agent.pos);
        Ok((observation(py, &mut self.env), out.reward, out.terminated, out.truncated))
    }

    /// What Gymnasium's `info` reports of the env.
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let a = &self.env.world().agent;
        d.set_item("layout", self.env.layout_name())?;
        d.set_item("episode", self.env.episode())?;
        d.set_item("env_steps", self.env.steps())?;
        d.set_item("position", (a.pos.x, a.pos.y))?;
        d.set_item("heading", a.heading)?;
        Ok(d)
    }

    /// The camera's view now (84x84x3 bytes).
    fn observation<'py>(&mut self, py: Python<'py>) -> Bound<'py, PyArray3<u8>> {
        observation(py, &mut self.env)
    }

    /// The arena from above with the agent's trail, `size` x `size` RGB bytes.
    #[pyo3(signature = (size=256))]
    fn top_down<'py>(&mut self, py: Python<'py>, size: u32) -> PyResult<Bound<'py, PyArray3<u8>>> {
        let rgba = self.trail.render(self.env.world(), size).map_err(value_error)?;
        let n = size as usize;
        let rgb: Vec<u8> = rgba.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
        Ok(Array3::from_shape_vec((n, n, 3), rgb).expect("size x size x 3").into_pyarray(py))
    }

    /// Seconds of simulated time per `step`.
    #[getter]
    fn step_seconds(&self) -> f64 {
        (FRAME_DT * FRAMES_PER_STEP as f32) as f64 * self.frame_skip as f64
    }

    #[getter]
    fn frame_skip(&self) -> u32 {
        self.frame_skip
    }

    /// The episode limit in env steps (0: none).
    #[getter]
    fn t(&self) -> u32 {
        self.env.t()
    }

    #[getter]
    fn task(&self) -> String {
        self.env.config().task.name.clone()
    }
}

/// `n` arenas of one task stepped in one call, across cores, with the GIL released. Each resets
/// itself on the call after its episode ended (Gymnasium's next-step autoreset): that call
/// ignores its action and returns the new episode's first observation with reward 0.
#[pyclass(module = "sec_playground._core", name = "VecEnv")]
struct PyVecEnv {
    envs: Vec<Env>,
    frame_skip: u32,
    ended: Vec<bool>,
}

#[pymethods]
impl PyVecEnv {
    #[new]
    #[pyo3(signature = (task, n, t=None, yaml=None, frame_skip=1))]
    fn new(task: &str, n: usize, t: Option<u32>, yaml: Option<&str>, frame_skip: u32) -> PyResult<Self> {
        if !(1..=4096).contains(&n) {
            return Err(value_error(format!("num_envs: {n} is out of range 1..=4096")));
        }
        if !(1..=MAX_FRAME_SKIP).contains(&frame_skip) {
            return Err(value_error(format!("frame_skip: {frame_skip} is out of range 1..={MAX_FRAME_SKIP}")));
        }
        let env = Env::new(EnvConfig { task: task_of(task, yaml)?, t }, 0).map_err(value_error)?;
        Ok(PyVecEnv { envs: vec![env; n], frame_skip, ended: vec![false; n] })
    }

    /// Restarts every arena, arena i from `seeds[i]`: the observations, (n, 84, 84, 3).
    fn reset<'py>(&mut self, py: Python<'py>, seeds: Vec<u64>) -> PyResult<Bound<'py, PyArray4<u8>>> {
        if seeds.len() != self.envs.len() {
            return Err(value_error(format!("seeds: {} seeds for {} envs", seeds.len(), self.envs.len())));
        }
        for &s in &seeds {
            check_seed(s)?;
        }
        let obs = py.detach(|| {
            let mut obs = vec![0u8; self.envs.len() * IMAGE];
            self.envs.par_iter_mut().zip(obs.par_chunks_mut(IMAGE)).zip(&seeds).for_each(|((env, o), &s)| {
                rgb(env.reset(Some(s)), o);
            });
            obs
        });
        self.ended.iter_mut().for_each(|e| *e = false);
        Ok(Array4::from_shape_vec((self.envs.len(), SIDE, SIDE, 3), obs).expect("n x 84 x 84 x 3").into_pyarray(py))
    }

    /// One action per arena: (observations, rewards, terminated, truncated).
    #[allow(clippy::type_complexity)]
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        actions: PyReadonlyArray1<'py, i64>,
    ) -> PyResult<(
        Bound<'py, PyArray4<u8>>,
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<bool>>,
        Bound<'py, PyArray1<bool>>,
    )> {
        let actions = actions.as_slice().map_err(value_error)?;
        if actions.len() != self.envs.len() {
            return Err(value_error(format!("actions: {} actions for {} envs", actions.len(), self.envs.len())));
        }
        let actions: Vec<Action> = actions.iter().map(|&a| check_action(a)).collect::<PyResult<_>>()?;
        let (n, k) = (self.envs.len(), self.frame_skip);
        let (obs, outcomes) = py.detach(|| {
            let mut obs = vec![0u8; n * IMAGE];
            let outcomes: Vec<(f64, bool, bool)> = self
                .envs
                .par_iter_mut()
                .zip(obs.par_chunks_mut(IMAGE))
                .zip(self.ended.par_iter_mut())
                .zip(&actions)
                .map(|(((env, o), ended), &a)| {
                    if *ended {
                        *ended = false;
                        rgb(env.reset(None), o);
                        return (0.0, false, false);
                    }
                    let out = env.advance(a, k).expect("a running episode takes a step");
                    *ended = out.terminated || out.truncated;
                    rgb(env.observation(), o);
                    (out.reward, out.terminated, out.truncated)
                })
                .collect();
            (obs, outcomes)
        });
        let obs = Array4::from_shape_vec((n, SIDE, SIDE, 3), obs).expect("n x 84 x 84 x 3").into_pyarray(py);
        let rewards = Array1::from_iter(outcomes.iter().map(|o| o.0)).into_pyarray(py);
        let terminated = Array1::from_iter(outcomes.iter().map(|o| o.1)).into_pyarray(py);
        let truncated = Array1::from_iter(outcomes.iter().map(|o| o.2)).into_pyarray(py);
        Ok((obs, rewards, terminated, truncated))
    }

    /// Each arena's layout, episode and env steps.
    fn infos(&self) -> Vec<(String, u64, u32)> {
        self.envs.iter().map(|e| (e.layout_name().to_string(), e.episode(), e.steps())).collect()
    }

    #[getter]
    fn num_envs(&self) -> usize {
        self.envs.len()
    }

    #[getter]
    fn step_seconds(&self) -> f64 {
        (FRAME_DT * FRAMES_PER_STEP as f32) as f64 * self.frame_skip as f64
    }
}

/// A run of SEC (NSEC, MFEC, the reactive walk) with the RunConfig of the CLI and the page, as
/// JSON text (`sec_playground.Run` takes a dict): an adapter over the core's `Session`, so its
/// views and explanations are the page's.
#[pyclass(module = "sec_playground._core", name = "Run")]
struct PyRun {
    /// A class shared with Python must be `Sync`; a run's agent is only `Send`.
    session: Mutex<Session>,
}

impl PyRun {
    fn session(&self) -> std::sync::MutexGuard<'_, Session> {
        self.session.lock().expect("a run's episode does not panic")
    }
}

fn json<T: serde::Serialize>(value: &T) -> String {
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

    /// Applies a configuration (JSON): "live" or "restart" (see `Session::configure`).
    fn configure(&self, config: &str) -> PyResult<&'static str> {
        let cfg = RunConfig::from_json(config).map_err(value_error)?;
        Ok(self.session().configure(cfg).map_err(value_error)?.as_str())
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
}

/// A bundled encoder: the task's trained autoencoder, or the untrained one the authors' agent
/// embedded with (D20), drawn from `seed`.
#[pyclass(module = "sec_playground._core", name = "Encoder")]
struct PyEncoder {
    perception: Perception,
    scratch: Scratch,
}

#[pymethods]
impl PyEncoder {
    #[new]
    #[pyo3(signature = (task, perception="trained", seed=0))]
    fn new(task: &str, perception: &str, seed: u64) -> PyResult<Self> {
        check_seed(seed)?;
        let kind: PerceptionKind = serde_json::from_value(serde_json::Value::String(perception.into()))
            .map_err(|_| value_error(format!("perception: '{perception}' is not 'trained' or 'untrained'")))?;
        let perception = Perception::new(kind, task, None, seed).map_err(value_error)?;
        Ok(PyEncoder { perception, scratch: Scratch::default() })
    }

    /// The embedding of one camera frame (84x84x3 bytes): 20 floats.
    fn encode<'py>(
        &mut self,
        py: Python<'py>,
        frame: PyReadonlyArray3<'py, u8>,
    ) -> PyResult<Bound<'py, PyArray1<f32>>> {
        let bytes = frame.as_array();
        if bytes.shape() != [SIDE, SIDE, 3] {
            return Err(value_error(format!("frame: shape {:?} is not (84, 84, 3)", bytes.shape())));
        }
        let image: Vec<f32> = bytes.iter().map(|&b| b as f32 / 255.0).collect();
        let mut e = [0.0f32; EMBEDDING];
        self.perception.embed(&image, &mut self.scratch, &mut e);
        Ok(e.to_vec().into_pyarray(py))
    }
}

/// The fingerprint the golden traces hold of a frame: FNV-1a over its RGBA bytes (alpha 255).
#[pyfunction]
fn fingerprint(frame: PyReadonlyArray3<'_, u8>) -> PyResult<u64> {
    let bytes = frame.as_array();
    if bytes.shape() != [SIDE, SIDE, 3] {
        return Err(value_error(format!("frame: shape {:?} is not (84, 84, 3)", bytes.shape())));
    }
    let rgb: Vec<u8> = bytes.iter().copied().collect();
    let rgba: Vec<u8> = rgb.chunks_exact(3).flat_map(|p| [p[0], p[1], p[2], 255]).collect();
    Ok(sec_playground::render::fnv1a(&rgba))
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyEnv>()?;
    m.add_class::<PyVecEnv>()?;
    m.add_class::<PyRun>()?;
    m.add_class::<PyEncoder>()?;
    m.add_function(wrap_pyfunction!(fingerprint, m)?)?;
    m.add("TASKS", TASK_NAMES.to_vec())?;
    m.add("MAX_SEED", MAX_SEED)?;
    m.add("TASKS_JSON", serde_json::to_string(&sec_playground::arena::TASKS).expect("the task table serialises"))?;
    m.add("AGENTS_JSON", serde_json::to_string(sec_playground::agent::AGENTS).expect("the agent table serialises"))?;
    Ok(())
}

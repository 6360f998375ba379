#![warn(missing_docs)]
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
use sec_playground::arena::{
    Action, ConfigError, Env, EnvConfig, StepOutcome, Task, FRAMES_PER_STEP, FRAME_DT, TASK_NAMES,
};
use sec_playground::encoder::{Perception, PerceptionKind, Scratch, EMBEDDING, IMAGE};
use sec_playground::experiment::checkpoint::ResumeCheck;
use sec_playground::experiment::RunConfig;
use sec_playground::render::{Frame, Surface, Trail};
use sec_playground::seed::MAX_SEED;
use sec_playground::session::Session;
use std::io::Cursor;
use std::sync::Mutex;

mod grid;

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

/// An arena with what rebuilds it exactly: the seed of its last seeded reset, the unseeded resets
/// since (its generator draws only at resets) and this episode's actions. `state` and `restore`
/// are what pickling and `get_state`/`set_state` use: a restored arena replays them and goes on
/// bit for bit as the original would.
#[derive(Clone)]
struct Tracked {
    env: Env,
    trail: Trail,
    frame_skip: u32,
    seed: u64,
    resets: u64,
    actions: Vec<u8>,
    /// The last step touched a good goal.
    success: bool,
    /// Gymnasium's `max_episode_steps`: a limit in agent steps (calls to `advance`), which
    /// truncates without rescaling the reward (the arena's own `t` counts env steps).
    max_steps: Option<u64>,
    /// Agent steps this episode.
    agent_steps: u64,
    /// The episode was cut at `max_steps`.
    cut: bool,
}

/// A surface by name ("flat" or "textured"), refused by name otherwise.
fn surface_of(name: &str) -> PyResult<Surface> {
    Surface::from_name(name).map_err(|e| value_error(format!("surface: {e}")))
}

/// What `Tracked::state` gives: seed, resets since, this episode's actions.
type ArenaState = (u64, u64, Vec<u8>);

impl Tracked {
    fn new(task: Task, t: Option<u32>, surface: Surface, frame_skip: u32, max_steps: Option<u64>) -> PyResult<Self> {
        if !(1..=MAX_FRAME_SKIP).contains(&frame_skip) {
            return Err(value_error(format!("frame_skip: {frame_skip} is out of range 1..={MAX_FRAME_SKIP}")));
        }
        if max_steps == Some(0) {
            return Err(value_error("max_episode_steps: 0 is out of range 1.. (None: no limit)"));
        }
        // `Env::new` resets with seed 0.
        let env = Env::new(EnvConfig { task, t, surface }, 0).map_err(value_error)?;
        let trail = Trail::new(env.world().agent.pos);
        let actions = Vec::new();
        Ok(Tracked {
            env,
            trail,
            frame_skip,
            seed: 0,
            resets: 0,
            actions,
            success: false,
            max_steps,
            agent_steps: 0,
            cut: false,
        })
    }

    fn reset(&mut self, seed: Option<u64>) -> &Frame {
        match seed {
            Some(s) => (self.seed, self.resets) = (s, 0),
            None => self.resets += 1,
        }
        self.actions.clear();
        self.success = false;
        (self.agent_steps, self.cut) = (0, false);
        self.env.reset(seed);
        self.trail.restart(self.env.world().agent.pos);
        self.env.observation()
    }

    fn advance(&mut self, a: Action) -> Result<StepOutcome, ConfigError> {
        if self.cut {
            return Err(ConfigError::new("step", "the episode is over (max_episode_steps): call reset first"));
        }
        let mut out = self.env.advance(a, self.frame_skip)?;
        self.actions.push(a.into());
        self.trail.push(self.env.world().agent.pos);
        self.success = out.good_goal;
        self.agent_steps += 1;
        if self.max_steps.is_some_and(|m| self.agent_steps >= m) && !out.terminated && !out.truncated {
            out.truncated = true;
            self.cut = true;
        }
        Ok(out)
    }

    fn state(&self) -> ArenaState {
        (self.seed, self.resets, self.actions.clone())
    }

    /// Brings a fresh copy of this arena to `state` by replaying it; on error nothing changes.
    fn restore(&mut self, (seed, resets, actions): ArenaState) -> PyResult<()> {
        check_seed(seed)?;
        if resets > MAX_REPLAYED_RESETS {
            return Err(value_error(format!("state: {resets} resets is out of range 0..={MAX_REPLAYED_RESETS}")));
        }
        let mut next = self.clone();
        next.reset(Some(seed));
        for _ in 0..resets {
            next.reset(None);
        }
        for (i, &a) in actions.iter().enumerate() {
            let action = Action::new(a as u32).map_err(|e| value_error(format!("state: action {i}: {e}")))?;
            next.advance(action).map_err(|e| value_error(format!("state: action {i}: {e}")))?;
        }
        *self = next;
        Ok(())
    }
}

/// Most unseeded resets a restored arena replays (each is a layout draw and a frame).
const MAX_REPLAYED_RESETS: u64 = 10_000_000;

/// One arena. The Python class `sec_playground.ArenaEnv` wraps it as a `gymnasium.Env`.
#[pyclass(module = "sec_playground._core", name = "Env")]
struct PyEnv {
    arena: Tracked,
}

#[pymethods]
impl PyEnv {
    /// `task`: a preset name (`TASKS`), or the name of the arena whose YAML text is `yaml`;
    /// `t`: the arena's episode limit in env steps (the task's own if None; each env step costs
    /// 1/t); `frame_skip`: env steps each action is held for (SEC's 4); `max_steps`: a limit in
    /// agent steps (Gymnasium's `max_episode_steps`).
    #[new]
    #[pyo3(signature = (task, t=None, yaml=None, frame_skip=1, max_steps=None, surface="flat"))]
    fn new(
        task: &str,
        t: Option<u32>,
        yaml: Option<&str>,
        frame_skip: u32,
        max_steps: Option<u64>,
        surface: &str,
    ) -> PyResult<Self> {
        Ok(PyEnv { arena: Tracked::new(task_of(task, yaml)?, t, surface_of(surface)?, frame_skip, max_steps)? })
    }

    /// Starts an episode: with a seed the run restarts from it, without one the next layout.
    #[pyo3(signature = (seed=None))]
    fn reset<'py>(&mut self, py: Python<'py>, seed: Option<u64>) -> PyResult<Bound<'py, PyArray3<u8>>> {
        if let Some(s) = seed {
            check_seed(s)?;
        }
        self.arena.reset(seed);
        Ok(observation(py, &mut self.arena.env))
    }

    /// Holds `action` (3 * a0 + a1) for `frame_skip` env steps: (observation, reward,
    /// terminated, truncated).
    fn step<'py>(&mut self, py: Python<'py>, action: i64) -> PyResult<(Bound<'py, PyArray3<u8>>, f64, bool, bool)> {
        let a = check_action(action)?;
        let out = self.arena.advance(a).map_err(value_error)?;
        Ok((observation(py, &mut self.arena.env), out.reward, out.terminated, out.truncated))
    }

    /// What Gymnasium's `info` reports of the env (see `ArenaEnv`).
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        info(py, &self.arena)
    }

    /// The camera's view now (84x84x3 bytes).
    fn observation<'py>(&mut self, py: Python<'py>) -> Bound<'py, PyArray3<u8>> {
        observation(py, &mut self.arena.env)
    }

    /// The arena from above with the agent's trail, `size` x `size` RGB bytes.
    #[pyo3(signature = (size=256))]
    fn top_down<'py>(&mut self, py: Python<'py>, size: u32) -> PyResult<Bound<'py, PyArray3<u8>>> {
        top_down(py, &mut self.arena, size)
    }

    /// (seed, resets since it, this episode's actions): what rebuilds the arena.
    fn get_state(&self) -> ArenaState {
        self.arena.state()
    }

    /// Replays a `get_state` on this arena; a bad state raises and changes nothing.
    fn set_state(&mut self, state: ArenaState) -> PyResult<()> {
        self.arena.restore(state)
    }

    /// Seconds of simulated time per `step`.
    #[getter]
    fn step_seconds(&self) -> f64 {
        step_seconds(self.arena.frame_skip)
    }

    #[getter]
    fn frame_skip(&self) -> u32 {
        self.arena.frame_skip
    }

    /// The episode limit in env steps (0: none).
    #[getter]
    fn t(&self) -> u32 {
        self.arena.env.t()
    }

    #[getter]
    fn task(&self) -> String {
        self.arena.env.config().task.name.clone()
    }
}

fn step_seconds(frame_skip: u32) -> f64 {
    (FRAME_DT * FRAMES_PER_STEP as f32) as f64 * frame_skip as f64
}

/// An arena's `info`: layout, episode_index (not `episode`, which Gymnasium's
/// RecordEpisodeStatistics owns), env_steps, agent_steps, position, heading and success.
fn info<'py>(py: Python<'py>, arena: &Tracked) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let a = &arena.env.world().agent;
    d.set_item("layout", arena.env.layout_name())?;
    d.set_item("episode_index", arena.env.episode())?;
    d.set_item("env_steps", arena.env.steps())?;
    d.set_item("position", (a.pos.x, a.pos.y))?;
    d.set_item("heading", a.heading)?;
    d.set_item("success", arena.success)?;
    d.set_item("agent_steps", arena.agent_steps)?;
    Ok(d)
}

fn top_down<'py>(py: Python<'py>, arena: &mut Tracked, size: u32) -> PyResult<Bound<'py, PyArray3<u8>>> {
    let rgba = arena.trail.render(arena.env.world(), size).map_err(value_error)?;
    let n = size as usize;
    let rgb: Vec<u8> = rgba.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
    Ok(Array3::from_shape_vec((n, n, 3), rgb).expect("size x size x 3").into_pyarray(py))
}

/// `n` arenas of one task stepped in one call, across cores, with the GIL released. Each resets
/// itself on the call after its episode ended (Gymnasium's next-step autoreset): that call
/// ignores its action and returns the new episode's first observation with reward 0.
#[pyclass(module = "sec_playground._core", name = "VecEnv")]
struct PyVecEnv {
    arenas: Vec<Tracked>,
    ended: Vec<bool>,
}

#[pymethods]
impl PyVecEnv {
    #[new]
    #[pyo3(signature = (task, n, t=None, yaml=None, frame_skip=1, max_steps=None, surface="flat"))]
    fn new(
        task: &str,
        n: usize,
        t: Option<u32>,
        yaml: Option<&str>,
        frame_skip: u32,
        max_steps: Option<u64>,
        surface: &str,
    ) -> PyResult<Self> {
        if !(1..=4096).contains(&n) {
            return Err(value_error(format!("num_envs: {n} is out of range 1..=4096")));
        }
        let arena = Tracked::new(task_of(task, yaml)?, t, surface_of(surface)?, frame_skip, max_steps)?;
        Ok(PyVecEnv { arenas: vec![arena; n], ended: vec![false; n] })
    }

    /// Restarts every arena, arena i from `seeds[i]`: the observations, (n, 84, 84, 3).
    fn reset<'py>(&mut self, py: Python<'py>, seeds: Vec<u64>) -> PyResult<Bound<'py, PyArray4<u8>>> {
        if seeds.len() != self.arenas.len() {
            return Err(value_error(format!("seeds: {} seeds for {} envs", seeds.len(), self.arenas.len())));
        }
        for &s in &seeds {
            check_seed(s)?;
        }
        let obs = py.detach(|| {
            let mut obs = vec![0u8; self.arenas.len() * IMAGE];
            self.arenas.par_iter_mut().zip(obs.par_chunks_mut(IMAGE)).zip(&seeds).for_each(|((arena, o), &s)| {
                rgb(arena.reset(Some(s)), o);
            });
            obs
        });
        self.ended.iter_mut().for_each(|e| *e = false);
        Ok(Array4::from_shape_vec((self.arenas.len(), SIDE, SIDE, 3), obs).expect("n x 84 x 84 x 3").into_pyarray(py))
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
        if actions.len() != self.arenas.len() {
            return Err(value_error(format!("actions: {} actions for {} envs", actions.len(), self.arenas.len())));
        }
        let actions: Vec<Action> = actions.iter().map(|&a| check_action(a)).collect::<PyResult<_>>()?;
        let n = self.arenas.len();
        let (obs, outcomes) = py.detach(|| {
            let mut obs = vec![0u8; n * IMAGE];
            let outcomes: Vec<(f64, bool, bool)> = self
                .arenas
                .par_iter_mut()
                .zip(obs.par_chunks_mut(IMAGE))
                .zip(self.ended.par_iter_mut())
                .zip(&actions)
                .map(|(((arena, o), ended), &a)| {
                    if *ended {
                        *ended = false;
                        rgb(arena.reset(None), o);
                        return (0.0, false, false);
                    }
                    let out = arena.advance(a).expect("a running episode takes a step");
                    *ended = out.terminated || out.truncated;
                    rgb(arena.env.observation(), o);
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

    /// Each arena's `info`, as the single env reports it.
    fn infos<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        self.arenas.iter().map(|a| info(py, a)).collect()
    }

    /// Arena `i` from above with its trail, `size` x `size` RGB bytes.
    #[pyo3(signature = (i, size=256))]
    fn top_down<'py>(&mut self, py: Python<'py>, i: usize, size: u32) -> PyResult<Bound<'py, PyArray3<u8>>> {
        let n = self.arenas.len();
        let arena =
            self.arenas.get_mut(i).ok_or_else(|| value_error(format!("i: {i} is out of range 0..={}", n - 1)))?;
        top_down(py, arena, size)
    }

    /// Arena `i`'s camera now (84x84x3 bytes).
    fn observation<'py>(&mut self, py: Python<'py>, i: usize) -> PyResult<Bound<'py, PyArray3<u8>>> {
        let n = self.arenas.len();
        let arena =
            self.arenas.get_mut(i).ok_or_else(|| value_error(format!("i: {i} is out of range 0..={}", n - 1)))?;
        Ok(observation(py, &mut arena.env))
    }

    /// Per arena (seed, resets since it, this episode's actions, whether its next step resets it).
    fn get_state(&self) -> Vec<(u64, u64, Vec<u8>, bool)> {
        self.arenas.iter().zip(&self.ended).map(|(a, &e)| (a.seed, a.resets, a.actions.clone(), e)).collect()
    }

    /// Replays a `get_state`; a bad state raises and changes nothing.
    fn set_state(&mut self, state: Vec<(u64, u64, Vec<u8>, bool)>) -> PyResult<()> {
        if state.len() != self.arenas.len() {
            return Err(value_error(format!("state: {} arenas for {} envs", state.len(), self.arenas.len())));
        }
        let mut arenas = self.arenas.clone();
        for (arena, (seed, resets, actions, _)) in arenas.iter_mut().zip(&state) {
            arena.restore((*seed, *resets, actions.clone()))?;
        }
        self.arenas = arenas;
        self.ended = state.iter().map(|s| s.3).collect();
        Ok(())
    }

    #[getter]
    fn num_envs(&self) -> usize {
        self.arenas.len()
    }

    #[getter]
    fn step_seconds(&self) -> f64 {
        step_seconds(self.arenas[0].frame_skip)
    }

    /// The episode limit in env steps (0: none).
    #[getter]
    fn t(&self) -> u32 {
        self.arenas[0].env.t()
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
    fn encode<'py>(&mut self, py: Python<'py>, frame: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray1<f32>>> {
        let frame = frame_of(frame)?;
        let bytes = frame.as_array();
        let image: Vec<f32> = bytes.iter().map(|&b| b as f32 / 255.0).collect();
        let mut e = [0.0f32; EMBEDDING];
        self.perception.embed(&image, &mut self.scratch, &mut e);
        Ok(e.to_vec().into_pyarray(py))
    }
}

/// A camera frame: a uint8 array of shape (84, 84, 3); anything else is refused naming what it
/// is (its dtype and shape, or its type), not with numpy's "type mismatch".
fn frame_of<'py>(obj: &Bound<'py, PyAny>) -> PyResult<PyReadonlyArray3<'py, u8>> {
    let what = || match (obj.getattr("dtype"), obj.getattr("shape")) {
        (Ok(dtype), Ok(shape)) => format!("an array of {dtype} and shape {shape}"),
        _ => format!("a {}", obj.get_type().name().map(|n| n.to_string()).unwrap_or_default()),
    };
    let frame = obj
        .extract::<PyReadonlyArray3<'py, u8>>()
        .map_err(|_| value_error(format!("frame: {} is not a uint8 array of shape (84, 84, 3)", what())))?;
    if frame.as_array().shape() != [SIDE, SIDE, 3] {
        return Err(value_error(format!("frame: {} is not a uint8 array of shape (84, 84, 3)", what())));
    }
    Ok(frame)
}

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
    let params = sec_playground::experiment::settings::params_for(agent).map_err(value_error)?;
    Ok(json(&params))
}

/// The configuration (JSON) `config` with the page's settings `pairs` (key, value as the URL hash
/// writes it) applied in order and checked as a whole, as JSON; a bad one raises ValueError
/// naming the key and its range.
#[pyfunction]
fn apply_settings(config: &str, pairs: Vec<(String, String)>) -> PyResult<String> {
    let cfg = RunConfig::from_json(config).map_err(value_error)?;
    let next = sec_playground::experiment::settings::with_settings(&cfg, &pairs).map_err(value_error)?;
    Ok(json(&next))
}

/// The fingerprint the golden traces hold of a frame: FNV-1a over its RGBA bytes (alpha 255).
#[pyfunction]
fn fingerprint(frame: &Bound<'_, PyAny>) -> PyResult<u64> {
    let frame = frame_of(frame)?;
    let bytes = frame.as_array();
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
    m.add_function(wrap_pyfunction!(read_text_file, m)?)?;
    m.add_function(wrap_pyfunction!(parameters_json, m)?)?;
    m.add_function(wrap_pyfunction!(apply_settings, m)?)?;
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

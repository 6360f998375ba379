//! `Env`: one arena with Gymnasium's reset and step, its frames as numpy arrays, and what it
//! tracks to save and restore its state (`Tracked`).

use crate::checks::{check_action, check_seed, value_error, MAX_FRAME_SKIP, SIDE};
use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray3};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sec_playground::arena::yaml::load_task;
use sec_playground::arena::{Action, ConfigError, Task, FRAMES_PER_STEP, FRAME_DT};
use sec_playground::encoder::IMAGE;
use sec_playground::env::{Env, EnvConfig, StepOutcome};
use sec_playground::render::{Frame, Surface, Trail};

/// What `Tracked::state` gives: seed, resets since, this episode's actions.
pub(crate) type ArenaState = (u64, u64, Vec<u8>);

/// The camera's RGB bytes, channel-last (the alpha dropped).
pub(crate) fn rgb(frame: &Frame, out: &mut [u8]) {
    for (o, p) in out.chunks_exact_mut(3).zip(frame.rgba.chunks_exact(4)) {
        o.copy_from_slice(&p[..3]);
    }
}

pub(crate) fn observation<'py>(py: Python<'py>, env: &mut Env) -> Bound<'py, PyArray3<u8>> {
    let mut out = vec![0u8; IMAGE];
    rgb(env.observation(), &mut out);
    Array3::from_shape_vec((SIDE, SIDE, 3), out).expect("84x84x3").into_pyarray(py)
}

/// The task of a preset name, or of an Animal-AI YAML file's text (named `task`).
pub(crate) fn task_of(task: &str, yaml: Option<&str>) -> PyResult<Task> {
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
pub(crate) struct Tracked {
    pub(crate) env: Env,
    pub(crate) trail: Trail,
    pub(crate) frame_skip: u32,
    pub(crate) seed: u64,
    pub(crate) resets: u64,
    pub(crate) actions: Vec<u8>,
    /// The last step touched a good goal.
    pub(crate) success: bool,
    /// Gymnasium's `max_episode_steps`: a limit in agent steps (calls to `advance`), which
    /// truncates without rescaling the reward (the arena's own `t` counts env steps).
    pub(crate) max_steps: Option<u64>,
    /// Agent steps this episode.
    pub(crate) agent_steps: u64,
    /// The episode was cut at `max_steps`.
    pub(crate) cut: bool,
}

/// A surface by name ("flat" or "textured"), refused by name otherwise.
pub(crate) fn surface_of(name: &str) -> PyResult<Surface> {
    Surface::from_name(name).map_err(|e| value_error(format!("surface: {e}")))
}

impl Tracked {
    pub(crate) fn new(
        task: Task,
        t: Option<u32>,
        surface: Surface,
        frame_skip: u32,
        max_steps: Option<u64>,
    ) -> PyResult<Self> {
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

    pub(crate) fn reset(&mut self, seed: Option<u64>) -> &Frame {
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

    pub(crate) fn advance(&mut self, a: Action) -> Result<StepOutcome, ConfigError> {
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

    pub(crate) fn state(&self) -> ArenaState {
        (self.seed, self.resets, self.actions.clone())
    }

    /// Brings a fresh copy of this arena to `state` by replaying it; on error nothing changes.
    pub(crate) fn restore(&mut self, (seed, resets, actions): ArenaState) -> PyResult<()> {
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
pub(crate) const MAX_REPLAYED_RESETS: u64 = 10_000_000;

/// One arena. The Python class `sec_playground.ArenaEnv` wraps it as a `gymnasium.Env`.
#[pyclass(module = "sec_playground._core", name = "Env")]
pub(crate) struct PyEnv {
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

    /// What loading the arena file changed to read it as v1 does (a size clamped), one line each.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.arena.env.config().task.warnings.clone()
    }
}

pub(crate) fn step_seconds(frame_skip: u32) -> f64 {
    (FRAME_DT * FRAMES_PER_STEP as f32) as f64 * frame_skip as f64
}

/// An arena's `info`: layout, episode_index (not `episode`, which Gymnasium's
/// RecordEpisodeStatistics owns), env_steps, agent_steps, position, height, heading and success.
pub(crate) fn info<'py>(py: Python<'py>, arena: &Tracked) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let a = &arena.env.world().agent;
    d.set_item("layout", arena.env.layout_name())?;
    d.set_item("episode_index", arena.env.episode())?;
    d.set_item("env_steps", arena.env.steps())?;
    d.set_item("position", (a.pos.x, a.pos.y))?;
    d.set_item("height", a.y)?;
    d.set_item("heading", a.heading)?;
    d.set_item("success", arena.success)?;
    d.set_item("agent_steps", arena.agent_steps)?;
    Ok(d)
}

pub(crate) fn top_down<'py>(py: Python<'py>, arena: &mut Tracked, size: u32) -> PyResult<Bound<'py, PyArray3<u8>>> {
    let rgba = arena.trail.render(arena.env.world(), size).map_err(value_error)?;
    let n = size as usize;
    let rgb: Vec<u8> = rgba.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
    Ok(Array3::from_shape_vec((n, n, 3), rgb).expect("size x size x 3").into_pyarray(py))
}

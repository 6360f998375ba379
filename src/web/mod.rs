//! The JavaScript API (wasm32 only). Every value from JS is validated; a bad one is a JS
//! `Error` whose message names the parameter and its range, and leaves the state as it was.

use crate::arena::{trace, yaml, Action, ConfigError, Env, EnvConfig, Task, MAX_T, TASK_NAMES};
use crate::encoder::{bundled, reconstruction_to_rgba, Autoencoder, Scratch, EMBEDDING, IMAGE};
use crate::render::{render_top_down, Frame, WIDTH};
use glam::Vec2;
use serde::Serialize;
use std::collections::VecDeque;
use wasm_bindgen::prelude::*;

mod run;
pub use run::{apply_settings, has_model, parameters, parse_settings, preset_settings, register_model, SecRun};

/// Positions kept for the top-down trail (about 30 s of simulated time).
const TRAIL: usize = 500;
/// Largest seed a JS number holds exactly.
const MAX_SEED: f64 = 9_007_199_254_740_991.0;

fn js_err(e: ConfigError) -> JsError {
    JsError::new(&e.to_string())
}

fn seed_from_js(seed: f64) -> Result<u64, JsError> {
    if seed.is_finite() && seed.fract() == 0.0 && (0.0..=MAX_SEED).contains(&seed) {
        Ok(seed as u64)
    } else {
        Err(JsError::new(&format!("seed: {seed} is out of range 0..=9007199254740991 (whole numbers)")))
    }
}

fn t_from_js(t: Option<f64>) -> Result<Option<u32>, JsError> {
    match t {
        None => Ok(None),
        Some(v) if v.is_finite() && v.fract() == 0.0 && (0.0..=MAX_T as f64).contains(&v) => Ok(Some(v as u32)),
        Some(v) => Err(JsError::new(&format!("t: {v} is out of range 0..={MAX_T} (whole numbers)"))),
    }
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct StepJs {
    reward: f64,
    terminated: bool,
    truncated: bool,
    good_goal: bool,
    env_steps: u32,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct AgentJs {
    x: f32,
    z: f32,
    heading: f32,
    speed: f32,
    steps: u32,
    t: u32,
    episode: f64,
    layout: String,
    over: bool,
}

/// An arena environment for the page: Gymnasium-style `reset`/`step`, the camera image and the
/// top-down view with the agent's trail.
#[wasm_bindgen]
pub struct ArenaEnv {
    env: Env,
    trail: VecDeque<Vec2>,
    top: Vec<u8>,
}

#[wasm_bindgen]
impl ArenaEnv {
    /// A built-in task (see `taskNames()`), a seed, and an optional episode limit `t`.
    #[wasm_bindgen(constructor)]
    pub fn new(task: &str, seed: f64, t: Option<f64>) -> Result<ArenaEnv, JsError> {
        let task = Task::preset(task).map_err(js_err)?;
        Self::build(task, seed, t)
    }

    /// An environment from the text of an Animal-AI YAML arena file.
    #[wasm_bindgen(js_name = fromYaml)]
    pub fn from_yaml(name: &str, source: &str, seed: f64, t: Option<f64>) -> Result<ArenaEnv, JsError> {
        let task = yaml::load_task(name, source).map_err(js_err)?;
        Self::build(task, seed, t)
    }

    fn build(task: Task, seed: f64, t: Option<f64>) -> Result<ArenaEnv, JsError> {
        let seed = seed_from_js(seed)?;
        let config = EnvConfig { task, t: t_from_js(t)? };
        let env = Env::new(config, seed).map_err(js_err)?;
        let mut me = ArenaEnv { env, trail: VecDeque::with_capacity(TRAIL), top: Vec::new() };
        me.trail.push_back(me.env.world().agent.pos);
        Ok(me)
    }

    /// Starts the next episode, or restarts the run when a seed is given.
    pub fn reset(&mut self, seed: Option<f64>) -> Result<(), JsError> {
        let seed = seed.map(seed_from_js).transpose()?;
        self.env.reset(seed);
        self.trail.clear();
        self.trail.push_back(self.env.world().agent.pos);
        Ok(())
    }

    /// One env step with action `3*a0 + a1`; returns `{reward, terminated, truncated, goodGoal, envSteps}`.
    pub fn step(&mut self, action: u32) -> Result<JsValue, JsError> {
        self.step_held(action, 1)
    }

    /// Holds the action for `k` env steps (1..=1000) without rendering in between.
    #[wasm_bindgen(js_name = stepHeld)]
    pub fn step_held(&mut self, action: u32, k: u32) -> Result<JsValue, JsError> {
        let a = Action::new(action).map_err(js_err)?;
        let o = self.env.advance(a, k).map_err(js_err)?;
        if self.trail.len() == TRAIL {
            self.trail.pop_front();
        }
        self.trail.push_back(self.env.world().agent.pos);
        let out = StepJs {
            reward: o.reward,
            terminated: o.terminated,
            truncated: o.truncated,
            good_goal: o.good_goal,
            env_steps: o.env_steps,
        };
        Ok(serde_wasm_bindgen::to_value(&out)?)
    }

    /// The agent's 84x84 view as RGBA bytes (a copy, ready for `ImageData`).
    pub fn observation(&mut self) -> Vec<u8> {
        self.env.observation().rgba.clone()
    }

    /// The top-down view, `size` x `size` RGBA bytes (size 32..=2048).
    #[wasm_bindgen(js_name = topDown)]
    pub fn top_down(&mut self, size: u32) -> Result<Vec<u8>, JsError> {
        if !(32..=2048).contains(&size) {
            return Err(JsError::new(&format!("size: {size} is out of range 32..=2048")));
        }
        let n = size as usize;
        self.top.resize(n * n * 4, 0);
        let trail: Vec<Vec2> = self.trail.iter().copied().collect();
        render_top_down(self.env.world(), &trail, n, &mut self.top);
        Ok(self.top.clone())
    }

    /// Agent pose and episode state.
    pub fn agent(&self) -> Result<JsValue, JsError> {
        let a = &self.env.world().agent;
        let out = AgentJs {
            x: a.pos.x,
            z: a.pos.y,
            heading: a.heading,
            speed: a.vel.length(),
            steps: self.env.steps(),
            t: self.env.t(),
            episode: self.env.episode() as f64,
            layout: self.env.layout_name().to_string(),
            over: self.env.is_over(),
        };
        Ok(serde_wasm_bindgen::to_value(&out)?)
    }

    #[wasm_bindgen(js_name = taskName)]
    pub fn task_name(&self) -> String {
        self.env.config().task.name.clone()
    }
}

/// The built-in task names.
#[wasm_bindgen(js_name = taskNames)]
pub fn task_names() -> Vec<String> {
    TASK_NAMES.iter().map(|s| s.to_string()).collect()
}

/// A task's one-paragraph description.
#[wasm_bindgen(js_name = taskDescription)]
pub fn task_description(task: &str) -> Result<String, JsError> {
    Ok(Task::preset(task).map_err(js_err)?.description)
}

/// Camera image side in pixels (84).
#[wasm_bindgen(js_name = frameSize)]
pub fn frame_size() -> u32 {
    WIDTH as u32
}

/// The scripted determinism run (see `arena::trace`), for cross-target checks.
#[wasm_bindgen(js_name = scriptedRun)]
pub fn scripted_run(task: &str, seed: f64, steps: u32) -> Result<String, JsError> {
    trace::scripted_run(task, seed_from_js(seed)?, steps).map_err(js_err)
}

/// Benchmark helper: `n` physics-only env steps of the shared script (see `bench/wasm-bench.mjs`).
#[wasm_bindgen(js_name = benchEnvSteps)]
pub fn bench_env_steps(task: &str, n: u32) -> Result<f64, JsError> {
    let mut env = Env::new(EnvConfig::new(Task::preset(task).map_err(js_err)?), 1).map_err(js_err)?;
    Ok(trace::bench_env_steps(&mut env, n))
}

/// Benchmark helper: `n` camera renders cycling through the benchmark poses of a task.
#[wasm_bindgen(js_name = benchRenders)]
pub fn bench_renders(task: &str, n: u32) -> Result<u32, JsError> {
    let worlds = trace::bench_worlds(task).map_err(js_err)?;
    let mut cam = crate::render::Camera::new();
    let mut frame = crate::render::Frame::new();
    let mut acc = 0u32;
    for i in 0..n as usize {
        cam.render(&worlds[i % worlds.len()], &mut frame);
        acc = acc.wrapping_add(frame.rgba[i % frame.rgba.len()] as u32);
    }
    Ok(acc)
}

/// The trained autoencoder of a task (bundled with the wasm): the embedding SEC sees, the
/// reconstruction the page shows, and the reconstruction error that gates the contextual layer.
#[wasm_bindgen]
pub struct Encoder {
    ae: Autoencoder,
    scratch: Scratch,
    frame: Frame,
    img: Vec<f32>,
    rec: Vec<f32>,
}

#[wasm_bindgen]
impl Encoder {
    /// The model of a built-in task (see `taskNames()`).
    #[wasm_bindgen(constructor)]
    pub fn new(task: &str) -> Result<Encoder, JsError> {
        let ae = bundled::autoencoder(task).map_err(js_err)?;
        Ok(Encoder { ae, scratch: Scratch::default(), frame: Frame::new(), img: vec![0.0; IMAGE], rec: Vec::new() })
    }

    fn load(&mut self, rgba: &[u8]) -> Result<(), JsError> {
        if rgba.len() != self.frame.rgba.len() {
            return Err(JsError::new(&format!(
                "rgba: {} bytes, expected {} (an 84x84 RGBA image)",
                rgba.len(),
                self.frame.rgba.len()
            )));
        }
        self.frame.rgba.copy_from_slice(rgba);
        self.frame.to_rgb_f32(&mut self.img);
        Ok(())
    }

    /// The 20 embedding values of an 84x84 RGBA image (e.g. `ArenaEnv.observation()`).
    pub fn encode(&mut self, rgba: &[u8]) -> Result<Vec<f32>, JsError> {
        self.load(rgba)?;
        let mut e = [0.0; EMBEDDING];
        self.ae.encode(&self.img, &mut self.scratch, &mut e);
        Ok(e.to_vec())
    }

    /// The autoencoder's reconstruction of an 84x84 RGBA image, as RGBA bytes.
    pub fn reconstruct(&mut self, rgba: &[u8]) -> Result<Vec<u8>, JsError> {
        self.load(rgba)?;
        let mut e = [0.0; EMBEDDING];
        self.ae.encode(&self.img, &mut self.scratch, &mut e);
        self.ae.decode(&e, &mut self.scratch, &mut self.rec);
        let mut out = vec![0u8; self.frame.rgba.len()];
        reconstruction_to_rgba(&self.rec, &mut out);
        Ok(out)
    }

    /// Mean squared reconstruction error (inputs in [0, 1]): the gate's measure.
    #[wasm_bindgen(js_name = reconstructionMse)]
    pub fn reconstruction_mse(&mut self, rgba: &[u8]) -> Result<f32, JsError> {
        self.load(rgba)?;
        Ok(self.ae.reconstruction_mse(&self.img, &mut self.scratch))
    }

    /// The model's fixed embedding scale (docs/ENCODER.md, deviation D17).
    #[wasm_bindgen(getter, js_name = embeddingScale)]
    pub fn embedding_scale(&self) -> f32 {
        self.ae.embedding_scale
    }
}

/// Benchmark helper: `n` encodes (`decode` false) or decodes of a T-maze frame with the bundled
/// T-maze model; returns a checksum.
#[wasm_bindgen(js_name = benchAutoencoder)]
pub fn bench_autoencoder(n: u32, decode: bool) -> Result<f32, JsError> {
    let mut env = Env::new(EnvConfig::new(Task::preset("double-t-maze").map_err(js_err)?), 3).map_err(js_err)?;
    let mut img = vec![0.0; IMAGE];
    env.observation().to_rgb_f32(&mut img);
    let ae = bundled::autoencoder("double-t-maze").map_err(js_err)?;
    let mut s = Scratch::default();
    let mut e = [0.0; EMBEDDING];
    let mut rec = Vec::new();
    let mut acc = 0.0;
    ae.encode(&img, &mut s, &mut e);
    for _ in 0..n {
        if decode {
            ae.decode(&e, &mut s, &mut rec);
            acc += rec[0];
        } else {
            ae.encode(&img, &mut s, &mut e);
            acc += e[0];
        }
    }
    Ok(acc)
}

/// Test hook for the page's error path: panics, which traps the wasm instance like a bug would.
#[wasm_bindgen(js_name = panicForTest)]
pub fn panic_for_test() {
    panic!("panicForTest: testing the page's error path")
}

//! The JavaScript API (wasm32 only). Every value from JS is validated; a bad one is a JS
//! `Error` whose message names the parameter and its range, and leaves the state as it was.

use crate::arena::{Action, Task, MAX_T, TASK_NAMES};
use crate::encoder::{bundled, reconstruction_to_rgba, Autoencoder, Scratch, EMBEDDING, IMAGE};
use crate::env::{Env, EnvConfig};
use crate::render::{Frame, Trail, WIDTH};
use crate::seed::MAX_SEED;
use serde::Serialize;
use wasm_bindgen::prelude::*;

mod args;
#[cfg(feature = "test-hooks")]
mod hooks;
mod run;
pub use run::{
    agents, apply_settings, has_model, parameters, parse_settings, preset_settings, register_model, tasks, SecRun,
};

/// Error messages are cut to this many characters (a value in a message is already cut to 40).
const MAX_MESSAGE: usize = 400;

/// Any of the crate's errors as a JS `Error` with the same message, cut to `MAX_MESSAGE`.
fn js_err(e: impl std::fmt::Display) -> JsError {
    let message = e.to_string();
    match message.char_indices().nth(MAX_MESSAGE) {
        Some((at, _)) => JsError::new(&format!("{}…", &message[..at])),
        None => JsError::new(&message),
    }
}

fn seed_from_js(seed: &JsValue) -> Result<u64, JsError> {
    args::whole(seed, "seed", 0, MAX_SEED)
}

fn t_from_js(t: Option<JsValue>) -> Result<Option<u32>, JsError> {
    Ok(args::optional(t, "t", 0, MAX_T as u64)?.map(|t| t as u32))
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
    /// The height of the agent's bottom: 0 on the floor.
    y: f32,
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
    trail: Trail,
}

#[wasm_bindgen]
impl ArenaEnv {
    /// A built-in task (see `taskNames()`), a seed, and an optional episode limit `t`.
    #[wasm_bindgen(constructor)]
    pub fn new(
        #[wasm_bindgen(unchecked_param_type = "string")] task: JsValue,
        #[wasm_bindgen(unchecked_param_type = "number")] seed: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "number")] t: Option<JsValue>,
    ) -> Result<ArenaEnv, JsError> {
        let task = Task::preset(&args::string(&task, "task")?).map_err(js_err)?;
        Self::build(task, &seed, t)
    }

    /// An environment from the text of an Animal-AI YAML arena file. Only in builds with the
    /// `yaml-arenas` feature (the default; the playground page's own build leaves it out).
    #[cfg(feature = "yaml-arenas")]
    #[wasm_bindgen(js_name = fromYaml)]
    pub fn from_yaml(
        #[wasm_bindgen(unchecked_param_type = "string")] name: JsValue,
        #[wasm_bindgen(unchecked_param_type = "string")] source: JsValue,
        #[wasm_bindgen(unchecked_param_type = "number")] seed: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "number")] t: Option<JsValue>,
    ) -> Result<ArenaEnv, JsError> {
        let (name, source) = (args::string(&name, "name")?, args::string(&source, "source")?);
        let task = crate::arena::yaml::load_task(&name, &source).map_err(js_err)?;
        Self::build(task, &seed, t)
    }

    fn build(task: Task, seed: &JsValue, t: Option<JsValue>) -> Result<ArenaEnv, JsError> {
        let seed = seed_from_js(seed)?;
        let config = EnvConfig { t: t_from_js(t)?, ..EnvConfig::new(task) };
        let env = Env::new(config, seed).map_err(js_err)?;
        let trail = Trail::new(env.world().agent.pos);
        Ok(ArenaEnv { env, trail })
    }

    /// Starts the next episode, or restarts the run when a seed is given.
    pub fn reset(
        &mut self,
        #[wasm_bindgen(unchecked_optional_param_type = "number")] seed: Option<JsValue>,
    ) -> Result<(), JsError> {
        let seed = args::optional(seed, "seed", 0, MAX_SEED)?;
        self.env.reset(seed);
        self.trail.restart(self.env.world().agent.pos);
        Ok(())
    }

    /// One env step with action `3*a0 + a1`; returns `{reward, terminated, truncated, goodGoal, envSteps}`.
    pub fn step(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "number")] action: JsValue,
    ) -> Result<JsValue, JsError> {
        self.step_held(action, JsValue::from_f64(1.0))
    }

    /// Holds the action for `k` env steps (1..=1000) without rendering in between.
    #[wasm_bindgen(js_name = stepHeld)]
    pub fn step_held(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "number")] action: JsValue,
        #[wasm_bindgen(unchecked_param_type = "number")] k: JsValue,
    ) -> Result<JsValue, JsError> {
        let a = Action::new(args::whole(&action, "action", 0, 8)? as u32).map_err(js_err)?;
        let k = args::whole(&k, "k", 1, 1000)? as u32;
        let o = self.env.advance(a, k).map_err(js_err)?;
        self.trail.push(self.env.world().agent.pos);
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
    pub fn top_down(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "number")] size: JsValue,
    ) -> Result<Vec<u8>, JsError> {
        let size = args::whole(&size, "size", *Trail::SIZES.start() as u64, *Trail::SIZES.end() as u64)? as u32;
        Ok(self.trail.render(self.env.world(), size).map_err(js_err)?.to_vec())
    }

    /// Agent pose and episode state.
    pub fn agent(&self) -> Result<JsValue, JsError> {
        let a = &self.env.world().agent;
        let out = AgentJs {
            x: a.pos.x,
            y: a.y,
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

    /// The task's name.
    #[wasm_bindgen(js_name = taskName)]
    pub fn task_name(&self) -> String {
        self.env.config().task.name.clone()
    }

    /// What loading the arena file changed to read it as v1 does (a size clamped), one line each.
    pub fn warnings(&self) -> Vec<String> {
        self.env.config().task.warnings.clone()
    }
}

/// The built-in task names.
#[wasm_bindgen(js_name = taskNames)]
pub fn task_names() -> Vec<String> {
    TASK_NAMES.iter().map(|s| s.to_string()).collect()
}

/// A task's one-paragraph description.
#[wasm_bindgen(js_name = taskDescription)]
pub fn task_description(#[wasm_bindgen(unchecked_param_type = "string")] task: JsValue) -> Result<String, JsError> {
    Ok(Task::preset(&args::string(&task, "task")?).map_err(js_err)?.description)
}

/// The largest text file (a YAML arena) the page may read, in bytes: checked on the file's size
/// before it is read.
#[wasm_bindgen(js_name = maxTextFileBytes)]
pub fn max_text_file_bytes() -> u32 {
    crate::util::MAX_TEXT_FILE_BYTES as u32
}

/// Camera image side in pixels (84).
#[wasm_bindgen(js_name = frameSize)]
pub fn frame_size() -> u32 {
    WIDTH as u32
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
    pub fn new(#[wasm_bindgen(unchecked_param_type = "string")] task: JsValue) -> Result<Encoder, JsError> {
        let ae = bundled::autoencoder(&args::string(&task, "task")?).map_err(js_err)?;
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
    pub fn encode(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Uint8Array")] rgba: JsValue,
    ) -> Result<Vec<f32>, JsError> {
        self.load(&args::bytes(&rgba, "rgba")?)?;
        let mut e = [0.0; EMBEDDING];
        self.ae.encode(&self.img, &mut self.scratch, &mut e);
        Ok(e.to_vec())
    }

    /// The autoencoder's reconstruction of an 84x84 RGBA image, as RGBA bytes.
    pub fn reconstruct(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Uint8Array")] rgba: JsValue,
    ) -> Result<Vec<u8>, JsError> {
        self.load(&args::bytes(&rgba, "rgba")?)?;
        let mut e = [0.0; EMBEDDING];
        self.ae.encode(&self.img, &mut self.scratch, &mut e);
        self.ae.decode(&e, &mut self.scratch, &mut self.rec);
        let mut out = vec![0u8; self.frame.rgba.len()];
        reconstruction_to_rgba(&self.rec, &mut out);
        Ok(out)
    }

    /// Mean squared reconstruction error (inputs in [0, 1]): the gate's measure.
    #[wasm_bindgen(js_name = reconstructionMse)]
    pub fn reconstruction_mse(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Uint8Array")] rgba: JsValue,
    ) -> Result<f32, JsError> {
        let rgba = &args::bytes(&rgba, "rgba")?[..];
        self.load(rgba)?;
        Ok(self.ae.reconstruction_mse(&self.img, &mut self.scratch))
    }

    /// The model's fixed embedding scale (docs/ENCODER.md, deviation D17).
    #[wasm_bindgen(getter, js_name = embeddingScale)]
    pub fn embedding_scale(&self) -> f32 {
        self.ae.embedding_scale
    }
}

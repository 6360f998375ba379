//! `SecRun`: a whole run (SEC, MFEC or the reactive walk in a task) for the page's worker. The
//! configuration comes in and the metrics go out through serde-wasm-bindgen; the images are
//! typed-array views into wasm memory, valid until the next call into wasm (copy them, as the
//! worker does when it posts them). Every error names the parameter and its range, and a refused
//! value leaves the run as it was.

use super::{args, js_err, seed_from_js};
use crate::agent::SecConfig;
use crate::arena::Action;
use crate::encoder::{reconstruction_to_rgba, Scratch, EMBEDDING, IMAGE};
use crate::experiment::settings::{self, Settings};
use crate::experiment::{Driver, EpisodeMetrics, RunConfig};
use crate::memory::ACTIONS;
use crate::render::Trail;
use crate::session::{MemoryMap, Session, MAX_BATCH};
use serde::Serialize;
use std::collections::BTreeMap;
use wasm_bindgen::prelude::*;

/// The declarations of the JSON values this adapter hands out, in their own file so that a
/// native test (`tests/typescript.rs`) checks them against the core.
#[wasm_bindgen(typescript_custom_section)]
const TS_TYPES: &str = include_str!("types.d.ts");

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct StepResult {
    decided: bool,
    finished: Option<EpisodeMetrics>,
}

/// A run of SEC (or a baseline) in a task, stepped by the page's worker: an adapter over the
/// core's `Session`.
#[wasm_bindgen]
pub struct SecRun {
    pub(super) session: Session,
    image: Vec<f32>,
    scratch: Scratch,
    rec: Vec<f32>,
    rec_rgba: Vec<u8>,
    heat: Vec<f32>,
    marks: Vec<u32>,
}

/// Serialises for JS as JSON would (maps as objects, no `undefined`).
fn to_js<T: Serialize>(value: &T) -> Result<JsValue, JsError> {
    Ok(value.serialize(&serde_wasm_bindgen::Serializer::json_compatible())?)
}

fn config_from_js(config: JsValue) -> Result<RunConfig, JsError> {
    if config.is_undefined() || config.is_null() {
        return Ok(RunConfig::default());
    }
    // Through JSON text (`args::json`: read in full, NaN refused) to the core's one parser, which
    // sees every key, so a misspelt one is refused by name.
    RunConfig::from_json(&args::json(&config, "config")?).map_err(js_err)
}

impl SecRun {
    fn of(session: Session) -> SecRun {
        SecRun {
            session,
            image: vec![0.0; IMAGE],
            scratch: Scratch::default(),
            rec: Vec::new(),
            rec_rgba: vec![0; IMAGE / 3 * 4],
            heat: Vec::new(),
            marks: Vec::new(),
        }
    }
}

#[wasm_bindgen]
impl SecRun {
    /// A run of `config` (a `RunConfig`; missing fields take the defaults) with `seed`.
    #[wasm_bindgen(constructor)]
    pub fn new(
        #[wasm_bindgen(unchecked_param_type = "RunConfig")] config: JsValue,
        #[wasm_bindgen(unchecked_param_type = "number")] seed: JsValue,
    ) -> Result<SecRun, JsError> {
        let cfg = config_from_js(config)?;
        let seed = seed_from_js(&seed)?;
        Ok(SecRun::of(Session::new(cfg, seed).map_err(js_err)?))
    }

    /// The configuration in force (a `RunConfig` with every field).
    #[wasm_bindgen(unchecked_return_type = "RunConfig")]
    pub fn config(&self) -> Result<JsValue, JsError> {
        to_js(self.session.config())
    }

    /// The run's seed.
    #[wasm_bindgen(getter)]
    pub fn seed(&self) -> f64 {
        self.session.seed() as f64
    }

    /// Applies a change of the configuration: `config` names the fields to change (a partial
    /// `RunConfig`, `{agent: {memory: {tau: 0.5}}}`); the fields it leaves out keep their values.
    /// SEC's parameters (thresholds, alpha, beta, tau, m, the value function, forgetting, the
    /// bias, the gate) change live; anything else (task, t, n, the agent...) restarts the run
    /// with the same seed. Returns `{applied: "live" | "restart", changed: [{field, from, to,
    /// live}]}`. A bad change throws, naming the field, and changes nothing.
    #[wasm_bindgen(unchecked_return_type = "ConfigChange")]
    pub fn configure(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Partial<RunConfig>")] config: JsValue,
    ) -> Result<JsValue, JsError> {
        let patch =
            if config.is_undefined() || config.is_null() { "{}".to_string() } else { args::json(&config, "config")? };
        to_js(&self.session.configure_patch(&patch).map_err(js_err)?)
    }

    /// Replaces the whole configuration: the fields `config` leaves out take their defaults
    /// (what the page's settings table makes is a whole configuration). Answers as `configure`.
    #[wasm_bindgen(js_name = replaceConfig, unchecked_return_type = "ConfigChange")]
    pub fn replace_config(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "RunConfig")] config: JsValue,
    ) -> Result<JsValue, JsError> {
        let cfg = config_from_js(config)?;
        to_js(&self.session.replace_config(cfg).map_err(js_err)?)
    }

    /// Restarts the run from scratch, with `seed` or the run's own.
    pub fn reset(
        &mut self,
        #[wasm_bindgen(unchecked_optional_param_type = "number")] seed: Option<JsValue>,
    ) -> Result<(), JsError> {
        let seed = args::optional(seed, "seed", 0, crate::seed::MAX_SEED)?;
        self.session.reset(seed).map_err(js_err)
    }

    /// Runs `decisions` decisions (1..=100000); returns the episodes they finished
    /// (`EpisodeMetrics[]`).
    #[wasm_bindgen(js_name = runDecisions, unchecked_return_type = "EpisodeMetrics[]")]
    pub fn run_decisions(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "number")] decisions: JsValue,
    ) -> Result<JsValue, JsError> {
        let decisions = args::whole(&decisions, "decisions", 1, MAX_BATCH as u64)? as u32;
        to_js(&self.session.run_decisions(decisions).map_err(js_err)?)
    }

    /// Plays to the next decision: `{decided, finished}` (`finished` is the episode it ended, if
    /// any).
    #[wasm_bindgen(js_name = stepDecision)]
    pub fn step_decision(&mut self) -> Result<JsValue, JsError> {
        let t = self.session.step_decision();
        to_js(&StepResult { decided: t.decision.is_some(), finished: t.finished })
    }

    /// Plays the current episode to its end; returns its `EpisodeMetrics`.
    #[wasm_bindgen(js_name = stepEpisode, unchecked_return_type = "EpisodeMetrics")]
    pub fn step_episode(&mut self) -> Result<JsValue, JsError> {
        to_js(&self.session.step_episode())
    }

    /// The last decision and the run's state (`DecisionView`).
    #[wasm_bindgen(unchecked_return_type = "DecisionView")]
    pub fn view(&mut self) -> Result<JsValue, JsError> {
        to_js(&self.session.view())
    }

    /// The last decision's contextual layer term by term (`Explanation`): every selected couplet
    /// with G, T, rr, d and its value, and how they sum into Q per action. Empty for a run
    /// without SEC or a decision where nothing was selected.
    #[wasm_bindgen(unchecked_return_type = "Explanation")]
    pub fn explain(&self) -> Result<JsValue, JsError> {
        to_js(&self.session.explain())
    }

    /// The agent's 84x84 camera as RGBA bytes (a view: copy before the next call).
    pub fn observation(&mut self) -> js_sys::Uint8Array {
        let rgba = &self.session.run_mut().observation().rgba;
        // SAFETY: the view is into wasm memory and is documented as valid until the next call.
        unsafe { js_sys::Uint8Array::view(rgba) }
    }

    /// The autoencoder's reconstruction of the current camera image, RGBA (a view); empty in an
    /// arena file's run, which has no trained model.
    pub fn reconstruction(&mut self) -> js_sys::Uint8Array {
        let run = self.session.run_mut();
        if run.encoder().is_none() {
            return js_sys::Uint8Array::new_with_length(0);
        }
        run.observation().to_rgb_f32(&mut self.image);
        let mut e = [0.0; EMBEDDING];
        let ae = run.encoder().expect("checked above");
        ae.encode(&self.image, &mut self.scratch, &mut e);
        ae.decode(&e, &mut self.scratch, &mut self.rec);
        reconstruction_to_rgba(&self.rec, &mut self.rec_rgba);
        // SAFETY: as `observation`.
        unsafe { js_sys::Uint8Array::view(&self.rec_rgba) }
    }

    /// The top-down view with the agent's trail, `size` x `size` RGBA (size 32..=2048; a view).
    #[wasm_bindgen(js_name = topDown)]
    pub fn top_down(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "number")] size: JsValue,
    ) -> Result<js_sys::Uint8Array, JsError> {
        let size = args::whole(&size, "size", *Trail::SIZES.start() as u64, *Trail::SIZES.end() as u64)? as u32;
        let rgba = self.session.top_down(size).map_err(js_err)?;
        // SAFETY: as `observation`.
        Ok(unsafe { js_sys::Uint8Array::view(rgba) })
    }

    /// The LTM as a heat map, sequences x STM positions, row-major: `which` "g" (the last
    /// decision's biased similarity G) or "t" (the bias T). Empty for a run without SEC.
    #[wasm_bindgen(js_name = memoryMap)]
    pub fn memory_map(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "string")] which: JsValue,
    ) -> Result<js_sys::Float32Array, JsError> {
        let which: MemoryMap = args::string(&which, "which")?.parse().map_err(js_err)?;
        self.session.memory_map(which, &mut self.heat);
        // SAFETY: as `observation`.
        Ok(unsafe { js_sys::Float32Array::view(&self.heat) })
    }

    /// Flat indices (row * n + column) of the couplets selected at the last decision (a view).
    #[wasm_bindgen(js_name = selectedCouplets)]
    pub fn selected_couplets(&mut self) -> js_sys::Uint32Array {
        self.session.selected_couplets(&mut self.marks);
        // SAFETY: as `observation`.
        unsafe { js_sys::Uint32Array::view(&self.marks) }
    }

    /// A person takes the controls with `action` (0..=8: 3 x forward/back + turn right/left)
    /// from the next decision on, or gives them back with `null`. With `record` (SEC only) the
    /// decisions go into the agent's memory with the person's actions, so a rewarded episode is
    /// stored in the LTM like any other; without it the agent learns nothing from them.
    #[wasm_bindgen(js_name = setDriver)]
    pub fn set_driver(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "number | null")] action: JsValue,
        record: bool,
    ) -> Result<(), JsError> {
        let action = args::optional_whole(&action, "action", 0, ACTIONS as u64 - 1)?;
        let driver = action.map(|a| Action::new(a as u32).map(|action| Driver { action, record })).transpose();
        self.session.set_driver(driver.map_err(js_err)?);
        Ok(())
    }

    /// SEC's memory (STM and LTM) as a versioned file (`memory::file`): bytes to download.
    #[wasm_bindgen(js_name = saveMemory)]
    pub fn save_memory(&self) -> Result<Vec<u8>, JsError> {
        self.session.save_memory().map_err(js_err)
    }

    /// Replaces SEC's memory with a saved file's; returns the sequences loaded. A corrupt,
    /// foreign or mismatched file (another task, encoder, n, or more sequences than m) throws an
    /// Error naming what is wrong, and the memory is left as it was.
    #[wasm_bindgen(js_name = loadMemory)]
    pub fn load_memory(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Uint8Array")] bytes: JsValue,
    ) -> Result<u32, JsError> {
        let bytes = args::bytes(&bytes, "bytes")?;
        self.session.load_memory(&bytes).map(|n| n as u32).map_err(js_err)
    }

    /// Whether the run can be written as a checkpoint between episodes (`checkpoint`): SEC and
    /// its variants can; MFEC cannot (its buffers hold up to 100,000 entries per action).
    #[wasm_bindgen(getter, js_name = canCheckpoint)]
    pub fn can_checkpoint(&self) -> bool {
        self.session.run().can_checkpoint()
    }

    /// Whether an episode is under way (a checkpoint is written only between two).
    #[wasm_bindgen(getter, js_name = midEpisode)]
    pub fn mid_episode(&self) -> bool {
        self.session.run().current().is_some()
    }

    /// The run between two episodes as checkpoint bytes (`experiment::checkpoint`), so that
    /// another worker resumes it (`SecRun.resume`) and plays the same episodes. Throws in the
    /// middle of an episode and for agents that do not checkpoint (`canCheckpoint`).
    pub fn checkpoint(&self) -> Result<Vec<u8>, JsError> {
        let mut bytes = Vec::new();
        self.session.run().save_checkpoint(&mut bytes).map_err(js_err)?;
        Ok(bytes)
    }

    /// The run of `config` and `seed` brought to `checkpoint` (bytes from `checkpoint`), which
    /// may claim at most `max_episodes` episodes (the caller's count, not the file's). A
    /// checkpoint of another configuration or seed, or a changed one, throws naming why.
    pub fn resume(
        #[wasm_bindgen(unchecked_param_type = "RunConfig")] config: JsValue,
        #[wasm_bindgen(unchecked_param_type = "number")] seed: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Uint8Array")] checkpoint: JsValue,
        #[wasm_bindgen(unchecked_param_type = "number")] max_episodes: JsValue,
    ) -> Result<SecRun, JsError> {
        let cfg = config_from_js(config)?;
        let seed = seed_from_js(&seed)?;
        let bytes = args::bytes(&checkpoint, "checkpoint")?;
        let max = args::whole(&max_episodes, "max_episodes", 0, crate::experiment::checkpoint::MAX_EPISODES)?;
        let check = crate::experiment::checkpoint::ResumeCheck::at_most(max);
        let session = Session::resume(cfg, seed, None, &mut bytes.as_slice(), &check, 0).map_err(js_err)?;
        Ok(SecRun::of(session))
    }

    /// STM length n: the heat map's row length.
    #[wasm_bindgen(getter, js_name = stmLength)]
    pub fn stm_length(&self) -> u32 {
        self.session.config().section::<SecConfig>().memory.n as u32
    }
}

/// Settings from JS: an object whose values are strings, numbers or booleans.
fn settings_from_js(value: JsValue, what: &str) -> Result<Settings, JsError> {
    let text = args::json(&value, what)?;
    let map: BTreeMap<String, serde_json::Value> =
        serde_json::from_str(&text).map_err(|e| js_err(format!("{what}: {e}")))?;
    map.into_iter()
        .map(|(k, v)| {
            let s = match v {
                serde_json::Value::String(s) => s,
                serde_json::Value::Bool(b) => (b as u8).to_string(),
                serde_json::Value::Number(n) => n.to_string(),
                other => return Err(JsError::new(&format!("{k}: {other} is not a string, number or boolean"))),
            };
            Ok((k, s))
        })
        .collect()
}

#[derive(Serialize)]
struct ParsedSettings {
    config: RunConfig,
    seed: f64,
    settings: Settings,
    errors: Vec<String>,
}

fn parsed(config: RunConfig, seed: u64, errors: Vec<String>) -> Result<JsValue, JsError> {
    let settings = settings::to_settings(&config, seed);
    to_js(&ParsedSettings { config, seed: seed as f64, settings, errors })
}

/// The page's settings (`Param[]`): key, symbol, help, kind with range or options, live or not.
#[wasm_bindgen(unchecked_return_type = "Param[]")]
pub fn parameters() -> Result<JsValue, JsError> {
    to_js(&settings::params())
}

/// The agent table (`AgentInfo[]`): every agent, its label and what it can do.
#[wasm_bindgen(unchecked_return_type = "AgentInfo[]")]
pub fn agents() -> Result<JsValue, JsError> {
    to_js(&crate::agent::AGENTS)
}

/// The task table (`TaskInfo[]`): every built-in task, its title, Gymnasium id and model file.
#[wasm_bindgen(unchecked_return_type = "TaskInfo[]")]
pub fn tasks() -> Result<JsValue, JsError> {
    to_js(&crate::arena::TASKS)
}

/// Settings as the URL hash holds them (`{alpha: "0.01", ...}`) to `{config, seed, settings,
/// errors}`: a bad key or value keeps its default and adds an error message naming it.
#[wasm_bindgen(js_name = parseSettings, unchecked_return_type = "ParsedSettings")]
pub fn parse_settings(settings: JsValue) -> Result<JsValue, JsError> {
    let s = settings_from_js(settings, "settings")?;
    let (cfg, seed, errors) = settings::from_settings(&s);
    parsed(cfg, seed, errors.iter().map(|e| e.to_string()).collect())
}

/// `current` settings with `changes` applied as one batch (`settings::apply_all`: in any order,
/// all or none), as `{config, seed, settings, errors: []}`; bad changes throw one Error naming
/// each key and its range, `; `-separated, and nothing is applied.
#[wasm_bindgen(js_name = applySettings, unchecked_return_type = "ParsedSettings")]
pub fn apply_settings(current: JsValue, changes: JsValue) -> Result<JsValue, JsError> {
    let (cfg, seed, errors) = settings::from_settings(&settings_from_js(current, "current")?);
    if let Some(e) = errors.first() {
        return Err(JsError::new(&e.to_string()));
    }
    match settings::apply_all(&cfg, seed, &settings_from_js(changes, "changes")?) {
        Ok((cfg, seed)) => parsed(cfg, seed, Vec::new()),
        Err(errors) => Err(JsError::new(&errors.iter().map(|e| e.to_string()).collect::<Vec<_>>().join("; "))),
    }
}

/// `config` (a `RunConfig`) playing the Animal-AI arena file `yaml` named `name`
/// (`RunConfig::with_arena`: the untrained encoder, SEC's gate off), as a `RunConfig`. A file the
/// loader refuses, or a build without the YAML parser (the playground's; the arena build,
/// pkg/arena/, has it), throws naming the field.
#[wasm_bindgen(js_name = withArena, unchecked_return_type = "RunConfig")]
pub fn with_arena(
    #[wasm_bindgen(unchecked_param_type = "RunConfig")] config: JsValue,
    #[wasm_bindgen(unchecked_param_type = "string")] name: JsValue,
    #[wasm_bindgen(unchecked_param_type = "string")] yaml: JsValue,
) -> Result<JsValue, JsError> {
    let cfg = config_from_js(config)?;
    let (name, yaml) = (args::string(&name, "name")?, args::string(&yaml, "yaml")?);
    to_js(&cfg.with_arena(&name, &yaml).map_err(js_err)?)
}

/// Makes a weights file (`assets/encoders/<task>.secae`, as bytes) the model of its task; returns
/// the task. The wasm build holds no model: register the task's before a run in it. A corrupt
/// file or one of an unknown task throws.
#[wasm_bindgen(js_name = registerModel)]
pub fn register_model(#[wasm_bindgen(unchecked_param_type = "Uint8Array")] bytes: JsValue) -> Result<String, JsError> {
    crate::encoder::bundled::register(&args::bytes(&bytes, "bytes")?).map_err(js_err)
}

/// Whether the model of `task` is registered.
#[wasm_bindgen(js_name = hasModel)]
pub fn has_model(#[wasm_bindgen(unchecked_param_type = "string")] task: JsValue) -> Result<bool, JsError> {
    Ok(crate::encoder::bundled::has(&args::string(&task, "task")?))
}

/// The settings a preset ("code" or "paper") sets.
#[wasm_bindgen(js_name = presetSettings, unchecked_return_type = "Record<string, string>")]
pub fn preset_settings(#[wasm_bindgen(unchecked_param_type = "string")] name: JsValue) -> Result<JsValue, JsError> {
    let name = args::string(&name, "name")?;
    to_js(&settings::preset(&name).map_err(js_err)?)
}

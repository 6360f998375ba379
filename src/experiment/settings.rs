//! The page's settings: the flat keys of the URL hash and the controls (`alpha=0.01&m=500&...`),
//! each with its symbol, a one-line explanation and its range, and their mapping onto a
//! `RunConfig` and a seed. The page builds its controls from `params()`, so the ranges shown are
//! the ranges checked here.

use super::RunConfig;
use crate::agent::controller::Input;
use crate::agent::mfec::Embedding;
use crate::agent::{AgentInfo, SecConfig};
use crate::arena::{ConfigError, StartHeading, DEFAULT_T, MAX_T, TASK_NAMES};
use crate::encoder::perception::SCALE_RANGE;
use crate::encoder::PerceptionKind;
use crate::memory::{
    Forgetting, ValueFn, ALPHA_RANGE, BETA_RANGE, M_RANGE, N_RANGE, TAU_RANGE, THETA_ABS_RANGE, THETA_PROP_RANGE,
};
use crate::render::Surface;
use crate::util::shown;
use std::collections::BTreeMap;

/// Flat settings, key to value, as the URL hash holds them.
pub type Settings = BTreeMap<String, String>;

use crate::agent::mfec::MfecConfig;
use crate::seed::MAX_SEED;

/// What values a setting takes.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[serde(tag = "type", rename_all = "camelCase")]
pub enum Kind {
    /// A real number in [min, max] (or (min, max] when `min_open`); with `auto`, also the word
    /// `auto`, which leaves the value to the run (an empty control shows it).
    #[serde(rename_all = "camelCase")]
    Number {
        /// Lower bound.
        min: f64,
        /// Upper bound.
        max: f64,
        /// The lower bound itself is excluded.
        min_open: bool,
        /// The control's step.
        step: f64,
        /// `auto` is a value too.
        auto: bool,
    },
    /// A whole number in min..=max.
    Integer {
        /// Lower bound.
        min: u64,
        /// Upper bound.
        max: u64,
    },
    /// One of the options.
    Choice {
        /// The values, as the URL hash spells them.
        options: Vec<String>,
    },
    /// On ("1") or off ("0").
    Switch,
}

/// One setting as the page shows it.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Param {
    /// The URL hash's key.
    pub key: &'static str,
    /// The paper's symbol (Greek letters as Unicode), or a short label.
    pub symbol: &'static str,
    /// One line on what it does.
    pub help: &'static str,
    /// What values it takes.
    pub kind: Kind,
    /// Applies to the running agent; otherwise a change starts a new run.
    pub live: bool,
    /// The page's group of controls: run, perception, memory or retrieval.
    pub group: &'static str,
    /// The page's agents (`page_agents()` keys) that use it; empty: every agent.
    pub agents: Vec<&'static str>,
}

/// The page's agents with a sequential memory: SEC's parameters are theirs.
fn sec_only() -> Vec<&'static str> {
    AgentInfo::keys_where(|a| a.has_memory && !a.native_only)
}

/// The page's agents whose states come from the perception.
fn embedders() -> Vec<&'static str> {
    AgentInfo::keys_where(|a| a.reads == Input::Embedding && !a.native_only)
}

/// The agents the page offers (the table's, less the native-only ones).
pub fn page_agents() -> Vec<&'static str> {
    AgentInfo::keys_where(|a| !a.native_only)
}

impl Param {
    fn group(self, group: &'static str) -> Param {
        Param { group, ..self }
    }
    fn agents(self, agents: Vec<&'static str>) -> Param {
        Param { agents, ..self }
    }
}

/// One setting: what the page shows (`param`) and how it reads and writes a run's configuration
/// and seed. `set` receives the value `parse` checked: the number, the choice's index, 1/0 for a
/// switch, NaN for `auto`.
struct Setting {
    param: Param,
    get: fn(&RunConfig, u64) -> String,
    set: fn(&mut RunConfig, &mut u64, f64),
}

fn number(key: &'static str, symbol: &'static str, help: &'static str, r: (f64, f64), open: bool, step: f64) -> Param {
    Param {
        key,
        symbol,
        help,
        kind: Kind::Number { min: r.0, max: r.1, min_open: open, step, auto: false },
        live: true,
        group: "retrieval",
        agents: sec_only(),
    }
}

fn choice(key: &'static str, symbol: &'static str, help: &'static str, options: &[&str], live: bool) -> Param {
    let kind = Kind::Choice { options: options.iter().map(|s| s.to_string()).collect() };
    Param { key, symbol, help, kind, live, group: "run", agents: Vec::new() }
}

fn integer(key: &'static str, symbol: &'static str, help: &'static str, r: (u64, u64), live: bool) -> Param {
    Param { key, symbol, help, kind: Kind::Integer { min: r.0, max: r.1 }, live, group: "run", agents: Vec::new() }
}

fn names<T>(table: &[(&'static str, T)]) -> Vec<&'static str> {
    table.iter().map(|(n, _)| *n).collect()
}

/// The name `table` gives `value`.
fn name_of<T: PartialEq>(table: &[(&'static str, T)], value: T) -> String {
    table.iter().find(|(_, v)| *v == value).expect("every option is listed").0.to_string()
}

fn agent_name(cfg: &RunConfig) -> &'static str {
    AgentInfo::of(cfg.kind, cfg.section::<MfecConfig>().embedding).key
}

/// Runs the agent of the table's row `key` (one of the page's).
fn set_agent(cfg: &mut RunConfig, key: &str) {
    let row = AgentInfo::find(key).expect("the page's choices are the table's keys");
    cfg.kind = row.kind;
    cfg.section_mut::<MfecConfig>().embedding = row.embedding.unwrap_or(Embedding::Autoencoder);
}

/// Every setting, each declared once, in the order the page shows them.
#[rustfmt::skip]
fn table() -> Vec<Setting> {
    vec![
        Setting {
            param: choice("task", "task", "The arena the agent learns in (a new run).", &TASK_NAMES, false),
            get: |c, _| c.task.clone(),
            set: |c, _, v| c.task = TASK_NAMES[v as usize].to_string(),
        },
        Setting {
            param: choice("agent", "agent", "SEC, MFEC on the autoencoder's or a random projection's embedding, or the reactive walk alone (a new run).", &page_agents(), false),
            get: |c, _| agent_name(c).to_string(),
            set: |c, _, v| set_agent(c, page_agents()[v as usize]),
        },
        Setting {
            param: choice("perception", "encoder", "Which encoder embeds the camera image: untrained random weights (what the authors' code ran) or the trained one (the paper's text); the trained one always runs the gate (a new run).", &names(&PerceptionKind::ALL), false).group("perception").agents(embedders()),
            get: |c, _| name_of(&PerceptionKind::ALL, c.perception),
            set: |c, _, v| c.perception = PerceptionKind::ALL[v as usize].1,
        },
        Setting {
            param: choice("surface", "surface", "How the camera draws the floor and fences: flat colours, or v1's tiled floor and planked fences (textured); the gate uses the model trained on that surface's frames (a new run).", &names(&Surface::ALL), false).group("perception"),
            get: |c, _| name_of(&Surface::ALL, c.surface),
            set: |c, _, v| c.surface = Surface::ALL[v as usize].1,
        },
        Setting {
            param: Param { key: "embeddingScale", symbol: "scale", help: "Multiplies every embedding, so it sets how alike two views must be to pass θ_abs; auto: 1 untrained, the calibrated scale trained (a new run).", kind: Kind::Number { min: SCALE_RANGE.0 as f64, max: SCALE_RANGE.1 as f64, min_open: true, step: 0.01, auto: true }, live: false, group: "perception", agents: embedders() },
            get: |c, _| c.scale_override().map_or("auto".to_string(), |s| s.to_string()),
            set: |c, _, v| {
                c.embedding_scale = (!v.is_nan()).then_some(v as f32);
                c.raw_embeddings = false;
            },
        },
        Setting {
            param: Param { key: "bias", symbol: "T", help: "Sequential bias: on is SEC, off is NSEC (T restarts at 1).", kind: Kind::Switch, live: true, group: "retrieval", agents: sec_only() },
            get: |c, _| (c.section::<SecConfig>().memory.sequential_bias as u8).to_string(),
            set: |c, _, v| c.section_mut::<SecConfig>().memory.sequential_bias = v == 1.0,
        },
        Setting {
            param: number("alpha", "α", "How much T rises for the successor of a selected couplet.", ALPHA_RANGE, false, 0.001),
            get: |c, _| c.section::<SecConfig>().memory.alpha.to_string(),
            set: |c, _, v| c.section_mut::<SecConfig>().memory.alpha = v,
        },
        Setting {
            param: number("beta", "β", "How fast T decays back towards 1 at every decision.", BETA_RANGE, false, 0.001),
            get: |c, _| c.section::<SecConfig>().memory.beta.to_string(),
            set: |c, _, v| c.section_mut::<SecConfig>().memory.beta = v,
        },
        Setting {
            param: number("tau", "τ", "Distance discount exp(-d/τ): lower favours couplets near the goal.", TAU_RANGE, false, 0.01),
            get: |c, _| c.section::<SecConfig>().memory.tau.to_string(),
            set: |c, _, v| c.section_mut::<SecConfig>().memory.tau = v,
        },
        Setting {
            param: number("thetaAbs", "θ_abs", "A couplet is selected only if its biased similarity G exceeds this...", THETA_ABS_RANGE, false, 0.001),
            get: |c, _| c.section::<SecConfig>().memory.theta_abs.to_string(),
            set: |c, _, v| c.section_mut::<SecConfig>().memory.theta_abs = v,
        },
        Setting {
            param: number("thetaProp", "θ_prop", "...and G / Gmax exceeds this.", THETA_PROP_RANGE, false, 0.001),
            get: |c, _| c.section::<SecConfig>().memory.theta_prop.to_string(),
            set: |c, _, v| c.section_mut::<SecConfig>().memory.theta_prop = v,
        },
        Setting {
            param: integer("n", "n", "STM length: couplets per stored sequence (a new run).", (N_RANGE.0 as u64, N_RANGE.1 as u64), false).group("memory").agents(sec_only()),
            get: |c, _| c.section::<SecConfig>().memory.n.to_string(),
            set: |c, _, v| c.section_mut::<SecConfig>().memory.n = v as usize,
        },
        Setting {
            param: integer("m", "m", "LTM capacity in sequences; a smaller m forgets the oldest now.", (M_RANGE.0 as u64, M_RANGE.1 as u64), true).group("memory").agents(sec_only()),
            get: |c, _| c.section::<SecConfig>().memory.m.to_string(),
            set: |c, _, v| c.section_mut::<SecConfig>().memory.m = v as usize,
        },
        Setting {
            param: integer("minSequences", "min", "Memory acts only once the LTM holds this many sequences (at most m).", (0, M_RANGE.1 as u64), true).group("memory").agents(sec_only()),
            get: |c, _| c.section::<SecConfig>().min_sequences.to_string(),
            set: |c, _, v| c.section_mut::<SecConfig>().min_sequences = v as usize,
        },
        Setting {
            param: choice("forgetting", "forget", "What a full LTM does: nothing, drop the oldest, the lowest reward, the 10% lowest, or one drawn by low reward.", &names(&Forgetting::ALL), true).group("memory").agents(sec_only()),
            get: |c, _| name_of(&Forgetting::ALL, c.section::<SecConfig>().memory.forgetting),
            set: |c, _, v| c.section_mut::<SecConfig>().memory.forgetting = Forgetting::ALL[v as usize].1,
        },
        Setting {
            param: choice("value", "value", "How a couplet's similarity g, relative reward rr and distance d make its value.", &names(&ValueFn::ALL), true).agents(sec_only()).group("retrieval"),
            get: |c, _| name_of(&ValueFn::ALL, c.section::<SecConfig>().memory.value_function),
            set: |c, _, v| c.section_mut::<SecConfig>().memory.value_function = ValueFn::ALL[v as usize].1,
        },
        Setting {
            param: integer("t", "t", "Episode limit in env steps; every step costs 1/t (a new run).", (0, MAX_T as u64), false),
            get: |c, _| c.t.unwrap_or(DEFAULT_T).to_string(),
            set: |c, _, v| c.t = Some(v as u32),
        },
        Setting {
            param: choice("startHeading", "heading", "Where the double T-maze's agent starts looking: a new random heading every episode, or always facing the centre (a new run).", &names(&StartHeading::ALL), false),
            get: |c, _| name_of(&StartHeading::ALL, c.start_heading),
            set: |c, _, v| c.start_heading = StartHeading::ALL[v as usize].1,
        },
        Setting {
            param: integer("seed", "seed", "The run is a pure function of its settings and this seed (a new run).", (0, MAX_SEED), false),
            get: |_, seed| seed.to_string(),
            set: |_, seed, v| *seed = v as u64,
        },
    ]
}

impl RunConfig {
    /// Whether going from `self` to `next` needs a new run: it does unless every field that
    /// differs is one a live setting sets (the rows' `live`, the one place liveness is declared).
    /// A field no setting shows (`agent.gate`, the reactive walk's lengths) is fixed for a run.
    pub fn needs_restart(&self, next: &RunConfig) -> bool {
        let (mut probe, mut seed) = (self.clone(), 0);
        for s in table().iter().filter(|s| s.param.live) {
            let value = parse(&s.param, &(s.get)(next, 0)).expect("a setting reads back what it shows");
            (s.set)(&mut probe, &mut seed, value);
        }
        probe != *next
    }
}

/// Every setting, in the order the page shows them.
pub fn params() -> Vec<Param> {
    table().into_iter().map(|s| s.param).collect()
}

/// The settings `agent` uses (an agent table key; `None`: every setting): what the page builds
/// that agent's controls from, and what Python's and the CLI's `parameters` list. An unknown
/// agent is an error naming the agents.
pub fn params_for(agent: Option<&str>) -> Result<Vec<Param>, ConfigError> {
    let Some(agent) = agent else { return Ok(params()) };
    if !crate::agent::AGENTS.iter().any(|a| a.key == agent) {
        let keys: Vec<&str> = crate::agent::AGENTS.iter().map(|a| a.key).collect();
        return Err(ConfigError::new("agent", format!("'{}' is not one of {}", shown(agent), keys.join(", "))));
    }
    Ok(params().into_iter().filter(|p| p.agents.is_empty() || p.agents.contains(&agent)).collect())
}

/// `cfg` and `seed` with a batch of `changes` applied as one: every change is read (each bad key
/// or value is reported, naming it and its range), then the whole is checked, so the order of
/// the changes does not matter (m and minSequences may go together either way). All or none:
/// on any error nothing is applied and every error is returned.
pub fn apply_all(cfg: &RunConfig, seed: u64, changes: &Settings) -> Result<(RunConfig, u64), Vec<ConfigError>> {
    let (mut next, mut next_seed) = (cfg.clone(), seed);
    let errors: Vec<ConfigError> =
        changes.iter().filter_map(|(k, v)| apply(&mut next, &mut next_seed, k, v).err()).collect();
    if !errors.is_empty() {
        return Err(errors);
    }
    next.validate().map_err(|e| vec![e])?;
    Ok((next, next_seed))
}

/// `cfg` with the settings `pairs` (page keys and their values as the URL hash writes them)
/// applied in order, checked as a whole; the run's seed is not one of them (a run's seed is
/// its own argument). On an error, naming the key and its range, `cfg` is returned unchanged.
pub fn with_settings(cfg: &RunConfig, pairs: &[(String, String)]) -> Result<RunConfig, ConfigError> {
    let mut next = cfg.clone();
    let mut seed = 0;
    for (k, v) in pairs {
        if canonical_key(k) == Some("seed") {
            return Err(ConfigError::new("seed", "is the run's own argument, not a setting to change here"));
        }
        apply(&mut next, &mut seed, k, v)?;
    }
    next.validate()?;
    Ok(next)
}

fn range_error(key: &str, value: &str, kind: &Kind) -> ConfigError {
    let range = match kind {
        Kind::Number { min, max, min_open: true, auto: true, .. } => format!("({min}, {max}] or auto"),
        Kind::Number { min, max, min_open: true, .. } => format!("({min}, {max}]"),
        Kind::Number { min, max, .. } => format!("[{min}, {max}]"),
        Kind::Integer { min, max } => format!("{min}..={max} (whole numbers)"),
        Kind::Choice { options } => format!("one of {}", options.join(", ")),
        Kind::Switch => "0 or 1".into(),
    };
    let number = matches!(kind, Kind::Number { .. } | Kind::Integer { .. });
    let message = if number && value.trim().is_empty() {
        format!("is empty, not a number in {range}")
    } else if number && value.trim().parse::<f64>().is_err() {
        format!("'{}' is not a number in {range}", shown(value))
    } else {
        format!("'{}' is out of range {range}", shown(value))
    };
    ConfigError::new(shown(key), message)
}

/// The setting's value parsed and range-checked, as a number (choices: their index; `auto`:
/// NaN).
fn parse(p: &Param, value: &str) -> Result<f64, ConfigError> {
    let bad = || range_error(p.key, value, &p.kind);
    match &p.kind {
        Kind::Number { auto: true, .. } if value.trim() == "auto" => Ok(f64::NAN),
        Kind::Number { min, max, min_open, .. } => {
            let v: f64 = value.trim().parse().map_err(|_| bad())?;
            let above = if *min_open { v > *min } else { v >= *min };
            (v.is_finite() && above && v <= *max).then_some(v).ok_or_else(bad)
        }
        Kind::Integer { min, max } => {
            let digits = !value.is_empty() && value.bytes().all(|b| b.is_ascii_digit());
            let v: u64 = if digits { value.parse().map_err(|_| bad())? } else { return Err(bad()) };
            (*min..=*max).contains(&v).then_some(v as f64).ok_or_else(bad)
        }
        Kind::Choice { options } => options.iter().position(|o| o == value).map(|i| i as f64).ok_or_else(bad),
        Kind::Switch => match value {
            "1" | "on" | "true" => Ok(1.0),
            "0" | "off" | "false" => Ok(0.0),
            _ => Err(bad()),
        },
    }
}

/// Sets one setting on `cfg` and `seed`; an unknown key or a bad value is an error that names
/// the key and its range, and changes nothing.
pub fn apply(cfg: &mut RunConfig, seed: &mut u64, key: &str, value: &str) -> Result<(), ConfigError> {
    let all = table();
    let s = all.iter().find(|s| s.param.key == key || loose(s.param.key) == loose(key)).ok_or_else(|| {
        let keys: Vec<&str> = all.iter().map(|s| s.param.key).collect();
        let name = if key.is_empty() { "\"\"".to_string() } else { shown(key) };
        ConfigError::new(name, format!("is not a setting (settings: {})", keys.join(", ")))
    })?;
    let v = parse(&s.param, value)?;
    (s.set)(cfg, seed, v);
    Ok(())
}

/// A key as HTML attributes and hand-typed links may write it: `startHeading`, `startheading`,
/// `start-heading` and `start_heading` are one key.
fn loose(key: &str) -> String {
    key.chars().filter(|c| !matches!(c, '-' | '_')).flat_map(char::to_lowercase).collect()
}

/// The table's name of a key written in any case or kebab form (see `apply`), if it is one.
pub fn canonical_key(key: &str) -> Option<&'static str> {
    table().iter().map(|s| s.param.key).find(|k| *k == key || loose(k) == loose(key))
}

/// The settings that describe `cfg` and `seed` (what the URL hash shows).
pub fn to_settings(cfg: &RunConfig, seed: u64) -> Settings {
    table().into_iter().map(|s| (s.param.key.to_string(), (s.get)(cfg, seed))).collect()
}

/// The page's default run: double T-maze, SEC, the code preset, seed 1. The episode limit is
/// explicit (the tasks' 1000), so that configurations made from settings compare equal.
pub fn defaults() -> (RunConfig, u64) {
    (RunConfig { t: Some(DEFAULT_T), ..RunConfig::default() }, 1)
}

/// The run that `settings` describe, starting from the defaults. A bad key or value keeps its
/// default and is reported; if the values are each fine but not together (`RunConfig::validate`,
/// e.g. m below the 5 sequences SEC needs to act), every default is kept and that is reported.
pub fn from_settings(settings: &Settings) -> (RunConfig, u64, Vec<ConfigError>) {
    let (mut cfg, mut seed) = defaults();
    let mut errors = Vec::new();
    for (k, v) in settings {
        if let Err(e) = apply(&mut cfg, &mut seed, k, v) {
            errors.push(e);
        }
    }
    if let Err(e) = cfg.validate() {
        errors.push(e);
        (cfg, seed) = defaults();
    }
    (cfg, seed, errors)
}

/// The settings of the presets "code" (the authors' code, the default) and "paper" (the paper's
/// text: D2, D3 and the trained encoder, D20): only the keys they set.
pub fn preset(name: &str) -> Result<Settings, ConfigError> {
    let (agent, perception) = match name {
        "code" => (SecConfig::code(), PerceptionKind::Untrained),
        "paper" => (SecConfig::paper(), PerceptionKind::Trained),
        _ => return Err(ConfigError::new("preset", format!("'{name}' is not one of code, paper"))),
    };
    let cfg = RunConfig { perception, ..RunConfig::default() }.with_section(agent);
    let all = to_settings(&cfg, 1);
    let keys = ["perception", "embeddingScale", "alpha", "beta", "tau", "thetaAbs", "thetaProp"];
    Ok(keys.iter().map(|k| (k.to_string(), all[*k].clone())).collect())
}

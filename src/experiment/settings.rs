//! The page's settings: the flat keys of the URL hash and the controls (`alpha=0.01&m=500&...`),
//! each with its symbol, a one-line explanation and its range, and their mapping onto a
//! `RunConfig` and a seed. The page builds its controls from `params()`, so the ranges shown are
//! the ranges checked here.

use super::RunConfig;
use crate::agent::controller::Input;
use crate::agent::mfec::Embedding;
use crate::agent::section::SectionSetting;
use crate::agent::{AgentInfo, SecConfig};
use crate::arena::{ConfigError, StartHeading, DEFAULT_T, MAX_T, TASK_NAMES};
use crate::encoder::perception::SCALE_RANGE;
use crate::encoder::PerceptionKind;
use crate::param::{name_of, names};
pub use crate::param::{Kind, Param};
use crate::render::Surface;
use crate::util::shown;
use std::collections::BTreeMap;

/// Flat settings, key to value, as the URL hash holds them.
pub type Settings = BTreeMap<String, String>;

use crate::agent::mfec::MfecConfig;
use crate::seed::MAX_SEED;

/// The page's agents whose states come from the perception.
fn embedders() -> Vec<&'static str> {
    AgentInfo::keys_where(|a| a.reads == Input::Embedding && !a.native_only)
}

/// The agents the page offers (the table's, less the native-only ones).
pub fn page_agents() -> Vec<&'static str> {
    AgentInfo::keys_where(|a| !a.native_only)
}

/// One setting: what the page shows (`param`) and how it reads and writes a run's configuration
/// and seed. `set` receives the value `parse` checked: the number, the choice's index, 1/0 for a
/// switch, NaN for `auto`.
struct Setting {
    param: Param,
    get: Get,
    set: Set,
}

/// Reads a setting from a run's configuration and seed.
type Get = Box<dyn Fn(&RunConfig, u64) -> String>;
/// Writes a setting's checked value into a run's configuration and seed.
type Set = Box<dyn Fn(&mut RunConfig, &mut u64, f64)>;

fn agent_name(cfg: &RunConfig) -> &'static str {
    AgentInfo::of(cfg.kind, cfg.section::<MfecConfig>().embedding).key
}

/// Runs the agent of the table's row `key` (one of the page's).
fn set_agent(cfg: &mut RunConfig, key: &str) {
    let row = AgentInfo::find(key).expect("the page's choices are the table's keys");
    cfg.kind = row.kind;
    cfg.section_mut::<MfecConfig>().embedding = row.embedding.unwrap_or(Embedding::Autoencoder);
}

/// Every setting, each declared once, in the order the page shows them: the run's own (here),
/// with each agent's section's (declared by the agent, `AgentConfig::settings`) after the
/// perception's.
fn table() -> Vec<Setting> {
    let (mut rows, after) = run_settings();
    rows.extend(section_settings());
    rows.extend(after);
    rows
}

/// The rows of every agent's section, each applying to the page's agents that hold the section.
fn section_settings() -> Vec<Setting> {
    let mut rows = Vec::new();
    for spec in AgentInfo::sections() {
        let key = spec.key;
        let holds = |a: &&AgentInfo| !a.native_only && a.section.is_some_and(|s| s.key == key);
        let agents: Vec<&'static str> = crate::agent::AGENTS.iter().filter(holds).map(|a| a.key).collect();
        for SectionSetting { param, get, set } in (spec.settings)() {
            rows.push(Setting {
                param: param.agents(agents.clone()),
                get: Box::new(move |c, _| get(c.sections.get(key).expect("every section is held").as_any())),
                set: Box::new(move |c, _, v| {
                    set(c.sections.get_mut(key).expect("every section is held").as_any_mut(), v)
                }),
            });
        }
    }
    rows
}

/// The run's own settings, in the page's order: those shown before the agents' and those after.
#[rustfmt::skip]
fn run_settings() -> (Vec<Setting>, Vec<Setting>) {
    let before = vec![
        Setting {
            param: Param::choice("task", "task", "The arena the agent learns in (a new run).", &TASK_NAMES, false),
            get: Box::new(|c, _| c.task.clone()),
            set: Box::new(|c, _, v| c.task = TASK_NAMES[v as usize].to_string()),
        },
        Setting {
            param: Param::choice("agent", "agent", "Which agent learns: SEC or one of its rivals, each described in the agent list (a new run).", &page_agents(), false),
            get: Box::new(|c, _| agent_name(c).to_string()),
            set: Box::new(|c, _, v| set_agent(c, page_agents()[v as usize])),
        },
        Setting {
            param: Param::choice("perception", "encoder", "Which encoder embeds the camera image: untrained random weights (what the authors' code ran) or the trained one (the paper's text); the trained one always runs the gate (a new run).", &names(&PerceptionKind::ALL), false).group("perception").agents(embedders()),
            get: Box::new(|c, _| name_of(&PerceptionKind::ALL, c.perception)),
            set: Box::new(|c, _, v| c.perception = PerceptionKind::ALL[v as usize].1),
        },
        Setting {
            param: Param::choice("surface", "surface", "How the camera draws the floor and fences: flat colours, or v1's tiled floor and planked fences (textured); the gate uses the model trained on that surface's frames (a new run).", &names(&Surface::ALL), false).group("perception"),
            get: Box::new(|c, _| name_of(&Surface::ALL, c.surface)),
            set: Box::new(|c, _, v| c.surface = Surface::ALL[v as usize].1),
        },
        Setting {
            param: Param { key: "embeddingScale", symbol: "scale", help: "Multiplies every embedding, so it sets how alike two views must be to pass θ_abs; auto: 1 untrained, the calibrated scale trained (a new run).", kind: Kind::Number { min: SCALE_RANGE.0 as f64, max: SCALE_RANGE.1 as f64, min_open: true, step: 0.01, auto: true }, live: false, group: "perception", agents: embedders() },
            get: Box::new(|c, _| c.scale_override().map_or("auto".to_string(), |s| s.to_string())),
            set: Box::new(|c, _, v| {
                c.embedding_scale = (!v.is_nan()).then_some(v as f32);
                c.raw_embeddings = false;
            }),
        },
    ];
    let after = vec![
        Setting {
            param: Param::integer("t", "t", "Episode limit in env steps; every step costs 1/t (a new run).", (0, MAX_T as u64), false),
            get: Box::new(|c, _| c.t.unwrap_or(DEFAULT_T).to_string()),
            set: Box::new(|c, _, v| c.t = Some(v as u32)),
        },
        Setting {
            param: Param::choice("startHeading", "heading", "Where the double T-maze's agent starts looking: a new random heading every episode, or always facing the centre (a new run).", &names(&StartHeading::ALL), false),
            get: Box::new(|c, _| name_of(&StartHeading::ALL, c.start_heading)),
            set: Box::new(|c, _, v| c.start_heading = StartHeading::ALL[v as usize].1),
        },
        Setting {
            param: Param::integer("seed", "seed", "The run is a pure function of its settings and this seed (a new run).", (0, MAX_SEED), false),
            get: Box::new(|_, seed| seed.to_string()),
            set: Box::new(|_, seed, v| *seed = v as u64),
        },
    ];
    (before, after)
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

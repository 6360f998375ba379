//! What a run is, as data: `RunConfig`, its defaults, its one JSON parser and its range checks.
//! A run is a pure function of this and the seed; which changes act live is the settings'
//! (`settings`), and the run loop that plays it is `run`.

use crate::agent::section::{same_settings, Section, SectionSpec};
use crate::agent::{AgentInfo, AgentKind};
use crate::arena::{ConfigError, StartHeading, Task};
use crate::encoder::perception::check_scale;
use crate::encoder::PerceptionKind;
use crate::env::EnvConfig;
use crate::render::Surface;

/// What a run is: a pure function of this and the seed.
///
/// Its JSON is the run's fields with each agent's section under its key (`agent` for SEC's,
/// `mfec`, `dqn`, `erlam`), in the agent table's order. (The derives write the run's own
/// fields; the `Serialize` and `Deserialize` below add the sections, which the agents own.)
/// Two configurations are equal when every field and section is; `same_run` asks less.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(remote = "Self", rename_all = "camelCase", default, deny_unknown_fields)]
pub struct RunConfig {
    /// The task (`arena::TASK_NAMES`).
    pub task: String,
    /// Episode limit in env steps (`None`: the task's, 1000).
    pub t: Option<u32>,
    /// Env steps per decision; the action is held in between (D1).
    pub decision_period: u32,
    /// Which agent runs: SEC (NSEC is SEC without `sequentialBias`), MFEC or the reactive walk.
    pub kind: AgentKind,
    /// Every agent's parameters, one section per key of the agent table (`section`), so that
    /// switching agents keeps each one's settings; the run's agent reads its own.
    #[serde(flatten, skip_deserializing)]
    pub sections: Sections,
    /// Which encoder embeds the frames: `untrained` (the authors' code, D20) or `trained` (the
    /// paper's text). The trained model runs the reconstruction gate either way.
    pub perception: PerceptionKind,
    /// Replaces the embedding scale (`None`: the trained model's calibrated scale, or 1 for the
    /// untrained encoder); finite and > 0.
    pub embedding_scale: Option<f32>,
    /// Shorthand for `embeddingScale: 1`: the encoder's raw outputs (with `trained`, deviation
    /// D17 undone).
    pub raw_embeddings: bool,
    /// The start heading of layouts that leave it open (the double T-maze's corners, D11, D21):
    /// drawn at every reset, or fixed facing the arena's centre.
    pub start_heading: StartHeading,
    /// How the camera draws the floor and fences (docs/ARENAS.md section 4): `flat` or
    /// `textured`; the gate's trained model is the one trained on that surface's frames. Left out
    /// of the JSON when flat, so every configuration from before it has its old identity (the
    /// committed runs' manifests, memory files and checkpoints name it).
    #[serde(skip_serializing_if = "Surface::is_flat")]
    pub surface: Surface,
    /// An Animal-AI arena file (its YAML text) played instead of a preset task: one of the
    /// Olympics arenas (`assets/arenas/competition/`) or a user's own; `task` then names it (any
    /// name but a preset task's). No model was trained on its frames, so its runs embed with the
    /// untrained encoder and SEC runs without the reconstruction gate (`with_arena` sets both).
    /// Left out of the JSON when absent.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub arena: Option<String>,
}

impl Default for RunConfig {
    fn default() -> Self {
        RunConfig {
            task: "double-t-maze".into(),
            t: None,
            decision_period: 4,
            kind: AgentKind::Sec,
            sections: Sections::default(),
            perception: PerceptionKind::Untrained,
            embedding_scale: None,
            raw_embeddings: false,
            start_heading: StartHeading::Random,
            surface: Surface::Flat,
            arena: None,
        }
    }
}

impl RunConfig {
    /// Every field in its range, the error naming the parameter: what `Run::new` checks, without
    /// building a run.
    pub fn validate(&self) -> Result<(), ConfigError> {
        if !(1..=100).contains(&self.decision_period) {
            return Err(ConfigError::new(
                "decisionPeriod",
                format!("{} is out of range 1..=100", self.decision_period),
            ));
        }
        if self.arena.is_some() {
            self.check_arena_run()?;
        }
        EnvConfig { task: self.task()?, t: self.t, surface: self.surface }.validate()?;
        if let Some(s) = self.embedding_scale {
            check_scale(s)?;
            if self.raw_embeddings && s != 1.0 {
                return Err(ConfigError::new(
                    "rawEmbeddings",
                    format!("means embeddingScale 1, which contradicts embeddingScale {s}"),
                ));
            }
        }
        self.sections.0.iter().try_for_each(|(_, s)| s.validate())
    }

    /// A configuration from JSON text (an object; missing fields take the defaults), validated:
    /// the one parser of the page, Python and the CLI. A refused value is an error naming its
    /// field path (`agent.memory.tau`), or `config` for the text as a whole.
    pub fn from_json(text: &str) -> Result<RunConfig, ConfigError> {
        crate::util::check_text_size(text, "config").map_err(|e| ConfigError::new("config", e))?;
        // serde reads a struct from a JSON array too; a RunConfig is an object only.
        if !text.trim_start().starts_with('{') {
            return Err(ConfigError::new(
                "config",
                format!("{} is not an object (a RunConfig)", crate::util::shown(text)),
            ));
        }
        let value: serde_json::Value =
            serde_json::from_str(text).map_err(|e| ConfigError::new("config", e.to_string()))?;
        // The sections are read from the text itself, so that their errors say where they are.
        let cfg = RunConfig::read(value, |spec, _| (spec.parse_text)(spec.key, text))?;
        cfg.validate()?;
        Ok(cfg)
    }

    /// The embedding scale the run uses, if it overrides the perception's own.
    pub fn scale_override(&self) -> Option<f32> {
        self.embedding_scale.or(self.raw_embeddings.then_some(1.0))
    }

    /// The trained model of the run's reconstruction gate: the task's, trained on frames of the
    /// run's surface (`encoder::model_name`); `None` for an arena file, which has none.
    pub fn gate_model(&self) -> Option<String> {
        self.arena.is_none().then(|| crate::encoder::model_name(&self.task, self.surface))
    }

    /// The task with the start heading applied: the preset `task`, or the arena file's.
    pub fn task(&self) -> Result<Task, ConfigError> {
        let task = match &self.arena {
            None => Task::preset(&self.task)?,
            Some(yaml) => arena_task(&self.task, yaml)?,
        };
        Ok(task.with_start_heading(self.start_heading))
    }

    /// This configuration playing the arena file `yaml` named `name` (see `arena`): with the
    /// untrained encoder and SEC's gate off, which an arena without a trained model needs, and
    /// the file's own episode limits (`t` None: each of its arenas has its own). Checked like any
    /// configuration.
    pub fn with_arena(mut self, name: &str, yaml: &str) -> Result<RunConfig, ConfigError> {
        self.task = name.to_string();
        self.arena = Some(yaml.to_string());
        self.t = None;
        self.perception = PerceptionKind::Untrained;
        self.section_mut::<crate::agent::SecConfig>().gate = None;
        self.validate()?;
        Ok(self)
    }

    /// What an arena file's run needs besides a valid file: a name that is not a preset's, and
    /// no part that needs a model trained on the arena.
    fn check_arena_run(&self) -> Result<(), ConfigError> {
        let name = self.task.trim();
        if name.is_empty() || name.len() > MAX_ARENA_NAME || name != self.task {
            return Err(ConfigError::new(
                "task",
                format!(
                    "'{}' cannot name an arena file: 1 to {MAX_ARENA_NAME} bytes, no spaces at its ends",
                    crate::util::shown(&self.task)
                ),
            ));
        }
        if crate::arena::TASK_NAMES.contains(&name) {
            return Err(ConfigError::new(
                "task",
                format!("'{name}' is a preset task; a run of an arena file names the file's arena instead"),
            ));
        }
        if self.perception == PerceptionKind::Trained {
            return Err(ConfigError::new(
                "perception",
                "'trained' needs a model trained on the arena; an arena file has none: use 'untrained'",
            ));
        }
        let gate = self.section::<crate::agent::SecConfig>().gate;
        if let (true, Some(g)) = (self.agent_row().has_gate, gate) {
            return Err(ConfigError::new(
                "agent.gate",
                format!("{g} needs the arena's trained model, and an arena file has none: set it to null (off)"),
            ));
        }
        Ok(())
    }

    /// A configuration from its JSON value, not yet validated: each agent's section is read by
    /// its row's parser, the run's own fields by the derived reader. A refused value is an error
    /// naming its field path (`agent.memory.tau`).
    pub fn from_value(value: serde_json::Value) -> Result<RunConfig, ConfigError> {
        RunConfig::read(value, |spec, v| (spec.parse)(spec.key, v))
    }

    /// `from_value`, each section present read by `section` (from its value, or otherwise).
    fn read(
        value: serde_json::Value,
        section: impl Fn(SectionSpec, serde_json::Value) -> Result<Box<dyn Section>, ConfigError>,
    ) -> Result<RunConfig, ConfigError> {
        let serde_json::Value::Object(mut map) = value else {
            return Err(ConfigError::new("config", "is not an object (a RunConfig)"));
        };
        let mut sections = Sections::default();
        for spec in AgentInfo::sections() {
            if let Some(v) = map.remove(spec.key) {
                let held = sections.0.iter_mut().find(|(k, _)| *k == spec.key).expect("every row's section is held");
                held.1 = section(spec, v)?;
            }
        }
        let fields: RunFields = serde_path_to_error::deserialize(serde_json::Value::Object(map)).map_err(|e| {
            let path = e.path().to_string();
            ConfigError::new(if path == "." { "config".to_string() } else { path }, e.inner().to_string())
        })?;
        Ok(RunConfig { sections, ..fields.0 })
    }

    /// The agent section of type `T` (SEC's `SecConfig`, MFEC's `MfecConfig`, ...).
    ///
    /// Panics if no agent of the table has a section of that type: a section is its agent's
    /// type, so asking for another is a mistake in the code, not in the configuration.
    pub fn section<T: Section>(&self) -> &T {
        self.sections.0.iter().find_map(|(_, s)| s.as_any().downcast_ref()).unwrap_or_else(|| no_section::<T>())
    }

    /// The agent section of type `T`, to change (see `section`).
    pub fn section_mut<T: Section>(&mut self) -> &mut T {
        self.sections.0.iter_mut().find_map(|(_, s)| s.as_any_mut().downcast_mut()).unwrap_or_else(|| no_section::<T>())
    }

    /// `self` with the agent section of `section`'s type replaced.
    pub fn with_section<T: Section>(mut self, section: T) -> RunConfig {
        *self.section_mut::<T>() = section;
        self
    }

    /// The keys of the sections the run reads: its agent's own; in a native agent's run, every
    /// native agent's (ERLAM's network is DQN's).
    fn read_keys(&self) -> Vec<&'static str> {
        let row = self.agent_row();
        if row.native_only {
            AgentInfo::native_section_keys()
        } else {
            row.section.map(|s| s.key).into_iter().collect()
        }
    }

    /// The table's row of the run's agent.
    pub fn agent_row(&self) -> &'static AgentInfo {
        AgentInfo::of(self.kind, self.section::<crate::agent::mfec::MfecConfig>().embedding)
    }

    /// The configuration section of the run's agent (the one its table row names; `()` for an
    /// agent without one), as its builder and a live change hand it to the agent.
    pub fn agent_section(&self) -> &dyn std::any::Any {
        match self.agent_row().section {
            Some(spec) => self.sections.get(spec.key).expect("every row's section is held").as_any(),
            None => &(),
        }
    }
}

impl PartialEq for RunConfig {
    /// The same configuration: every field and every agent's section (a native one held opaque
    /// here and typed there compares through its registered type, `same_settings`).
    fn eq(&self, other: &Self) -> bool {
        self.same_fields(other) && self.same_sections(other, &self.sections.keys())
    }
}

impl RunConfig {
    /// Whether `other` makes the same run: the run's fields and the sections its agent reads
    /// agree (the other agents' sections, which a configuration keeps so that switching agents
    /// keeps each one's settings, do not change the run). What the runner compares a result's
    /// configuration with, so a configuration written by a build that holds a native agent's
    /// crate (the CLI) matches one read by a build that does not (Python) and the other way round.
    pub fn same_run(&self, other: &RunConfig) -> bool {
        self.same_fields(other) && self.same_sections(other, &self.read_keys())
    }

    fn same_fields(&self, other: &RunConfig) -> bool {
        let fields = |c: &RunConfig| {
            let bare = RunConfig { sections: Sections(Vec::new()), ..c.clone() };
            RunConfig::serialize(&bare, serde_json::value::Serializer).expect("configurations serialise")
        };
        fields(self) == fields(other)
    }

    fn same_sections(&self, other: &RunConfig, keys: &[&str]) -> bool {
        keys.iter().all(|&key| match (self.sections.get(key), other.sections.get(key)) {
            (Some(a), Some(b)) => same_settings(key, a, b),
            (a, b) => a.is_none() && b.is_none(),
        })
    }
}

/// The longest name of an arena file's run (its memory files and the page show it).
pub const MAX_ARENA_NAME: usize = 200;

/// The task of an arena file, a file error reported under `arena`.
#[cfg(any(not(target_arch = "wasm32"), feature = "yaml-arenas"))]
fn arena_task(name: &str, yaml: &str) -> Result<Task, ConfigError> {
    crate::arena::yaml::load_task(name, yaml).map_err(|e| ConfigError {
        line: e.line,
        field: if e.field == "arena" { e.field } else { format!("arena.{}", e.field) },
        message: e.message,
    })
}

/// Without the YAML parser (the page's playground builds leave it out: 41 KB gzipped), an arena
/// file is refused, naming the build that reads it.
#[cfg(not(any(not(target_arch = "wasm32"), feature = "yaml-arenas")))]
fn arena_task(_name: &str, _yaml: &str) -> Result<Task, ConfigError> {
    Err(ConfigError::new("arena", "this build reads no arena files: the arena build (pkg/arena/) does"))
}

fn no_section<T>() -> ! {
    panic!("no agent of the table has a section of type {}", std::any::type_name::<T>())
}

/// Every agent's configuration section, one per key of the agent table, in the table's order
/// (the order the JSON writes them).
#[derive(Clone, Debug, PartialEq)]
pub struct Sections(Vec<(&'static str, Box<dyn Section>)>);

impl Default for Sections {
    fn default() -> Self {
        Sections(AgentInfo::sections().map(|s| (s.key, (s.default)())).collect())
    }
}

impl Sections {
    /// The section under `key`.
    pub fn get(&self, key: &str) -> Option<&dyn Section> {
        self.0.iter().find(|(k, _)| *k == key).map(|(_, s)| s.as_ref())
    }

    /// The keys of the sections held, in the table's order.
    pub fn keys(&self) -> Vec<&'static str> {
        self.0.iter().map(|(k, _)| *k).collect()
    }

    /// The section under `key`, to change.
    pub fn get_mut(&mut self, key: &str) -> Option<&mut dyn Section> {
        self.0.iter_mut().find(|(k, _)| *k == key).map(|(_, s)| s.as_mut())
    }

    /// Sets `field` of the section under `key` to `value`, as the JSON writes them, without
    /// naming the section's type (an experiment's preset of a native agent): read back through
    /// the section's parser and checked, or an error naming the field, the section as it was.
    pub fn set_field(&mut self, key: &str, field: &str, value: serde_json::Value) -> Result<(), ConfigError> {
        let spec = AgentInfo::sections()
            .find(|s| s.key == key)
            .ok_or_else(|| ConfigError::new(key, "is no agent's section"))?;
        let held = self.0.iter_mut().find(|(k, _)| *k == key).expect("every row's section is held");
        let mut object = match held.1.to_value() {
            serde_json::Value::Object(o) => o,
            _ => serde_json::Map::new(),
        };
        object.insert(field.to_string(), value);
        let section = (spec.parse)(spec.key, serde_json::Value::Object(object))?;
        section.validate()?;
        held.1 = section;
        Ok(())
    }
}

impl serde::Serialize for Sections {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        // A native agent's section that this build does not know and no one wrote is left out.
        let written: Vec<_> = self.0.iter().filter(|(_, section)| section.written()).collect();
        let mut map = s.serialize_map(Some(written.len()))?;
        for (key, section) in written {
            map.serialize_entry(key, section.as_ref())?;
        }
        map.end()
    }
}

impl serde::Serialize for RunConfig {
    /// The run's fields and the sections of the agents the core runs (kept, so that switching
    /// agents keeps each one's settings); the native agents' sections only in their own runs,
    /// so a run is written the same by a build that holds their crate (the CLI) and one that
    /// does not (Python).
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        if self.agent_row().native_only {
            return RunConfig::serialize(self, s);
        }
        let native = AgentInfo::native_section_keys();
        let sections = Sections(self.sections.0.iter().filter(|(k, _)| !native.contains(k)).cloned().collect());
        RunConfig::serialize(&RunConfig { sections, ..self.clone() }, s)
    }
}

impl<'de> serde::Deserialize<'de> for RunConfig {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let value = <serde_json::Value as serde::Deserialize>::deserialize(d)?;
        RunConfig::from_value(value).map_err(serde::de::Error::custom)
    }
}

/// The run's own fields, read by the derived reader (`RunConfig::deserialize`, inherent: serde's
/// `remote = "Self"`), which leaves the sections at their defaults.
struct RunFields(RunConfig);

impl<'de> serde::Deserialize<'de> for RunFields {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        RunConfig::deserialize(d).map(RunFields)
    }
}

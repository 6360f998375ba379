//! What a run is, as data: `RunConfig`, its defaults, its one JSON parser and its range checks.
//! A run is a pure function of this and the seed; which changes act live is the settings'
//! (`settings`), and the run loop that plays it is `run`.

use crate::agent::dqn::{DqnConfig, ErlamConfig};
use crate::agent::mfec::MfecConfig;
use crate::agent::{AgentInfo, AgentKind, SecConfig};
use crate::arena::{ConfigError, StartHeading, Task};
use crate::encoder::perception::check_scale;
use crate::encoder::PerceptionKind;
use crate::env::EnvConfig;
use crate::render::Surface;

/// What a run is: a pure function of this and the seed.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase", default, deny_unknown_fields)]
pub struct RunConfig {
    /// The task (`arena::TASK_NAMES`).
    pub task: String,
    /// Episode limit in env steps (`None`: the task's, 1000).
    pub t: Option<u32>,
    /// Env steps per decision; the action is held in between (D1).
    pub decision_period: u32,
    /// Which agent runs: SEC (NSEC is SEC without `sequentialBias`), MFEC or the reactive walk.
    pub kind: AgentKind,
    /// SEC's parameters (used when `kind` is sec).
    pub agent: SecConfig,
    /// MFEC's parameters (used when `kind` is mfec).
    pub mfec: MfecConfig,
    /// DQN's parameters (used when `kind` is dqn or erlam; the agents run natively,
    /// `crates/sec-dqn`).
    pub dqn: DqnConfig,
    /// ERLAM's associative memory (used when `kind` is erlam).
    pub erlam: ErlamConfig,
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
}

impl Default for RunConfig {
    fn default() -> Self {
        RunConfig {
            task: "double-t-maze".into(),
            t: None,
            decision_period: 4,
            kind: AgentKind::Sec,
            agent: SecConfig::default(),
            mfec: MfecConfig::default(),
            dqn: DqnConfig::default(),
            erlam: ErlamConfig::default(),
            perception: PerceptionKind::Untrained,
            embedding_scale: None,
            raw_embeddings: false,
            start_heading: StartHeading::Random,
            surface: Surface::Flat,
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
        EnvConfig { task: Task::preset(&self.task)?, t: self.t, surface: self.surface }.validate()?;
        if let Some(s) = self.embedding_scale {
            check_scale(s)?;
            if self.raw_embeddings && s != 1.0 {
                return Err(ConfigError::new(
                    "rawEmbeddings",
                    format!("means embeddingScale 1, which contradicts embeddingScale {s}"),
                ));
            }
        }
        self.agent.validate()?;
        self.mfec.validate()?;
        self.dqn.validate()?;
        self.erlam.validate()
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
        let mut de = serde_json::Deserializer::from_str(text);
        let cfg: RunConfig = serde_path_to_error::deserialize(&mut de).map_err(|e| {
            let path = e.path().to_string();
            ConfigError::new(if path == "." { "config".to_string() } else { path }, e.inner().to_string())
        })?;
        de.end().map_err(|e| ConfigError::new("config", e.to_string()))?;
        cfg.validate()?;
        Ok(cfg)
    }

    /// The embedding scale the run uses, if it overrides the perception's own.
    pub fn scale_override(&self) -> Option<f32> {
        self.embedding_scale.or(self.raw_embeddings.then_some(1.0))
    }

    /// The trained model of the run's reconstruction gate: the task's, trained on frames of the
    /// run's surface (`encoder::model_name`).
    pub fn gate_model(&self) -> String {
        crate::encoder::model_name(&self.task, self.surface)
    }

    /// The task with the start heading applied.
    pub fn task(&self) -> Result<Task, ConfigError> {
        Ok(Task::preset(&self.task)?.with_start_heading(self.start_heading))
    }

    /// The configuration section of the run's agent (the one its table row names; `()` for an
    /// agent without one), as its builder and a live change hand it to the agent.
    pub fn section(&self) -> &dyn std::any::Any {
        match AgentInfo::of(self.kind, self.mfec.embedding).section {
            Some("agent") => &self.agent,
            Some("mfec") => &self.mfec,
            Some("dqn") => &self.dqn,
            Some("erlam") => &self.erlam,
            _ => &(),
        }
    }
}

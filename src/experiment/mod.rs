//! A run of SEC, or of a baseline (MFEC, the reactive walk), in a task (docs/ALGORITHM.md, "The
//! run loop"): the environment, the perception, the reconstruction gate and the agent, one env
//! step at a time with a decision every 4, and the per-episode metrics the paper's tables count,
//! one JSON line per episode.

use crate::agent::controller::{AgentSettings, AgentView, Controller, EpisodeEnd, Input, Observation, Step};
use crate::agent::dqn::{DqnConfig, ErlamConfig};
use crate::agent::mfec::MfecConfig;
pub use crate::agent::AgentKind;
use crate::agent::{AgentInfo, Decision, Layer, SecConfig};
use crate::arena::{Action, ConfigError, Env, EnvConfig, StartHeading, StepOutcome, Task};
use crate::encoder::perception::check_scale;
use crate::encoder::{
    cache, Autoencoder, FrameCache, Perception, PerceptionKind, ReconstructionGate, Scratch, EMBEDDING, IMAGE,
};
use crate::error::Error;
use crate::memory;
use crate::render::{Frame, Surface};
use crate::seed::{self, Stream};
pub mod change;
pub mod checkpoint;
#[cfg(feature = "test-hooks")]
pub mod fixtures;
pub mod metrics;
pub mod presets;
pub mod settings;
pub mod trace;

pub use metrics::{EpisodeMetrics, EpisodeState};

use rand_chacha::ChaCha8Rng;

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

    /// The agents' sections, as a live change hands them to the running agent.
    pub fn agent_settings(&self) -> AgentSettings<'_> {
        AgentSettings { sec: &self.agent, mfec: &self.mfec, dqn: &self.dqn, erlam: &self.erlam }
    }

    /// Whether going from `self` to `next` needs a new run: everything but SEC's parameters
    /// (and among them the STM length n) is fixed for a run.
    pub fn needs_restart(&self, next: &RunConfig) -> bool {
        let same_but_agent = RunConfig { agent: self.agent.clone(), ..next.clone() } == *self;
        !same_but_agent || next.agent.memory.n != self.agent.memory.n
    }
}

/// Builds the agents the core does not hold itself (DQN, trained with burn in `crates/sec-dqn`,
/// which the wasm build leaves out), given the run's perception (ERLAM embeds with it): `None`
/// for a kind it does not know either.
pub type AgentFactory =
    fn(&RunConfig, &Perception, u64, &mut ChaCha8Rng) -> Option<Result<Box<dyn Controller>, ConfigError>>;

/// The run's agent, drawing its initial state from the agent stream `rng`: the agent table's
/// row builds it, or `extra` for the agents a native crate holds.
fn controller(
    cfg: &RunConfig,
    perception: &Perception,
    seed: u64,
    rng: &mut ChaCha8Rng,
    extra: Option<AgentFactory>,
) -> Result<Box<dyn Controller>, ConfigError> {
    if let Some(made) = extra.and_then(|f| f(cfg, perception, seed, rng)) {
        return made;
    }
    let row = AgentInfo::of(cfg.kind, cfg.mfec.embedding);
    match row.build {
        Some(build) => build(cfg, perception, seed, rng),
        None => Err(ConfigError::new(
            "kind",
            format!(
                "{} is trained with burn and runs only natively, through sec-experiment (not in this build)",
                row.key
            ),
        )),
    }
}

/// A run in progress: an agent learning a task, a pure function of its configuration and seed.
///
/// ```
/// use sec_playground::experiment::{Run, RunConfig};
/// let cfg = RunConfig { task: "object-permanence".into(), t: Some(100), ..RunConfig::default() };
/// let mut run = Run::new(cfg.clone(), 1)?;
/// let first = run.episode(); // the metrics of the runner's JSON lines
/// assert_eq!(first.episode, 0);
/// assert_eq!(first.reward, first.raw_reward.max(0.0));
/// assert_eq!(Run::new(cfg, 1)?.episode(), first, "the same configuration and seed, the same run");
/// # Ok::<(), sec_playground::error::Error>(())
/// ```
pub struct Run {
    cfg: RunConfig,
    seed: u64,
    env: Env,
    perception: Perception,
    scratch: Scratch,
    image: Vec<f32>,
    /// What the encoders made of frames seen before in this run, and the current frame's entry.
    cache: FrameCache,
    slot: Option<cache::Slot>,
    /// The env's view serials that `image` and `slot` are of.
    seen: Seen,
    gate: ReconstructionGate,
    controller: Box<dyn Controller>,
    /// SEC's events, when recorded (see `trace`).
    events: Option<Vec<trace::Event>>,
    /// The agent's draws; the environment has its own stream of the same seed.
    rng: ChaCha8Rng,
    /// The episode in progress (`None` between episodes).
    current: Option<Episode>,
    /// A person at the controls, if any.
    driver: Option<Driver>,
    /// FNV-1a 64 of the episode log so far (each episode's `EpisodeMetrics::to_json` and a
    /// newline, as the runner writes it): a checkpoint carries it, so a resume can tell whether
    /// a log's head is the one the checkpoint continues.
    log_digest: u64,
}

/// Which views (`Env::view_serial`) a run's image and cache entry hold.
#[derive(Clone, Copy, Debug, Default)]
struct Seen {
    image: Option<u64>,
    slot: Option<u64>,
}

/// The episode in progress: its metrics so far and where the loop stands.
struct Episode {
    metrics: EpisodeState,
    /// The env step taken but not yet processed by `tick`.
    out: StepOutcome,
    /// Env steps processed (the first, the no-op after the reset, is step 0).
    step: u32,
    /// The action held until the next decision.
    action: Action,
}

/// A person driving the agent (the page's arrow keys): the action held from the next decision
/// on. With `record` (SEC only) the decisions go through the agent's memory with the person's
/// actions, so a rewarded episode is stored in the LTM like any other; without it the agent
/// neither sees nor learns from them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Driver {
    /// The action held.
    pub action: Action,
    /// Whether the agent learns from the person's decisions.
    pub record: bool,
}

impl Run {
    /// A run of `cfg` with `seed`: refused when `cfg` is out of range, or when the task's
    /// trained model (the gate's) cannot be had.
    pub fn new(cfg: RunConfig, seed: u64) -> Result<Self, Error> {
        Self::with_agents(cfg, seed, None)
    }

    /// `new`, with `extra` building the agents the core does not hold (DQN).
    pub fn with_agents(cfg: RunConfig, seed: u64, extra: Option<AgentFactory>) -> Result<Self, Error> {
        cfg.validate()?;
        let task = cfg.task()?;
        let perception = Perception::new(cfg.perception, &cfg.gate_model(), cfg.scale_override(), seed)?;
        let env = Env::new(EnvConfig { task, t: cfg.t, surface: cfg.surface }, seed)?;
        let mut rng = seed::rng(seed, Stream::Agent);
        let controller = controller(&cfg, &perception, seed, &mut rng, extra)?;
        Ok(Run {
            cfg,
            seed,
            env,
            perception,
            scratch: Scratch::default(),
            image: vec![0.0; IMAGE],
            cache: FrameCache::new(),
            slot: None,
            seen: Seen::default(),
            gate: ReconstructionGate::new(),
            controller,
            events: None,
            rng,
            current: None,
            driver: None,
            log_digest: crate::util::FNV_OFFSET,
        })
    }

    /// The configuration in force.
    pub fn config(&self) -> &RunConfig {
        &self.cfg
    }

    /// The run's seed.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// Applies `cfg` mid-run (the page's live controls): SEC's parameters act from the next
    /// decision (see `Memory::reconfigure`). Returns `Ok(false)` and changes nothing when the
    /// change needs a new run (`RunConfig::needs_restart`); an invalid `cfg` is an error and
    /// changes nothing either.
    pub fn reconfigure(&mut self, cfg: RunConfig) -> Result<bool, ConfigError> {
        cfg.validate()?;
        if self.cfg.needs_restart(&cfg) {
            return Ok(false);
        }
        self.controller.reconfigure(&cfg.agent_settings())?;
        self.cfg = cfg;
        Ok(true)
    }

    /// The agent, through its hooks.
    pub fn controller(&self) -> &dyn Controller {
        self.controller.as_ref()
    }

    /// What the agent shows of itself (its memory, its last embedding), read-only.
    pub fn inspect(&self) -> AgentView<'_> {
        self.controller.inspect()
    }

    /// The environment.
    pub fn env(&self) -> &Env {
        &self.env
    }

    /// What the agent sees now (rendered on demand; rendering changes nothing in the run).
    pub fn observation(&mut self) -> &Frame {
        self.env.observation()
    }

    /// The task's trained autoencoder: the reconstruction gate's model and the page's
    /// reconstruction view.
    pub fn encoder(&self) -> &Autoencoder {
        self.perception.trained()
    }

    /// What the encoders made of the frames seen so far (a memo: see `encoder::cache`).
    pub fn frame_cache(&self) -> &FrameCache {
        &self.cache
    }

    /// Where the run's embeddings come from.
    pub fn perception(&self) -> &Perception {
        &self.perception
    }

    /// The reconstruction error the gate measured last (`None` before its first measurement,
    /// and always for an agent without the gate).
    pub fn gate_mse(&mut self) -> Option<f32> {
        self.gate.has_measured().then(|| self.gate.mse(self.perception.trained(), &mut self.scratch, &mut self.cache))
    }

    /// A person takes (`Some`) or gives back (`None`) the controls; see `Driver`.
    pub fn set_driver(&mut self, driver: Option<Driver>) {
        self.driver = driver;
    }

    /// Who drives, if a person does.
    pub fn driver(&self) -> Option<Driver> {
        self.driver
    }

    /// Whether the controller sees this decision: always unless a person drives without
    /// recording (or records for an agent that does not learn from a person).
    fn controller_sees(&self) -> bool {
        match self.driver {
            None => true,
            Some(d) => d.record && self.controller.learns_from_person(),
        }
    }

    /// What this run's embeddings mean, for memory files.
    fn identity(&self) -> memory::file::Identity {
        memory::file::Identity { task: self.cfg.task.clone(), model: self.perception.embedder().fingerprint() }
    }

    /// The agent's memory (SEC's STM and LTM) as a file (`memory::file`).
    pub fn save_memory(&self) -> Result<Vec<u8>, ConfigError> {
        self.controller.save_memory(&self.identity())
    }

    /// Replaces the agent's memory with a file's; a corrupt, foreign or mismatched file is
    /// refused and the memory is left as it was. Returns the number of sequences loaded.
    pub fn load_memory(&mut self, bytes: &[u8]) -> Result<usize, Error> {
        let id = self.identity();
        self.controller.load_memory(bytes, &id)
    }

    /// Starts recording SEC's events (embeddings with the gate's MSE, goals, episode ends): fed
    /// to `trace::trace` with the run's seed they give the run's actions again. A run of
    /// another agent records the perception line only.
    pub fn record_events(&mut self) {
        if self.events.is_none() {
            let (perception, embedding_scale) = (self.perception.kind(), self.perception.embedder().embedding_scale);
            self.events = Some(vec![trace::Event::Perception { perception, embedding_scale }]);
        }
    }

    /// The events recorded since the last call.
    pub fn take_events(&mut self) -> Vec<trace::Event> {
        self.events.as_mut().map(std::mem::take).unwrap_or_default()
    }

    /// The event log, if recording and the agent's decisions replay from it.
    fn sec_events(&mut self) -> Option<&mut Vec<trace::Event>> {
        self.events.as_mut().filter(|_| self.controller.traces())
    }

    /// The decision at the current frame (its image is already in `self.image`): the embedding
    /// the controller reads, then its decision, or the person's when it does not see this one.
    fn decide(&mut self, terminal: bool) -> Decision {
        if let Some(d) = self.driver.filter(|_| !self.controller_sees()) {
            return Decision { action: d.action, layer: Layer::Human, selected: false };
        }
        let mut e = [0.0; EMBEDDING];
        if self.controller.input() == Input::Embedding {
            let (perception, image, scratch) = (&self.perception, &self.image, &mut self.scratch);
            self.cache.embedding(self.slot, &mut e, |e| perception.embed(image, scratch, e));
            if self.perception.embeds_with_gate_model() {
                self.gate.share_embedding(&e);
            }
        }
        if self.sec_events().is_some() {
            let rec_mse = self.gate.mse(self.perception.trained(), &mut self.scratch, &mut self.cache);
            let ev = self.sec_events().expect("checked above");
            ev.push(trace::Event::Decision { embedding: e.to_vec(), rec_mse });
        }
        let obs = Observation { embedding: &e, image: &self.image, terminal, person: self.driver.map(|d| d.action) };
        let (gate, encoder, scratch, cache) =
            (&mut self.gate, self.perception.trained(), &mut self.scratch, &mut self.cache);
        self.controller.decide(&obs, &mut || gate.mse(encoder, scratch, cache), &mut self.rng)
    }

    /// The current frame into `image`, unless it holds that view already (the agent against a
    /// wall): then the frame is neither rendered nor converted again.
    fn see(&mut self) {
        let serial = self.env.view_serial();
        if self.seen.image != Some(serial) || !crate::reuse::on() {
            self.env.observation().to_rgb_f32(&mut self.image);
            self.seen.image = Some(serial);
        }
    }

    /// `see`, and the frame's cache entry into `slot`: the same view as at the last lookup takes
    /// the same entry without hashing the frame.
    fn look(&mut self) {
        self.see();
        let serial = self.seen.image;
        let same = self.seen.slot == serial && crate::reuse::on();
        let again = self.slot.filter(|_| same).and_then(|s| self.cache.refind(s));
        self.slot = again.or_else(|| self.cache.find(self.env.observation()));
        self.seen.slot = serial;
    }

    /// Plays one episode to its end and starts the next.
    pub fn episode(&mut self) -> EpisodeMetrics {
        loop {
            if let Some(m) = self.tick().finished {
                return m;
            }
        }
    }

    /// Plays until the next decision (returned with the episode it ended, if any): the page's
    /// "step one decision". The first tick of an episode decides, so this is at most `period` ticks.
    pub fn decision(&mut self) -> Tick {
        loop {
            let t = self.tick();
            if t.decision.is_some() || t.finished.is_some() {
                return t;
            }
        }
    }

    /// The episode in progress, if one has started.
    pub fn current(&self) -> Option<&EpisodeState> {
        self.current.as_ref().map(|ep| &ep.metrics)
    }

    /// One env step of the run loop (docs/ALGORITHM.md): the reward of the step just taken, the
    /// controller told of it (SEC stores on the goal event), the gate, the decision every
    /// `decisionPeriod` steps; then the next env step, or the episode's end (its metrics) and the
    /// reset for the next one. `episode` is built on this, so stepping by ticks, decisions or
    /// episodes gives the same run.
    pub fn tick(&mut self) -> Tick {
        let mut ep = match self.current.take() {
            Some(ep) => ep,
            None => {
                let metrics = EpisodeState::new(self.env.episode(), self.env.layout_name().to_string());
                // As the authors' loop: the first observation comes from a no-op step after the reset.
                let out = self.env.advance(Action::NOOP, 1).expect("a fresh episode takes a step");
                Episode { metrics, out, step: 0, action: Action::NOOP }
            }
        };
        let out = ep.out;
        ep.metrics.reward += out.reward;
        let decides = ep.step % self.cfg.decision_period == 0;
        let goal_event = out.good_goal && ep.metrics.reward > 0.0;
        ep.metrics.goal |= goal_event;
        if self.controller_sees() {
            let step = Step {
                reward: out.reward,
                episode_reward: ep.metrics.reward,
                good_goal: out.good_goal,
                goal_event,
                decides,
                done: self.env.is_over(),
            };
            let wants = self.controller.wants_frame(&step);
            if wants {
                self.see();
            }
            let frame = wants.then_some(self.image.as_slice());
            if self.controller.on_step(&step, frame, &mut self.rng) {
                let reward = ep.metrics.reward;
                if let Some(ev) = self.sec_events() {
                    ev.push(trace::Event::Goal { reward });
                }
            }
        }
        let uses_gate = self.controller.uses_gate();
        if self.controller.input() != Input::Nothing && (decides || (uses_gate && self.gate.due())) {
            self.look();
        }
        if uses_gate {
            self.gate.watch(&self.image, self.slot);
        }
        let mut decision = None;
        if decides {
            let d = self.decide(self.env.is_over());
            ep.action = d.action;
            ep.metrics.record(&d, self.controller.entropy());
            decision = Some(d);
        }
        if !self.env.is_over() {
            ep.out = self.env.advance(ep.action, 1).expect("the episode is not over");
            ep.step += 1;
            self.current = Some(ep);
            return Tick { decision, finished: None };
        }
        let end = EpisodeEnd { goal: ep.metrics.goal, driven: ep.metrics.human > 0 };
        self.controller.on_episode_end(&end);
        if let Some(ev) = self.sec_events() {
            ev.push(trace::Event::EpisodeEnd);
        }
        let mut metrics = ep.metrics.finish(self.env.steps(), self.controller.memory_use().used);
        metrics.census = self.controller.census();
        self.log_digest = checkpoint::extend_log(self.log_digest, &metrics.to_json());
        self.env.reset(None);
        Tick { decision, finished: Some(metrics) }
    }
}

/// What one `Run::tick` did.
#[derive(Clone, Debug, PartialEq)]
pub struct Tick {
    /// The decision taken at this env step, if one was due.
    pub decision: Option<Decision>,
    /// The metrics of the episode this tick ended.
    pub finished: Option<EpisodeMetrics>,
}

//! The run loop (docs/ALGORITHM.md, "The run loop"): the environment, the perception, the
//! reconstruction gate and the agent, one env step at a time with a decision every 4, and the
//! per-episode metrics the paper's tables count, one JSON line per episode.

use super::metrics::{self, EpisodeMetrics, EpisodeState};
use super::{trace, RunConfig};
use crate::agent::controller::{AgentView, Controller, EpisodeEnd, Input, Observation, Step};
use crate::agent::{AgentInfo, Decision, Layer};
use crate::arena::{Action, ConfigError};
use crate::encoder::{cache, Autoencoder, FrameCache, Perception, ReconstructionGate, Scratch, EMBEDDING, IMAGE};
use crate::env::{Env, EnvConfig, StepOutcome};
use crate::error::Error;
use crate::memory;
use crate::render::Frame;
use crate::seed::{self, Stream};
use rand_chacha::ChaCha8Rng;

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
    let row = cfg.agent_row();
    match row.build {
        Some(build) => build(cfg.agent_section(), perception, seed, rng),
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
    pub(super) cfg: RunConfig,
    pub(super) seed: u64,
    pub(super) env: Env,
    pub(super) perception: Perception,
    pub(super) scratch: Scratch,
    pub(super) image: Vec<f32>,
    /// What the encoders made of frames seen before in this run, and the current frame's entry.
    pub(super) cache: FrameCache,
    pub(super) slot: Option<cache::Slot>,
    /// The env's view serials that `image` and `slot` are of.
    pub(super) seen: Seen,
    pub(super) gate: ReconstructionGate,
    /// The agent's table row: what it reads, whether it has a gate, whether it can be driven.
    pub(super) agent: &'static AgentInfo,
    pub(super) controller: Box<dyn Controller>,
    /// SEC's events, when recorded (see `trace`).
    pub(super) events: Option<Vec<trace::Event>>,
    /// The agent's draws; the environment has its own stream of the same seed.
    pub(super) rng: ChaCha8Rng,
    /// The episode in progress (`None` between episodes).
    pub(super) current: Option<Episode>,
    /// A person at the controls, if any.
    pub(super) driver: Option<Driver>,
    /// FNV-1a 64 of the episode log so far (each episode's `EpisodeMetrics::to_json` and a
    /// newline, as the runner writes it): a checkpoint carries it, so a resume can tell whether
    /// a log's head is the one the checkpoint continues.
    pub(super) log_digest: u64,
}

/// Which views (`Env::view_serial`) a run's image and cache entry hold.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Seen {
    image: Option<u64>,
    slot: Option<u64>,
}

/// The episode in progress: its metrics so far and where the loop stands.
pub(super) struct Episode {
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
        let perception = match cfg.gate_model() {
            Some(model) => Perception::new(cfg.perception, &model, cfg.scale_override(), seed)?,
            None => Perception::without_model(&cfg.task, cfg.scale_override(), seed)?,
        };
        let env = Env::new(EnvConfig { task, t: cfg.t, surface: cfg.surface }, seed)?;
        let mut rng = seed::rng(seed, Stream::Agent);
        let controller = controller(&cfg, &perception, seed, &mut rng, extra)?;
        let agent = cfg.agent_row();
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
            agent,
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
        self.controller.reconfigure(cfg.agent_section())?;
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
    /// reconstruction view (`None` in an arena file's run).
    pub fn encoder(&self) -> Option<&Autoencoder> {
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
        let model = self.perception.trained().filter(|_| self.gate.has_measured())?;
        Some(self.gate.mse(model, &mut self.scratch, &mut self.cache))
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
            Some(d) => d.record && self.agent.can_be_driven,
        }
    }

    /// What this run's embeddings mean, for memory files.
    pub(super) fn identity(&self) -> memory::file::Identity {
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
        if self.agent.reads == Input::Embedding {
            let (perception, image, scratch) = (&self.perception, &self.image, &mut self.scratch);
            self.cache.embedding(self.slot, &mut e, |e| perception.embed(image, scratch, e));
            if self.perception.embeds_with_gate_model() {
                self.gate.share_embedding(&e);
            }
        }
        if self.sec_events().is_some() {
            // Without a gate model (an arena file's run, whose gate is off) the log's default, 0.
            let rec_mse = match self.perception.trained() {
                Some(model) => self.gate.mse(model, &mut self.scratch, &mut self.cache),
                None => 0.0,
            };
            let ev = self.sec_events().expect("checked above");
            ev.push(trace::Event::Decision { embedding: e.to_vec(), rec_mse });
        }
        let obs = Observation { embedding: &e, image: &self.image, terminal, person: self.driver.map(|d| d.action) };
        let (gate, encoder, scratch, cache) =
            (&mut self.gate, self.perception.trained(), &mut self.scratch, &mut self.cache);
        // A run without a gate model has its gate off (`RunConfig::validate`), so never asks.
        let mut measure = || gate.mse(encoder.expect("a run whose gate is on has its model"), scratch, cache);
        self.controller.decide(&obs, &mut measure, &mut self.rng)
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
        let uses_gate = self.agent.has_gate && self.perception.trained().is_some();
        if self.agent.reads != Input::Nothing && (decides || (uses_gate && self.gate.due())) {
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
        self.log_digest = metrics::extend_log(self.log_digest, &metrics.to_json());
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

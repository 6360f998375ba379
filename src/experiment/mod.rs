//! A run of SEC in a task (sec-algorithm.md section 3): the environment, the frozen encoder, the
//! reconstruction gate and the agent, one env step at a time with a decision every 4, and the
//! per-episode metrics the paper's tables count (section 8).

use crate::agent::mfec::{Embedding, Mfec, MfecConfig, RandomProjection};
use crate::agent::{Agent, AgentConfig, Decision, Layer, Reactive};
use crate::arena::{Action, ConfigError, Env, EnvConfig, Task};
use crate::encoder::{bundled, Autoencoder, ReconstructionGate, Scratch, EMBEDDING, IMAGE};
pub mod presets;
pub mod trace;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// What a run is: a pure function of this and the seed.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase", default, deny_unknown_fields)]
pub struct RunConfig {
    pub task: String,
    /// Episode limit in env steps (`None`: the task's, 1000).
    pub t: Option<u32>,
    /// Env steps per decision; the action is held in between (D1).
    pub decision_period: u32,
    /// Which agent runs: SEC (NSEC is SEC without `sequentialBias`), MFEC or the reactive walk.
    pub kind: AgentKind,
    /// SEC's parameters (used when `kind` is sec).
    pub agent: AgentConfig,
    /// MFEC's parameters (used when `kind` is mfec).
    pub mfec: MfecConfig,
    /// Use the encoder's raw outputs, without the calibrated per-model scale (deviation D17
    /// undone: the thresholds then act on raw embedding units, as in the authors' code).
    pub raw_embeddings: bool,
}

impl Default for RunConfig {
    fn default() -> Self {
        RunConfig {
            task: "double-t-maze".into(),
            t: None,
            decision_period: 4,
            kind: AgentKind::Sec,
            agent: AgentConfig::default(),
            mfec: MfecConfig::default(),
            raw_embeddings: false,
        }
    }
}

/// The agents a run can hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum AgentKind {
    Sec,
    Mfec,
    /// The reactive layer alone.
    Reactive,
}

/// The agent of a run (one per run, so the variants' sizes do not matter).
#[derive(Clone, Debug)]
#[allow(clippy::large_enum_variant)]
pub enum Controller {
    Sec(Agent),
    Mfec(Mfec),
    Reactive(Reactive),
}

/// One episode as the paper's tables count it.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct EpisodeMetrics {
    pub episode: u64,
    pub layout: String,
    /// R_ep when positive, else 0 (the tables' reward).
    pub reward: f64,
    /// R_ep itself: goal reward plus the per-step penalties.
    pub raw_reward: f64,
    pub goal: bool,
    pub env_steps: u32,
    pub decisions: u32,
    /// Mean entropy (bits) logged at every decision, stale values included (the authors').
    pub entropy: f64,
    /// Mean over the decisions whose entropy was computed afresh; `None` if none was.
    pub entropy_fresh: Option<f64>,
    /// Sequences in the LTM at the end of the episode.
    pub ltm: usize,
    /// Share of decisions taken by the contextual layer.
    pub contextual_share: f64,
}

impl EpisodeMetrics {
    /// One JSON line (no newline): the runner's output format.
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).expect("metrics serialise")
    }
}

/// A run in progress.
pub struct Run {
    cfg: RunConfig,
    env: Env,
    encoder: Autoencoder,
    scratch: Scratch,
    image: Vec<f32>,
    gate: ReconstructionGate,
    controller: Controller,
    /// MFEC-rp's projection, drawn from the run's seed.
    projection: Option<RandomProjection>,
    /// SEC's events, when recorded (see `trace`).
    events: Option<Vec<trace::Event>>,
    /// The agent's draws; the environment has its own stream of the same seed.
    rng: ChaCha8Rng,
}

impl Run {
    pub fn new(cfg: RunConfig, seed: u64) -> Result<Self, ConfigError> {
        if !(1..=100).contains(&cfg.decision_period) {
            return Err(ConfigError::new("decisionPeriod", format!("{} is out of range 1..=100", cfg.decision_period)));
        }
        let task = Task::preset(&cfg.task)?;
        let mut encoder = bundled::autoencoder(&cfg.task)?;
        if cfg.raw_embeddings {
            encoder.embedding_scale = 1.0;
        }
        let env = Env::new(EnvConfig { task, t: cfg.t }, seed)?;
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        rng.set_stream(1);
        let mut projection = None;
        let controller = match cfg.kind {
            AgentKind::Sec => Controller::Sec(Agent::new(cfg.agent.clone(), &mut rng)?),
            AgentKind::Mfec => {
                if cfg.mfec.embedding == Embedding::RandomProjection {
                    let mut prng = ChaCha8Rng::seed_from_u64(seed);
                    prng.set_stream(2);
                    projection = Some(RandomProjection::new(&mut prng));
                }
                Controller::Mfec(Mfec::new(cfg.mfec.clone(), &mut rng)?)
            }
            AgentKind::Reactive => Controller::Reactive(Reactive::new(&mut rng)),
        };
        Ok(Run {
            cfg,
            env,
            encoder,
            scratch: Scratch::default(),
            image: vec![0.0; IMAGE],
            gate: ReconstructionGate::new(),
            controller,
            projection,
            events: None,
            rng,
        })
    }

    pub fn config(&self) -> &RunConfig {
        &self.cfg
    }

    pub fn controller(&self) -> &Controller {
        &self.controller
    }

    /// The SEC agent, if the run holds one.
    pub fn agent(&self) -> Option<&Agent> {
        match &self.controller {
            Controller::Sec(a) => Some(a),
            _ => None,
        }
    }

    pub fn env(&self) -> &Env {
        &self.env
    }

    /// Starts recording SEC's events (embeddings with the gate's MSE, goals, episode ends): fed
    /// to `trace::trace` with the run's seed they give the run's actions again.
    pub fn record_events(&mut self) {
        self.events.get_or_insert_with(Vec::new);
    }

    /// The events recorded since the last call.
    pub fn take_events(&mut self) -> Vec<trace::Event> {
        self.events.as_mut().map(std::mem::take).unwrap_or_default()
    }

    /// The current frame's embedding (the image is already in `self.image`), then the agent's
    /// decision.
    fn decide(&mut self) -> Decision {
        let mut e = [0.0; EMBEDDING];
        match &self.projection {
            Some(p) => p.project(&self.image, &mut e),
            None if !matches!(self.controller, Controller::Reactive(_)) => {
                self.encoder.encode(&self.image, &mut self.scratch, &mut e)
            }
            None => {}
        }
        match &mut self.controller {
            Controller::Sec(agent) => {
                if let Some(ev) = &mut self.events {
                    ev.push(trace::Event::Decision { embedding: e.to_vec(), rec_mse: self.gate.mse });
                }
                agent.decide(&e, self.gate.mse, &mut self.rng)
            }
            Controller::Mfec(mfec) => mfec.decide(&e, self.env.is_over(), &mut self.rng),
            Controller::Reactive(r) => {
                Decision { action: r.step(&mut self.rng), layer: Layer::Reactive, selected: false }
            }
        }
    }

    /// The entropy (bits) the last decision logs: SEC's stale-inclusive value (D14), MFEC's
    /// softmax over Q, 0 for the reactive walk.
    fn entropy(&self) -> f64 {
        match &self.controller {
            Controller::Sec(agent) => agent.memory.entropy(),
            Controller::Mfec(mfec) => mfec.entropy(),
            Controller::Reactive(_) => 0.0,
        }
    }

    /// Plays one episode to its end and starts the next.
    pub fn episode(&mut self) -> EpisodeMetrics {
        let period = self.cfg.decision_period;
        let episode = self.env.episode();
        let layout = self.env.layout_name().to_string();
        // As the authors' loop: the first observation comes from a no-op step after the reset.
        let mut out = self.env.advance(Action::NOOP, 1).expect("a fresh episode takes a step");
        let (mut r_ep, mut step, mut action) = (0.0, 0u32, Action::NOOP);
        let (mut decisions, mut contextual, mut goal) = (0u32, 0u32, false);
        let (mut entropy_sum, mut fresh_sum, mut fresh_n) = (0.0, 0.0, 0u32);
        let is_sec = matches!(self.controller, Controller::Sec(_));
        loop {
            r_ep += out.reward;
            let decide = step % period == 0;
            let reached = out.good_goal && r_ep > 0.0;
            goal |= reached;
            match &mut self.controller {
                // Storage on the goal event with a positive episode reward, before this frame's
                // decision, so the last decision's couplet is not in the sequence (D4, D12).
                Controller::Sec(agent) if reached => {
                    agent.goal(r_ep, &mut self.rng);
                    if let Some(ev) = &mut self.events {
                        ev.push(trace::Event::Goal { reward: r_ep });
                    }
                }
                Controller::Mfec(mfec) => mfec.frame(out.reward, r_ep, out.good_goal, decide),
                _ => {}
            }
            let needs_image = !matches!(self.controller, Controller::Reactive(_));
            if needs_image && (decide || (is_sec && self.gate.due())) {
                self.env.observation().to_rgb_f32(&mut self.image);
            }
            if is_sec {
                self.gate.advance(&self.encoder, &self.image, &mut self.scratch);
            }
            if decide {
                let d = self.decide();
                action = Action::new(d.action as u32).expect("actions are 0..9");
                decisions += 1;
                contextual += (d.layer == Layer::Contextual) as u32;
                let h = self.entropy();
                entropy_sum += h;
                if d.selected {
                    fresh_sum += h;
                    fresh_n += 1;
                }
            }
            if self.env.is_over() {
                break;
            }
            out = self.env.advance(action, 1).expect("the episode is not over");
            step += 1;
        }
        let ltm = match &mut self.controller {
            Controller::Sec(agent) => {
                agent.episode_end();
                if let Some(ev) = &mut self.events {
                    ev.push(trace::Event::EpisodeEnd);
                }
                agent.memory.len()
            }
            Controller::Mfec(mfec) => {
                mfec.episode_end(goal);
                mfec.len()
            }
            Controller::Reactive(_) => 0,
        };
        let metrics = EpisodeMetrics {
            episode,
            layout,
            reward: r_ep.max(0.0),
            raw_reward: r_ep,
            goal,
            env_steps: self.env.steps(),
            decisions,
            entropy: entropy_sum / decisions.max(1) as f64,
            entropy_fresh: (fresh_n > 0).then(|| fresh_sum / fresh_n as f64),
            ltm,
            contextual_share: contextual as f64 / decisions.max(1) as f64,
        };
        self.env.reset(None);
        metrics
    }
}

/// The short runs whose JSON lines `tests/golden/run.txt` holds: native and wasm builds must
/// reproduce them bit for bit (the JSON numbers are shortest round-trip decimals).
pub fn golden_run() -> String {
    // Object permanence: goals come early, so the LTM fills and the contextual layer acts.
    let sec = RunConfig { task: "object-permanence".into(), ..RunConfig::default() };
    let mut mfec_rp = RunConfig { kind: AgentKind::Mfec, t: Some(250), ..sec.clone() };
    mfec_rp.mfec.embedding = Embedding::RandomProjection;
    mfec_rp.mfec.warmup_decisions = 100;
    mfec_rp.mfec.warmup_rewarded_episodes = 1;
    let mfec_ae = RunConfig {
        mfec: MfecConfig { warmup_decisions: 100, warmup_rewarded_episodes: 1, ..MfecConfig::default() },
        ..mfec_rp.clone()
    };
    let reactive = RunConfig { kind: AgentKind::Reactive, ..mfec_rp.clone() };
    let mut log = String::new();
    for (cfg, episodes) in [(sec, 16), (mfec_ae, 6), (mfec_rp, 6), (reactive, 2)] {
        let mut run = Run::new(cfg, 7).expect("the golden configurations are valid");
        for _ in 0..episodes {
            log += &run.episode().to_json();
            log.push('\n');
        }
    }
    log
}

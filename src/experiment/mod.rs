//! A run of SEC in a task (sec-algorithm.md section 3): the environment, the frozen encoder, the
//! reconstruction gate and the agent, one env step at a time with a decision every 4, and the
//! per-episode metrics the paper's tables count (section 8).

use crate::agent::{Agent, AgentConfig, Layer};
use crate::arena::{Action, ConfigError, Env, EnvConfig, Task};
use crate::encoder::{bundled, Autoencoder, ReconstructionGate, Scratch, EMBEDDING, IMAGE};
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
    pub agent: AgentConfig,
}

impl Default for RunConfig {
    fn default() -> Self {
        RunConfig { task: "double-t-maze".into(), t: None, decision_period: 4, agent: AgentConfig::default() }
    }
}

/// One episode as the paper's tables count it.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
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

/// A run in progress.
pub struct Run {
    cfg: RunConfig,
    env: Env,
    encoder: Autoencoder,
    scratch: Scratch,
    image: Vec<f32>,
    gate: ReconstructionGate,
    agent: Agent,
    /// The agent's draws; the environment has its own stream of the same seed.
    rng: ChaCha8Rng,
}

impl Run {
    pub fn new(cfg: RunConfig, seed: u64) -> Result<Self, ConfigError> {
        if !(1..=100).contains(&cfg.decision_period) {
            return Err(ConfigError::new("decisionPeriod", format!("{} is out of range 1..=100", cfg.decision_period)));
        }
        let task = Task::preset(&cfg.task)?;
        let encoder = bundled::autoencoder(&cfg.task)?;
        let env = Env::new(EnvConfig { task, t: cfg.t }, seed)?;
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        rng.set_stream(1);
        let agent = Agent::new(cfg.agent.clone(), &mut rng)?;
        Ok(Run {
            cfg,
            env,
            encoder,
            scratch: Scratch::default(),
            image: vec![0.0; IMAGE],
            gate: ReconstructionGate::new(),
            agent,
            rng,
        })
    }

    pub fn agent(&self) -> &Agent {
        &self.agent
    }

    pub fn env(&self) -> &Env {
        &self.env
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
        loop {
            r_ep += out.reward;
            // Storage on the goal event with a positive episode reward, before this frame's
            // decision, so the last decision's couplet is not in the sequence (D4, D12).
            if out.good_goal && r_ep > 0.0 {
                goal = true;
                self.agent.goal(r_ep, &mut self.rng);
            }
            let decide = step % period == 0;
            if decide || self.gate.due() {
                self.env.observation().to_rgb_f32(&mut self.image);
            }
            self.gate.advance(&self.encoder, &self.image, &mut self.scratch);
            if decide {
                let mut e = [0.0; EMBEDDING];
                self.encoder.encode(&self.image, &mut self.scratch, &mut e);
                let d = self.agent.decide(&e, self.gate.mse, &mut self.rng);
                action = Action::new(d.action as u32).expect("actions are 0..9");
                decisions += 1;
                contextual += (d.layer == Layer::Contextual) as u32;
                let h = self.agent.memory.entropy();
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
        self.agent.episode_end();
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
            ltm: self.agent.memory.len(),
            contextual_share: contextual as f64 / decisions.max(1) as f64,
        };
        self.env.reset(None);
        metrics
    }
}

/// The short run whose per-episode log `tests/golden/run.txt` holds: native and wasm builds must
/// reproduce it bit for bit (Debug formatting of f64 round-trips exactly).
pub fn golden_run() -> String {
    // Object permanence: goals come early, so the LTM fills and the contextual layer acts.
    let cfg = RunConfig { task: "object-permanence".into(), ..RunConfig::default() };
    let mut run = Run::new(cfg, 7).expect("the default configuration is valid");
    (0..16).map(|_| format!("{:?}\n", run.episode())).collect()
}

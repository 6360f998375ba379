//! The paper's DQN baseline as the authors ran it (`agent_dqn.py`, `exp_setup_dqn.py`; see
//! docs/ALGORITHM.md, "DQN"), trained with burn on the CPU. It is an agent of the core's `Run`
//! (`kind: "dqn"`), built through `factory`, so the run loop, the metrics and the runner are the
//! same as SEC's; only this crate depends on burn.
//!
//! What the authors' loop does, and this agent with it:
//! - Decision: a uniform draw below epsilon, or fewer decisions than `randomDecisions`, takes the
//!   reactive walk's action; otherwise the argmax of Q (the first on ties). Epsilon then falls by
//!   (start - end) / epsilonDecisions.
//! - Storage: on every decision frame and on any frame with a positive reward, a transition
//!   (state, action, reward, the frame, done) with the frame's own reward, or the episode's reward
//!   on a goal frame (D13; `sumRewards` sums the frames since the last transition instead); the
//!   frame becomes the next state.
//! - Training: every `trainEvery` decisions, once the buffer holds a batch, one RMSprop step on
//!   MSE(Q(s, a), r + gamma (1 - done) max Q_target(s')) over uniformly drawn transitions; the
//!   target network is synced every `targetSync` decisions.
//! - Entropy: of the softmax over Q, in bits, computed on the network's own decisions (stale on
//!   the reactive walk's, as theirs).
//!
//! One deviation: the authors count frames across episodes, so their decision clock does not
//! restart with an episode; here, as for SEC, every episode starts its clock at its first frame.

pub mod net;
pub mod replay;

use burn::optim::{GradientsParams, ModuleOptimizer, RmsPropConfig};
use burn::prelude::*;
use burn::tensor::TensorData;
use net::{batch, values, NatureCnn};
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use replay::{Meta, Replay};
use sec_playground::agent::controller::{Controller, EpisodeEnd, Input, MemoryUse, Observation, Step};
use sec_playground::agent::dqn::DqnConfig;
use sec_playground::agent::mfec::softmax_entropy_bits;
use sec_playground::agent::{Decision, Layer, Reactive};
use sec_playground::arena::ConfigError;
use sec_playground::experiment::{AgentKind, RunConfig};
use sec_playground::memory::ACTIONS;
use sec_playground::seed::{self, Stream};

/// The training device: burn's CPU backend with autodiff.
pub fn device() -> Device {
    Device::flex().autodiff()
}

/// Builds the agents of this crate for `Run::with_agents`.
pub fn factory(cfg: &RunConfig, seed: u64, rng: &mut ChaCha8Rng) -> Option<Result<Box<dyn Controller>, ConfigError>> {
    match cfg.kind {
        AgentKind::Dqn => Some(Dqn::new(cfg.dqn.clone(), seed, rng).map(|d| Box::new(d) as Box<dyn Controller>)),
        _ => None,
    }
}

type Rms = ModuleOptimizer;

pub struct Dqn {
    cfg: DqnConfig,
    device: Device,
    /// The online network (taken out only while an optimiser step consumes it).
    net: Option<NatureCnn>,
    /// The target network (a validation copy: no autodiff).
    target: NatureCnn,
    optim: Rms,
    replay: Replay,
    reactive: Reactive,
    epsilon: f64,
    decisions: u64,
    /// The action of the last decision, which the next transition records.
    action: u8,
    /// Rewards since the last transition (for `sumRewards`).
    pending: f64,
    entropy: f64,
}

impl Dqn {
    pub fn new(cfg: DqnConfig, seed: u64, rng: &mut ChaCha8Rng) -> Result<Self, ConfigError> {
        cfg.validate()?;
        let device = device();
        // The network's initial weights from their own stream of the run's seed.
        let net = NatureCnn::new(&mut seed::rng(seed, Stream::Network), &device);
        let target = net.valid();
        // PyTorch's RMSprop defaults, as the authors' optimiser: alpha 0.99, eps 1e-8, no momentum.
        let optim = RmsPropConfig::new().with_alpha(0.99).with_epsilon(1e-8).with_momentum(0.0).init();
        Ok(Dqn {
            replay: Replay::new(cfg.replay_size),
            reactive: Reactive::new(rng),
            epsilon: cfg.epsilon_start,
            decisions: 0,
            action: 0,
            pending: 0.0,
            entropy: 0.0,
            cfg,
            device,
            net: Some(net),
            target,
            optim,
        })
    }

    pub fn config(&self) -> &DqnConfig {
        &self.cfg
    }

    pub fn epsilon(&self) -> f64 {
        self.epsilon
    }

    pub fn decisions(&self) -> u64 {
        self.decisions
    }

    pub fn replay(&self) -> &Replay {
        &self.replay
    }

    pub fn network(&self) -> &NatureCnn {
        self.net.as_ref().expect("the network is back after every step")
    }

    /// Q of one frame (RGB floats in [0, 1], channel-last), by the online network.
    pub fn q(&self, image: &[f32]) -> [f64; ACTIONS] {
        let q = values(self.network().valid().forward(frame_tensor(image, &self.device)));
        std::array::from_fn(|a| q[a] as f64)
    }

    /// Q of one frame by the target network.
    pub fn target_q(&self, image: &[f32]) -> [f64; ACTIONS] {
        let q = values(self.target.forward(frame_tensor(image, &self.device)));
        std::array::from_fn(|a| q[a] as f64)
    }

    /// One RMSprop step on a batch drawn from the replay buffer; returns the loss.
    pub fn train_step(&mut self, rng: &mut ChaCha8Rng) -> f32 {
        let idx = self.replay.sample_indices(self.cfg.batch_size, rng);
        let samples: Vec<_> = idx.iter().map(|&i| self.replay.get(i)).collect();
        let states: Vec<&[u8]> = samples.iter().map(|s| s.state).collect();
        let nexts: Vec<&[u8]> = samples.iter().map(|s| s.next).collect();
        let n = samples.len();
        let q2 = values(self.target.forward(batch(&nexts, &self.device)));
        let y: Vec<f32> = samples
            .iter()
            .enumerate()
            .map(|(b, s)| {
                let best = q2[b * ACTIONS..(b + 1) * ACTIONS].iter().copied().fold(f32::NEG_INFINITY, f32::max);
                s.meta.reward + self.cfg.gamma as f32 * (1.0 - s.meta.done as u8 as f32) * best
            })
            .collect();
        // Q(s, a) through a one-hot mask of the actions taken.
        let mut mask = vec![0.0f32; n * ACTIONS];
        for (b, s) in samples.iter().enumerate() {
            mask[b * ACTIONS + s.meta.action as usize] = 1.0;
        }
        let x = batch(&states, &self.device);
        let net = self.net.take().expect("the network is back after every step");
        let q1 = net.forward(x);
        let mask = Tensor::<2>::from_data(TensorData::new(mask, [n, ACTIONS]), &self.device);
        let target = Tensor::<1>::from_data(TensorData::new(y, [n]), &self.device);
        let taken = (q1 * mask).sum_dim(1).reshape([n]);
        let loss = (taken - target).square().mean();
        let value = values(loss.clone())[0];
        let grads = GradientsParams::from_grads(loss.backward(), &net);
        self.net = Some(self.optim.step(self.cfg.learning_rate, net, grads));
        value
    }

    pub fn sync_target(&mut self) {
        self.target = self.network().valid();
    }
}

/// One channel-last frame of floats as a [1, 3, 84, 84] tensor.
fn frame_tensor(image: &[f32], device: &Device) -> Tensor<4> {
    let mut chw = vec![0.0f32; 3 * net::PIXELS];
    for p in 0..net::PIXELS {
        for c in 0..3 {
            chw[c * net::PIXELS + p] = image[p * 3 + c];
        }
    }
    Tensor::<4>::from_data(TensorData::new(chw, [1, 3, 84, 84]), device)
}

/// A frame's floats back to the bytes they came from (the camera's values are bytes / 255).
fn to_bytes(image: &[f32]) -> Vec<u8> {
    image.iter().map(|&v| (v * 255.0).round() as u8).collect()
}

impl Controller for Dqn {
    fn input(&self) -> Input {
        Input::Image
    }

    fn wants_frame(&self, step: &Step) -> bool {
        step.decides || step.reward > 0.0
    }

    fn on_step(&mut self, step: &Step, frame: Option<&[f32]>, rng: &mut ChaCha8Rng) -> bool {
        self.pending += step.reward;
        let Some(frame) = frame else { return false };
        if !self.replay.started() {
            self.replay.start(to_bytes(frame));
            self.pending = 0.0;
            return false;
        }
        let reward = if self.cfg.sum_rewards {
            self.pending
        } else if step.reward > 0.0 {
            step.episode_reward
        } else {
            step.reward
        };
        self.pending = 0.0;
        self.replay.push(Meta { action: self.action, reward: reward as f32, done: step.done }, to_bytes(frame));
        if step.decides && self.decisions > 0 {
            if self.decisions % self.cfg.train_every == 0 && self.replay.len() >= self.cfg.batch_size {
                self.train_step(rng);
            }
            if self.decisions % self.cfg.target_sync == 0 {
                self.sync_target();
            }
        }
        false
    }

    fn decide(&mut self, obs: &Observation, _: &mut dyn FnMut() -> f32, rng: &mut ChaCha8Rng) -> Decision {
        self.decisions += 1;
        let explore = rng.gen::<f64>() < self.epsilon || self.decisions < self.cfg.random_decisions;
        let (action, layer) = if explore {
            (self.reactive.step(rng), Layer::Reactive)
        } else {
            let q = self.q(obs.image);
            self.entropy = softmax_entropy_bits(&q);
            let best = (0..ACTIONS).fold(0, |b, a| if q[a] > q[b] { a } else { b });
            (best as u8, Layer::Contextual)
        };
        self.epsilon = self.cfg.next_epsilon(self.epsilon);
        self.action = action;
        Decision { action, layer, selected: !explore }
    }

    fn on_episode_end(&mut self, _: &EpisodeEnd) {}

    fn entropy(&self) -> f64 {
        self.entropy
    }

    fn memory_use(&self) -> MemoryUse {
        MemoryUse { used: self.replay.len(), capacity: self.cfg.replay_size }
    }
}

#![warn(missing_docs)]
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

pub mod checkpoint;
pub mod config;
pub mod graph;
pub mod net;
pub mod replay;

use burn::optim::{GradientsParams, ModuleOptimizer, RmsPropConfig};
use burn::prelude::*;
use burn::tensor::TensorData;
pub use config::{register, DqnConfig, ErlamConfig};
use graph::{Graph, Pending};
use net::{values, NatureCnn};
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use replay::{Meta, Replay};
use sec_playground::agent::controller::{Controller, EpisodeEnd, MemoryCensus, MemoryUse, Observation, Step};
use sec_playground::agent::mfec::softmax_entropy_bits;
use sec_playground::agent::{Decision, Layer, Reactive};
use sec_playground::arena::{Action, ConfigError};
use sec_playground::encoder::{Perception, Scratch, EMBEDDING};
use sec_playground::experiment::{AgentKind, RunConfig};
use sec_playground::memory::ACTIONS;
use sec_playground::seed::{self, Stream};

/// The training device: burn's CPU backend with autodiff.
pub fn device() -> Device {
    Device::flex().autodiff()
}

/// Builds the agents of this crate for `Run::with_agents`.
pub fn factory(
    cfg: &RunConfig,
    perception: &Perception,
    seed: u64,
    rng: &mut ChaCha8Rng,
) -> Option<Result<Box<dyn Controller>, ConfigError>> {
    let made = match cfg.kind {
        AgentKind::Dqn => config::dqn(cfg).and_then(|c| Dqn::new(c, seed, rng)),
        AgentKind::Erlam => config::dqn(cfg)
            .and_then(|c| Ok((c, config::erlam(cfg)?)))
            .and_then(|(c, graph)| Dqn::erlam(c, graph, perception.clone(), seed, rng)),
        _ => return None,
    };
    Some(made.map(|d| Box::new(d) as Box<dyn Controller>))
}

/// Where the training batches come from: DQN's replay buffer, or ERLAM's graph.
enum Memory {
    Replay(Replay),
    Graph(Box<Associative>),
}

/// ERLAM's side: the graph, the perception that embeds its states (a copy of the run's: the
/// authors' ERLAM embeds with the trained model's `dense_1`, so exp1 sets `perception: trained`),
/// and the state the next transition starts from.
struct Associative {
    graph: Graph,
    lambda: f64,
    perception: Perception,
    scratch: Scratch,
    state: Option<(Vec<u8>, [f32; EMBEDDING])>,
    episodes: u64,
}

/// One training batch: the transitions and the graph's value of each (0 for DQN).
struct Batch<'a> {
    states: Vec<&'a [u8]>,
    nexts: Vec<&'a [u8]>,
    meta: Vec<Meta>,
    graph: Vec<f32>,
}

type Rms = ModuleOptimizer;

/// PyTorch's RMSprop defaults, as the authors' optimiser: alpha 0.99, eps 1e-8, no momentum.
fn optimiser_config() -> RmsPropConfig {
    RmsPropConfig::new().with_alpha(0.99).with_epsilon(1e-8).with_momentum(0.0)
}

/// The DQN agent (and ERLAM's, with its graph as `memory`): the networks, the optimiser, the
/// replay buffer or graph, and where the run stands.
pub struct Dqn {
    cfg: DqnConfig,
    device: Device,
    /// The online network (taken out only while an optimiser step consumes it).
    net: Option<NatureCnn>,
    /// The target network (a validation copy: no autodiff).
    target: NatureCnn,
    optim: Rms,
    memory: Memory,
    progress: Progress,
}

/// Where the agent stands between two steps besides what it learned: the exploration walk, the
/// schedule's counters and the bookkeeping of the next transition (a checkpoint holds it whole).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
struct Progress {
    reactive: Reactive,
    epsilon: f64,
    decisions: u64,
    /// The action of the last decision, which the next transition records.
    action: Action,
    /// Rewards since the last transition (for `sumRewards`).
    pending: f64,
    entropy: f64,
}

impl Dqn {
    /// A DQN agent of `cfg`: its network's weights from the run's `seed` (their own stream), its
    /// reactive walk from the agent stream `rng`. A `cfg` out of range is refused by name.
    pub fn new(cfg: DqnConfig, seed: u64, rng: &mut ChaCha8Rng) -> Result<Self, ConfigError> {
        cfg.validate()?;
        let device = device();
        // The network's initial weights from their own stream of the run's seed.
        let net = NatureCnn::new(&mut seed::rng(seed, Stream::Network), &device);
        let target = net.valid();
        let optim = optimiser_config().init();
        Ok(Dqn {
            memory: Memory::Replay(Replay::new(cfg.replay_size)),
            progress: Progress {
                reactive: Reactive::new(rng),
                epsilon: cfg.epsilon_start,
                decisions: 0,
                action: Action::NOOP,
                pending: 0.0,
                entropy: 0.0,
            },
            cfg,
            device,
            net: Some(net),
            target,
            optim,
        })
    }

    /// ERLAM: this DQN with the associative graph over the embeddings of `perception`.
    pub fn erlam(
        cfg: DqnConfig,
        graph: ErlamConfig,
        perception: Perception,
        seed: u64,
        rng: &mut ChaCha8Rng,
    ) -> Result<Self, ConfigError> {
        graph.validate()?;
        let mut dqn = Dqn::new(cfg, seed, rng)?;
        let gamma = dqn.cfg.gamma;
        dqn.memory = Memory::Graph(Box::new(Associative {
            lambda: graph.lambda,
            graph: Graph::new(graph, gamma),
            perception,
            scratch: Scratch::default(),
            state: None,
            episodes: 0,
        }));
        Ok(dqn)
    }

    /// Its settings.
    pub fn config(&self) -> &DqnConfig {
        &self.cfg
    }

    /// ERLAM's graph, if this is ERLAM.
    pub fn graph(&self) -> Option<&Graph> {
        match &self.memory {
            Memory::Graph(a) => Some(&a.graph),
            Memory::Replay(_) => None,
        }
    }

    /// The exploration rate of the next decision.
    pub fn epsilon(&self) -> f64 {
        self.progress.epsilon
    }

    /// Decisions taken so far.
    pub fn decisions(&self) -> u64 {
        self.progress.decisions
    }

    /// DQN's replay buffer, if this is DQN.
    pub fn replay(&self) -> Option<&Replay> {
        match &self.memory {
            Memory::Replay(r) => Some(r),
            Memory::Graph(_) => None,
        }
    }

    /// Transitions the training batches are drawn from.
    fn stored(&self) -> usize {
        match &self.memory {
            Memory::Replay(r) => r.len(),
            Memory::Graph(a) => a.graph.len(),
        }
    }

    /// The online network.
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

    /// One RMSprop step on a batch drawn from the replay buffer (DQN) or the graph's nodes
    /// (ERLAM); returns the loss, mean[(Y - Q)^2 + lambda (G - Q)^2] (lambda 0 for DQN: MSE).
    pub fn train_step(&mut self, rng: &mut ChaCha8Rng) -> f32 {
        let n = self.cfg.batch_size;
        let (batch, lambda) = match &self.memory {
            Memory::Replay(r) => {
                let samples: Vec<_> = r.sample_indices(n, rng).into_iter().map(|i| r.get(i)).collect();
                let batch = Batch {
                    states: samples.iter().map(|s| s.state).collect(),
                    nexts: samples.iter().map(|s| s.next).collect(),
                    meta: samples.iter().map(|s| s.meta).collect(),
                    graph: vec![0.0; n],
                };
                (batch, 0.0)
            }
            Memory::Graph(a) => {
                let ids = a.graph.sample(n, rng);
                let nodes: Vec<_> = ids.iter().map(|id| a.graph.node(*id).expect("sampled from the graph")).collect();
                let batch = Batch {
                    states: nodes.iter().map(|n| n.state.as_slice()).collect(),
                    nexts: nodes.iter().map(|n| n.next_state.as_slice()).collect(),
                    meta: nodes.iter().map(|n| Meta { action: n.action, reward: n.reward, done: n.done }).collect(),
                    graph: ids.iter().map(|&id| a.graph.value(id) as f32).collect(),
                };
                (batch, a.lambda as f32)
            }
        };
        let q2 = values(self.target.forward(net::batch(&batch.nexts, &self.device)));
        let y: Vec<f32> = batch
            .meta
            .iter()
            .enumerate()
            .map(|(b, m)| {
                let best = q2[b * ACTIONS..(b + 1) * ACTIONS].iter().copied().fold(f32::NEG_INFINITY, f32::max);
                m.reward + self.cfg.gamma as f32 * (1.0 - m.done as u8 as f32) * best
            })
            .collect();
        // Q(s, a) through a one-hot mask of the actions taken.
        let mut mask = vec![0.0f32; n * ACTIONS];
        for (b, m) in batch.meta.iter().enumerate() {
            mask[b * ACTIONS + m.action as usize] = 1.0;
        }
        let x = net::batch(&batch.states, &self.device);
        let graph = Tensor::<1>::from_data(TensorData::new(batch.graph, [n]), &self.device);
        let net = self.net.take().expect("the network is back after every step");
        let q1 = net.forward(x);
        let mask = Tensor::<2>::from_data(TensorData::new(mask, [n, ACTIONS]), &self.device);
        let target = Tensor::<1>::from_data(TensorData::new(y, [n]), &self.device);
        let taken = (q1 * mask).sum_dim(1).reshape([n]);
        let loss = ((target - taken.clone()).square() + (graph - taken).square() * lambda).mean();
        let value = values(loss.clone())[0];
        let grads = GradientsParams::from_grads(loss.backward(), &net);
        self.net = Some(self.optim.step(self.cfg.learning_rate, net, grads));
        value
    }

    /// Copies the online network into the target network.
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
    fn wants_frame(&self, step: &Step) -> bool {
        step.decides || step.reward > 0.0
    }

    fn on_step(&mut self, step: &Step, frame: Option<&[f32]>, rng: &mut ChaCha8Rng) -> bool {
        self.progress.pending += step.reward;
        let Some(frame) = frame else { return false };
        let reward = if self.cfg.sum_rewards {
            self.progress.pending
        } else if step.reward > 0.0 {
            step.episode_reward
        } else {
            step.reward
        };
        let bytes = to_bytes(frame);
        let action = u8::from(self.progress.action);
        let stored = match &mut self.memory {
            Memory::Replay(r) if !r.started() => {
                r.start(bytes);
                false
            }
            Memory::Replay(r) => {
                r.push(Meta { action, reward: reward as f32, done: step.done }, bytes);
                true
            }
            Memory::Graph(a) => {
                let mut e = [0.0; EMBEDDING];
                a.perception.embed(frame, &mut a.scratch, &mut e);
                let stored = match a.state.take() {
                    Some((state, embedding)) => {
                        let next_state = bytes.clone();
                        a.graph.remember(Pending {
                            embedding,
                            state,
                            next_state,
                            action,
                            reward: reward as f32,
                            done: step.done,
                        });
                        true
                    }
                    None => false,
                };
                a.state = Some((bytes, e));
                stored
            }
        };
        self.progress.pending = 0.0;
        if stored && step.decides && self.progress.decisions > 0 {
            if self.progress.decisions % self.cfg.train_every == 0 && self.stored() >= self.cfg.batch_size {
                self.train_step(rng);
            }
            if self.progress.decisions % self.cfg.target_sync == 0 {
                self.sync_target();
            }
        }
        false
    }

    fn decide(&mut self, obs: &Observation, _: &mut dyn FnMut() -> f32, rng: &mut ChaCha8Rng) -> Decision {
        self.progress.decisions += 1;
        let explore = rng.gen::<f64>() < self.progress.epsilon || self.progress.decisions < self.cfg.random_decisions;
        let (action, layer) = if explore {
            (self.progress.reactive.step(rng), Layer::Reactive)
        } else {
            let q = self.q(obs.image);
            self.progress.entropy = softmax_entropy_bits(&q);
            let best = (0..ACTIONS).fold(0, |b, a| if q[a] > q[b] { a } else { b });
            (Action::ALL[best], Layer::Contextual)
        };
        self.progress.epsilon = self.cfg.next_epsilon(self.progress.epsilon);
        self.progress.action = action;
        Decision { action, layer, selected: !explore }
    }

    /// ERLAM adds the episode to its graph and, every `propagateEvery` episodes, propagates.
    fn on_episode_end(&mut self, _: &EpisodeEnd) {
        if let Memory::Graph(a) = &mut self.memory {
            a.episodes += 1;
            a.graph.end_episode();
            a.graph.propagate(a.episodes);
        }
    }

    fn census(&self) -> Option<MemoryCensus> {
        let Memory::Graph(a) = &self.memory else { return None };
        let every = a.graph.config().census_every;
        if every == 0 || a.episodes % every != 0 {
            return None;
        }
        let c = a.graph.census();
        let valued = c.values.iter().filter(|&&v| v != 0.0).count();
        // `values` is sorted: the middle one, or the mean of the middle two.
        let n = c.values.len();
        let median = match n {
            0 => 0.0,
            _ if n % 2 == 1 => c.values[n / 2],
            _ => (c.values[n / 2 - 1] + c.values[n / 2]) / 2.0,
        };
        Some(MemoryCensus {
            nodes: c.nodes,
            valued_share: if c.nodes == 0 { 0.0 } else { valued as f64 / c.nodes as f64 },
            median_value: median,
        })
    }

    fn entropy(&self) -> f64 {
        self.progress.entropy
    }

    fn memory_use(&self) -> MemoryUse {
        match &self.memory {
            Memory::Replay(r) => MemoryUse { used: r.len(), capacity: self.cfg.replay_size },
            Memory::Graph(a) => MemoryUse { used: a.graph.len(), capacity: a.graph.capacity() },
        }
    }

    fn checkpoints(&self) -> bool {
        true
    }

    fn save_state(&self, out: &mut dyn std::io::Write) -> Result<(), String> {
        checkpoint::save(self, out)
    }

    fn load_state(&mut self, input: &mut dyn std::io::Read) -> Result<(), String> {
        checkpoint::load(self, input)
    }
}

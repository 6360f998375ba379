//! The replay buffer: the last `capacity` transitions (state, action, reward, next state, done),
//! as the authors' deque keeps them. Their agent always continues from the next state it stored,
//! so transition k's state is transition k-1's next state: one ring of frames holds both, and the
//! buffer costs one 84x84x3 byte frame per transition instead of two float ones.

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use sec_playground::memory::ACTIONS;
use std::collections::VecDeque;

/// A transition besides its frames.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Meta {
    /// The action taken (0..=8).
    pub action: u8,
    /// Its reward.
    pub reward: f32,
    /// Whether it ended the episode.
    pub done: bool,
}

/// The replay buffer: a chain of frames, each transition between two neighbours, so a frame is
/// stored once.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Replay {
    capacity: usize,
    /// Frames of the stored transitions' states, then the newest next state.
    #[serde(with = "frames")]
    frames: VecDeque<Vec<u8>>,
    meta: VecDeque<Meta>,
}

/// One sampled transition.
pub struct Sample<'a> {
    /// The state's frame.
    pub state: &'a [u8],
    /// The next state's frame.
    pub next: &'a [u8],
    /// The rest of the transition.
    pub meta: Meta,
}

impl Replay {
    /// An empty buffer of `capacity` transitions.
    pub fn new(capacity: usize) -> Self {
        Replay { capacity, frames: VecDeque::new(), meta: VecDeque::new() }
    }

    /// Transitions stored.
    pub fn len(&self) -> usize {
        self.meta.len()
    }

    /// Whether it stores no transition.
    pub fn is_empty(&self) -> bool {
        self.meta.is_empty()
    }

    /// Whether the chain has a state to continue from.
    pub fn started(&self) -> bool {
        !self.frames.is_empty()
    }

    /// The first state, before any transition.
    pub fn start(&mut self, frame: Vec<u8>) {
        self.frames.clear();
        self.meta.clear();
        self.frames.push_back(frame);
    }

    /// A transition from the newest state to `next`; the oldest falls out of a full buffer.
    pub fn push(&mut self, meta: Meta, next: Vec<u8>) {
        debug_assert!(self.started(), "start() first");
        self.meta.push_back(meta);
        self.frames.push_back(next);
        if self.meta.len() > self.capacity {
            self.meta.pop_front();
            self.frames.pop_front();
        }
    }

    /// Transition `i` (0 the oldest).
    pub fn get(&self, i: usize) -> Sample<'_> {
        Sample { state: &self.frames[i], next: &self.frames[i + 1], meta: self.meta[i] }
    }

    /// Whether a buffer read from a checkpoint is one `push` could have made: a frame per
    /// transition and one more, frames of `frame_len` bytes, at most `capacity` transitions.
    pub fn check(&self, capacity: usize, frame_len: usize) -> Result<(), String> {
        if self.capacity != capacity || self.meta.len() > capacity {
            return Err(format!(
                "replay: {} transitions of capacity {}, not {capacity}",
                self.meta.len(),
                self.capacity
            ));
        }
        if self.frames.len() != self.meta.len() + usize::from(!self.frames.is_empty()) {
            return Err(format!("replay: {} frames for {} transitions", self.frames.len(), self.meta.len()));
        }
        if self.frames.iter().any(|f| f.len() != frame_len) {
            return Err(format!("replay: a frame is not {frame_len} bytes"));
        }
        if let Some(m) = self.meta.iter().find(|m| m.action as usize >= ACTIONS || !m.reward.is_finite()) {
            return Err(format!("replay: a transition of action {} and reward {}", m.action, m.reward));
        }
        Ok(())
    }

    /// `n` indices drawn uniformly with replacement (numpy's `randint(0, len, n)`).
    pub fn sample_indices(&self, n: usize, rng: &mut ChaCha8Rng) -> Vec<usize> {
        (0..n).map(|_| rng.gen_range(0..self.len() as u32) as usize).collect()
    }
}

/// The frames as CBOR byte strings (a sequence of integers would double the size).
mod frames {
    use serde::{Deserialize, Deserializer, Serializer};
    use serde_bytes::{ByteBuf, Bytes};
    use std::collections::VecDeque;

    pub fn serialize<S: Serializer>(frames: &VecDeque<Vec<u8>>, s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(frames.iter().map(|f| Bytes::new(f)))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<VecDeque<Vec<u8>>, D::Error> {
        Ok(Vec::<ByteBuf>::deserialize(d)?.into_iter().map(ByteBuf::into_vec).collect())
    }
}

//! The reactive layer (docs/ALGORITHM.md, "The reactive layer"): a random walk of straight runs and turns in
//! place, the only exploration SEC has. It advances at every decision, even when the contextual
//! layer's action is the one taken, and keeps its state across episodes.

use super::controller::{Controller, EpisodeEnd, MemoryUse, Observation, Step};
use super::{Decision, Layer};
use crate::arena::Action;
use crate::error::FileError;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// The walk's straight run: forward (1, 0).
pub const FORWARD: Action = Action::FORWARD;
/// The walk's turn in place one way (0, 1), right.
pub const TURN_1: Action = Action::RIGHT;
/// The walk's turn in place the other way (0, 2), left.
pub const TURN_2: Action = Action::LEFT;

/// The longest straight run or turn of a cycle after the first (numpy `randint(1, 21)`).
const MAX_LENGTH: u32 = 20;

/// The walk's state as its four counters: what a checkpoint holds, checked into a `Reactive`.
#[derive(serde::Deserialize)]
struct Words {
    c: u32,
    straight: u32,
    turns: u32,
    dir: u32,
}

impl TryFrom<Words> for Reactive {
    type Error = FileError;
    fn try_from(w: Words) -> Result<Self, FileError> {
        Reactive::from_words([w.c, w.straight, w.turns, w.dir])
    }
}

/// The walk's state: a counter through `straight` forward steps then `turns` turns. Read back
/// from a checkpoint only through `from_words`, which refuses a state no walk reaches.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "Words")]
pub struct Reactive {
    c: u32,
    straight: u32,
    turns: u32,
    dir: u32,
}

impl Reactive {
    /// The first cycle draws its lengths from 1..=19 (numpy `randint(1, 20)`) and turns with
    /// direction 0.
    pub fn new(rng: &mut ChaCha8Rng) -> Self {
        let straight = rng.gen_range(1..20u32);
        let turns = rng.gen_range(1..20u32);
        Reactive { c: 0, straight, turns, dir: 0 }
    }

    /// The walk's state as four words (a run checkpoint's), and back.
    pub(crate) fn words(&self) -> [u32; 4] {
        [self.c, self.straight, self.turns, self.dir]
    }

    /// The walk of `words`, refused (by the counter's name and value) unless a walk reaches it:
    /// lengths in 1..=20, a direction of 0 or 1, the counter within the cycle. An unchecked
    /// length of 2^32 - 1 overflows the next step's sum.
    pub fn from_words([c, straight, turns, dir]: [u32; 4]) -> Result<Self, FileError> {
        let bad = |name: &str, rule: String| FileError::field("checkpoint", format!("reactive.{name}"), rule);
        for (name, v) in [("straight", straight), ("turns", turns)] {
            if !(1..=MAX_LENGTH).contains(&v) {
                return Err(bad(name, format!("{v} is out of range 1..={MAX_LENGTH}")));
            }
        }
        if dir > 1 {
            return Err(bad("dir", format!("{dir} is out of range 0..=1")));
        }
        if c > straight + turns {
            return Err(bad("c", format!("{c} is out of range 0..={} (straight + turns)", straight + turns)));
        }
        Ok(Reactive { c, straight, turns, dir })
    }

    /// The next action. After the first cycle each one is `straight + 1` forward steps then
    /// `turns` turns, with lengths from 1..=20 and a direction drawn anew.
    pub fn step(&mut self, rng: &mut ChaCha8Rng) -> Action {
        self.c += 1;
        if self.c > self.straight + self.turns {
            self.c = 0;
            self.dir = rng.gen_range(0..2u32);
            self.straight = rng.gen_range(1..=MAX_LENGTH);
            self.turns = rng.gen_range(1..=MAX_LENGTH);
        }
        if self.c <= self.straight {
            FORWARD
        } else if self.dir == 0 {
            TURN_1
        } else {
            TURN_2
        }
    }
}

/// The reactive walk alone, as a baseline.
impl Controller for Reactive {
    fn on_step(&mut self, _: &Step, _: Option<&[f32]>, _: &mut ChaCha8Rng) -> bool {
        false
    }

    fn decide(&mut self, _: &Observation, _: &mut dyn FnMut() -> f32, rng: &mut ChaCha8Rng) -> Decision {
        Decision { action: self.step(rng), layer: Layer::Reactive, selected: false }
    }

    fn on_episode_end(&mut self, _: &EpisodeEnd) {}

    fn entropy(&self) -> f64 {
        0.0
    }

    fn memory_use(&self) -> MemoryUse {
        MemoryUse::default()
    }

    fn checkpoints(&self) -> bool {
        true
    }

    fn save_state(&self, out: &mut dyn std::io::Write) -> Result<(), String> {
        serde_json::to_writer(out, self).map_err(|e| e.to_string())
    }

    fn load_state(&mut self, input: &mut dyn std::io::Read) -> Result<(), String> {
        *self = serde_json::from_reader(input).map_err(|e| e.to_string())?;
        Ok(())
    }
}

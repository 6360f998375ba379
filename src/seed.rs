//! The random streams of a run: every consumer draws from its own ChaCha8 stream of the run's
//! seed, so a run is a pure function of (configuration, seed) and extra draws in one part never
//! shift another's.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The largest seed: the largest integer a JS number holds exactly (2^53 - 1), so a seed goes
/// through the page, the URL and JSON unchanged.
pub const MAX_SEED: u64 = (1 << 53) - 1;

/// Who draws from which stream of a seed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stream {
    /// The environment: layout order, start positions and headings.
    Env = 0,
    /// The agent: the reactive walk, SEC's draws, MFEC's exploration. The trace replays it.
    Agent = 1,
    /// MFEC-rp's random projection.
    Projection = 2,
    /// The untrained encoder's Glorot weights (D20).
    UntrainedEncoder = 3,
    /// DQN's initial network weights.
    Network = 4,
}

/// The generator of `stream` of `seed`.
pub fn rng(seed: u64, stream: Stream) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(stream as u64);
    rng
}

/// Draws an index with probabilities `p` (summing to 1): the first index whose cumulative sum
/// exceeds a uniform draw; never an index of probability 0.
pub fn sample(p: &[f64], rng: &mut ChaCha8Rng) -> usize {
    let u: f64 = rng.gen();
    let mut c = 0.0;
    let mut last = 0;
    for (i, &pi) in p.iter().enumerate() {
        if pi > 0.0 {
            c += pi;
            last = i;
            if u < c {
                return i;
            }
        }
    }
    last
}

//! Test and benchmark fixtures (`--features test-hooks`, which the tests and benchmarks turn on):
//! the golden runs whose logs every target must reproduce, and an LTM filled for timing decisions.

use super::{AgentKind, Run, RunConfig};
use crate::agent::mfec::{Embedding, MfecConfig};
use crate::agent::SecConfig;
use crate::arena::Action;
use crate::encoder::{PerceptionKind, Scratch, EMBEDDING, IMAGE};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// Benchmark helper: fills SEC's LTM up to `rows` sequences (at most m) of real embeddings
/// from a random walk of a copy of the environment, with random rewards, as if that many
/// goals had been reached. This changes the run (its memory), so it is for measuring
/// decisions over a full LTM only; the env, the STM position and the run's own draws stay.
pub fn fill_ltm(run: &mut Run, rows: usize) {
    use rand::Rng;
    let Some(memory) = run.inspect().memory else { return };
    let mut memory = memory.clone();
    let mut rng = ChaCha8Rng::seed_from_u64(0xBE7C);
    let mut env = run.env.clone();
    let (mut image, mut scratch) = (vec![0.0; IMAGE], Scratch::default());
    let mut action = Action::NOOP;
    // Counted in stores, not in rows: with forgetting on, a full LTM stays one row short.
    let target = rows.min(memory.config().m);
    let mut stores = 0;
    while stores < target && memory.len() < target {
        if env.is_over() {
            env.reset(None);
        }
        env.advance(action, 4).expect("the episode is not over");
        env.observation().to_rgb_f32(&mut image);
        let mut e = [0.0; EMBEDDING];
        run.perception.embed(&image, &mut scratch, &mut e);
        action = Action::new(rng.gen_range(0..9)).expect("actions are 0..9");
        memory.push(crate::memory::Couplet { embedding: e, action });
        if rng.gen_bool(0.2) {
            memory.store(rng.gen_range(0.5..3.0), &mut rng);
            stores += 1;
        }
    }
    // Through the agent's own door: a memory file, as the page loads one.
    let file = memory.to_file(&run.identity());
    run.load_memory(&file).expect("a memory of the run's own configuration loads");
}

/// The short runs whose JSON lines the golden files hold: `tests/golden/run.txt` with the
/// trained perception (the log from before the untrained one existed, kept to prove it
/// unchanged) and `tests/golden/run-untrained.txt` with the default, untrained one. Native and
/// wasm builds must reproduce them bit for bit (the JSON numbers are shortest round-trip
/// decimals).
pub fn golden_run(perception: PerceptionKind) -> String {
    // Object permanence: goals come early, so the LTM fills and the contextual layer acts (with
    // the untrained encoder from the 16th episode of seed 2).
    let (seed, sec_episodes) = match perception {
        PerceptionKind::Trained => (7, 16),
        PerceptionKind::Untrained => (2, 20),
    };
    let sec = RunConfig { task: "object-permanence".into(), perception, ..RunConfig::default() };
    let mut mfec_rp = RunConfig { kind: AgentKind::Mfec, t: Some(250), ..sec.clone() };
    mfec_rp.section_mut::<MfecConfig>().embedding = Embedding::RandomProjection;
    mfec_rp.section_mut::<MfecConfig>().warmup_decisions = 100;
    mfec_rp.section_mut::<MfecConfig>().warmup_rewarded_episodes = 1;
    let mfec_ae = mfec_rp.clone().with_section(MfecConfig {
        warmup_decisions: 100,
        warmup_rewarded_episodes: 1,
        ..MfecConfig::default()
    });
    let reactive = RunConfig { kind: AgentKind::Reactive, ..mfec_rp.clone() };
    let mut log = String::new();
    for (cfg, episodes) in [(sec, sec_episodes), (mfec_ae, 6), (mfec_rp, 6), (reactive, 2)] {
        let mut run = Run::new(cfg, seed).expect("the golden configurations are valid");
        for _ in 0..episodes {
            log += &run.episode().to_json();
            log.push('\n');
        }
    }
    log
}

/// Episodes of [`golden_textured_run`].
pub const TEXTURED_EPISODES: usize = 30;

/// The short run whose JSON lines `tests/golden/run-textured.txt` holds: SEC in the double T-maze
/// drawn textured (its gate the textured model), seed 1, acting from memory after its first stored
/// sequence so that the textured model's gate decides within a few episodes. Native, wasm and
/// Python reproduce it bit for bit.
pub fn golden_textured_run() -> String {
    let cfg = RunConfig { surface: crate::render::Surface::Textured, ..RunConfig::default() };
    acting_at_once_log(cfg, 1, TEXTURED_EPISODES)
}

/// The JSON lines of `episodes` episodes of SEC with `cfg` and `seed`, acting from memory after
/// its first stored sequence (`minSequences` 1).
fn acting_at_once_log(mut cfg: RunConfig, seed: u64, episodes: usize) -> String {
    cfg.section_mut::<SecConfig>().min_sequences = 1;
    let mut run = Run::new(cfg, seed).expect("the golden configuration is valid");
    (0..episodes).map(|_| run.episode().to_json() + "\n").collect()
}

/// The Olympics arena of the golden arena run: a ramp up to a platform (the 3-D world) in
/// spatial reasoning, with its own t of 500.
pub const ARENA_FILE: (&str, &str) = ("05-25-01", include_str!("../../assets/arenas/competition/05-25-01.yaml"));
/// Episodes of `golden_arena_run`.
pub const ARENA_EPISODES: usize = 12;

/// The golden log of SEC playing an Olympics arena file (`RunConfig::with_arena`: the untrained
/// encoder, no gate), seed 3, acting from memory after its first stored sequence. Native, wasm
/// (the arena build) and Python reproduce it bit for bit.
pub fn golden_arena_run() -> String {
    let cfg = RunConfig::default().with_arena(ARENA_FILE.0, ARENA_FILE.1).expect("the golden arena loads");
    acting_at_once_log(cfg, 3, ARENA_EPISODES)
}

//! The fuzz suite: mutations of every format the crate parses (Animal-AI YAML arenas, memory
//! files, weights files, RunConfig JSON, the URL hash's settings), each of which must be accepted
//! or refused with an error, never a panic or a hang, and a refused memory file must leave the
//! memory as it was; a run checkpoint too (a SEC run with sequences in its LTM, its checksum
//! recomputed in three cases of four), whose resumed run must play an episode of finite numbers. Mutations: byte flips, inserted bytes or format tokens, deletions and
//! duplicated spans; for the binary files half the cases get their checksum recomputed, so the
//! parser behind the checksum is reached. Then the regression corpus (`tests/corpus/`, issue 20's
//! reproducers), all refused.
//!
//! `cargo test --test fuzz` runs 256 cases per format (under a second); more on demand:
//! `PROPTEST_CASES=20000 cargo test --release --test fuzz`.
#![cfg(not(target_arch = "wasm32"))]

use proptest::prelude::*;
use proptest::test_runner::Config;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use sec_playground::arena::survey::features;
use sec_playground::arena::yaml::load_task;
use sec_playground::arena::World;
use sec_playground::encoder::{bundled, Autoencoder, DType, Weights};
use sec_playground::experiment::checkpoint::ResumeCheck;
use sec_playground::experiment::settings::{self, Settings};
use sec_playground::experiment::RunConfig;
use sec_playground::memory::file::Identity;
use sec_playground::memory::{Couplet, Memory, MemoryConfig};
use sec_playground::render::fnv1a;
use std::path::Path;

/// Words of the formats, inserted whole so that mutations reach past the tokenizer.
const TOKENS: &[&str] = &[
    "- ",
    "[",
    "]",
    "{",
    "}",
    ": ",
    "\n",
    "  ",
    "!Item",
    "!Arena",
    "!Vector3",
    "!RGB",
    "name: ",
    "positions: ",
    "sizes: ",
    "colors: ",
    "rotations: ",
    "items:",
    "t: ",
    "-1",
    "0",
    "1e39",
    "NaN",
    "inf",
    "Wall",
    "GoodGoal",
    "Agent",
    "DeathZone",
    "\"",
    "&a",
    "*a",
    "x: 5",
    "99999999999",
    "\"agent\"",
    "\"memory\"",
    ":",
    ",",
    "null",
    "true",
    "-0.0",
    "1e308",
];

#[derive(Clone, Debug)]
enum Edit {
    Flip(usize, u8),
    Insert(usize, Vec<u8>),
    Token(usize, usize),
    Delete(usize, usize),
    Duplicate(usize, usize),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        (any::<usize>(), any::<u8>()).prop_map(|(i, b)| Edit::Flip(i, b)),
        (any::<usize>(), prop::collection::vec(any::<u8>(), 1..8)).prop_map(|(i, b)| Edit::Insert(i, b)),
        (any::<usize>(), 0..TOKENS.len()).prop_map(|(i, t)| Edit::Token(i, t)),
        (any::<usize>(), 1usize..64).prop_map(|(i, n)| Edit::Delete(i, n)),
        (any::<usize>(), 1usize..256).prop_map(|(i, n)| Edit::Duplicate(i, n)),
    ]
}

fn edits() -> impl Strategy<Value = Vec<Edit>> {
    prop::collection::vec(edit(), 1..6)
}

/// `seed` with `edits` applied (positions taken modulo the length).
fn mutate(seed: &[u8], edits: &[Edit]) -> Vec<u8> {
    let mut b = seed.to_vec();
    for e in edits {
        let at = |i: usize, b: &Vec<u8>| if b.is_empty() { 0 } else { i % (b.len() + 1) };
        match e {
            Edit::Flip(i, x) if !b.is_empty() => {
                let i = i % b.len();
                b[i] ^= x | 1;
            }
            Edit::Flip(..) => {}
            Edit::Insert(i, bytes) => {
                let i = at(*i, &b);
                b.splice(i..i, bytes.iter().copied());
            }
            Edit::Token(i, t) => {
                let i = at(*i, &b);
                b.splice(i..i, TOKENS[*t].bytes());
            }
            Edit::Delete(i, n) => {
                let i = at(*i, &b);
                let end = (i + n).min(b.len());
                b.drain(i..end);
            }
            Edit::Duplicate(i, n) => {
                let i = at(*i, &b);
                let end = (i + n).min(b.len());
                let span: Vec<u8> = b[i..end].to_vec();
                b.splice(i..i, span);
            }
        }
    }
    b
}

/// A binary file's body mutated, its FNV-1a checksum (the last 8 bytes) recomputed or not.
fn mutate_checked(file: &[u8], edits: &[Edit], fix: bool) -> Vec<u8> {
    if !fix || file.len() < 8 {
        return mutate(file, edits);
    }
    let mut body = mutate(&file[..file.len() - 8], edits);
    let sum = fnv1a(&body);
    body.extend_from_slice(&sum.to_le_bytes());
    body
}

fn cases() -> Config {
    let cases = std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(256);
    Config { cases, failure_persistence: None, ..Config::default() }
}

/// The arena files the mutations start from: the tasks' and the 900 Olympics arenas (read once).
fn arena_files() -> &'static [String] {
    static FILES: std::sync::OnceLock<Vec<String>> = std::sync::OnceLock::new();
    FILES.get_or_init(|| {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/arenas");
        let mut files = Vec::new();
        for dir in [root.clone(), root.join("competition")] {
            files.extend(
                std::fs::read_dir(dir)
                    .unwrap()
                    .map(|e| e.unwrap().path())
                    .filter(|p| p.extension().is_some_and(|e| e == "yml" || e == "yaml")),
            );
        }
        files.sort();
        files.iter().map(|p| std::fs::read_to_string(p).unwrap()).collect()
    })
}

/// What a fuzzed memory file is loaded into, and the file it was made from.
fn memory_and_file() -> (Memory, Vec<u8>, Identity) {
    let id = Identity { task: "detour".into(), model: 0x5EC };
    let cfg = MemoryConfig { n: 4, m: 6, ..MemoryConfig::default() };
    let mut mem = Memory::new(cfg.clone()).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for k in 0..12u32 {
        let embedding = std::array::from_fn(|i| ((k as usize * 7 + i) % 11) as f32 / 11.0);
        mem.push(Couplet { embedding, action: sec_playground::arena::Action::ALL[k as usize % 9] });
        if k % 4 == 3 {
            mem.store(1.0 + k as f64, &mut rng);
        }
    }
    let file = mem.to_file(&id);
    (Memory::new(cfg).unwrap(), file, id)
}

proptest! {
    #![proptest_config(cases())]

    #[test]
    fn yaml_arenas(file in 0usize..1000, edits in edits()) {
        let files = arena_files();
        let src = mutate(files[file % files.len()].as_bytes(), &edits);
        let text = String::from_utf8_lossy(&src);
        // What the arenas report reads of a file, leniently: never a panic either.
        let _ = features(&text);
        if let Ok(task) = load_task("fuzzed", &text) {
            for layout in &task.layouts {
                World::spawn(layout, &mut ChaCha8Rng::seed_from_u64(1));
            }
        }
    }

    #[test]
    fn memory_files(edits in edits(), fix in any::<bool>()) {
        let (mut mem, file, id) = memory_and_file();
        let before = mem.to_file(&id);
        let bytes = mutate_checked(&file, &edits, fix);
        match mem.load_file(&bytes, &id) {
            Ok(rows) => prop_assert!(rows <= mem.config().m && mem.len() == rows),
            Err(_) => prop_assert_eq!(mem.to_file(&id), before, "a refused file leaves the memory as it was"),
        }
    }

    #[test]
    fn weights_files(edits in edits(), fix in any::<bool>()) {
        let file = WEIGHTS.with(|w| w.clone());
        let bytes = mutate_checked(&file, &edits, fix);
        if let Ok(w) = Weights::from_bytes(&bytes) {
            let _ = Autoencoder::from_weights(&w);
        }
    }

    #[test]
    fn run_configs(edits in edits()) {
        let valid = serde_json::to_string(&RunConfig::default()).unwrap();
        let text = String::from_utf8_lossy(&mutate(valid.as_bytes(), &edits)).into_owned();
        if let Ok(cfg) = serde_json::from_str::<RunConfig>(&text) {
            let _ = cfg.validate();
        }
    }

    #[test]
    fn hash_settings(pairs in prop::collection::vec((0usize..40, prop::collection::vec(any::<u8>(), 0..12), 0usize..TOKENS.len()), 0..8)) {
        let keys: Vec<String> = settings::params().iter().map(|p| p.key.to_string()).collect();
        let mut s = Settings::new();
        for (k, raw, token) in pairs {
            let key = keys.get(k).cloned().unwrap_or_else(|| String::from_utf8_lossy(&raw).into_owned());
            let value = if k % 2 == 0 { TOKENS[token].to_string() } else { String::from_utf8_lossy(&raw).into_owned() };
            s.insert(key, value);
        }
        let (cfg, _, _) = settings::from_settings(&s);
        prop_assert!(cfg.validate().is_ok(), "bad settings keep their defaults, so the config stays valid");
    }
}

thread_local! {
    /// The smallest bundled model's file (f16).
    static WEIGHTS: Vec<u8> = bundled::autoencoder("detour").unwrap().to_weights().to_bytes(DType::F16Planes);
}

/// Issue 20's reproducers, kept as files: every one is refused with an error naming its line and
/// field (the YAML ones) or the file and field, quickly.
#[test]
fn the_regression_corpus_is_refused_cleanly() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/corpus");
    let mut seen = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let bytes = std::fs::read(&path).unwrap();
        let t0 = std::time::Instant::now();
        let message = match path.extension().and_then(|e| e.to_str()) {
            Some("yaml") => load_task(&name, &String::from_utf8_lossy(&bytes)).err().map(|e| e.to_string()),
            // As the CLI's --config reads it: the field named (serde_path_to_error).
            Some("json") => match serde_path_to_error::deserialize::<_, RunConfig>(
                &mut serde_json::Deserializer::from_slice(&bytes),
            ) {
                Ok(cfg) => cfg.validate().err().map(|e| e.to_string()),
                Err(e) => Some(format!("{}: {}", e.path(), e.inner())),
            },
            Some("hash") => {
                let text = String::from_utf8_lossy(&bytes);
                let s: Settings = text
                    .trim()
                    .split('&')
                    .map(|kv| kv.split_once('=').unwrap_or((kv, "")))
                    .map(|(k, v)| (k.to_string(), v.to_string()))
                    .collect();
                settings::from_settings(&s).2.first().map(|e| e.to_string())
            }
            _ => continue,
        };
        let message = message.unwrap_or_else(|| panic!("{name} was accepted"));
        assert!(message.len() < 1000, "{name}: a message of {} bytes", message.len());
        assert!(!message.starts_with(": "), "{name}: the message names nothing: {message}");
        assert!(t0.elapsed().as_secs_f64() < 2.0, "{name} took {:?}", t0.elapsed());
        seen += 1;
    }
    assert!(seen >= 6, "the corpus holds {seen} files");
}

/// A SEC run's checkpoint with a few sequences in its LTM, the run's configuration and its log.
fn sec_checkpoint() -> (Vec<u8>, RunConfig, String) {
    let cfg = RunConfig { task: "object-permanence".into(), t: Some(100), ..RunConfig::default() };
    let mut run = sec_playground::experiment::Run::new(cfg.clone(), 3).unwrap();
    sec_playground::experiment::fixtures::fill_ltm(&mut run, 6);
    let log = run.episode().to_json() + "\n";
    let mut bytes = Vec::new();
    run.save_checkpoint(&mut bytes).unwrap();
    (bytes, cfg, log)
}

thread_local! {
    static CHECKPOINT: (Vec<u8>, RunConfig, String) = sec_checkpoint();
}

proptest! {
    #![proptest_config(cases())]

    /// Three cases in four get their checksum recomputed, so the value checks behind it are
    /// reached; half of those resume beside the run's log. A checkpoint that loads must play an
    /// episode of finite numbers, without a panic (the tests build with overflow checks: a walk
    /// counter at 2^32 - 1 panicked in the first decision before its check).
    #[test]
    fn run_checkpoints(edits in edits(), fix in 0u8..4) {
        let (file, cfg, log) = CHECKPOINT.with(|c| c.clone());
        let bytes = mutate_checked(&file, &edits, fix != 0);
        let check = ResumeCheck { max_episodes: 1000, log: (fix >= 2).then_some(log.as_str()), legacy: false };
        if let Ok(mut run) = sec_playground::experiment::Run::resume(cfg, 3, None, &mut bytes.as_slice(), &check) {
            let m = run.episode();
            prop_assert!(m.reward.is_finite() && m.entropy.is_finite() && m.contextual_share.is_finite());
        }
    }
}

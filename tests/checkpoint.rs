//! Run checkpoints are as trustworthy as the memory files (issue 39): a checksum over the whole
//! file and every value checked on load. The regression corpus is the 17 hostile edits that
//! version 2 accepted (or accepted holding NaN or infinity): each is refused by name, by the
//! checksum as it stands and, with the checksum recomputed, by the check of the value it broke
//! (where the value is not a legal one: an episode count one off or a word position of 0 are
//! legal values, which only the checksum and the runner's log check catch). Version 2 still loads.
#![cfg(not(target_arch = "wasm32"))]

use sec_playground::agent::SecConfig;
use sec_playground::encoder::{EMBEDDING, IMAGE};
use sec_playground::experiment::checkpoint::ResumeCheck;
use sec_playground::experiment::{fixtures, Run, RunConfig};
use sec_playground::render::fnv1a;
use serde_json::Value;

const SEED: u64 = 3;

fn config() -> RunConfig {
    RunConfig { task: "object-permanence".into(), t: Some(100), ..RunConfig::default() }
}

/// A SEC run with six sequences in its LTM, two episodes played, and its checkpoint.
fn checkpoint(cfg: &RunConfig) -> Vec<u8> {
    with_log(cfg).0
}

/// `checkpoint` and the run's log (one JSON line per episode, as the runner writes it).
fn with_log(cfg: &RunConfig) -> (Vec<u8>, String) {
    let mut run = Run::new(cfg.clone(), SEED).unwrap();
    fixtures::fill_ltm(&mut run, 6);
    let log: String = (0..2).map(|_| run.episode().to_json() + "\n").collect();
    let mut bytes = Vec::new();
    run.save_checkpoint(&mut bytes).unwrap();
    (bytes, log)
}

fn u64_at(b: &[u8], at: usize) -> usize {
    u64::from_le_bytes(b[at..at + 8].try_into().unwrap()) as usize
}

/// Where the values of a version-4 SEC checkpoint lie (the named ones the edits below poke).
struct Layout {
    header: std::ops::Range<usize>,
    gate_mse: usize,
    gate_steps: usize,
    ltm: usize,
    rewards: usize,
    t: usize,
    p: usize,
    entropy: usize,
}

/// What a field of the format holds, which says the value that no live run could hold there.
#[derive(Clone, Copy, Debug)]
enum Kind {
    /// A u64 length before an array (more than the array may hold).
    Count,
    F32,
    F64,
    /// A byte that is 0 or 1.
    Bool,
    /// An action index (0..=8).
    Action,
    /// A selection mask byte (0 or 1).
    Mask,
    /// A u32 counter or index (its largest value is out of every range).
    U32,
    /// A u64 counter or index.
    U64,
}

impl Kind {
    fn poison(self) -> Vec<u8> {
        match self {
            Kind::Count | Kind::U64 => u64::MAX.to_le_bytes().to_vec(),
            Kind::F32 => f32::NAN.to_le_bytes().to_vec(),
            Kind::F64 => f64::NAN.to_le_bytes().to_vec(),
            Kind::Bool | Kind::Mask => vec![2],
            Kind::Action => vec![9],
            Kind::U32 => u32::MAX.to_le_bytes().to_vec(),
        }
    }
}

/// Every field of a version-4 SEC checkpoint after its header, in file order: (name, offset,
/// kind, the word its refusal must hold). An array is one field (its first element is poisoned)
/// after its count. Walking the file this way fails (the assertion at the end) when the format
/// gains a field this list does not know, so no field is added without a value check behind it.
fn fields(b: &[u8]) -> (Layout, Vec<(String, usize, Kind, &'static str)>) {
    let hlen = u32::from_le_bytes(b[8..12].try_into().unwrap()) as usize;
    let header = 12..12 + hlen;
    let mut f: Vec<(String, usize, Kind, &'static str)> = Vec::new();
    let mut at = header.end;
    let field = |f: &mut Vec<_>, at: &mut usize, name: &str, kind: Kind, size: usize, word: &'static str| {
        f.push((name.to_string(), *at, kind, word));
        *at += size;
    };
    // An array: its u64 count, then `n` values of `size` bytes.
    let array = |f: &mut Vec<_>, at: &mut usize, name: &'static str, kind: Kind, size: usize, word: &'static str| {
        let n = u64_at(b, *at);
        f.push((format!("{name} count"), *at, Kind::Count, name));
        *at += 8;
        if n > 0 {
            f.push((name.to_string(), *at, kind, word));
        }
        *at += n * size;
        n
    };
    field(&mut f, &mut at, "gate length", Kind::Count, 8, "gate");
    let gate_mse = at;
    field(&mut f, &mut at, "gate.mse", Kind::F32, 4, "gate.mse");
    let gate_steps = at;
    field(&mut f, &mut at, "gate.steps", Kind::U64, 8, "gate.steps");
    field(&mut f, &mut at, "gate.pending", Kind::Bool, 1, "boolean");
    assert_eq!(array(&mut f, &mut at, "gate.image", Kind::F32, 4, "gate.image"), IMAGE);
    field(&mut f, &mut at, "gate.known", Kind::Bool, 1, "boolean");
    for i in 0..EMBEDDING {
        field(&mut f, &mut at, &format!("gate.embedding[{i}]"), Kind::F32, 4, "gate.embedding");
    }
    for name in ["reactive.c", "reactive.straight", "reactive.turns", "reactive.dir"] {
        field(&mut f, &mut at, name, Kind::U32, 4, "reactive.");
    }
    for i in 0..EMBEDDING {
        field(&mut f, &mut at, &format!("previous.embedding[{i}]"), Kind::F32, 4, "previous");
    }
    field(&mut f, &mut at, "previous.action", Kind::Action, 1, "previous");
    field(&mut f, &mut at, "previous pushed", Kind::Bool, 1, "boolean");
    field(&mut f, &mut at, "stm head", Kind::U64, 8, "stmHead");
    let n = 50;
    for i in 0..n {
        field(&mut f, &mut at, &format!("stm[{i}].embedding"), Kind::F32, EMBEDDING * 4, "finite");
        field(&mut f, &mut at, &format!("stm[{i}].action"), Kind::Action, 1, "action");
    }
    let ltm = at + 8;
    array(&mut f, &mut at, "ltm", Kind::F32, 4, "ltm");
    array(&mut f, &mut at, "actions", Kind::Action, 1, "ltm");
    let rewards = at + 8;
    array(&mut f, &mut at, "rewards", Kind::F64, 8, "rewards");
    let t = at + 8;
    array(&mut f, &mut at, "t", Kind::F64, 8, "t");
    array(&mut f, &mut at, "sel", Kind::Mask, 1, "sel");
    array(&mut f, &mut at, "selPrev", Kind::Mask, 1, "sel");
    array(&mut f, &mut at, "g", Kind::F64, 8, "g");
    field(&mut f, &mut at, "forgot", Kind::Bool, 1, "boolean");
    array(&mut f, &mut at, "sim", Kind::F32, 4, "g");
    let selected = u64_at(b, at);
    field(&mut f, &mut at, "selected count", Kind::Count, 8, "selected");
    for i in 0..selected {
        field(&mut f, &mut at, &format!("selected[{i}].row"), Kind::U32, 4, "selected");
        field(&mut f, &mut at, &format!("selected[{i}].col"), Kind::U32, 4, "selected");
        for v in ["g", "t", "rr", "d", "value"] {
            field(&mut f, &mut at, &format!("selected[{i}].{v}"), Kind::F64, 8, "selected");
        }
        field(&mut f, &mut at, &format!("selected[{i}].action"), Kind::Action, 1, "selected");
    }
    for (name, word) in [("q", "q"), ("p", "p")] {
        for i in 0..9 {
            field(&mut f, &mut at, &format!("{name}[{i}]"), Kind::F64, 8, word);
        }
    }
    let p = at - 9 * 8;
    let entropy = at;
    field(&mut f, &mut at, "entropy", Kind::F64, 8, "entropy");
    assert_eq!(at + 8, b.len(), "the walk covers the whole file: a field was added to the format without a check here");
    (Layout { header, gate_mse, gate_steps, ltm, rewards, t, p, entropy }, f)
}

fn layout(b: &[u8]) -> Layout {
    fields(b).0
}

fn reseal(mut b: Vec<u8>) -> Vec<u8> {
    let body = b.len() - 8;
    let sum = fnv1a(&b[..body]);
    b[body..].copy_from_slice(&sum.to_le_bytes());
    b
}

fn put(b: &mut [u8], at: usize, bytes: &[u8]) {
    b[at..at + bytes.len()].copy_from_slice(bytes);
}

/// The checkpoint with its JSON header changed by `f` (lengths fixed up, checksum kept).
fn with_header(b: &[u8], f: impl FnOnce(&mut Value)) -> Vec<u8> {
    let l = layout(b);
    let mut h: Value = serde_json::from_slice(&b[l.header.clone()]).unwrap();
    f(&mut h);
    let json = serde_json::to_vec(&h).unwrap();
    let mut out = b[..8].to_vec();
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(&json);
    out.extend_from_slice(&b[l.header.end..]);
    out
}

/// The 17 edits: (name, the edited file, the configuration to resume with, the value check
/// that refuses it once the checksum is recomputed, if the value is not a legal one).
#[allow(clippy::type_complexity)]
fn edits(b: &[u8]) -> Vec<(&'static str, Vec<u8>, RunConfig, Option<&'static str>)> {
    let l = layout(b);
    let cfg = config();
    let at = |at: usize, bytes: &[u8]| {
        let mut e = b.to_vec();
        put(&mut e, at, bytes);
        e
    };
    let episodes = |d: i64| with_header(b, |h| h["episodes"] = Value::from(h["episodes"].as_i64().unwrap() + d));
    let mut m8 = cfg.clone();
    m8.section_mut::<SecConfig>().memory.m = 8;
    let mut small = config();
    small.section_mut::<SecConfig>().memory.m = 9;
    let nine = {
        let mut run = Run::new(small.clone(), SEED).unwrap();
        fixtures::fill_ltm(&mut run, 9);
        run.episode();
        let mut bytes = Vec::new();
        run.save_checkpoint(&mut bytes).unwrap();
        with_header(&bytes, |h| h["config"]["agent"]["memory"]["m"] = Value::from(8))
    };
    vec![
        ("episodes + 1", episodes(1), cfg.clone(), None),
        ("episodes - 1", episodes(-1), cfg.clone(), None),
        ("agent stream 0", with_header(b, |h| h["agentStream"] = "0".into()), cfg.clone(), None),
        (
            "agent stream 2^128 - 1",
            with_header(b, |h| h["agentStream"] = u128::MAX.to_string().into()),
            cfg.clone(),
            Some("agentStream"),
        ),
        ("reward NaN", at(l.rewards, &f64::NAN.to_le_bytes()), cfg.clone(), Some("rewards")),
        ("reward -1", at(l.rewards, &(-1f64).to_le_bytes()), cfg.clone(), Some("rewards")),
        ("reward 0", at(l.rewards, &0f64.to_le_bytes()), cfg.clone(), Some("rewards")),
        ("reward 1e308", at(l.rewards, &1e308f64.to_le_bytes()), cfg.clone(), Some("rewards")),
        ("reward inf", at(l.rewards, &f64::INFINITY.to_le_bytes()), cfg.clone(), Some("rewards")),
        ("gate MSE NaN", at(l.gate_mse, &f32::NAN.to_le_bytes()), cfg.clone(), Some("gate.mse")),
        ("m = 9 under a header of m = 8", nine, m8, Some("ltm")),
        ("LTM NaN", at(l.ltm, &f32::NAN.to_le_bytes()), cfg.clone(), Some("ltm")),
        ("LTM inf", at(l.ltm + 4, &f32::INFINITY.to_le_bytes()), cfg.clone(), Some("ltm")),
        ("T NaN", at(l.t, &f64::NAN.to_le_bytes()), cfg.clone(), Some("t")),
        ("entropy NaN", at(l.entropy, &f64::NAN.to_le_bytes()), cfg.clone(), Some("entropy")),
        ("p inf", at(l.p, &f64::INFINITY.to_le_bytes()), cfg.clone(), Some("p")),
        ("gate steps u64::MAX", at(l.gate_steps, &u64::MAX.to_le_bytes()), cfg, Some("gate.steps")),
    ]
}

fn refusal(bytes: &[u8], cfg: &RunConfig) -> Option<String> {
    Run::resume(cfg.clone(), SEED, None, &mut &bytes[..], &ResumeCheck::at_most(1000)).err().map(|e| e.to_string())
}

#[test]
fn the_seventeen_edits_are_refused_by_the_checksum_and_by_their_value() {
    let b = checkpoint(&config());
    assert!(b.starts_with(b"SECCKPT4"));
    assert!(refusal(&b, &config()).is_none(), "the file itself loads");
    let cases = edits(&b);
    assert_eq!(cases.len(), 17);
    for (name, edited, cfg, value) in cases {
        let err = refusal(&edited, &cfg).unwrap_or_else(|| panic!("{name}: accepted as it stands"));
        assert!(err.contains("checksum"), "{name}: {err}");
        let resealed = reseal(edited);
        match value {
            Some(field) => {
                let err =
                    refusal(&resealed, &cfg).unwrap_or_else(|| panic!("{name}: accepted with the checksum recomputed"));
                assert!(err.contains(field), "{name}: '{err}' does not name {field}");
            }
            // A legal value: the checksum is what catches it (and the runner's log check).
            None => assert!(refusal(&resealed, &cfg).is_none() || name.starts_with("episodes")),
        }
    }
}

#[test]
fn a_cut_file_and_another_version_are_refused_by_name() {
    let b = checkpoint(&config());
    for cut in [0, 7, 8, 20, b.len() / 2, b.len() - 1] {
        let err = refusal(&b[..cut], &config()).expect("a cut file is refused");
        assert!(["checksum", "truncated", "checkpoint", "end of file"].iter().any(|w| err.contains(w)), "{cut}: {err}");
    }
    let mut other = b.clone();
    other[7] = b'9';
    assert!(refusal(&other, &config()).unwrap().contains("re-run"));
}

#[test]
fn earlier_versions_load_only_when_asked_and_beside_their_log() {
    let cfg = config();
    let (b, log) = with_log(&cfg);
    let l = layout(&b);
    // Version 3: the same body without the log digest in the header; version 2: no checksum.
    let v3 = reseal(with_header(&b, |h| {
        h.as_object_mut().unwrap().remove("log");
    }));
    let mut v3 = v3;
    v3[..8].copy_from_slice(b"SECCKPT3");
    let v3 = reseal(v3);
    let mut v2 = v3[..v3.len() - 8].to_vec();
    v2[..8].copy_from_slice(b"SECCKPT2");
    // Relabelled as version 2 and cut by its checksum: no longer loads by default.
    for (name, file) in [("v3", &v3), ("v2", &v2)] {
        let err = refusal(file, &cfg).unwrap_or_else(|| panic!("{name} loaded without being asked"));
        assert!(err.contains("version") && err.contains("--legacy-checkpoint"), "{name}: {err}");
        let asked = ResumeCheck { max_episodes: 1000, log: None, legacy: true };
        let err = Run::resume(cfg.clone(), SEED, None, &mut &file[..], &asked).err().unwrap().to_string();
        assert!(err.contains("log"), "{name} without its log: {err}");
    }
    let legacy = ResumeCheck { max_episodes: 2, log: Some(&log), legacy: true };
    let mut a = Run::resume(cfg.clone(), SEED, None, &mut &b[..], &ResumeCheck::at_most(2)).unwrap();
    let mut c = Run::resume(cfg.clone(), SEED, None, &mut &v2[..], &legacy).unwrap();
    let mut d = Run::resume(cfg.clone(), SEED, None, &mut &v3[..], &legacy).unwrap();
    for _ in 0..3 {
        let line = a.episode().to_json();
        assert_eq!(line, c.episode().to_json());
        assert_eq!(line, d.episode().to_json());
    }
    // A legacy file's values are checked the same way (version 2 has no checksum to stop an
    // edit first).
    let shift = v2.len() as isize - (b.len() as isize - 8);
    let mut bad = v2.clone();
    put(&mut bad, (l.rewards as isize + shift) as usize, &f64::NAN.to_le_bytes());
    let err = Run::resume(cfg, SEED, None, &mut &bad[..], &legacy).err().unwrap().to_string();
    assert!(err.contains("rewards"), "{err}");
}

#[test]
fn every_field_of_the_format_is_checked() {
    let cfg = config();
    let (b, log) = with_log(&cfg);
    let check = ResumeCheck { max_episodes: 2, log: Some(&log), legacy: false };
    assert!(Run::resume(cfg.clone(), SEED, None, &mut &b[..], &check).is_ok(), "the file itself loads");
    let (_, walk) = fields(&b);
    assert!(walk.len() > 150, "{} fields", walk.len());
    let mut refused = 0;
    for (name, at, kind, word) in &walk {
        let mut e = b.clone();
        put(&mut e, *at, &kind.poison());
        let e = reseal(e);
        let err = Run::resume(cfg.clone(), SEED, None, &mut &e[..], &check)
            .err()
            .unwrap_or_else(|| panic!("{name} ({kind:?}) = {:?}: resumed", kind.poison()))
            .to_string();
        assert!(err.contains(word), "{name}: '{err}' does not name {word}");
        refused += 1;
    }
    // The header's fields, each to a value the run could not have written.
    let header_edits: Vec<(&str, Vec<u8>, &str)> = vec![
        ("seed", with_header(&b, |h| h["seed"] = (SEED + 1).into()), "seed"),
        ("config", with_header(&b, |h| h["config"]["t"] = 101.into()), "config"),
        ("episodes + 1", with_header(&b, |h| h["episodes"] = 3.into()), "episodes"),
        ("episodes - 1", with_header(&b, |h| h["episodes"] = 1.into()), "log"),
        ("agentStream", with_header(&b, |h| h["agentStream"] = u128::MAX.to_string().into()), "agentStream"),
        ("log", with_header(&b, |h| h["log"] = "0123456789abcdef".into()), "log"),
        ("log missing", with_header(&b, |h| drop(h.as_object_mut().unwrap().remove("log"))), "log"),
        ("unknown field", with_header(&b, |h| h["extra"] = 1.into()), "header"),
    ];
    for (name, edited, word) in header_edits {
        let err = Run::resume(cfg.clone(), SEED, None, &mut &reseal(edited)[..], &check)
            .err()
            .unwrap_or_else(|| panic!("header {name}: resumed"))
            .to_string();
        assert!(err.contains(word), "header {name}: '{err}' does not name {word}");
        refused += 1;
    }
    eprintln!("{refused} poisoned fields refused by name");
}

/// The reactive walk's counters: a state no walk reaches, written by the reactive baseline (its
/// state is JSON) or inside SEC's state, is refused by the counter's name. The 14 states below
/// are the two classes that panicked with "attempt to add with overflow" in the first decision
/// after a resume (a counter at 2^32 - 1, or lengths whose sum overflows).
#[test]
fn the_walks_counters_are_checked_and_the_overflow_states_are_refused() {
    const MAX: u32 = u32::MAX;
    let overflowing: [[u32; 4]; 14] = [
        [MAX, 5, 5, 0],
        [0, MAX, 1, 0],
        [0, 1, MAX, 0],
        [0, MAX, MAX, 1],
        [0, 1 << 31, 1 << 31, 0],
        [0, MAX - 5, 6, 0],
        [MAX, MAX, 1, 0],
        [MAX, 3, 4, 1],
        [2, 7, MAX, 1],
        [0, 0xFFFF_FF00, 0x100, 0],
        [0, MAX, 20, 1],
        [5, 20, MAX, 0],
        [1, 0x8000_0001, 0x7FFF_FFFF, 1],
        [MAX, MAX, MAX, MAX],
    ];
    let cfg = config();
    let (b, log) = with_log(&cfg);
    let check = ResumeCheck { max_episodes: 2, log: Some(&log), legacy: false };
    let walk_at = fields(&b).1.iter().find(|f| f.0 == "reactive.c").unwrap().1;
    for words in overflowing {
        let mut e = b.clone();
        for (i, w) in words.iter().enumerate() {
            put(&mut e, walk_at + 4 * i, &w.to_le_bytes());
        }
        let err = Run::resume(cfg.clone(), SEED, None, &mut &reseal(e)[..], &check)
            .err()
            .unwrap_or_else(|| panic!("{words:?}: resumed"))
            .to_string();
        assert!(err.contains("reactive."), "{words:?}: {err}");
    }
    // The reactive baseline's own checkpoint: the same checks through its JSON.
    let reactive = RunConfig { kind: sec_playground::experiment::AgentKind::Reactive, ..config() };
    let mut run = Run::new(reactive.clone(), SEED).unwrap();
    let log = run.episode().to_json() + "\n";
    let mut bytes = Vec::new();
    run.save_checkpoint(&mut bytes).unwrap();
    let check = ResumeCheck { max_episodes: 1, log: Some(&log), legacy: false };
    let key = b"{\"c\":";
    let state_at = bytes.windows(key.len()).rposition(|w| w == key).expect("the walk's JSON");
    for words in overflowing.iter().chain(&[[0, 0, 3, 0], [0, 3, 0, 0], [0, 21, 3, 0], [0, 3, 3, 2], [7, 3, 3, 0]]) {
        let json = format!(r#"{{"c":{},"straight":{},"turns":{},"dir":{}}}"#, words[0], words[1], words[2], words[3]);
        let mut e = bytes[..state_at].to_vec();
        e.extend_from_slice(json.as_bytes());
        e.extend_from_slice(&[0; 8]);
        let err = Run::resume(reactive.clone(), SEED, None, &mut &reseal(e)[..], &check)
            .err()
            .unwrap_or_else(|| panic!("reactive {words:?}: resumed"))
            .to_string();
        assert!(err.contains("reactive."), "reactive {words:?}: {err}");
    }
}

#[test]
fn a_claimed_count_is_bounded_by_the_caller_and_must_agree_with_the_log() {
    let cfg = config();
    let (b, log) = with_log(&cfg);
    fn at(n: u64, log: Option<&str>) -> ResumeCheck<'_> {
        ResumeCheck { max_episodes: n, log, legacy: false }
    }
    let field = |bytes: &[u8], check: &ResumeCheck| {
        Run::resume(cfg.clone(), SEED, None, &mut &bytes[..], check).err().map(|e| e.field().to_string())
    };
    assert_eq!(field(&b, &at(2, Some(&log))), None);
    assert_eq!(field(&b, &at(1, None)), Some("episodes".into()), "the caller's bound, not the file's");
    // A log with lines after the checkpoint's (episodes played after it) still resumes.
    let longer = log.clone() + &log.lines().next().unwrap().replace("\"episode\":0", "\"episode\":2") + "\n";
    assert_eq!(field(&b, &at(3, Some(&longer))), None);
    // A log that lacks a line, or whose lines were edited, does not.
    assert_eq!(field(&b, &at(2, Some(log.lines().next().unwrap()))), Some("log".into()));
    assert_eq!(field(&b, &at(2, Some(&log.replacen("\"goal\":", "\"goal\": ", 1)))), Some("log".into()));
    // A claim of ten million is refused at once, before any reset is replayed.
    let forged = reseal(with_header(&b, |h| h["episodes"] = 10_000_000.into()));
    let t0 = std::time::Instant::now();
    assert_eq!(field(&forged, &at(2, Some(&log))), Some("episodes".into()));
    assert_eq!(field(&forged, &at(10_000_000, Some(&log))), Some("log".into()));
    assert!(t0.elapsed().as_secs() < 60, "refused without replaying");
}

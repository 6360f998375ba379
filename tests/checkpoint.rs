//! Run checkpoints are as trustworthy as the memory files (issue 39): a checksum over the whole
//! file and every value checked on load. The regression corpus is the 17 hostile edits that
//! version 2 accepted (or accepted holding NaN or infinity): each is refused by name, by the
//! checksum as it stands and, with the checksum recomputed, by the check of the value it broke
//! (where the value is not a legal one: an episode count one off or a word position of 0 are
//! legal values, which only the checksum and the runner's log check catch). Version 2 still loads.
#![cfg(not(target_arch = "wasm32"))]

use sec_playground::encoder::{EMBEDDING, IMAGE};
use sec_playground::experiment::{fixtures, Run, RunConfig};
use sec_playground::render::fnv1a;
use serde_json::Value;

const SEED: u64 = 3;

fn config() -> RunConfig {
    RunConfig { task: "object-permanence".into(), t: Some(100), ..RunConfig::default() }
}

/// A SEC run with six sequences in its LTM, one episode played, and its checkpoint.
fn checkpoint(cfg: &RunConfig) -> Vec<u8> {
    let mut run = Run::new(cfg.clone(), SEED).unwrap();
    fixtures::fill_ltm(&mut run, 6);
    run.episode();
    let mut bytes = Vec::new();
    run.save_checkpoint(&mut bytes).unwrap();
    bytes
}

fn u64_at(b: &[u8], at: usize) -> usize {
    u64::from_le_bytes(b[at..at + 8].try_into().unwrap()) as usize
}

/// Where the values of a version-3 SEC checkpoint lie.
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

fn layout(b: &[u8]) -> Layout {
    let hlen = u32::from_le_bytes(b[8..12].try_into().unwrap()) as usize;
    let header = 12..12 + hlen;
    let gate = header.end + 8;
    let (gate_mse, gate_steps) = (gate, gate + 4);
    let gate_end = gate + u64_at(b, header.end);
    assert_eq!(gate_end, gate + 4 + 8 + 1 + 8 + IMAGE * 4 + 1 + EMBEDDING * 4);
    // The agent: the walk's 4 words, the waiting couplet, a flag; the memory's STM head and STM.
    let n = 50;
    let mut at = gate_end + 16 + EMBEDDING * 4 + 1 + 1 + 8 + n * (EMBEDDING * 4 + 1);
    let ltm = at + 8;
    at = ltm + u64_at(b, at) * 4;
    at += 8 + u64_at(b, at); // actions
    let rewards = at + 8;
    at = rewards + u64_at(b, at) * 8;
    let t = at + 8;
    at = t + u64_at(b, at) * 8;
    at += 8 + u64_at(b, at); // sel
    at += 8 + u64_at(b, at); // sel_prev
    at += 8 + u64_at(b, at) * 8; // g
    at += 1; // forgot
    at += 8 + u64_at(b, at) * 4; // sim
    at += 8 + u64_at(b, at) * (4 + 4 + 5 * 8 + 1); // selected
    let p = at + 9 * 8;
    let entropy = p + 9 * 8;
    assert_eq!(entropy + 8 + 8, b.len(), "the layout walks the whole file");
    Layout { header, gate_mse, gate_steps, ltm, rewards, t, p, entropy }
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
    m8.agent.memory.m = 8;
    let mut small = config();
    small.agent.memory.m = 9;
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
    Run::resume(cfg.clone(), SEED, None, &mut &bytes[..]).err().map(|e| e.to_string())
}

#[test]
fn the_seventeen_edits_are_refused_by_the_checksum_and_by_their_value() {
    let b = checkpoint(&config());
    assert!(b.starts_with(b"SECCKPT3"));
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
fn a_version_2_checkpoint_still_loads_and_resumes_the_same_run() {
    let cfg = config();
    let b = checkpoint(&cfg);
    let mut v2 = b[..b.len() - 8].to_vec();
    v2[..8].copy_from_slice(b"SECCKPT2");
    let mut a = Run::resume(cfg.clone(), SEED, None, &mut &b[..]).unwrap();
    let mut c = Run::resume(cfg, SEED, None, &mut &v2[..]).unwrap();
    for _ in 0..3 {
        assert_eq!(a.episode().to_json(), c.episode().to_json());
    }
    // Its values are checked the same way (it has no checksum to stop an edit first).
    let l = layout(&b);
    let mut bad = v2.clone();
    put(&mut bad, l.rewards, &f64::NAN.to_le_bytes());
    assert!(refusal(&bad, &config()).unwrap().contains("rewards"));
}

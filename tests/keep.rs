//! The page's "drive it yourself" and "save / load memory", at the level of a run: a person's
//! rewarded episode is stored in SEC's LTM only when recorded, and a memory file loads only into
//! a run whose embeddings mean the same; anything else is refused and changes nothing.
#![cfg(not(target_arch = "wasm32"))]

use sec_playground::agent::SecConfig;
use sec_playground::arena::Action;
use sec_playground::encoder::PerceptionKind;
use sec_playground::experiment::{AgentKind, Driver, EpisodeMetrics, Run, RunConfig};

/// Object permanence: the small goal (+0.999) stands in the open at (20, 25).
fn permanence() -> RunConfig {
    RunConfig { task: "object-permanence".into(), ..RunConfig::default() }
}

/// Steers the agent to (x, z) like a person with arrow keys: turn towards it, then forward.
fn steer(run: &Run, x: f32, z: f32) -> Action {
    let a = &run.env().world().agent;
    let want = libm::atan2f(x - a.pos.x, z - a.pos.y).to_degrees();
    let diff = (want - a.heading + 540.0).rem_euclid(360.0) - 180.0;
    match diff {
        d if d > 12.0 => Action::RIGHT, // clockwise
        d if d < -12.0 => Action::LEFT,
        _ => Action::FORWARD,
    }
}

/// Drives one whole episode towards the small goal; returns its metrics.
fn drive_episode(run: &mut Run, record: bool) -> EpisodeMetrics {
    loop {
        let action = steer(run, 20.0, 25.0);
        run.set_driver(Some(Driver { action, record }));
        if let Some(m) = run.decision().finished {
            return m;
        }
    }
}

fn sec_ltm(run: &Run) -> usize {
    run.inspect().memory.unwrap().len()
}

#[test]
fn a_recorded_rewarded_drive_is_stored_like_any_sequence() {
    let mut run = Run::new(permanence(), 3).unwrap();
    // Finish the episode the agent started, so the next one is driven from its start.
    let before = loop {
        if let Some(m) = run.decision().finished {
            break m.ltm;
        }
    };
    let m = drive_episode(&mut run, true);
    assert!(m.goal && m.reward > 0.9 && m.human, "{m:?}");
    assert_eq!(m.ltm, before + 1);
    assert_eq!(sec_ltm(&run), before + 1);
    // The stored sequence ends with the person's last actions (forward, towards the goal).
    let memory = run.inspect().memory.unwrap();
    let n = memory.config().n;
    assert_eq!(memory.ltm_action(before, n - 1), Action::FORWARD);
    // The agent takes over again.
    run.set_driver(None);
    let next = run.episode();
    assert!(!next.human);
}

#[test]
fn an_unrecorded_drive_leaves_the_memory_untouched() {
    let mut run = Run::new(permanence(), 3).unwrap();
    let saved = run.save_memory().unwrap();
    let m = drive_episode(&mut run, false);
    assert!(m.goal && m.human && m.ltm == 0, "{m:?}");
    assert_eq!(run.save_memory().unwrap(), saved, "neither the STM nor the LTM changed");
    // MFEC and the reactive walk can be driven too; they learn nothing from it.
    // (MFEC's buffers start with one entry per action.)
    for (kind, entries) in [(AgentKind::Mfec, 9), (AgentKind::Reactive, 0)] {
        let mut run = Run::new(RunConfig { kind, ..permanence() }, 3).unwrap();
        let m = drive_episode(&mut run, true);
        assert!(m.goal && m.human && m.ltm == entries, "{kind:?}: {m:?}");
    }
}

#[test]
fn a_bad_action_is_refused() {
    // An action index out of range never becomes an `Action`, so no driver can hold one; as a
    // number in a file or from serde it is refused by name.
    let e = Action::new(9).unwrap_err().to_string();
    assert!(e.contains("action") && e.contains("0..=8"), "{e}");
    let e = serde_json::from_str::<Action>("9").unwrap_err().to_string();
    assert!(e.contains("action") && e.contains("0..=8"), "{e}");
    assert_eq!(serde_json::from_str::<Action>("3").unwrap(), Action::FORWARD);
    assert_eq!(serde_json::to_string(&Action::LEFT).unwrap(), "2");
    let run = Run::new(permanence(), 3).unwrap();
    assert_eq!(run.driver(), None);
}

/// A run whose LTM holds a few sequences.
fn learnt(cfg: RunConfig, seed: u64) -> Run {
    let mut run = Run::new(cfg, seed).unwrap();
    while sec_ltm(&run) < 3 {
        run.episode();
    }
    run
}

#[test]
fn a_saved_memory_loads_into_a_new_run_and_saves_back_identically() {
    // The untrained encoder is the seed's: its memory loads into a new run of the same seed.
    let a = learnt(permanence(), 2);
    let mut b = Run::new(permanence(), 2).unwrap();
    let file = a.save_memory().unwrap();
    assert_eq!(b.load_memory(&file).unwrap(), sec_ltm(&a));
    assert_eq!(b.save_memory().unwrap(), file);
    let e = Run::new(permanence(), 3).unwrap().load_memory(&file).unwrap_err().to_string();
    assert!(e.contains("another encoder"), "{e}");
    // The trained encoder is the task's: its memory loads into a run of any seed.
    let trained = RunConfig { perception: PerceptionKind::Trained, ..permanence() };
    let a = learnt(trained.clone(), 7);
    let file = a.save_memory().unwrap();
    let mut b = Run::new(trained, 99).unwrap();
    assert_eq!(b.load_memory(&file).unwrap(), sec_ltm(&a));
    assert_eq!(sec_ltm(&b), sec_ltm(&a));
    assert_eq!(b.save_memory().unwrap(), file);
    let (ma, mb) = (a.inspect().memory.unwrap(), b.inspect().memory.unwrap());
    assert_eq!(ma.rewards(), mb.rewards());
    assert!(mb.bias().iter().all(|&t| t == 1.0), "T restarts at 1");
    // The loaded memory is used: the run goes on and keeps its sequences.
    let m = b.episode();
    assert!(m.ltm >= sec_ltm(&a));
}

#[test]
fn corrupt_foreign_and_mismatched_memory_files_are_refused_and_change_nothing() {
    let file = learnt(permanence(), 2).save_memory().unwrap();
    let mut run = learnt(permanence(), 2);
    let before = run.save_memory().unwrap();
    let refused = |run: &mut Run, bytes: &[u8], words: &[&str]| {
        let e = run.load_memory(bytes).unwrap_err().to_string();
        for w in words {
            assert!(e.contains(w), "'{e}' should mention '{w}'");
        }
    };
    let mut flipped = file.clone();
    flipped[file.len() / 2] ^= 0x10;
    refused(&mut run, &flipped, &["memory", "checksum"]);
    refused(&mut run, &file[..file.len() - 20], &["memory"]);
    refused(&mut run, b"{\"not\": \"a memory\"}", &["memory", "magic"]);
    refused(&mut run, &[], &["memory", "magic"]);
    // Another task, another model scale, another n, too small an m.
    let detour = Run::new(RunConfig { task: "detour".into(), ..RunConfig::default() }, 1).unwrap();
    refused(&mut run, &detour.save_memory().unwrap(), &["memory", "detour", "object-permanence"]);
    let scaled = Run::new(RunConfig { embedding_scale: Some(2.0), ..permanence() }, 2).unwrap();
    refused(&mut run, &scaled.save_memory().unwrap(), &["memory", "encoder"]);
    refused(&mut run, &Run::new(permanence(), 5).unwrap().save_memory().unwrap(), &["memory", "encoder", "per seed"]);
    let mut short = permanence();
    short.section_mut::<SecConfig>().memory.n = 20;
    refused(&mut run, &Run::new(short, 2).unwrap().save_memory().unwrap(), &["n", "20", "50"]);
    let mut small = permanence();
    small.section_mut::<SecConfig>().memory.m = 2;
    small.section_mut::<SecConfig>().min_sequences = 1;
    refused(&mut Run::new(small, 2).unwrap(), &file, &["m", "2"]);
    // Agents without SEC's memory.
    let mut mfec = Run::new(RunConfig { kind: AgentKind::Mfec, ..permanence() }, 1).unwrap();
    refused(&mut mfec, &file, &["agent", "SEC"]);
    assert!(mfec.save_memory().is_err());
    // A bad file is a file error; a run that cannot hold a memory is a configuration error.
    use sec_playground::{Error, FileError};
    assert!(matches!(run.load_memory(&flipped), Err(Error::File(FileError { file: "memory", .. }))));
    assert!(matches!(mfec.load_memory(&file), Err(Error::Config(e)) if e.field == "agent"));
    assert_eq!(run.save_memory().unwrap(), before, "the run's memory is as it was");
}

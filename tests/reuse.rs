//! Work not done changes no run: the convolutions' window reuse, the run's frame cache,
//! retrieval's reuse of its similarity row and its coarse bounds give
//! the episodes of computing everything, and a run resumed with an empty cache goes on as the
//! uninterrupted one with a warm cache did.
#![cfg(not(target_arch = "wasm32"))]

use sec_playground::experiment::checkpoint::ResumeCheck;
use sec_playground::experiment::{Run, RunConfig};

fn log(run: &mut Run, n: usize) -> Vec<String> {
    (0..n).map(|_| format!("{:?}", run.episode())).collect()
}

/// The default run (SEC, the double T-maze, the untrained encoder and the gate) for 50 episodes.
#[test]
fn a_default_run_is_the_same_with_and_without_reuse() {
    let cfg = RunConfig::default();
    let mut fast = Run::new(cfg.clone(), 4).unwrap();
    let a = log(&mut fast, 50);
    let (hits, lookups) = fast.frame_cache().hit_rate();
    eprintln!("frame cache: {hits} of {lookups} frames found");
    assert!(hits * 5 > lookups && lookups > 1000, "the cache found {hits} of {lookups} frames");

    sec_playground::reuse::set(false);
    let mut plain = Run::new(cfg.clone(), 4).unwrap();
    let b = log(&mut plain, 50);
    assert_eq!(plain.frame_cache().hit_rate(), (0, 0), "the cache is off");
    sec_playground::reuse::set(true);
    assert_eq!(a, b);
    // The whole state too: a checkpoint holds the last retrieval's similarities in full, which
    // the coarse bounds of retrieval computed only in part.
    let (mut saved_fast, mut saved_plain) = (Vec::new(), Vec::new());
    fast.save_checkpoint(&mut saved_fast).unwrap();
    plain.save_checkpoint(&mut saved_plain).unwrap();
    assert!(saved_fast == saved_plain, "the checkpoints differ");

    // Saved after 25 episodes and resumed with an empty cache: the same last 25.
    let mut first = Run::new(cfg.clone(), 4).unwrap();
    assert_eq!(log(&mut first, 25), a[..25]);
    let mut bytes = Vec::new();
    first.save_checkpoint(&mut bytes).unwrap();
    let mut resumed = Run::resume(cfg, 4, None, &mut bytes.as_slice(), &ResumeCheck::at_most(1000)).unwrap();
    assert!(resumed.frame_cache().is_empty());
    assert_eq!(log(&mut resumed, 25), a[25..]);
}

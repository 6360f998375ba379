//! Runs of SEC in a task: deterministic, and counted as the paper counts them.

use sec_playground::experiment::{golden_run, Run, RunConfig};

fn episodes(cfg: &RunConfig, seed: u64, n: usize) -> Vec<String> {
    let mut run = Run::new(cfg.clone(), seed).unwrap();
    (0..n).map(|_| format!("{:?}", run.episode())).collect()
}

#[test]
fn the_same_configuration_and_seed_give_the_same_episodes() {
    let cfg = RunConfig { t: Some(200), ..RunConfig::default() };
    let a = episodes(&cfg, 7, 6);
    assert_eq!(a, episodes(&cfg, 7, 6));
    assert_ne!(a, episodes(&cfg, 8, 6), "another seed, another run");
}

#[test]
fn episodes_are_counted_as_the_paper_counts_them() {
    let mut run = Run::new(RunConfig::default(), 3).unwrap();
    for _ in 0..4 {
        let m = run.episode();
        assert_eq!(m.reward, m.raw_reward.max(0.0));
        if m.goal {
            assert!(m.raw_reward > 0.0 && m.decisions < 250 && m.ltm >= 1);
        } else {
            // A timed-out episode: 1000 env steps (the first a no-op after the reset), a decision
            // every 4 of them, -1 in all.
            assert_eq!((m.env_steps, m.decisions), (1000, 250));
            assert!((m.raw_reward + 1.0).abs() < 1e-9, "{}", m.raw_reward);
            assert_eq!(m.reward, 0.0);
        }
        assert!(m.contextual_share == 0.0, "fewer than 5 sequences: the reactive layer acts");
    }
}

#[test]
fn bad_run_configurations_are_refused() {
    let e = |c: RunConfig| Run::new(c, 1).err().unwrap().to_string();
    assert!(e(RunConfig { task: "maze".into(), ..RunConfig::default() }).starts_with("task"));
    assert_eq!(
        e(RunConfig { decision_period: 0, ..RunConfig::default() }),
        "decisionPeriod: 0 is out of range 1..=100"
    );
}

/// `tests/wasm.rs` checks the same log under Node. `SEC_UPDATE_GOLDEN=1` rewrites it.
#[test]
fn a_short_run_gives_the_golden_episode_log() {
    let log = golden_run();
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/golden/run.txt");
    if std::env::var("SEC_UPDATE_GOLDEN").is_ok_and(|v| v == "1") {
        std::fs::write(path, &log).unwrap();
    }
    assert_eq!(log, std::fs::read_to_string(path).unwrap());
}

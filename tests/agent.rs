//! Arbitration between the contextual and reactive layers (docs/ALGORITHM.md) and the
//! agent's documented deviations.
#![cfg(not(target_arch = "wasm32"))]

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use sec_playground::agent::{Layer, Sec, SecConfig};
use sec_playground::encoder::EMBEDDING;

fn emb(v: f32) -> [f32; EMBEDDING] {
    [v; EMBEDDING]
}

/// An agent whose LTM holds `k` sequences of couplets all equal to `emb(0.5)`.
fn agent_with(cfg: SecConfig, k: usize, rng: &mut ChaCha8Rng) -> Sec {
    let n = cfg.memory.n;
    let mut a = Sec::new(cfg, rng).unwrap();
    for _ in 0..k {
        for _ in 0..n {
            a.decide(&emb(0.5), 100.0, rng);
        }
        a.goal(1.0, rng);
        a.episode_end();
    }
    assert_eq!(a.memory().len(), k);
    a
}

fn small() -> SecConfig {
    let mut c = SecConfig::default();
    c.memory.n = 4;
    c
}

#[test]
fn the_contextual_layer_acts_from_five_sequences_with_the_gate_open() {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let mut a = agent_with(small(), 4, &mut rng);
    let d = a.decide(&emb(0.5), 0.001, &mut rng);
    assert!(d.selected, "the memory selects even with 4 sequences");
    assert_eq!(d.layer, Layer::Reactive, "but acts only from 5");
    let mut a = agent_with(small(), 5, &mut rng);
    assert_eq!(a.decide(&emb(0.5), 0.001, &mut rng).layer, Layer::Contextual);
    // The gate: MSE must be strictly below 0.01.
    let d = a.decide(&emb(0.5), 0.01, &mut rng);
    assert!(d.selected);
    assert_eq!(d.layer, Layer::Reactive);
    // Nothing similar: the reactive layer acts.
    let d = a.decide(&emb(3.0), 0.001, &mut rng);
    assert!(!d.selected);
    assert_eq!(d.layer, Layer::Reactive);
}

#[test]
fn the_gate_can_be_turned_off() {
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let mut a = agent_with(SecConfig { gate: None, ..small() }, 5, &mut rng);
    assert_eq!(a.decide(&emb(0.5), 100.0, &mut rng).layer, Layer::Contextual);
}

#[test]
fn by_default_the_goal_couplet_is_not_stored_and_with_d4_it_is() {
    for store_last in [false, true] {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut a = Sec::new(SecConfig { store_last_couplet: store_last, ..small() }, &mut rng).unwrap();
        for v in [0.25, 0.5, 0.75, 1.0, 1.25] {
            a.decide(&emb(v), 100.0, &mut rng);
        }
        a.goal(2.0, &mut rng);
        let newest: Vec<f32> = (0..4).map(|j| a.memory().ltm_embedding(0, j)[0]).collect();
        if store_last {
            assert_eq!(newest, [0.5, 0.75, 1.0, 1.25]);
        } else {
            // The last decision (1.25) has not been pushed yet: the sequence lags by one (D4).
            assert_eq!(newest, [0.25, 0.5, 0.75, 1.0]);
        }
        // Either way the next decision does not push 1.25 a second time.
        a.episode_end();
        a.decide(&emb(1.5), 100.0, &mut rng);
        let stm: Vec<f32> = a.memory().stm().map(|c| c.embedding[0]).collect();
        assert_eq!(stm, [0.5, 0.75, 1.0, 1.25]);
    }
}

#[test]
fn the_stm_rolls_across_episodes_unless_reset() {
    for reset in [false, true] {
        let mut rng = ChaCha8Rng::seed_from_u64(4);
        let mut a = Sec::new(SecConfig { reset_stm_on_episode: reset, ..small() }, &mut rng).unwrap();
        for v in [0.25, 0.5] {
            a.decide(&emb(v), 100.0, &mut rng);
        }
        a.episode_end();
        a.decide(&emb(0.75), 100.0, &mut rng);
        let stm: Vec<f32> = a.memory().stm().map(|c| c.embedding[0]).collect();
        if reset {
            assert_eq!(stm, [0.0; 4]);
        } else {
            // The initial zero couplet, 0.25, and 0.5 carried over from the last episode.
            assert_eq!(stm, [0.0, 0.0, 0.25, 0.5]);
        }
    }
}

#[test]
fn presets_and_validation() {
    let p = SecConfig::paper();
    assert_eq!((p.memory.theta_abs, p.memory.theta_prop, p.memory.alpha), (0.995, 0.98, 0.1));
    let c = SecConfig::code();
    assert_eq!((c.memory.theta_abs, c.memory.theta_prop, c.memory.alpha, c.memory.beta), (0.98, 0.995, 0.01, 0.05));
    assert_eq!((c.memory.n, c.memory.m, c.min_sequences, c.gate), (50, 500, 5, Some(0.01)));
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let e = |c: SecConfig| Sec::new(c, &mut ChaCha8Rng::seed_from_u64(5)).unwrap_err().to_string();
    let mut bad = SecConfig::default();
    bad.memory.m = 3;
    let message = e(bad);
    assert!(message.starts_with("minSequences: 5 is out of range 0..=3 (the LTM capacity m): "), "{message}");
    assert_eq!(e(SecConfig { gate: Some(0.0), ..SecConfig::default() }), "gate: 0 is out of range (0, 100]");
    assert!(Sec::new(SecConfig::default(), &mut rng).is_ok());
}

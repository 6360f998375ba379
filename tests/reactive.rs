//! The reactive layer's cycles (docs/ALGORITHM.md).
#![cfg(not(target_arch = "wasm32"))]

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use sec_playground::agent::reactive::{Reactive, FORWARD, TURN_1, TURN_2};
use sec_playground::arena::Action;

/// Run lengths of equal actions in a sequence.
fn runs(actions: &[Action]) -> Vec<(Action, usize)> {
    let mut out: Vec<(Action, usize)> = Vec::new();
    for &a in actions {
        match out.last_mut() {
            Some((b, n)) if *b == a => *n += 1,
            _ => out.push((a, 1)),
        }
    }
    out
}

#[test]
fn cycles_of_straight_runs_then_turns_in_place() {
    for seed in 0..20 {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut r = Reactive::new(&mut rng);
        let acts: Vec<Action> = (0..5000).map(|_| r.step(&mut rng)).collect();
        assert!(acts.iter().all(|a| [FORWARD, TURN_1, TURN_2].contains(a)), "never backward, never move and turn");
        let rs = runs(&acts);
        // First cycle: 1..=19 forward (the counter starts at 1), 1..=19 turns with direction 0.
        assert_eq!(rs[0].0, FORWARD);
        assert!((1..=19).contains(&rs[0].1), "{:?}", &rs[..2]);
        assert_eq!(rs[1].0, TURN_1);
        assert!((1..=19).contains(&rs[1].1));
        // Later cycles: S + 1 forward steps with S in 1..=20, then T in 1..=20 turns one way.
        for w in rs[2..rs.len() - 2].chunks_exact(2) {
            assert_eq!(w[0].0, FORWARD);
            assert!((2..=21).contains(&w[0].1), "forward run {}", w[0].1);
            assert!(w[1].0 == TURN_1 || w[1].0 == TURN_2);
            assert!((1..=20).contains(&w[1].1), "turn run {}", w[1].1);
        }
    }
}

#[test]
fn both_turn_directions_and_all_lengths_occur() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut r = Reactive::new(&mut rng);
    let acts: Vec<Action> = (0..100_000).map(|_| r.step(&mut rng)).collect();
    let rs = runs(&acts);
    let fwd: std::collections::BTreeSet<usize> = rs[2..].iter().filter(|x| x.0 == FORWARD).map(|x| x.1).collect();
    assert_eq!(fwd.into_iter().collect::<Vec<_>>(), (2..=21).collect::<Vec<_>>());
    assert!(acts.contains(&TURN_1) && acts.contains(&TURN_2));
}

//! The MFEC baseline (docs/ALGORITHM.md, "MFEC") on hand-made states.
#![cfg(not(target_arch = "wasm32"))]

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use sec_playground::agent::mfec::{softmax_entropy_bits, Bookkeeping, Mfec, MfecConfig, RandomProjection};
use sec_playground::agent::Layer;
use sec_playground::arena::Action;
use sec_playground::encoder::{EMBEDDING, IMAGE};

/// Greedy from the first decision, with the per-episode bookkeeping (one episode's decisions are
/// its transitions); `authors` below is the default, D21's.
fn greedy(k: usize, capacity: usize, gamma: f64) -> MfecConfig {
    MfecConfig {
        k,
        capacity,
        gamma,
        epsilon: 0.0,
        warmup_decisions: 0,
        warmup_rewarded_episodes: 0,
        bookkeeping: Bookkeeping::PerEpisode,
        ..MfecConfig::default()
    }
}

fn authors(k: usize, capacity: usize, gamma: f64) -> MfecConfig {
    MfecConfig { bookkeeping: Bookkeeping::Authors, ..greedy(k, capacity, gamma) }
}

fn state(x: f32) -> [f32; EMBEDDING] {
    let mut e = [0.0; EMBEDDING];
    e[0] = x;
    e
}

/// Decisions on states 1, 2, 3 (every Q equal: action 0 each), each after a -0.001 decision
/// frame, then the goal (+1, episode reward 1) on a decision frame with a terminal decision on 4.
fn three_decisions_then_goal(m: &mut Mfec, r: &mut ChaCha8Rng) {
    for x in [1.0, 2.0, 3.0] {
        m.frame(-0.001, 0.0, false, true);
        m.decide(&state(x), false, r);
    }
    m.frame(1.0, 1.0, true, true);
    m.decide(&state(4.0), true, r);
    m.episode_end(true);
}

fn rng() -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(1)
}

#[test]
fn a_fresh_agent_values_everything_at_minus_ten_and_is_maximally_uncertain() {
    let mut r = rng();
    let mut m = Mfec::new(greedy(50, 10, 0.99), &mut r).unwrap();
    let d = m.decide(&state(3.0), false, &mut r);
    assert_eq!(m.q(), &[-10.0; 9]);
    assert_eq!((d.action, d.layer), (Action::NOOP, Layer::Contextual), "argmax takes the first of equals");
    assert!((m.entropy() - 9f64.log2()).abs() < 1e-12);
    assert_eq!(m.len(), 9, "one initial entry per action");
}

#[test]
fn returns_are_discounted_backwards_and_looked_up_exactly_or_by_nearest_neighbours() {
    let mut r = rng();
    let mut m = Mfec::new(greedy(2, 10, 0.5), &mut r).unwrap();
    // Three decisions (all action 0: every Q is -10), the goal on the third's following frame.
    three_decisions_then_goal(&mut m, &mut r);
    // The first frame's penalty came before any decision and reaches nothing; the next two
    // decision frames give -0.001 each, the goal frame the episode reward: g = r + 0.5 g'.
    let q = |m: &mut Mfec, x: f32, r: &mut ChaCha8Rng| {
        m.decide(&state(x), true, r);
        m.q()[0]
    };
    let (r1, r2, r3) = (-0.001, -0.001, 1.0);
    let g3 = r3;
    let g2 = r2 + 0.5 * g3;
    let g1 = r1 + 0.5 * g2;
    assert_eq!(q(&mut m, 3.0, &mut r), g3, "exact match");
    assert_eq!(q(&mut m, 1.0, &mut r), g1);
    // Unseen 2.4: its two nearest are 2 and 3.
    assert_eq!(q(&mut m, 2.4, &mut r), (g2 + g3) / 2.0);
    // Unseen 0.4: nearest 0 (the initial -10) and 1.
    assert_eq!(q(&mut m, 0.4, &mut r), (-10.0 + g1) / 2.0);
    assert_eq!(m.q()[1], -10.0, "other actions kept their initial entry only");
}

#[test]
fn faithful_bookkeeping_loses_a_goal_between_decisions_and_sum_rewards_keeps_it() {
    for sum in [false, true] {
        let mut r = rng();
        let mut m = Mfec::new(MfecConfig { sum_rewards: sum, ..greedy(1, 10, 1.0) }, &mut r).unwrap();
        m.decide(&state(1.0), false, &mut r);
        m.frame(-0.001, -0.001, false, false);
        m.frame(-0.001, -0.002, false, false);
        // The goal lands on a frame with no decision, and the episode ends there.
        m.frame(2.0, 1.998, true, false);
        m.episode_end(true);
        m.decide(&state(1.0), true, &mut r);
        let want = if sum { -0.001 + -0.001 + 2.0 } else { 0.0 };
        assert!((m.q()[0] - want).abs() < 1e-12, "sum_rewards {sum}: {}", m.q()[0]);
    }
}

#[test]
fn full_buffers_forget_the_oldest_and_a_revisited_state_keeps_its_best_value_and_moves_to_the_end() {
    let mut r = rng();
    // Capacity 3: the initial entry and two more.
    let mut m = Mfec::new(greedy(1, 3, 1.0), &mut r).unwrap();
    let episode = |m: &mut Mfec, x: f32, g: f64, r: &mut ChaCha8Rng| {
        m.decide(&state(x), false, r);
        m.frame(g, g, true, true);
        m.episode_end(true);
    };
    episode(&mut m, 1.0, 5.0, &mut r);
    episode(&mut m, 2.0, 6.0, &mut r);
    assert_eq!(m.len(), 3 + 8);
    // Revisit 1 with a worse return: the value stays 5 and 1 becomes the newest.
    episode(&mut m, 1.0, 4.0, &mut r);
    // A new state evicts the oldest: the initial zero entry, then 2 (1 was refreshed).
    episode(&mut m, 3.0, 7.0, &mut r);
    episode(&mut m, 4.0, 8.0, &mut r);
    assert_eq!(m.len(), 3 + 8, "the buffer stays at its capacity");
    let q = |m: &mut Mfec, x: f32, r: &mut ChaCha8Rng| {
        m.decide(&state(x), true, r);
        m.q()[0]
    };
    assert_eq!(q(&mut m, 1.0, &mut r), 5.0, "max kept, and it survived two evictions");
    assert_eq!(q(&mut m, 0.0, &mut r), 5.0, "the zero entry is gone: its nearest is now 1");
    assert_eq!(q(&mut m, 1.9, &mut r), 5.0, "2 is gone too: 1 is nearest");
    assert_eq!(q(&mut m, 2.1, &mut r), 7.0);
    assert_eq!(q(&mut m, 4.0, &mut r), 8.0);
}

#[test]
fn the_reactive_walk_explores_during_the_warm_up() {
    let mut r = rng();
    let cfg = MfecConfig { warmup_decisions: 3, warmup_rewarded_episodes: 0, epsilon: 0.0, ..MfecConfig::default() };
    let mut m = Mfec::new(cfg, &mut r).unwrap();
    let layers: Vec<Layer> = (0..5).map(|i| m.decide(&state(i as f32), false, &mut r).layer).collect();
    assert_eq!(layers, [Layer::Reactive, Layer::Reactive, Layer::Reactive, Layer::Contextual, Layer::Contextual]);
    // Until 5 rewarded episodes, whatever the decision count (counted at the episode's end with
    // the per-episode bookkeeping; at the goal's frame with the authors', tested below).
    let cfg = MfecConfig {
        warmup_decisions: 0,
        warmup_rewarded_episodes: 1,
        epsilon: 0.0,
        bookkeeping: Bookkeeping::PerEpisode,
        ..MfecConfig::default()
    };
    let mut m = Mfec::new(cfg, &mut r).unwrap();
    assert_eq!(m.decide(&state(1.0), false, &mut r).layer, Layer::Reactive);
    m.episode_end(false);
    assert_eq!(m.decide(&state(1.0), false, &mut r).layer, Layer::Reactive);
    m.episode_end(true);
    assert_eq!(m.decide(&state(1.0), false, &mut r).layer, Layer::Contextual);
}

#[test]
fn the_authors_bookkeeping_starts_with_a_dummy_couplet_and_carries_the_last_one_over() {
    let mut r = rng();
    let mut m = Mfec::new(authors(1, 100, 0.5), &mut r).unwrap();
    // Episode 1: decisions on 1 and 2 (argmax of equal -10s: action 0), the goal on a decision
    // frame, where a terminal decision on 3 is taken.
    m.frame(-0.001, -0.001, false, true);
    m.decide(&state(1.0), false, &mut r);
    m.frame(-0.001, -0.002, false, true);
    m.decide(&state(2.0), false, &mut r);
    m.frame(1.0, 0.998, true, true);
    m.decide(&state(3.0), true, &mut r);
    m.episode_end(true);
    let q = |m: &mut Mfec, x: f32, r: &mut ChaCha8Rng| {
        m.decide(&state(x), false, r);
        m.q()[0]
    };
    // The dummy (zeros, no-op) took the first frame's -0.001 and is the episode's first
    // transition: its return replaced the no-op buffer's (zeros, -10) start entry.
    let (g2, g1) = (0.998, -0.001 + 0.5 * 0.998);
    let g0 = -0.001 + 0.5 * g1;
    assert_eq!(q(&mut m, 0.0, &mut r), g0);
    assert_eq!(q(&mut m, 1.0, &mut r), g1);
    assert_eq!(q(&mut m, 2.0, &mut r), g2);
    // The terminal couplet (3) is not written yet: 3's nearest is 2.
    assert_eq!(q(&mut m, 3.0, &mut r), g2);
    assert_eq!(m.len(), 9 + 2, "the dummy replaced an entry; 1 and 2 are new");
}

#[test]
fn the_carried_couplet_gets_the_next_episodes_return() {
    let mut r = rng();
    let mut m = Mfec::new(authors(1, 100, 0.5), &mut r).unwrap();
    // Episode 1 ends between decisions: its last couplet (5) stays open.
    m.frame(-0.001, -0.001, false, true);
    m.decide(&state(5.0), false, &mut r);
    m.frame(-0.001, -0.002, false, false);
    m.episode_end(false);
    // Episode 2: the first frame's reward closes 5; one more decision, then the goal.
    m.frame(-0.001, -0.001, false, true);
    m.decide(&state(6.0), false, &mut r);
    m.frame(2.0, 1.999, true, true);
    m.decide(&state(7.0), true, &mut r);
    m.episode_end(true);
    m.decide(&state(5.0), false, &mut r);
    assert_eq!(m.q()[0], -0.001 + 0.5 * 1.999, "5 was credited in episode 2");
}

#[test]
fn the_authors_buffers_hold_capacity_minus_one_written_newest_first() {
    let mut r = rng();
    // Capacity 3 keeps 2 entries per buffer. Decisions on 1, 2, 3 (equal -10s: action 0 each),
    // the goal on a decision frame with a terminal decision on 4.
    let mut m = Mfec::new(authors(1, 3, 1.0), &mut r).unwrap();
    three_decisions_then_goal(&mut m, &mut r);
    // Transitions dummy(0) -> 1 -> 2 -> 3 with returns 0.997, 0.998, 0.999, 1. Written 3, 2,
    // 1, 0, each new state evicting the oldest: buffer 0 keeps the last two written, 1 and 0.
    assert_eq!(m.len(), 2 + 8);
    let q = |m: &mut Mfec, x: f32, r: &mut ChaCha8Rng| {
        m.decide(&state(x), false, r);
        m.q()[0]
    };
    assert_eq!(q(&mut m, 3.0, &mut r), -0.001 + (-0.001 + 1.0), "3 and 2 were evicted: 1 is nearest");
    assert_eq!(q(&mut m, 0.0, &mut r), -0.001 + (-0.001 + (-0.001 + 1.0)));
}

#[test]
fn the_authors_mfec_values_states_only_when_it_acts() {
    let mut r = rng();
    let cfg = MfecConfig { warmup_decisions: 2, ..authors(1, 100, 1.0) };
    let mut m = Mfec::new(cfg, &mut r).unwrap();
    let d = m.decide(&state(1.0), false, &mut r);
    assert_eq!((d.layer, d.selected, m.entropy(), m.q()), (Layer::Reactive, false, 0.0, &[0.0; 9]));
    m.decide(&state(1.0), false, &mut r);
    let d = m.decide(&state(1.0), false, &mut r);
    assert_eq!((d.layer, d.selected), (Layer::Contextual, true));
    assert_eq!(m.q(), &[-10.0; 9]);
    // A goal counts towards the warm-up on its own frame.
    let cfg = MfecConfig { warmup_rewarded_episodes: 1, ..authors(1, 100, 1.0) };
    let mut m = Mfec::new(cfg, &mut r).unwrap();
    m.frame(2.0, 1.9, true, true);
    assert_eq!(m.decide(&state(1.0), true, &mut r).layer, Layer::Contextual);
}

#[test]
fn softmax_entropy_is_in_bits() {
    let mut q = [f64::NEG_INFINITY; 9];
    q[4] = 1.0;
    assert_eq!(softmax_entropy_bits(&q), 0.0);
    q[5] = 1.0;
    assert!((softmax_entropy_bits(&q) - 1.0).abs() < 1e-12);
}

#[test]
fn bad_mfec_parameters_are_refused_by_name() {
    let e = |c: MfecConfig| Mfec::new(c, &mut rng()).err().unwrap().to_string();
    assert_eq!(e(MfecConfig { k: 0, ..MfecConfig::default() }), "mfec.k: 0 is out of range 1..=1000");
    assert_eq!(e(MfecConfig { gamma: f64::NAN, ..MfecConfig::default() }), "mfec.gamma: NaN is out of range [0, 1]");
    assert_eq!(e(MfecConfig { capacity: 1, ..MfecConfig::default() }), "mfec.capacity: 1 is out of range 2..=1000000");
    assert_eq!(e(MfecConfig { epsilon: 1.5, ..MfecConfig::default() }), "mfec.epsilon: 1.5 is out of range [0, 1]");
}

#[test]
fn the_random_projection_is_seeded_and_has_unit_variance_on_a_unit_image() {
    let p = RandomProjection::new(&mut ChaCha8Rng::seed_from_u64(3));
    let q = RandomProjection::new(&mut ChaCha8Rng::seed_from_u64(3));
    let image = vec![1.0f32; IMAGE];
    let (mut a, mut b) = ([0.0; EMBEDDING], [0.0; EMBEDDING]);
    p.project(&image, &mut a);
    q.project(&image, &mut b);
    assert_eq!(a.map(f32::to_bits), b.map(f32::to_bits));
    // Each output is a sum of IMAGE N(0, 1/IMAGE) draws: N(0, 1).
    let var = a.iter().map(|x| (x * x) as f64).sum::<f64>() / EMBEDDING as f64;
    assert!((0.3..3.0).contains(&var), "{var}");
    let mut c = [0.0; EMBEDDING];
    RandomProjection::new(&mut ChaCha8Rng::seed_from_u64(4)).project(&image, &mut c);
    assert_ne!(a, c);
}

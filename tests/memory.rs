//! The contextual layer against hand-computed values (docs/ALGORITHM.md, "The contextual layer") and its
//! invariants over random operation sequences.
#![cfg(not(target_arch = "wasm32"))]

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use sec_playground::arena::Action;
use sec_playground::encoder::EMBEDDING;
use sec_playground::memory::{Couplet, Forgetting, Memory, MemoryConfig, ValueFn};

/// An embedding whose every component is `v`. With v a multiple of 2^-6 every MAE below is
/// exact in f32, so the thresholds can be tested at equality.
fn emb(v: f32) -> [f32; EMBEDDING] {
    [v; EMBEDDING]
}

/// The action of index `i`.
fn a(i: usize) -> Action {
    Action::ALL[i]
}

fn couplet(v: f32, action: u8) -> Couplet {
    Couplet { embedding: emb(v), action: a(action as usize) }
}

fn rng() -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(9)
}

/// A memory with n couplets per sequence whose STM holds `values` (oldest first) with `action`,
/// stored as one sequence with reward `r`.
fn with_sequence(cfg: MemoryConfig, values: &[f32], action: u8, r: f64) -> Memory {
    let mut m = Memory::new(cfg).unwrap();
    for &v in values {
        m.update(couplet(v, action));
    }
    assert!(m.store(r, &mut rng()));
    m
}

/// numpy's `np.sum` of 20 values along a contiguous axis: eight pairs, a tree, then four more
/// (written independently of the library's order).
fn numpy_sum20<T: Copy + std::ops::Add<Output = T>>(a: &[T; EMBEDDING]) -> T {
    let r: Vec<T> = (0..8).map(|l| a[l] + a[8 + l]).collect();
    let mut s = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]));
    for &v in &a[16..] {
        s = s + v;
    }
    s
}

/// Thresholds as set live on the page: theta_abs drawn from `abs`, or both 0 one time in five.
fn new_thresholds(cfg: &mut MemoryConfig, src: &mut ChaCha8Rng, abs: std::ops::Range<f64>) {
    let zero = src.gen_bool(0.2);
    cfg.theta_abs = if zero { 0.0 } else { src.gen_range(abs) };
    cfg.theta_prop = if zero { 0.0 } else { src.gen_range(0.5..1.0) };
}

fn cfg(n: usize) -> MemoryConfig {
    MemoryConfig { n, ..MemoryConfig::default() }
}

#[test]
fn both_thresholds_are_strict() {
    // One stored couplet at MAE 2^-6 from the query: G = 1 - 0.015625 = 0.984375 exactly.
    let probe = |theta_abs: f64, theta_prop: f64| {
        let mut m = with_sequence(MemoryConfig { theta_abs, theta_prop, ..cfg(1) }, &[0.0], 1, 1.0);
        m.retrieve(&emb(0.015625), &mut rng())
    };
    assert_eq!(probe(0.984, 0.995), Some(a(1)));
    assert_eq!(probe(0.984375, 0.995), None, "G equal to theta_abs must not pass");
    // G / Gmax = 1 for the only couplet: theta_prop = 1 must not pass, just below must.
    assert_eq!(probe(0.98, 1.0), None, "G equal to theta_prop * Gmax must not pass");
    assert_eq!(probe(0.98, 0.999), Some(a(1)));
}

#[test]
fn gmax_at_or_below_zero_selects_nothing() {
    // MAE 2 > 1: every G is negative; even a theta_abs of 0 cannot select (D16).
    let mut m = with_sequence(MemoryConfig { theta_abs: 0.0, theta_prop: 0.0, ..cfg(3) }, &[0.0, 0.0, 0.0], 1, 1.0);
    assert_eq!(m.retrieve(&emb(2.0), &mut rng()), None);
    assert!(m.selected().is_empty());
    assert!(m.biased_similarity().iter().all(|&g| g == -1.0));
}

#[test]
fn relative_reward_is_over_the_selected_couplets_only() {
    // Three sequences of one couplet: rewards 1, 2 and 4; the one with 4 is far away.
    let mut m = Memory::new(MemoryConfig { theta_prop: 0.9, ..cfg(1) }).unwrap();
    for (v, a, r) in [(0.0, 1u8, 1.0), (0.0, 2, 2.0), (1.0, 3, 4.0)] {
        m.update(couplet(v, a));
        m.store(r, &mut rng());
    }
    m.retrieve(&emb(0.0), &mut rng());
    let sel: Vec<u32> = m.selected().iter().map(|s| s.row).collect();
    assert_eq!(sel, [0, 1]);
    // rr = 1/2 and 2/2 (rmax over the selected = 2, not 4); g = 1; d = (1 - 0)/1 = 1.
    let dist = (-1.0f64 / 0.9).exp();
    assert!((m.q()[1] - 0.5 * dist).abs() < 1e-12, "{:?}", m.q());
    assert!((m.q()[2] - 1.0 * dist).abs() < 1e-12);
    assert_eq!(m.q()[3], 0.0);
    assert!((m.p()[1] - 1.0 / 3.0).abs() < 1e-12 && (m.p()[2] - 2.0 / 3.0).abs() < 1e-12);
    let h = -(1.0f64 / 3.0) * (1.0f64 / 3.0).log2() - (2.0f64 / 3.0) * (2.0f64 / 3.0).log2();
    assert!((m.entropy() - h).abs() < 1e-12, "entropy {} vs {h}", m.entropy());
}

#[test]
fn distance_weights_run_from_the_newest_to_the_oldest_couplet() {
    // n = 4, all couplets identical to the query, actions 0..3 by position j (0 = oldest).
    let mut m = Memory::new(MemoryConfig { theta_prop: 0.5, ..cfg(4) }).unwrap();
    for a in 0..4 {
        m.update(couplet(0.0, a));
    }
    m.store(3.0, &mut rng());
    m.retrieve(&emb(0.0), &mut rng());
    for j in 0..4 {
        let d = (4 - j) as f64 / 4.0;
        let want = libm::exp(-d / 0.9);
        assert!((m.q()[j] - want).abs() < 1e-15, "j={j}: {} vs {want}", m.q()[j]);
    }
    // d = 1/n for the newest: exp(-1/(4*0.9)); the oldest d = 1: exp(-1/0.9).
    assert!(m.q()[3] > m.q()[0]);
}

#[test]
fn value_functions_combine_g_rr_and_distance_as_named() {
    let (g, rr, dist) = (1.1, 0.5, 0.3);
    let want = [
        ("default", g * rr * dist),
        ("noGi", rr * dist),
        ("noDist", g * rr),
        ("noRR", g * dist),
        ("soloGi", g),
        ("soloDist", dist),
        ("soloRR", rr),
    ];
    for (name, v) in want {
        assert_eq!(ValueFn::parse(name).unwrap().value(g, rr, dist), v, "{name}");
    }
    assert!(ValueFn::parse("solo").unwrap_err().to_string().starts_with("valueFunction:"));
}

#[test]
fn t_update_order_decay_clamp_reset_then_boost() {
    // n = 4: a query equal to couplet j selects exactly column j (the others are at MAE >= 0.5).
    let vals = [0.0, 0.5, 1.0, 1.5];
    let mut m = with_sequence(cfg(4), &vals, 1, 1.0);
    // Select column 1; the next update boosts column 2 and resets column 1.
    m.retrieve(&emb(0.5), &mut rng());
    assert_eq!(m.selected().iter().map(|s| s.col).collect::<Vec<_>>(), [1]);
    m.update(couplet(0.0, 0));
    assert_eq!(m.bias(), &[1.0, 1.0, 1.01, 1.0]);
    // Keep selecting column 1: T[2] follows x -> 0.95 x + 0.05 + 0.01, whose fixed point is 1.2.
    for _ in 0..2000 {
        m.retrieve(&emb(0.5), &mut rng());
        m.update(couplet(0.0, 0));
    }
    let t2 = m.bias()[2];
    assert!((t2 - 1.2).abs() < 1e-4, "fixed point {t2}");
    assert!(m.bias()[..2].iter().chain(&m.bias()[3..]).all(|&t| t == 1.0));
}

#[test]
fn j_and_j_plus_1_both_selected_ends_at_1_01() {
    let c = MemoryConfig { theta_abs: 0.7, theta_prop: 0.9, ..cfg(4) };
    let mut m = with_sequence(c, &[1.0, 0.0, 0.5, 1.0], 1, 1.0);
    // Select column 1 alone a few times, so that T[2] builds up above 1.
    for _ in 0..3 {
        m.retrieve(&emb(0.0), &mut rng());
        assert_eq!(m.selected().iter().map(|s| s.col).collect::<Vec<_>>(), [1]);
        m.update(couplet(0.0, 0));
    }
    assert!(m.bias()[2] > 1.02, "{:?}", m.bias());
    // A query between columns 1 and 2 selects both.
    m.retrieve(&emb(0.25), &mut rng());
    assert_eq!(m.selected().iter().map(|s| s.col).collect::<Vec<_>>(), [1, 2]);
    m.update(couplet(0.0, 0));
    // Column 2 is decayed, reset to 1 (selected), then boosted (successor of 1): 1.01, not 1
    // (boost before reset) or ~1.037 (no reset). Column 3 is boosted as the successor of 2.
    assert_eq!(m.bias(), &[1.0, 1.0, 1.01, 1.01]);
}

#[test]
fn column_0_is_never_boosted_and_there_is_no_wrap_around() {
    // Select the newest column (n - 1): its successor would wrap to column 0 of the next row.
    let vals = [1.0, 1.0, 0.0];
    let mut m = Memory::new(cfg(3)).unwrap();
    for _ in 0..2 {
        for &v in &vals {
            m.update(couplet(v, 1));
        }
        m.store(1.0, &mut rng());
    }
    m.retrieve(&emb(0.0), &mut rng());
    assert_eq!(m.selected().iter().map(|s| (s.row, s.col)).collect::<Vec<_>>(), [(0, 2), (1, 2)]);
    m.update(couplet(0.0, 0));
    assert!(m.bias().iter().all(|&t| t == 1.0), "{:?}", m.bias());
}

#[test]
fn nsec_never_touches_t() {
    let mut m = with_sequence(MemoryConfig { sequential_bias: false, ..cfg(4) }, &[0.0, 0.5, 1.0, 1.5], 1, 1.0);
    for _ in 0..10 {
        m.retrieve(&emb(0.5), &mut rng());
        m.update(couplet(0.0, 0));
    }
    assert!(m.bias().iter().all(|&t| t == 1.0));
}

#[test]
fn entropy_is_zero_at_first_and_stale_when_nothing_is_selected() {
    let mut m = Memory::new(MemoryConfig { theta_prop: 0.5, ..cfg(2) }).unwrap();
    assert_eq!(m.entropy(), 0.0);
    m.update(couplet(0.0, 1));
    m.update(couplet(0.0, 2));
    m.store(1.0, &mut rng());
    m.retrieve(&emb(0.0), &mut rng());
    let h = m.entropy();
    assert!(h > 0.9 && h < 1.0, "two actions with unequal weights: {h}");
    assert_eq!(m.retrieve(&emb(5.0), &mut rng()), None);
    assert_eq!(m.entropy(), h, "stale: the last computed value");
}

#[test]
fn the_stored_sequence_is_the_stm_oldest_first_and_t_resets_at_episode_end() {
    let mut m = Memory::new(cfg(3)).unwrap();
    for (v, a) in [(0.25, 1), (0.5, 2), (0.75, 3), (1.0, 4)] {
        m.update(couplet(v, a));
    }
    assert!(m.store(2.5, &mut rng()));
    assert_eq!((0..3).map(|j| m.ltm_embedding(0, j)[7]).collect::<Vec<_>>(), [0.5, 0.75, 1.0]);
    assert_eq!((0..3).map(|j| m.ltm_action(0, j)).collect::<Vec<_>>(), [a(2), a(3), a(4)]);
    assert_eq!(m.rewards(), &[2.5]);
    m.retrieve(&emb(0.5), &mut rng());
    m.update(couplet(0.0, 0));
    assert!(m.bias().iter().any(|&t| t > 1.0));
    m.reset_bias();
    assert!(m.bias().iter().all(|&t| t == 1.0));
    // R <= 0 is never stored.
    assert!(!m.store(0.0, &mut rng()));
    assert!(!m.store(-0.3, &mut rng()));
    assert_eq!(m.len(), 1);
}

/// A memory of capacity 4 filled with one-couplet sequences of rewards `rs` (and action = index).
fn filled(forgetting: Forgetting, rs: &[f64]) -> Memory {
    let mut m = Memory::new(MemoryConfig { m: 4, forgetting, ..cfg(1) }).unwrap();
    for (i, &r) in rs.iter().enumerate() {
        m.update(couplet(0.0, i as u8));
        m.store(r, &mut rng());
    }
    m
}

fn actions(m: &Memory) -> Vec<u8> {
    (0..m.len()).map(|i| m.ltm_action(i, 0).into()).collect()
}

#[test]
fn each_forgetting_mode() {
    // NONE: the LTM freezes at m.
    let m = filled(Forgetting::None, &[1.0, 2.0, 3.0, 4.0, 5.0]);
    assert_eq!(actions(&m), [0, 1, 2, 3]);
    // FIFO: filling to m drops the oldest at once, so m - 1 rows between rewards.
    let m = filled(Forgetting::Fifo, &[1.0, 2.0, 3.0, 4.0, 5.0]);
    assert_eq!(actions(&m), [2, 3, 4]);
    // RWD: the lowest reward goes (the older of equals), even the row just added.
    let m = filled(Forgetting::Rwd, &[3.0, 1.0, 2.0, 1.0]);
    assert_eq!(actions(&m), [0, 2, 3]);
    let m = filled(Forgetting::Rwd, &[3.0, 2.0, 2.5, 0.5]);
    assert_eq!(actions(&m), [0, 1, 2]);
    // RWD-PROP: floor(10 % of 4) = 0 rows: nothing goes and the LTM stays full.
    let m = filled(Forgetting::RwdProp, &[3.0, 1.0, 2.0, 1.0, 5.0]);
    assert_eq!(actions(&m), [0, 1, 2, 3]);
}

#[test]
fn rwd_prop_drops_the_lowest_tenth() {
    let mut m = Memory::new(MemoryConfig { m: 20, forgetting: Forgetting::RwdProp, ..cfg(1) }).unwrap();
    let rs = [5.0, 1.0, 7.0, 0.5, 9.0, 3.0, 2.0, 8.0, 6.0, 4.0, 5.5, 7.5, 8.5, 9.5, 2.5, 3.5, 4.5, 6.5, 1.5, 0.7];
    for (i, &r) in rs.iter().enumerate() {
        m.update(couplet(0.0, (i % 9) as u8));
        m.store(r, &mut rng());
    }
    // floor(0.1 * 20) = 2 rows: rewards 0.5 and 0.7.
    assert_eq!(m.len(), 18);
    assert!(!m.rewards().contains(&0.5) && !m.rewards().contains(&0.7));
}

#[test]
fn prior_forgets_in_proportion_to_the_reward_gap() {
    let mut m = Memory::new(MemoryConfig { m: 5, forgetting: Forgetting::Prior, ..cfg(1) }).unwrap();
    for (i, r) in [1.0, 2.0, 3.0, 4.0].into_iter().enumerate() {
        m.update(couplet(0.0, i as u8));
        m.store(r, &mut rng());
    }
    // w = (4 + 1) - r = 4, 3, 2, 1; p = w / 10.
    assert_eq!(m.prior_probabilities(), [0.4, 0.3, 0.2, 0.1]);
    // Storing a fifth (r = 5) fills the LTM and removes one row drawn with those odds.
    let mut counts = [0usize; 5];
    let mut r = ChaCha8Rng::seed_from_u64(1);
    for _ in 0..5000 {
        let mut mm = m.clone();
        mm.update(couplet(0.0, 4));
        mm.store(5.0, &mut r);
        assert_eq!(mm.len(), 4);
        let gone = (0..5u8).find(|a| !actions(&mm).contains(a)).unwrap();
        counts[gone as usize] += 1;
    }
    // w over five rows = 5, 4, 3, 2, 1 -> p = 1/3, 4/15, 1/5, 2/15, 1/15.
    let want = [5.0, 4.0, 3.0, 2.0, 1.0].map(|w| w / 15.0);
    for (c, p) in counts.iter().zip(want) {
        let f = *c as f64 / 5000.0;
        assert!((f - p).abs() < 0.025, "{counts:?} vs {want:?}");
    }
}

#[test]
fn bad_parameters_name_themselves_and_their_range() {
    let e = |c: MemoryConfig| Memory::new(c).unwrap_err().to_string();
    assert_eq!(e(MemoryConfig { n: 0, ..cfg(1) }), "n: 0 is out of range 1..=1000");
    assert_eq!(e(MemoryConfig { m: 0, ..cfg(1) }), "m: 0 is out of range 1..=100000");
    assert!(e(MemoryConfig { tau: 0.0, ..cfg(1) }).starts_with("tau: 0 is out of range [0.01, 100]"));
    assert!(e(MemoryConfig { alpha: f64::NAN, ..cfg(1) }).starts_with("alpha: NaN"));
    assert!(e(MemoryConfig { theta_prop: 1.5, ..cfg(1) }).starts_with("thetaProp: 1.5 is out of range [0, 1]"));
    assert!(Forgetting::parse("lru").unwrap_err().to_string().starts_with("forgetting:"));
}

/// Invariants over random operation sequences: T >= 1 (and <= 1 + alpha / beta), LTM <= m, p
/// sums to 1 and puts weight only on stored actions, the masks stay in lockstep.
#[test]
fn invariants_hold_over_random_runs() {
    let mut src = ChaCha8Rng::seed_from_u64(2024);
    for case in 0..60 {
        let forgetting = Forgetting::ALL[case % 5].1;
        let cfg = MemoryConfig {
            n: src.gen_range(1..12),
            m: src.gen_range(1..15),
            theta_abs: src.gen_range(0.8..0.99),
            theta_prop: src.gen_range(0.8..1.0),
            sequential_bias: case % 7 != 0,
            forgetting,
            ..MemoryConfig::default()
        };
        let mut m = Memory::new(cfg.clone()).unwrap();
        let mut r = ChaCha8Rng::seed_from_u64(case as u64);
        for step in 0..400 {
            // A few distinct places (multiples of 1/64) so that retrieval selects often.
            let e = [src.gen_range(0..4) as f32 / 64.0; EMBEDDING];
            let a = m.retrieve(&e, &mut r);
            if let Some(a) = a {
                let sum: f64 = m.p().iter().sum();
                assert!((sum - 1.0).abs() < 1e-12, "p sums to {sum}");
                let stored: Vec<Action> =
                    m.selected().iter().map(|s| m.ltm_action(s.row as usize, s.col as usize)).collect();
                assert!(stored.contains(&a), "chose {a:?}, stored {stored:?}");
            }
            m.update(Couplet { embedding: e, action: a.unwrap_or(Action::ALL[src.gen_range(0..9)]) });
            if step % 17 == 16 {
                m.store(src.gen_range(-1.0..3.0), &mut r);
            }
            if step % 53 == 52 {
                m.reset_bias();
            }
            assert!(m.len() <= cfg.m);
            assert!(m.bias().len() == m.len() * cfg.n);
            let cap = 1.0 + cfg.alpha / cfg.beta + 1e-4;
            assert!(m.bias().iter().all(|&t| (1.0..=cap).contains(&t)), "T out of [1, {cap}]: {:?}", m.bias());
        }
    }
}

#[test]
fn reconfiguring_keeps_the_memory_and_refuses_a_new_stm_length() {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let cfg = MemoryConfig { n: 3, m: 10, ..MemoryConfig::default() };
    let mut mem = Memory::new(cfg.clone()).unwrap();
    for r in 1..=4 {
        mem.push(Couplet { embedding: [r as f32; 20], action: a(r as usize) });
        assert!(mem.store(r as f64, &mut rng));
    }
    // The bias switched off and on starts again from T = 1.
    mem.retrieve(&[3.0; 20], &mut rng);
    mem.update_bias();
    assert!(mem.bias().iter().any(|&t| t > 1.0), "a selection boosts its successor");
    let err = mem.reconfigure(MemoryConfig { n: 4, ..cfg.clone() }).unwrap_err();
    assert_eq!(err.field, "n");
    let err = mem.reconfigure(MemoryConfig { beta: -1.0, ..cfg.clone() }).unwrap_err();
    assert_eq!(err.field, "beta");
    assert_eq!((mem.config(), mem.len()), (&cfg, 4), "a refused change changes nothing");
    assert!(mem.bias().iter().any(|&t| t > 1.0));
    mem.reconfigure(MemoryConfig { sequential_bias: false, ..cfg.clone() }).unwrap();
    assert!(mem.bias().iter().all(|&t| t == 1.0));
    // A smaller m forgets the oldest sequences; a larger one makes room.
    mem.reconfigure(MemoryConfig { m: 2, ..cfg.clone() }).unwrap();
    assert_eq!(mem.rewards(), &[3.0, 4.0]);
    assert_eq!(mem.ltm_action(0, 2), a(3), "row 0 is now the third sequence stored");
    mem.reconfigure(MemoryConfig { m: 3, ..cfg }).unwrap();
    mem.push(Couplet { embedding: [5.0; 20], action: a(5) });
    assert!(mem.store(5.0, &mut rng));
    assert_eq!(mem.rewards(), &[3.0, 4.0, 5.0]);
}

/// A one-couplet memory holding `x`, bias on or off, with forgetting `f` and capacity `m`.
fn single(x: [f32; EMBEDDING], bias: bool, f: Forgetting, m: usize) -> Memory {
    let cfg = MemoryConfig { n: 1, m, sequential_bias: bias, forgetting: f, ..MemoryConfig::default() };
    let mut mem = Memory::new(cfg).unwrap();
    mem.update(Couplet { embedding: x, action: a(1) });
    assert!(mem.store(1.0, &mut rng()));
    mem
}

#[test]
fn without_the_bias_g_is_compared_with_theta_abs_in_f32_as_numpy_does() {
    // A stored couplet whose 1 - MAE is exactly f32(0.98) = 0.98000001907...: above 0.98 in f64,
    // not above 0.98 cast to f32. numpy (f32 arrays, a Python float threshold) does the latter
    // without the bias; with it G = that x T is f64 and compared in f64.
    let v = (0..100_000)
        .map(|i| 0.39 + i as f32 * 1e-7)
        .find(|&v| 1.0f32 - v / EMBEDDING as f32 == 0.98f32)
        .expect("some component gives 1 - MAE = f32(0.98)");
    let mut x = [0.0; EMBEDDING];
    x[0] = v;
    let q = [0.0; EMBEDDING];
    let mut nsec = single(x, false, Forgetting::None, 10);
    nsec.retrieve(&q, &mut rng());
    assert_eq!(nsec.biased_similarity(), &[0.98f32 as f64]);
    assert!(nsec.selected().is_empty(), "f32(0.98) > f32(0.98) is false");
    let mut sec = single(x, true, Forgetting::None, 10);
    sec.retrieve(&q, &mut rng());
    assert_eq!(sec.selected().len(), 1, "0.98000001907 > 0.98 in f64");
}

#[test]
fn without_the_bias_g_over_gmax_is_rounded_to_f32_as_numpy_does() {
    // Two couplets: the best at G1, another at G2 with G2 / G1 just at theta_prop: find a pair
    // whose ratio passes in one precision and fails in the other.
    let g = |v: f32| 1.0f32 - v / EMBEDDING as f32;
    let mut found = None;
    'outer: for i in 0..200 {
        let a = 0.001 + i as f32 * 1e-6;
        for j in 0..2000 {
            let b = 0.0995 + j as f32 * 1e-6;
            let (g1, g2) = (g(a), g(b));
            if g2 <= 0.98f32 {
                continue;
            }
            let f32_pass = g2 / g1 > 0.995f32;
            let f64_pass = g2 as f64 / g1 as f64 > 0.995;
            if f32_pass != f64_pass {
                found = Some((a, b, f32_pass));
                break 'outer;
            }
        }
    }
    let (a, b, f32_pass) = found.expect("a pair on the edge exists");
    let cfg = MemoryConfig { n: 2, sequential_bias: false, ..MemoryConfig::default() };
    let mut mem = Memory::new(cfg).unwrap();
    let at = |v: f32| {
        let mut x = [0.0; EMBEDDING];
        x[0] = v;
        Couplet { embedding: x, action: Action::RIGHT }
    };
    mem.update(at(a));
    mem.update(at(b));
    assert!(mem.store(1.0, &mut rng()));
    mem.retrieve(&[0.0; EMBEDDING], &mut rng());
    let cols: Vec<u32> = mem.selected().iter().map(|s| s.col).collect();
    assert_eq!(cols, if f32_pass { vec![0, 1] } else { vec![0] }, "a = {a}, b = {b}");
}

#[test]
fn after_any_forgetting_the_similarity_is_computed_in_f64() {
    // Components whose f32 and f64 sums differ.
    let mut r = ChaCha8Rng::seed_from_u64(4);
    let x: [f32; EMBEDDING] = std::array::from_fn(|_| r.gen_range(0.0..3.0));
    let q: [f32; EMBEDDING] = std::array::from_fn(|_| r.gen_range(0.0..3.0));
    let f32_sim = 1.0 - x.iter().zip(&q).map(|(a, b)| (b - a).abs()).sum::<f32>() / EMBEDDING as f32;
    let f64_sum = x.iter().zip(&q).map(|(&a, &b)| (b as f64 - a as f64).abs()).sum::<f64>();
    let f64_sim = 1.0 - f64_sum / EMBEDDING as f64;
    assert_ne!(f32_sim as f64, f64_sim, "the example shows the difference");
    for bias in [false, true] {
        let mut mem = single(x, bias, Forgetting::Fifo, 2);
        mem.retrieve(&q, &mut rng());
        assert_eq!(mem.biased_similarity(), &[f32_sim as f64], "before forgetting: f32");
        // A second store fills the LTM (m = 2): FIFO drops the oldest; the LTM is now floats.
        mem.update(Couplet { embedding: x, action: a(1) });
        assert!(mem.store(1.0, &mut rng()));
        assert_eq!(mem.len(), 1);
        mem.retrieve(&q, &mut rng());
        assert_eq!(mem.biased_similarity(), &[f64_sim], "after forgetting: f64 (bias {bias})");
    }
    // Without forgetting a full LTM stays f32.
    let mut mem = single(x, false, Forgetting::None, 1);
    mem.update(Couplet { embedding: x, action: a(1) });
    assert!(!mem.store(1.0, &mut rng()));
    mem.retrieve(&q, &mut rng());
    assert_eq!(mem.biased_similarity(), &[f32_sim as f64]);
}

#[test]
fn the_similarity_sums_in_numpys_pairwise_order() {
    let mut r = ChaCha8Rng::seed_from_u64(8);
    let (mut differs_from_sequential, n) = (0, 13);
    let cfg = MemoryConfig { n, sequential_bias: false, ..MemoryConfig::default() };
    let mut mem = Memory::new(cfg).unwrap();
    let stored: Vec<[f32; EMBEDDING]> = (0..n).map(|_| std::array::from_fn(|_| r.gen_range(0.0..4.0))).collect();
    for x in &stored {
        mem.update(Couplet { embedding: *x, action: a(1) });
    }
    assert!(mem.store(1.0, &mut rng()));
    for _ in 0..50 {
        let q: [f32; EMBEDDING] = std::array::from_fn(|_| r.gen_range(0.0..4.0));
        mem.retrieve(&q, &mut rng());
        for (j, x) in stored.iter().enumerate() {
            let terms: [f32; EMBEDDING] = std::array::from_fn(|k| (q[k] - x[k]).abs());
            let want = 1.0 - numpy_sum20(&terms) / EMBEDDING as f32;
            assert_eq!(mem.biased_similarity()[j], want as f64, "couplet {j}");
            let sequential = 1.0 - terms.iter().sum::<f32>() / EMBEDDING as f32;
            differs_from_sequential += (sequential != want) as u32;
        }
    }
    assert!(differs_from_sequential > 0, "the example tells the orders apart");
}

#[test]
fn after_forgetting_the_similarity_sums_in_f64_in_numpys_order_for_long_rows_too() {
    // n = 13: the vectorised path (four couplets side by side) with an overlapping last block.
    let mut r = ChaCha8Rng::seed_from_u64(12);
    let n = 13;
    let cfg = MemoryConfig { n, m: 2, forgetting: Forgetting::Fifo, sequential_bias: false, ..MemoryConfig::default() };
    let mut mem = Memory::new(cfg).unwrap();
    let stored: Vec<[f32; EMBEDDING]> = (0..n).map(|_| std::array::from_fn(|_| r.gen_range(0.0..4.0))).collect();
    for x in &stored {
        mem.update(Couplet { embedding: *x, action: a(1) });
    }
    mem.store(1.0, &mut rng());
    mem.store(1.0, &mut rng());
    assert_eq!(mem.len(), 1, "the second store filled m = 2 and forgot the oldest");
    for _ in 0..20 {
        let q: [f32; EMBEDDING] = std::array::from_fn(|_| r.gen_range(0.0..4.0));
        mem.retrieve(&q, &mut rng());
        for (j, x) in stored.iter().enumerate() {
            let terms: [f64; EMBEDDING] = std::array::from_fn(|k| (q[k] as f64 - x[k] as f64).abs());
            assert_eq!(mem.biased_similarity()[j], 1.0 - numpy_sum20(&terms) / EMBEDDING as f64, "couplet {j}");
        }
    }
}

/// Retrieval computes G only where T is raised and tests only the couplets near both thresholds,
/// and T's update visits only the raised couplets (docs/ALGORITHM.md, "Retrieval"). Over random
/// runs whose similarities are sometimes negative (a raised G then falls below its similarity),
/// whose beta may leave T = 1 unsettled and whose forgetting removes rows, G must be the
/// similarity times T everywhere, the selection the thresholds applied to G in full, and T after
/// each update the rule applied to all of T. The thresholds change now and then (to 0 too) while
/// the same embedding comes back (the last similarity row reused), and rows of 1 to 19 couplets
/// take every kernel's block shapes.
#[test]
fn the_selection_is_the_thresholds_over_g_in_full() {
    let mut src = ChaCha8Rng::seed_from_u64(35);
    // Multiples of 1/64 and two far values: every MAE is exact, and 1 - MAE is negative at 2.
    let places = [0.0, 1.0 / 64.0, 2.0 / 64.0, 3.0 / 64.0, 2.0, -2.0];
    for case in 0..48 {
        let mut cfg = MemoryConfig {
            n: src.gen_range(1..20),
            m: src.gen_range(1..12),
            theta_abs: src.gen_range(0.0..0.99),
            theta_prop: src.gen_range(0.5..1.0),
            alpha: src.gen_range(0.0..0.5),
            beta: if case % 3 == 0 { src.gen_range(0.0..1.0) } else { 0.05 },
            forgetting: Forgetting::ALL[case % 5].1,
            ..MemoryConfig::default()
        };
        let mut m = Memory::new(cfg.clone()).unwrap();
        let mut r = ChaCha8Rng::seed_from_u64(case as u64);
        for step in 0..300 {
            let v: f32 = places[src.gen_range(0..places.len())];
            let a = m.retrieve(&emb(v), &mut r);
            let g = m.biased_similarity();
            assert_eq!(g.len(), m.len() * cfg.n, "case {case} step {step}");
            for (i, &g) in g.iter().enumerate() {
                let sim = 1.0 - (m.ltm_embedding(i / cfg.n, i % cfg.n)[0] - v).abs();
                assert_eq!(g, sim as f64 * m.bias()[i], "case {case} step {step}: G of couplet {i}");
            }
            let gmax = g.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let want: Vec<usize> = if gmax <= 0.0 {
                Vec::new()
            } else {
                (0..g.len()).filter(|&i| g[i] > cfg.theta_abs && g[i] / gmax > cfg.theta_prop).collect()
            };
            let got: Vec<usize> = m.selected().iter().map(|s| s.row as usize * cfg.n + s.col as usize).collect();
            assert_eq!(got, want, "case {case} step {step}");
            assert!(got.iter().all(|&i| m.selected().iter().any(|s| s.g == g[i])));
            // T's update over the whole LTM, as docs/ALGORITHM.md states it: decay, clamp at 1 and
            // reset of the selected, then +alpha after each selected couplet within its row.
            let mut t = m.bias().to_vec();
            for (i, t) in t.iter_mut().enumerate() {
                let v = *t * (1.0 - cfg.beta) + cfg.beta;
                *t = if got.contains(&i) || v < 1.0 { 1.0 } else { v };
            }
            for &i in got.iter().filter(|&&i| i % cfg.n != cfg.n - 1) {
                t[i + 1] += cfg.alpha;
            }
            m.update(Couplet { embedding: emb(v), action: a.unwrap_or(Action::ALL[src.gen_range(0..9)]) });
            assert_eq!(m.bias(), &t[..], "case {case} step {step}: T after the update");
            if step % 13 == 12 {
                m.store(src.gen_range(-1.0..3.0), &mut r);
            }
            if step % 41 == 40 {
                m.reset_bias();
            }
            if step % 29 == 28 {
                new_thresholds(&mut cfg, &mut src, 0.0..0.99);
                m.reconfigure(cfg.clone()).unwrap();
            }
        }
    }
}

/// Retrieval through the coarse copy (`memory::coarse`: most similarities bounded, only those
/// that can matter computed) gives the bits of computing every similarity: the action, the
/// selection, Q, p, the entropy and G in full, over random memories of embeddings like the
/// encoder's (near one another, non-negative), with values far outside the stored range and
/// negative ones now and then, every forgetting mode (f32 and f64), the bias on and off, rows of
/// 1 to 60 couplets and thresholds changed live (to 0 too).
#[test]
fn the_coarse_bounds_give_the_bits_of_every_similarity() {
    let mut src = ChaCha8Rng::seed_from_u64(56);
    for case in 0..40 {
        let mut cfg = MemoryConfig {
            n: src.gen_range(1..60),
            m: src.gen_range(1..40),
            theta_abs: src.gen_range(0.5..0.995),
            theta_prop: src.gen_range(0.5..1.0),
            alpha: src.gen_range(0.0..0.5),
            sequential_bias: case % 4 != 0,
            forgetting: Forgetting::ALL[case % 5].1,
            ..MemoryConfig::default()
        };
        let (mut fast, mut plain) = (Memory::new(cfg.clone()).unwrap(), Memory::new(cfg.clone()).unwrap());
        let (mut r1, mut r2) = (ChaCha8Rng::seed_from_u64(case as u64), ChaCha8Rng::seed_from_u64(case as u64));
        // A random walk through embedding space, as a moving agent's views.
        let mut e: [f32; EMBEDDING] = std::array::from_fn(|_| src.gen_range(0.0..0.3));
        for step in 0..400 {
            for v in e.iter_mut() {
                *v = (*v + src.gen_range(-0.01..0.01f32)).max(0.0);
            }
            let mut seen = e;
            match src.gen_range(0..40) {
                0 => seen[src.gen_range(0..EMBEDDING)] = 5.0,
                1 => seen[src.gen_range(0..EMBEDDING)] = -0.5,
                _ => {}
            }
            let a = fast.retrieve(&seen, &mut r1);
            sec_playground::reuse::set(false);
            let b = plain.retrieve(&seen, &mut r2);
            sec_playground::reuse::set(true);
            let at = format!("case {case} step {step}");
            assert_eq!(a, b, "{at}: the action");
            assert_eq!(format!("{:?}", fast.selected()), format!("{:?}", plain.selected()), "{at}");
            assert_eq!(fast.q().map(f64::to_bits), plain.q().map(f64::to_bits), "{at}: Q");
            assert_eq!(fast.p().map(f64::to_bits), plain.p().map(f64::to_bits), "{at}: p");
            assert_eq!(fast.entropy().to_bits(), plain.entropy().to_bits(), "{at}: entropy");
            let bits = |g: Vec<f64>| g.into_iter().map(f64::to_bits).collect::<Vec<_>>();
            assert_eq!(bits(fast.biased_similarity()), bits(plain.biased_similarity()), "{at}: G");
            let couplet = Couplet { embedding: seen, action: a.unwrap_or(Action::ALL[src.gen_range(0..9)]) };
            fast.update(couplet);
            plain.update(couplet);
            if src.gen_bool(0.08) {
                let r = src.gen_range(-1.0..3.0);
                assert_eq!(fast.store(r, &mut r1), plain.store(r, &mut r2), "{at}: stored");
            }
            if step % 53 == 52 {
                fast.reset_bias();
                plain.reset_bias();
            }
            if step % 37 == 36 {
                new_thresholds(&mut cfg, &mut src, 0.5..0.995);
                fast.reconfigure(cfg.clone()).unwrap();
                plain.reconfigure(cfg.clone()).unwrap();
            }
        }
    }
}

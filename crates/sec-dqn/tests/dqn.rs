//! DQN as the authors ran it: the network's size, the epsilon schedule, the target sync, the
//! replay buffer, training that lowers the loss, runs through the core's run loop, and bad
//! parameters refused by name.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use sec_dqn::replay::{Meta, Replay};
use sec_dqn::{factory, Dqn};
use sec_playground::agent::controller::{Controller, Step};
use sec_playground::agent::dqn::DqnConfig;
use sec_playground::experiment::{AgentKind, Run, RunConfig};

fn rng() -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(3)
}

#[test]
fn the_network_is_the_nature_cnn() {
    let dqn = Dqn::new(DqnConfig::default(), 1, &mut rng()).unwrap();
    // conv 3->32 8x8, 32->64 4x4, 64->64 3x3, dense 3136->512, 512->9, with biases.
    let expected = (3 * 32 * 64 + 32) + (32 * 64 * 16 + 64) + (64 * 64 * 9 + 64) + (3136 * 512 + 512) + (512 * 9 + 9);
    assert_eq!(dqn.network().parameters(), expected);
    assert_eq!(expected, 1_686_697);
}

#[test]
fn epsilon_falls_linearly_to_its_floor() {
    let c = DqnConfig { epsilon_decisions: 10, epsilon_start: 1.0, epsilon_end: 0.1, ..DqnConfig::default() };
    let mut e = c.epsilon_start;
    let mut seen = vec![e];
    for _ in 0..12 {
        e = c.next_epsilon(e);
        seen.push(e);
    }
    assert!((seen[5] - 0.55).abs() < 1e-12, "{seen:?}");
    assert!((seen[10] - 0.1).abs() < 1e-12 && seen[11] == 0.1 && seen[12] == 0.1, "{seen:?}");
}

#[test]
fn the_replay_buffer_keeps_the_newest_and_chains_states() {
    let mut r = Replay::new(3);
    r.start(vec![0]);
    for k in 1..=5u8 {
        r.push(Meta { action: k, reward: k as f32, done: false }, vec![k]);
    }
    assert_eq!(r.len(), 3);
    let t: Vec<(u8, u8, u8)> = (0..3).map(|i| (r.get(i).state[0], r.get(i).meta.action, r.get(i).next[0])).collect();
    assert_eq!(t, [(2, 3, 3), (3, 4, 4), (4, 5, 5)], "oldest first; each state is the previous next state");
    let idx = r.sample_indices(1000, &mut rng());
    assert!(idx.iter().all(|&i| i < 3));
    let count = |k| idx.iter().filter(|&&i| i == k).count();
    assert!((0..3).all(|k| count(k) > 250), "uniform with replacement");
}

#[test]
fn a_training_step_fits_the_targets_and_sync_copies_the_network() {
    let cfg = DqnConfig { batch_size: 4, replay_size: 8, learning_rate: 1e-3, ..DqnConfig::default() };
    let mut dqn = Dqn::new(cfg, 1, &mut rng()).unwrap();
    // Nine goal frames through the agent's own hook: the first starts the chain, each next one
    // stores a terminal transition with reward 1 (no decision yet, so no training on the way).
    for k in 0..9u8 {
        let frame = vec![(10 + 20 * k) as f32 / 255.0; 84 * 84 * 3];
        let step =
            Step { reward: 1.0, episode_reward: 1.0, good_goal: true, goal_event: true, decides: true, done: true };
        assert!(dqn.wants_frame(&step));
        dqn.on_step(&step, Some(&frame), &mut rng());
    }
    assert_eq!(dqn.replay().len(), 8);
    let first = dqn.train_step(&mut rng());
    let mut last = first;
    for _ in 0..30 {
        last = dqn.train_step(&mut rng());
    }
    assert!(last < first * 0.5, "the loss falls on fixed terminal targets: {first} -> {last}");
    // The target network is the online one after a sync, not before.
    let img = vec![0.5f32; 84 * 84 * 3];
    let before = dqn.target_q(&img);
    dqn.sync_target();
    assert_ne!(before, dqn.target_q(&img));
    assert_eq!(dqn.target_q(&img), dqn.q(&img));
}

#[test]
fn dqn_runs_episodes_through_the_core_run_loop_deterministically() {
    let cfg = RunConfig {
        task: "object-permanence".into(),
        kind: AgentKind::Dqn,
        t: Some(120),
        dqn: DqnConfig {
            random_decisions: 20,
            batch_size: 8,
            replay_size: 200,
            epsilon_decisions: 60,
            ..DqnConfig::default()
        },
        ..RunConfig::default()
    };
    let play = || {
        let mut run = Run::with_agents(cfg.clone(), 5, Some(factory)).unwrap();
        (0..3).map(|_| run.episode().to_json()).collect::<Vec<_>>()
    };
    let a = play();
    assert_eq!(a, play(), "a run is a function of its seed");
    let m: Vec<serde_json::Value> = a.iter().map(|l| serde_json::from_str(l).unwrap()).collect();
    assert!(m.iter().all(|m| m["decisions"].as_u64().unwrap() > 0));
    assert!(m[2]["ltm"].as_u64().unwrap() > 0, "the replay buffer fills");
    assert!(m.iter().any(|m| m["contextualShare"].as_f64().unwrap() > 0.0), "the network acts after the warm-up");
    // Without the native factory the core refuses the kind by name.
    let e = Run::new(cfg.clone(), 5).err().unwrap().to_string();
    assert!(e.starts_with("kind:") && e.contains("natively"), "{e}");
}

#[test]
fn bad_dqn_parameters_are_refused_by_name() {
    let bad = [
        (DqnConfig { learning_rate: 0.0, ..DqnConfig::default() }, "dqn.learningRate"),
        (DqnConfig { gamma: 1.5, ..DqnConfig::default() }, "dqn.gamma"),
        (DqnConfig { batch_size: 0, ..DqnConfig::default() }, "dqn.batchSize"),
        (DqnConfig { replay_size: 10, ..DqnConfig::default() }, "dqn.replaySize"),
        (DqnConfig { epsilon_end: 0.5, epsilon_start: 0.2, ..DqnConfig::default() }, "dqn.epsilonEnd"),
        (DqnConfig { target_sync: 0, ..DqnConfig::default() }, "dqn.targetSync"),
        (DqnConfig { learning_rate: f64::NAN, ..DqnConfig::default() }, "dqn.learningRate"),
    ];
    for (cfg, field) in bad {
        let e = RunConfig { kind: AgentKind::Dqn, dqn: cfg, ..RunConfig::default() }.validate().unwrap_err();
        assert_eq!(e.field, field);
        assert!(e.message.contains("out of range"), "{e}");
    }
    let e = serde_json::from_str::<RunConfig>(r#"{"kind":"dqn","dqn":{"lr":0.1}}"#).unwrap_err().to_string();
    assert!(e.contains("unknown field `lr`"), "{e}");
}

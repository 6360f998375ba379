//! DQN as the authors ran it: the network's size, the epsilon schedule, the target sync, the
//! replay buffer, training that lowers the loss, runs through the core's run loop, and bad
//! parameters refused by name.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use sec_dqn::replay::{Meta, Replay};
use sec_dqn::DqnConfig;
use sec_dqn::{factory, Dqn};
use sec_playground::agent::controller::{Controller, Step};
use sec_playground::experiment::checkpoint::ResumeCheck;
use sec_playground::experiment::{AgentKind, EpisodeMetrics, Run, RunConfig};

fn rng() -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(3)
}

#[test]
fn the_network_is_the_nature_cnn() {
    sec_dqn::register();
    let dqn = Dqn::new(DqnConfig::default(), 1, &mut rng()).unwrap();
    // conv 3->32 8x8, 32->64 4x4, 64->64 3x3, dense 3136->512, 512->9, with biases.
    let expected = (3 * 32 * 64 + 32) + (32 * 64 * 16 + 64) + (64 * 64 * 9 + 64) + (3136 * 512 + 512) + (512 * 9 + 9);
    assert_eq!(dqn.network().parameters(), expected);
    assert_eq!(expected, 1_686_697);
}

#[test]
fn epsilon_falls_linearly_to_its_floor() {
    sec_dqn::register();
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
    sec_dqn::register();
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
    sec_dqn::register();
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
    assert_eq!(dqn.replay().unwrap().len(), 8);
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
    sec_dqn::register();
    let cfg =
        RunConfig { task: "object-permanence".into(), kind: AgentKind::Dqn, t: Some(120), ..RunConfig::default() }
            .with_section(DqnConfig {
                random_decisions: 20,
                batch_size: 8,
                replay_size: 200,
                epsilon_decisions: 60,
                ..DqnConfig::default()
            });
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
    sec_dqn::register();
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
        let e = RunConfig { kind: AgentKind::Dqn, ..RunConfig::default() }.with_section(cfg).validate().unwrap_err();
        assert_eq!(e.field, field);
        assert!(e.message.contains("out of range"), "{e}");
    }
    let e = serde_json::from_str::<RunConfig>(r#"{"kind":"dqn","dqn":{"lr":0.1}}"#).unwrap_err().to_string();
    assert!(e.contains("unknown field `lr`"), "{e}");
}

use sec_dqn::graph::{Census, Graph, LinkKey, Pending};
use sec_dqn::ErlamConfig;

fn pending(e: f32, action: u8, reward: f32) -> Pending {
    let mut embedding = [0.0; 20];
    embedding[0] = e;
    Pending { embedding, state: vec![], next_state: vec![], action, reward, done: false }
}

#[test]
fn the_graph_adds_episodes_backwards_and_merges_near_states() {
    sec_dqn::register();
    let cfg = ErlamConfig { nodes: 100, ..ErlamConfig::default() };
    let mut g = Graph::new(cfg, 0.5);
    // A -> B -> C, the last paying 1: returns backwards with gamma 0.5.
    for (e, a, r) in [(0.0, 1, 0.0), (1.0, 2, 0.0), (2.0, 3, 1.0)] {
        g.remember(pending(e, a, r));
    }
    g.end_episode();
    assert_eq!(g.len(), 3);
    let rt: Vec<f64> = g.ids().iter().map(|&id| g.node(id).unwrap().rt).collect();
    assert_eq!(rt, [1.0, 0.5, 0.25], "inserted from the episode's end: C, B, A");
    let [c, b, a] = [g.ids()[0], g.ids()[1], g.ids()[2]];
    assert_eq!(g.node(a).unwrap().next.get(&LinkKey::Action(1)), Some(&b), "A's action led to B");
    assert_eq!(g.value(a), 0.5, "the graph's value of A: Rt of the node its action led to");
    assert_eq!(g.value(c), 0.0, "no successor");
    // A second episode passes 0.01 from A (within 0.02: the same node) straight to C's neighbour.
    for (e, act, r) in [(0.01, 4, 0.0), (2.005, 3, 2.0)] {
        g.remember(pending(e, act, r));
    }
    g.end_episode();
    assert_eq!(g.len(), 3, "both states merged into A and C");
    assert_eq!(g.node(c).unwrap().rt, 2.0, "the better return is kept");
    assert_eq!(g.node(a).unwrap().rt, 1.0, "A: 0 + 0.5 x 2");
    assert_eq!(g.node(a).unwrap().next.get(&LinkKey::Action(4)), Some(&c));
}

#[test]
fn value_propagation_spreads_the_best_successor_return() {
    sec_dqn::register();
    let cfg = ErlamConfig { nodes: 100, propagate_every: 2, ..ErlamConfig::default() };
    let mut g = Graph::new(cfg, 0.5);
    // Episode 1: X -> Y (pays 0). Episode 2: Y' (= Y) -> Z paying 4.
    g.remember(pending(0.0, 1, 0.0));
    g.remember(pending(1.0, 1, 0.0));
    g.end_episode();
    g.remember(pending(1.0, 2, 0.0));
    g.remember(pending(3.0, 2, 4.0));
    g.end_episode();
    let x = *g.ids().iter().find(|&&id| g.node(id).unwrap().embedding[0] == 0.0).unwrap();
    assert_eq!(g.node(x).unwrap().rt, 0.0, "before propagation X only knows its own episode");
    g.propagate(1);
    assert_eq!(g.node(x).unwrap().rt, 0.0, "not a propagation episode (every 2)");
    g.propagate(2);
    // Y = 0 + 0.5 x 4 = 2 (it already had it); X = 0 + 0.5 x Rt(Y) = 1.
    assert_eq!(g.node(x).unwrap().rt, 1.0);
    assert!(g.last_sweeps >= 2, "sweeps until nothing changes");
}

#[test]
fn a_full_graph_evicts_its_least_recently_improved_node_and_rekeys_links() {
    sec_dqn::register();
    let cfg = ErlamConfig { nodes: 3, ..ErlamConfig::default() };
    let mut g = Graph::new(cfg, 0.5);
    for (e, a, r) in [(0.0, 1, 0.0), (1.0, 1, 0.0), (2.0, 1, 1.0)] {
        g.remember(pending(e, a, r));
    }
    g.end_episode();
    // The third insertion filled it: the oldest stamp (the first inserted, C) went at once.
    assert_eq!(g.len(), 2, "the authors' graph holds capacity - 1");
    let a = *g.ids().iter().find(|&&id| g.node(id).unwrap().embedding[0] == 0.0).unwrap();
    assert!(g.node(a).unwrap().next.keys().all(|k| matches!(k, LinkKey::Node(_))), "links re-keyed by node id");
    assert_eq!(g.value(a), 0.0, "so the graph's value no longer finds A's successor");
}

#[test]
fn erlam_runs_episodes_through_the_core_run_loop() {
    sec_dqn::register();
    let cfg =
        RunConfig { task: "object-permanence".into(), kind: AgentKind::Erlam, t: Some(100), ..RunConfig::default() }
            .with_section(DqnConfig {
                random_decisions: 10,
                batch_size: 8,
                epsilon_decisions: 50,
                ..DqnConfig::default()
            })
            .with_section(ErlamConfig { propagate_every: 2, ..ErlamConfig::default() });
    let play = || {
        let mut run = Run::with_agents(cfg.clone(), 4, Some(factory)).unwrap();
        (0..3).map(|_| run.episode().to_json()).collect::<Vec<_>>()
    };
    let a = play();
    assert_eq!(a, play(), "a run is a function of its seed");
    let m: Vec<serde_json::Value> = a.iter().map(|l| serde_json::from_str(l).unwrap()).collect();
    let nodes: Vec<u64> = m.iter().map(|m| m["ltm"].as_u64().unwrap()).collect();
    assert!(nodes[0] > 0 && nodes[2] >= nodes[0], "the graph grows at episode ends: {nodes:?}");
    let e = cfg.with_section(ErlamConfig { nodes: 1, ..ErlamConfig::default() }).validate().unwrap_err();
    assert_eq!(e.field, "erlam.nodes");
}

/// `erlam.censusEvery` adds the graph's census to every N-th episode's line and nothing else:
/// the episodes are the same as without it.
#[test]
fn erlam_logs_its_graphs_census_every_n_episodes_and_changes_nothing_else() {
    sec_dqn::register();
    let cfg =
        RunConfig { task: "object-permanence".into(), kind: AgentKind::Erlam, t: Some(60), ..RunConfig::default() }
            .with_section(DqnConfig {
                random_decisions: 10,
                batch_size: 8,
                epsilon_decisions: 50,
                ..DqnConfig::default()
            })
            .with_section(ErlamConfig { propagate_every: 2, census_every: 2, ..ErlamConfig::default() });
    let play = |cfg: &RunConfig| {
        let mut run = Run::with_agents(cfg.clone(), 4, Some(factory)).unwrap();
        (0..4).map(|_| run.episode()).collect::<Vec<_>>()
    };
    let with = play(&cfg);
    let logged: Vec<bool> = with.iter().map(|m| m.census.is_some()).collect();
    assert_eq!(logged, [false, true, false, true], "after episodes 2 and 4");
    let c = with[1].census.unwrap();
    assert_eq!(c.nodes, with[1].ltm, "the census counts the graph the line's ltm counts");
    assert!((0.0..=1.0).contains(&c.valued_share) && c.median_value.is_finite(), "{c:?}");
    let json = with[1].to_json();
    assert!(json.contains("\"census\":{\"nodes\":"), "{json}");
    let without =
        play(&cfg.clone().with_section(ErlamConfig { census_every: 0, ..cfg.section::<ErlamConfig>().clone() }));
    for (a, b) in with.iter().zip(&without) {
        assert_eq!(EpisodeMetrics { census: None, ..a.clone() }, *b);
    }
    let e = cfg
        .clone()
        .with_section(ErlamConfig { census_every: 2_000_000, ..cfg.section::<ErlamConfig>().clone() })
        .validate()
        .unwrap_err();
    assert_eq!(e.field, "erlam.censusEvery");
}

#[test]
fn erlam_embeds_with_the_runs_perception_at_its_scale() {
    sec_dqn::register();
    use sec_playground::agent::controller::EpisodeEnd;
    use sec_playground::encoder::{Perception, PerceptionKind};
    // The graph's node for one frame, with the trained model at its calibrated scale (exp1's
    // ERLAM, D17) and raw (`rawEmbeddings`, ERLAM-raw): the same bottleneck times the scale.
    let node = |scale: Option<f32>| {
        let p = Perception::new(PerceptionKind::Trained, "double-t-maze", scale, 1).unwrap();
        let mut dqn = Dqn::erlam(DqnConfig::default(), ErlamConfig::default(), p, 1, &mut rng()).unwrap();
        let frame: Vec<f32> = (0..84 * 84 * 3).map(|i| (i % 251) as f32 / 251.0).collect();
        let step =
            Step { reward: 0.0, episode_reward: 0.0, good_goal: false, goal_event: false, decides: true, done: false };
        dqn.on_step(&step, Some(&frame), &mut rng());
        dqn.on_step(&Step { done: true, ..step }, Some(&frame), &mut rng());
        dqn.on_episode_end(&EpisodeEnd { goal: false, driven: false });
        let g = dqn.graph().unwrap();
        g.node(g.ids()[0]).unwrap().embedding
    };
    let calibrated = Perception::new(PerceptionKind::Trained, "double-t-maze", None, 1).unwrap();
    let scale = calibrated.embedder().embedding_scale;
    assert!((scale - 0.214).abs() < 0.01, "the T-maze model's calibrated scale: {scale}");
    let (scaled, raw) = (node(None), node(Some(1.0)));
    assert!(raw.iter().any(|&x| x > 0.0));
    for (s, r) in scaled.iter().zip(raw) {
        assert!((s - r * scale).abs() <= 1e-5 * r.abs().max(1.0), "{scaled:?} vs {raw:?}");
    }
}

/// Plays `before` episodes, checkpoints, drops the run, resumes it and plays `after` more: the
/// log equals the one of a run never interrupted.
fn resumed_equals_uninterrupted(cfg: RunConfig, seed: u64, before: usize, after: usize) -> Vec<u8> {
    let play = |run: &mut Run, n: usize| (0..n).map(|_| run.episode().to_json()).collect::<Vec<_>>();
    let mut whole = Run::with_agents(cfg.clone(), seed, Some(factory)).unwrap();
    let expected = play(&mut whole, before + after);
    let mut first = Run::with_agents(cfg.clone(), seed, Some(factory)).unwrap();
    let mut got = play(&mut first, before);
    let mut bytes = Vec::new();
    first.save_checkpoint(&mut bytes).unwrap();
    drop(first);
    let mut resumed =
        Run::resume(cfg, seed, Some(factory), &mut bytes.as_slice(), &ResumeCheck::at_most(1000)).unwrap();
    got.extend(play(&mut resumed, after));
    assert_eq!(got, expected);
    bytes
}

fn short_dqn() -> DqnConfig {
    DqnConfig {
        random_decisions: 20,
        batch_size: 8,
        replay_size: 50,
        epsilon_decisions: 120,
        target_sync: 25,
        ..DqnConfig::default()
    }
}

#[test]
fn a_dqn_run_resumed_from_a_checkpoint_plays_as_if_never_interrupted() {
    sec_dqn::register();
    // Interrupted mid-training: replay full, epsilon half-way, the target synced, Adam-free RMSprop
    // state accumulated; the entropy in the log is of the network's own Q values.
    let cfg =
        RunConfig { task: "object-permanence".into(), kind: AgentKind::Dqn, t: Some(120), ..RunConfig::default() }
            .with_section(short_dqn());
    let bytes = resumed_equals_uninterrupted(cfg.clone(), 3, 2, 3);
    // A checkpoint is refused by a run of another agent, and a truncated one by its checksum.
    let erlam = RunConfig { kind: AgentKind::Erlam, ..cfg.clone() };
    let e = Run::resume(erlam, 3, Some(factory), &mut bytes.as_slice(), &ResumeCheck::at_most(1000)).err().unwrap();
    assert_eq!(e.field(), "config");
    let e =
        Run::resume(cfg, 3, Some(factory), &mut &bytes[..bytes.len() / 2], &ResumeCheck::at_most(1000)).err().unwrap();
    assert_eq!(e.field(), "checksum");
}

#[test]
fn an_erlam_run_resumed_from_a_checkpoint_plays_as_if_never_interrupted() {
    sec_dqn::register();
    // A small graph that evicts, propagation every 2 episodes, the checkpoint after an odd one.
    let cfg =
        RunConfig { task: "object-permanence".into(), kind: AgentKind::Erlam, t: Some(100), ..RunConfig::default() }
            .with_section(short_dqn())
            .with_section(ErlamConfig { propagate_every: 2, nodes: 40, ..ErlamConfig::default() });
    resumed_equals_uninterrupted(cfg, 4, 3, 3);
}

#[test]
fn the_census_finds_a_goal_merged_with_a_later_state_and_the_inflated_values_it_makes() {
    sec_dqn::register();
    let cfg = ErlamConfig { nodes: 100, ..ErlamConfig::default() };
    let mut g = Graph::new(cfg, 0.5);
    // Episode 1: A -> B -> G, G terminal and paying 1.
    g.remember(pending(0.0, 1, 0.0));
    g.remember(pending(1.0, 2, 0.0));
    g.remember(Pending { done: true, ..pending(2.0, 3, 1.0) });
    g.end_episode();
    let c = g.census();
    assert_eq!((c.nodes, c.valued, c.rewarded, c.rewarded_linked), (3, 2, 1, 0));
    assert_eq!(c.values, [0.0, 0.5, 1.0], "G has no successor; B leads to G (1), A to B (0.5)");
    assert_eq!(c.hops, [0, 1, 2]);
    // Episode 2: a view next to G (merged into it) is followed by A: G, terminal, now links on.
    g.remember(pending(2.001, 1, 0.0));
    g.remember(pending(0.0, 1, 0.0));
    g.end_episode();
    g.propagate(50);
    let c = g.census();
    assert_eq!((c.nodes, c.rewarded_linked), (3, 1));
    // G -> A -> B -> G: Rt(G) = 1 + 0.5 Rt(A), Rt(A) = 0.25 Rt(G): 1 / (1 - 0.125).
    let goal = Census::quantile(&c.values, 1.0).unwrap();
    assert!((goal - 1.0 / 0.875).abs() < 1e-5, "B's value is G's, {goal}");
    assert!(goal > c.max_reward, "a cycle through the goal lifts values above any reward");
    // The deviation: propagation leaves terminal nodes alone, so no value exceeds the reward.
    let cfg = ErlamConfig { nodes: 100, propagate_past_terminals: false, ..ErlamConfig::default() };
    let mut g = Graph::new(cfg, 0.5);
    for (e, a, r, done) in [(0.0, 1, 0.0, false), (1.0, 2, 0.0, false), (2.0, 3, 1.0, true)] {
        g.remember(Pending { done, ..pending(e, a, r) });
    }
    g.end_episode();
    g.remember(pending(2.001, 1, 0.0));
    g.remember(pending(0.0, 1, 0.0));
    g.end_episode();
    g.propagate(50);
    let c = g.census();
    assert_eq!(c.rewarded_linked, 1, "the goal's node is linked on all the same");
    assert_eq!(c.values, [0.0, 0.5, 1.0], "but keeps its reward: B leads to 1, A to 0.5");
}

/// A run checkpoint's parts: everything before the agent's state, the agent's CBOR state.
fn split_checkpoint(b: &[u8]) -> (Vec<u8>, ciborium::Value) {
    let hlen = u32::from_le_bytes(b[8..12].try_into().unwrap()) as usize;
    let gate = 12 + hlen;
    let state = gate + 8 + u64::from_le_bytes(b[gate..gate + 8].try_into().unwrap()) as usize;
    let value = ciborium::from_reader(&b[state..b.len() - 8]).unwrap();
    (b[..state].to_vec(), value)
}

/// `head` and `state` as a checkpoint, its checksum computed.
fn sealed(head: &[u8], state: &ciborium::Value) -> Vec<u8> {
    let mut b = head.to_vec();
    ciborium::into_writer(state, &mut b).unwrap();
    let sum = sec_playground::render::fnv1a(&b);
    b.extend_from_slice(&sum.to_le_bytes());
    b
}

/// Every leaf of `v` as (path, the leaf with indices and map keys written `*`): the format's
/// fields, each once however many entries hold it.
fn leaves(v: &ciborium::Value, path: &mut Vec<String>, out: &mut Vec<(Vec<String>, String)>) {
    use ciborium::Value;
    let pattern = |p: &[String]| {
        p.iter().map(|s| if s.starts_with('#') { "*" } else { s.as_str() }).collect::<Vec<_>>().join(".")
    };
    match v {
        Value::Array(items) => {
            for (i, item) in items.iter().enumerate() {
                path.push(format!("#{i}"));
                leaves(item, path, out);
                path.pop();
            }
        }
        Value::Map(entries) => {
            for (i, (k, item)) in entries.iter().enumerate() {
                path.push(match k {
                    Value::Text(t) => t.clone(),
                    _ => format!("#{i}"),
                });
                leaves(item, path, out);
                path.pop();
            }
        }
        _ => {
            if !out.iter().any(|(_, p)| *p == pattern(path)) {
                out.push((path.clone(), pattern(path)));
            }
        }
    }
}

/// The leaf at `path` (map entries by key text, or by position where `#i`).
fn leaf_mut<'a>(v: &'a mut ciborium::Value, path: &[String]) -> &'a mut ciborium::Value {
    use ciborium::Value;
    let Some((first, rest)) = path.split_first() else { return v };
    let index = first.strip_prefix('#').map(|i| i.parse::<usize>().unwrap());
    match v {
        Value::Array(items) => leaf_mut(&mut items[index.unwrap()], rest),
        Value::Map(entries) => {
            let at = match index {
                Some(i) => i,
                None => entries.iter().position(|(k, _)| matches!(k, Value::Text(t) if t == first)).unwrap(),
            };
            leaf_mut(&mut entries[at].1, rest)
        }
        _ => panic!("no leaf at {path:?}"),
    }
}

/// A value no run writes there: NaN for a number with a fraction, the largest integer, an empty
/// byte string (a frame or a network of no bytes), an unknown name; `None` for a boolean (both
/// values are legal).
fn poison(v: &ciborium::Value) -> Option<ciborium::Value> {
    use ciborium::Value;
    match v {
        Value::Float(_) => Some(Value::Float(f64::NAN)),
        Value::Integer(_) => Some(Value::Integer(u64::MAX.into())),
        Value::Bytes(_) => Some(Value::Bytes(Vec::new())),
        Value::Text(_) => Some(Value::Text("?".into())),
        Value::Null => Some(Value::Integer(7.into())),
        Value::Bool(_) => None,
        other => panic!("an unexpected leaf {other:?}"),
    }
}

/// Every field of DQN's and ERLAM's checkpoint state, poisoned in turn, is refused: the walk goes
/// over the CBOR the agent writes, so a field added to it is poisoned too, and a field without a
/// check behind it fails this test. The networks' and optimiser's bytes get a NaN in their last
/// tensor value as well.
#[test]
fn every_field_of_dqns_and_erlams_checkpoints_is_checked() {
    sec_dqn::register();
    for kind in [AgentKind::Dqn, AgentKind::Erlam] {
        let cfg = RunConfig { task: "object-permanence".into(), kind, t: Some(100), ..RunConfig::default() }
            .with_section(short_dqn())
            .with_section(ErlamConfig { propagate_every: 2, nodes: 40, ..ErlamConfig::default() });
        let mut run = Run::with_agents(cfg.clone(), 4, Some(factory)).unwrap();
        let log: String = (0..3).map(|_| run.episode().to_json() + "\n").collect();
        let mut bytes = Vec::new();
        run.save_checkpoint(&mut bytes).unwrap();
        let check = ResumeCheck { max_episodes: 3, log: Some(&log), legacy: false };
        let resume =
            |b: &[u8]| Run::resume(cfg.clone(), 4, Some(factory), &mut &b[..], &check).err().map(|e| e.to_string());
        assert_eq!(resume(&bytes), None, "{kind:?}: the file itself loads");
        let (head, state) = split_checkpoint(&bytes);
        let mut fields = Vec::new();
        leaves(&state, &mut Vec::new(), &mut fields);
        let mut checked = 0;
        for (path, pattern) in &fields {
            let mut edited = state.clone();
            let leaf = leaf_mut(&mut edited, path);
            let Some(bad) = poison(leaf) else { continue };
            *leaf = bad;
            let err = resume(&sealed(&head, &edited)).unwrap_or_else(|| panic!("{kind:?} {pattern}: resumed"));
            assert!(err.contains("agent"), "{kind:?} {pattern}: {err}");
            checked += 1;
        }
        for net in ["online", "target", "optimiser"] {
            let mut edited = state.clone();
            let ciborium::Value::Bytes(b) = leaf_mut(&mut edited, &[net.to_string()]) else { panic!("{net}") };
            let n = b.len();
            b[n - 4..].copy_from_slice(&f32::NAN.to_le_bytes());
            let err = resume(&sealed(&head, &edited)).unwrap_or_else(|| panic!("{kind:?} {net} NaN: resumed"));
            assert!(err.contains(net), "{kind:?} {net}: {err}");
        }
        assert!(checked >= 12, "{kind:?}: {checked} fields");
        eprintln!("{kind:?}: {checked} fields of {} poisoned and refused", fields.len());
    }
}

/// Registered, the sections are written in full, as the committed configurations wrote them:
/// each committed configuration of the paper's first experiment, read and written again, is
/// its preset's text, and every line it had is there in its order and spelling, but for DQN's
/// and ERLAM's sections in the other agents' runs, which are no longer written (the settings
/// added since it was written are the only new lines).
#[test]
fn registered_sections_write_the_committed_configurations_as_they_were() {
    sec_dqn::register();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../results/experiments/exp1");
    let conditions = sec_playground::experiment::presets::experiment("exp1").unwrap();
    let lines = |t: &str, native: bool| {
        let mut kept = Vec::new();
        let mut skipping = false;
        for line in t.lines().map(|l| l.trim_end_matches(',')) {
            if !native && (line == "  \"dqn\": {" || line == "  \"erlam\": {") {
                skipping = true;
            } else if skipping {
                skipping = line != "  }";
            } else {
                kept.push(line.to_string());
            }
        }
        kept
    };
    let mut compared = 0;
    for c in conditions {
        let Ok(committed) = std::fs::read_to_string(root.join(&c.name).join("config.json")) else { continue };
        let written = serde_json::to_string_pretty(&c.config).unwrap() + "\n";
        let read = RunConfig::from_json(&committed).unwrap();
        assert_eq!(read, c.config, "{}", c.name);
        assert_eq!(serde_json::to_string_pretty(&read).unwrap() + "\n", written, "{}", c.name);
        let native = c.config.agent_row().native_only;
        assert_eq!(written.contains("\"dqn\": {"), native, "{}: DQN's section only in a native run", c.name);
        let mut new = lines(&written, true).into_iter();
        for line in lines(&committed, native) {
            assert!(new.any(|l| l == line), "{}: {line} is not written, or not in its place", c.name);
        }
        compared += 1;
    }
    assert!(compared >= 19, "only {compared} committed configurations found");
}

//! Runs of SEC in a task: deterministic, and counted as the paper counts them.
#![cfg(not(target_arch = "wasm32"))]

use sec_playground::agent::mfec::Embedding;
use sec_playground::agent::mfec::MfecConfig;
use sec_playground::agent::SecConfig;
use sec_playground::encoder::PerceptionKind;
use sec_playground::experiment::fixtures::golden_run;
use sec_playground::experiment::{AgentKind, Run, RunConfig};

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

/// `tests/wasm.rs` checks the same logs under Node. `SEC_UPDATE_GOLDEN=1` rewrites them.
#[test]
fn a_short_run_gives_the_golden_episode_log() {
    for (perception, file) in [(PerceptionKind::Trained, "run.txt"), (PerceptionKind::Untrained, "run-untrained.txt")] {
        let log = golden_run(perception);
        let path = format!("{}/tests/golden/{file}", env!("CARGO_MANIFEST_DIR"));
        if std::env::var("SEC_UPDATE_GOLDEN").is_ok_and(|v| v == "1") {
            std::fs::write(&path, &log).unwrap();
        }
        assert_eq!(log, std::fs::read_to_string(&path).unwrap(), "{file}");
    }
}

/// SEC drawn textured, its gate the textured model: `tests/wasm.rs` and the Python suite check the
/// same log. The contextual layer must act in it, or it would not test the gate's model.
#[test]
fn a_short_textured_run_gives_its_golden_episode_log() {
    let lines = check_golden(sec_playground::experiment::fixtures::golden_textured_run(), "run-textured.txt");
    let acted = lines.iter().any(|l| l["contextualShare"].as_f64() > Some(0.0));
    assert!(acted, "the contextual layer never acted: the log does not test the textured gate");
}

/// SEC in an Olympics arena file with a ramp and a platform: `tests/wasm.rs` (the arena build) and
/// the Python suite check the same log. Its agent must reach the goal and act from memory, or the
/// log would test neither the 3-D world nor the memory.
#[test]
fn a_short_arena_file_run_gives_its_golden_episode_log() {
    let lines = check_golden(sec_playground::experiment::fixtures::golden_arena_run(), "run-arena.txt");
    assert!(lines.iter().any(|l| l["goal"] == true), "no goal reached");
    assert!(lines.iter().any(|l| l["contextualShare"].as_f64() > Some(0.0)), "the memory never acted");
}

/// `log` equals `tests/golden/<file>` (rewritten first with `SEC_UPDATE_GOLDEN=1`); its lines.
fn check_golden(log: String, file: &str) -> Vec<serde_json::Value> {
    let path = format!("{}/tests/golden/{file}", env!("CARGO_MANIFEST_DIR"));
    if std::env::var("SEC_UPDATE_GOLDEN").is_ok_and(|v| v == "1") {
        std::fs::write(&path, &log).unwrap();
    }
    assert_eq!(log, std::fs::read_to_string(&path).unwrap(), "{file}");
    log.lines().map(|l| serde_json::from_str(l).unwrap()).collect()
}

fn json_lines(cfg: &RunConfig, seed: u64, n: usize) -> Vec<String> {
    let mut run = Run::new(cfg.clone(), seed).unwrap();
    (0..n).map(|_| run.episode().to_json()).collect()
}

#[test]
fn baselines_run_deterministically_and_count_their_decisions() {
    let base = RunConfig { task: "object-permanence".into(), t: Some(250), ..RunConfig::default() };
    let mut rp = RunConfig { kind: AgentKind::Mfec, ..base.clone() };
    rp.section_mut::<MfecConfig>().embedding = Embedding::RandomProjection;
    let ae = RunConfig { kind: AgentKind::Mfec, ..base.clone() };
    let reactive = RunConfig { kind: AgentKind::Reactive, ..base.clone() };
    for cfg in [&rp, &ae, &reactive] {
        let a = json_lines(cfg, 3, 3);
        assert_eq!(a, json_lines(cfg, 3, 3), "{:?}", cfg.kind);
        for line in &a {
            let v: serde_json::Value = serde_json::from_str(line).unwrap();
            // The warm-up (1250 decisions) is longer than these episodes: reactive throughout.
            assert_eq!(v["contextualShare"], 0.0);
            assert!(v["decisions"].as_u64().unwrap() <= 63);
        }
    }
    // With one neighbour and no warm-up, Q (so the entropy) depends on the embedding: rp and ae
    // differ.
    let (mut rp1, mut ae1) = (rp.clone(), ae.clone());
    for c in [&mut rp1, &mut ae1] {
        let m = c.section_mut::<MfecConfig>();
        (m.k, m.warmup_decisions, m.warmup_rewarded_episodes) = (1, 0, 0);
    }
    assert_ne!(json_lines(&rp1, 3, 2), json_lines(&ae1, 3, 2), "MFEC-rp's entropies differ from MFEC-ae's");
    // The reactive walk logs no entropy; MFEC logs its softmax entropy, which (as the authors')
    // it computes only when it acts: during the warm-up it stays at its initial 0.
    let v: serde_json::Value = serde_json::from_str(&json_lines(&reactive, 3, 1)[0]).unwrap();
    assert_eq!((v["entropy"].as_f64(), v["entropyFresh"].is_null()), (Some(0.0), true));
    let v: serde_json::Value = serde_json::from_str(&json_lines(&ae, 3, 1)[0]).unwrap();
    assert_eq!((v["entropy"].as_f64(), v["entropyFresh"].is_null()), (Some(0.0), true));
    let v: serde_json::Value = serde_json::from_str(&json_lines(&rp1, 3, 1)[0]).unwrap();
    assert!(v["entropy"].as_f64().unwrap() > 0.0 && !v["entropyFresh"].is_null(), "MFEC acting logs its entropy");
}

#[test]
fn configurations_round_trip_through_json_and_unknown_fields_are_refused() {
    let mut cfg = RunConfig { kind: AgentKind::Mfec, ..RunConfig::default() };
    cfg.section_mut::<MfecConfig>().sum_rewards = true;
    cfg.section_mut::<SecConfig>().memory.sequential_bias = false;
    let text = serde_json::to_string(&cfg).unwrap();
    assert_eq!(serde_json::from_str::<RunConfig>(&text).unwrap(), cfg);
    let partial: RunConfig = serde_json::from_str(r#"{"task":"detour","agent":{"memory":{"m":125}}}"#).unwrap();
    assert_eq!(
        (partial.task.as_str(), partial.section::<SecConfig>().memory.m, partial.section::<SecConfig>().memory.n),
        ("detour", 125, 50)
    );
    let e = serde_json::from_str::<RunConfig>(r#"{"agent":{"memory":{"alfa":0.1}}}"#).unwrap_err().to_string();
    assert!(e.contains("unknown field `alfa`"), "{e}");
}

#[test]
fn raw_embeddings_undo_the_calibrated_scale() {
    // The object-permanence model's scale is 1.51: with raw embeddings the same run sees other
    // similarities, so once the contextual layer is consulted the logs differ.
    let cfg =
        RunConfig { task: "object-permanence".into(), perception: PerceptionKind::Trained, ..RunConfig::default() };
    let raw = RunConfig { raw_embeddings: true, ..cfg.clone() };
    let mut a = Run::new(cfg, 7).unwrap();
    let mut b = Run::new(raw, 7).unwrap();
    let (la, lb): (Vec<_>, Vec<_>) = (0..8).map(|_| (a.episode().to_json(), b.episode().to_json())).unzip();
    assert_ne!(la, lb);
}

#[test]
fn stepping_by_ticks_or_decisions_gives_the_same_run_as_by_episodes() {
    // Object permanence, seed 2: goals come early, so storage, the contextual layer (from the
    // 16th episode) and T all act.
    let cfg = RunConfig { task: "object-permanence".into(), ..RunConfig::default() };
    let whole = episodes(&cfg, 2, 18);
    let mut run = Run::new(cfg, 2).unwrap();
    let mut stepped = Vec::new();
    let mut decisions = 0;
    while stepped.len() < 18 {
        // Alternate: a few episodes tick by tick, the rest decision by decision.
        let t = if stepped.len() % 2 == 0 { run.tick() } else { run.decision() };
        decisions += t.decision.is_some() as u32;
        stepped.extend(t.finished.map(|m| format!("{m:?}")));
    }
    assert_eq!(stepped, whole);
    assert!(decisions > 12, "each episode decides");
}

#[test]
fn live_changes_apply_to_the_running_agent_and_others_ask_for_a_new_run() {
    let cfg = RunConfig { task: "object-permanence".into(), ..RunConfig::default() };
    let mut run = Run::new(cfg.clone(), 2).unwrap();
    for _ in 0..12 {
        run.episode();
    }
    let ltm = run.inspect().memory.unwrap().len();
    assert!(ltm >= 4, "object permanence stores sequences early: {ltm}");
    // alpha, the thresholds and a smaller m apply now; m forgets the oldest sequences.
    let mut live = cfg.clone();
    live.section_mut::<SecConfig>().memory.alpha = 0.3;
    live.section_mut::<SecConfig>().memory.theta_abs = 0.9;
    live.section_mut::<SecConfig>().memory.m = 2;
    live.section_mut::<SecConfig>().min_sequences = 2;
    let newest = run.inspect().memory.unwrap().rewards()[ltm - 2..].to_vec();
    assert_eq!(run.reconfigure(live.clone()), Ok(true));
    assert_eq!(run.config(), &live);
    let mem = run.inspect().memory.unwrap();
    assert_eq!((mem.len(), mem.config().alpha, mem.rewards()), (2, 0.3, &newest[..]));
    // n, the task or the agent need a new run: nothing changes.
    let changes: [fn(&mut RunConfig); 3] = [
        |c| c.section_mut::<SecConfig>().memory.n = 20,
        |c| c.task = "detour".into(),
        |c| c.kind = AgentKind::Reactive,
    ];
    for change in changes {
        let mut next = live.clone();
        change(&mut next);
        assert_eq!(run.reconfigure(next), Ok(false));
        assert_eq!(run.config(), &live);
    }
    // A bad value is refused by name and changes nothing.
    let mut bad = live.clone();
    bad.section_mut::<SecConfig>().memory.tau = 0.0;
    assert_eq!(run.reconfigure(bad).unwrap_err().field, "tau");
    assert_eq!(run.config(), &live);
    // The run goes on with the new parameters; the LTM grows back to at most m.
    for _ in 0..4 {
        assert!(run.episode().ltm <= 2);
    }
}

#[test]
fn a_fixed_start_heading_faces_the_centre_from_each_corner() {
    use sec_playground::arena::{facing_centre, StartHeading, Task};
    use sec_playground::env::{Env, EnvConfig};
    assert_eq!([facing_centre(3.0, 37.0), facing_centre(37.0, 37.0)], [135.0, 225.0]);
    assert_eq!([facing_centre(3.0, 3.0), facing_centre(37.0, 3.0)], [45.0, 315.0]);
    let headings = |h: StartHeading| {
        let task = Task::preset("double-t-maze").unwrap().with_start_heading(h);
        let mut env = Env::new(EnvConfig::new(task), 5).unwrap();
        (0..8)
            .map(|_| {
                let out = (env.layout_name().to_string(), env.world().agent.heading);
                env.reset(None);
                out
            })
            .collect::<Vec<_>>()
    };
    let fixed = headings(StartHeading::Fixed);
    for (layout, h) in &fixed {
        let want = match layout.as_str() {
            "corner-1" => 135.0,
            "corner-2" => 225.0,
            "corner-3" => 45.0,
            _ => 315.0,
        };
        assert_eq!(*h, want, "{layout}");
    }
    let random = headings(StartHeading::Random);
    assert!(random.iter().any(|(l, h)| fixed.iter().any(|(fl, fh)| fl == l && fh != h)));
    // Layouts that fix their heading keep it.
    let permanence = Task::preset("object-permanence").unwrap();
    assert_eq!(permanence.clone().with_start_heading(StartHeading::Fixed), permanence);
}

#[test]
fn perception_scale_and_heading_are_checked_and_the_trained_perception_is_the_old_run() {
    let e = |c: RunConfig| Run::new(c, 1).err().unwrap().to_string();
    let scale = |s| RunConfig { embedding_scale: Some(s), ..RunConfig::default() };
    assert_eq!(e(scale(0.0)), "embeddingScale: 0 is out of range (0, 1000000]");
    assert_eq!(e(scale(f32::INFINITY)), "embeddingScale: inf is out of range (0, 1000000]");
    assert!(e(RunConfig { raw_embeddings: true, ..scale(2.0) }).starts_with("rawEmbeddings:"));
    for (json, field) in [
        (r#"{"perception":"random"}"#, "unknown variant `random`, expected `untrained` or `trained`"),
        (r#"{"startHeading":"north"}"#, "unknown variant `north`, expected `random` or `fixed`"),
    ] {
        let err = serde_json::from_str::<RunConfig>(json).unwrap_err().to_string();
        assert!(err.contains(field), "{err}");
    }
    // The default perception is the untrained one; rawEmbeddings is embeddingScale 1.
    assert_eq!(RunConfig::default().perception, PerceptionKind::Untrained);
    let trained = RunConfig { task: "detour".into(), perception: PerceptionKind::Trained, ..RunConfig::default() };
    let raw = json_lines(&RunConfig { raw_embeddings: true, ..trained.clone() }, 3, 4);
    assert_eq!(raw, json_lines(&RunConfig { embedding_scale: Some(1.0), ..trained }, 3, 4));
}

/// MFEC's bookkeeping before D21 is the `per-episode` option: with it the golden MFEC runs of
/// that time (`tests/golden/mfec-per-episode.txt`, MFEC-ae then MFEC-rp, seed 7) come back bit
/// for bit.
#[test]
fn the_per_episode_mfec_bookkeeping_gives_the_old_golden_runs() {
    use sec_playground::agent::mfec::{Bookkeeping, MfecConfig};
    let mfec = MfecConfig {
        warmup_decisions: 100,
        warmup_rewarded_episodes: 1,
        bookkeeping: Bookkeeping::PerEpisode,
        ..MfecConfig::default()
    };
    let ae = RunConfig {
        task: "object-permanence".into(),
        t: Some(250),
        kind: AgentKind::Mfec,
        perception: PerceptionKind::Trained,
        ..RunConfig::default()
    }
    .with_section(mfec);
    let mut rp = ae.clone();
    rp.section_mut::<MfecConfig>().embedding = Embedding::RandomProjection;
    let got: Vec<String> = [ae, rp].iter().flat_map(|c| json_lines(c, 7, 6)).collect();
    let want = include_str!("golden/mfec-per-episode.txt");
    assert_eq!(got, want.lines().collect::<Vec<_>>());
}

/// `perception: trained` is the run from before the untrained perception existed: the trained
/// golden SEC episodes equal the log of that time (`tests/golden/sec-trained-before.txt`) in
/// every field but the entropies, which changed in their last digits only when the entropy's sum
/// took numpy's pairwise order.
#[test]
fn the_trained_perception_gives_the_sec_run_of_before() {
    let now = golden_run(PerceptionKind::Trained);
    let before = include_str!("golden/sec-trained-before.txt");
    for (a, b) in now.lines().zip(before.lines()) {
        let (mut a, mut b): (serde_json::Value, serde_json::Value) =
            (serde_json::from_str(a).unwrap(), serde_json::from_str(b).unwrap());
        for key in ["entropy", "entropyFresh"] {
            let (x, y) = (a[key].take(), b[key].take());
            match (x.as_f64(), y.as_f64()) {
                (Some(x), Some(y)) => assert!((x - y).abs() <= 1e-9 * y.abs().max(1e-9), "{key}: {x} vs {y}"),
                _ => assert_eq!(x, y),
            }
        }
        assert_eq!(a, b);
    }
    assert_eq!(before.lines().count(), 16);
}

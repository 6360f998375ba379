//! Under `wasm-pack test --node`: the wasm build reproduces the native golden trace bit for bit,
//! and the JS API refuses bad values with the parameter named.
#![cfg(target_arch = "wasm32")]

use sec_playground::arena::TASK_NAMES;
use sec_playground::env::trace::scripted_run;
use sec_playground::render::Surface;
use sec_playground::web::ArenaEnv;
use wasm_bindgen::{JsError, JsValue};
use wasm_bindgen_test::*;

/// An argument as JS passes it.
fn v(x: impl Into<JsValue>) -> JsValue {
    x.into()
}

const GOLDEN: &str = include_str!("golden/trace.txt");
const GOLDEN_TEXTURED: &str = include_str!("golden/trace-textured.txt");

/// The wasm build holds no model: register the six as the page does with the files it fetches.
fn models() {
    macro_rules! file {
        ($t:literal) => {
            ($t, include_bytes!(concat!("../assets/encoders/", $t, ".secae")) as &[u8])
        };
    }
    for (task, bytes) in [
        file!("double-t-maze"),
        file!("detour"),
        file!("detour-transparent"),
        file!("cylinder"),
        file!("object-permanence"),
        file!("object-permanence-pits"),
    ] {
        assert_eq!(sec_playground::web::register_model(u8s(bytes)).unwrap(), task);
    }
}

#[wasm_bindgen_test]
fn wasm_matches_the_native_golden_trace() {
    models();
    for (surface, golden) in [(Surface::Flat, GOLDEN), (Surface::Textured, GOLDEN_TEXTURED)] {
        let log: String = TASK_NAMES.iter().map(|t| scripted_run(t, surface, 7, 200).unwrap()).collect();
        for (i, (a, b)) in log.lines().zip(golden.lines()).enumerate() {
            assert_eq!(a, b, "{} trace line {} differs between wasm and native", surface.name(), i + 1);
        }
        assert_eq!(log.lines().count(), golden.lines().count());
    }
}

/// An Olympics arena whose boxes the agent pushes: rapier3d's bodies, built with its
/// cross-platform determinism, give the native golden trace bit for bit.
#[wasm_bindgen_test]
fn wasm_pushes_boxes_as_the_native_golden_trace_does() {
    let yaml = include_str!("../assets/arenas/competition/03-22-01.yaml");
    let task = sec_playground::arena::yaml::load_task("03-22-01", yaml).unwrap();
    let log = sec_playground::env::trace::scripted_task_run(task, Surface::Flat, 7, 300).unwrap();
    assert_eq!(log, include_str!("golden/trace-pushables.txt"));
}

/// Bytes as JS passes them.
fn u8s(b: &[u8]) -> wasm_bindgen::JsValue {
    js_sys::Uint8Array::from(b).into()
}

fn message(e: wasm_bindgen::JsError) -> String {
    let v: wasm_bindgen::JsValue = e.into();
    js_sys::Error::from(v).message().into()
}

#[wasm_bindgen_test]
fn the_js_api_validates_its_inputs() {
    models();
    assert!(message(ArenaEnv::new(v("nope"), v(1.0), None).err().unwrap()).contains("task"));
    assert!(message(ArenaEnv::new(v("detour"), v(-1.0), None).err().unwrap()).starts_with("seed:"));
    assert!(message(ArenaEnv::new(v("detour"), v(0.5), None).err().unwrap()).starts_with("seed:"));
    assert!(message(ArenaEnv::new(v("detour"), v(1.0), Some(v(1e9))).err().unwrap()).starts_with("t:"));
    let mut env = ArenaEnv::new(v("detour"), v(1.0), Some(v(50.0))).unwrap();
    let e = message(env.step(v(9)).err().unwrap());
    assert!(e.contains("action") && e.contains("0..=8"), "{e}");
    assert!(message(env.top_down(v(5)).err().unwrap()).contains("32..=2048"));
    // A refused call changed nothing: the run goes on.
    assert!(env.step(v(3)).is_ok());
    assert_eq!(env.observation().len(), 84 * 84 * 4);
    let e =
        ArenaEnv::from_yaml(v("x"), v("arenas:\n  0:\n    items:\n    - name: Pillar\n"), v(1.0), None).err().unwrap();
    assert!(message(e).contains("line 4"));
}

#[wasm_bindgen_test]
fn wasm_gives_the_native_golden_embedding() {
    models();
    use sec_playground::arena::Task;
    use sec_playground::encoder::{bundled, Scratch, EMBEDDING, IMAGE};
    use sec_playground::env::{Env, EnvConfig};
    let mut env = Env::new(EnvConfig::new(Task::preset("double-t-maze").unwrap()), 1).unwrap();
    let mut rgb = vec![0.0; IMAGE];
    env.observation().to_rgb_f32(&mut rgb);
    let ae = bundled::autoencoder("double-t-maze").unwrap();
    let mut e = [0.0; EMBEDDING];
    ae.encode(&rgb, &mut Scratch::default(), &mut e);
    let mut rec = Vec::new();
    ae.decode(&e, &mut Scratch::default(), &mut rec);
    let bytes: Vec<u8> = rec.iter().flat_map(|v| v.to_le_bytes()).collect();
    let mut text: String = e.iter().map(|v| format!("{:08x}\n", v.to_bits())).collect();
    text += &format!("reconstruction fnv1a {:016x}\n", sec_playground::render::fnv1a(&bytes));
    assert_eq!(text, include_str!("golden/embedding.txt"));
}

#[wasm_bindgen_test]
fn the_encoder_api_embeds_and_reconstructs_an_observation() {
    models();
    use sec_playground::web::Encoder;
    assert!(message(Encoder::new(v("maze")).err().unwrap()).contains("task"));
    let mut enc = Encoder::new(v("detour")).unwrap();
    let mut env = ArenaEnv::new(v("detour"), v(1.0), None).unwrap();
    let obs = env.observation();
    let e = enc.encode(u8s(&obs)).unwrap();
    assert_eq!(e.len(), 20);
    assert!(e.iter().any(|&v| v > 0.0));
    let rec = enc.reconstruct(u8s(&obs)).unwrap();
    assert_eq!(rec.len(), obs.len());
    let mse = enc.reconstruction_mse(u8s(&obs)).unwrap();
    assert!(mse > 0.0 && mse < 0.01, "a trained model reconstructs its first frame: mse {mse}");
    for bad in [wasm_bindgen::JsValue::NULL, wasm_bindgen::JsValue::UNDEFINED] {
        assert!(message(enc.encode(bad.clone()).err().unwrap()).starts_with("rgba: "));
        assert!(message(enc.reconstruct(bad.clone()).err().unwrap()).starts_with("rgba: "));
        assert!(message(sec_playground::web::register_model(bad).err().unwrap()).starts_with("bytes: "));
    }
    let err = message(enc.encode(u8s(&obs[..100])).err().unwrap());
    assert!(err.starts_with("rgba:") && err.contains("28224"), "{err}");
    assert_eq!(enc.encode(u8s(&obs)).unwrap(), e, "a refused call changed nothing");
}

#[wasm_bindgen_test]
fn wasm_gives_the_native_golden_episode_log() {
    models();
    use sec_playground::encoder::PerceptionKind;
    for (perception, golden) in [
        (PerceptionKind::Trained, include_str!("golden/run.txt")),
        (PerceptionKind::Untrained, include_str!("golden/run-untrained.txt")),
    ] {
        let log = sec_playground::experiment::fixtures::golden_run(perception);
        for (i, (a, b)) in log.lines().zip(golden.lines()).enumerate() {
            assert_eq!(a, b, "{perception:?}: episode {i} differs between wasm and native");
        }
        assert_eq!(log.lines().count(), golden.lines().count());
    }
}

/// The textured model registers under its own name, and a textured run through the JS API gives
/// the native golden log (`fixtures::golden_textured_run`).
#[wasm_bindgen_test]
fn a_textured_run_through_the_js_api_gives_the_native_golden_log() {
    models();
    let bytes = include_bytes!("../assets/encoders/double-t-maze-textured.secae");
    assert_eq!(sec_playground::web::register_model(u8s(bytes)).unwrap(), "double-t-maze-textured");
    let mut run =
        sec_playground::web::SecRun::new(js(r#"{"surface": "textured", "agent": {"minSequences": 1}}"#), v(1.0))
            .unwrap();
    let got: Vec<String> = (0..sec_playground::experiment::fixtures::TEXTURED_EPISODES)
        .map(|_| metrics(run.step_episode().unwrap()).to_json())
        .collect();
    let golden: Vec<&str> = include_str!("golden/run-textured.txt").lines().collect();
    assert_eq!(got, golden);
}

/// An Olympics arena file through the JS API (a build with the YAML parser, as the arena build
/// is) gives the native golden log (`fixtures::golden_arena_run`), with no model registered for it.
#[wasm_bindgen_test]
fn an_arena_files_run_through_the_js_api_gives_the_native_golden_log() {
    use sec_playground::experiment::{fixtures, RunConfig};
    let (name, yaml) = fixtures::ARENA_FILE;
    let mut cfg = RunConfig::default().with_arena(name, yaml).unwrap();
    cfg.section_mut::<sec_playground::agent::SecConfig>().min_sequences = 1;
    let config = serde_json::to_string(&cfg).unwrap();
    let mut run = sec_playground::web::SecRun::new(js(&config), v(3.0)).unwrap();
    let got: Vec<String> =
        (0..fixtures::ARENA_EPISODES).map(|_| metrics(run.step_episode().unwrap()).to_json()).collect();
    let golden: Vec<&str> = include_str!("golden/run-arena.txt").lines().collect();
    assert_eq!(got, golden);
    assert_eq!(run.reconstruction().length(), 0, "no model: no reconstruction");
}

fn js(json: &str) -> wasm_bindgen::JsValue {
    js_sys::JSON::parse(json).unwrap()
}

fn metrics(v: wasm_bindgen::JsValue) -> sec_playground::experiment::EpisodeMetrics {
    serde_wasm_bindgen::from_value(v).unwrap()
}

#[wasm_bindgen_test]
fn a_run_through_the_js_api_gives_the_native_golden_episode_log() {
    models();
    use sec_playground::experiment::EpisodeMetrics;
    use sec_playground::web::SecRun;
    // The untrained golden log's first 20 lines are SEC in object permanence with seed 2
    // (`golden_run`), the default perception.
    let golden: Vec<EpisodeMetrics> =
        include_str!("golden/run-untrained.txt").lines().take(20).map(|l| serde_json::from_str(l).unwrap()).collect();
    let mut run = SecRun::new(js(r#"{"task": "object-permanence"}"#), v(2.0)).unwrap();
    let mut got = Vec::new();
    // Step by decisions, by episodes and in batches: all the same run.
    while got.len() < 4 {
        let s: serde_json::Value = serde_wasm_bindgen::from_value(run.step_decision().unwrap()).unwrap();
        if !s["finished"].is_null() {
            got.push(serde_json::from_value::<EpisodeMetrics>(s["finished"].clone()).unwrap());
        }
    }
    for _ in 0..4 {
        got.push(metrics(run.step_episode().unwrap()));
    }
    while got.len() < 20 {
        let batch: Vec<EpisodeMetrics> = serde_wasm_bindgen::from_value(run.run_decisions(v(37)).unwrap()).unwrap();
        got.extend(batch);
    }
    // Exact f64 comparison: bit for bit with the native run.
    assert_eq!(&got[..20], &golden[..]);
}

#[wasm_bindgen_test]
fn the_run_api_refuses_bad_configurations_by_name_and_keeps_running() {
    models();
    use sec_playground::web::SecRun;
    let bad = [
        (r#"{"agent": {"memory": {"alpha": 2}}}"#, "alpha"),
        (r#"{"agent": {"memory": {"alpah": 0.1}}}"#, "agent.memory"),
        (r#"{"agent": {"memory": {"tau": "x"}}}"#, "agent.memory.tau"),
        (r#"{"task": "maze"}"#, "task"),
        (r#"{"kind": "dqn"}"#, "kind"),
        (r#"{"t": -3}"#, "t"),
        (r#"{"decisionPeriod": 0}"#, "decisionPeriod"),
        (r#"{"mfec": {"k": 0}}"#, "mfec.k"),
        (r#"[1, 2]"#, "config"),
    ];
    for (cfg, name) in bad {
        let e = message(SecRun::new(js(cfg), v(1.0)).err().unwrap_or_else(|| panic!("{cfg} was accepted")));
        assert!(e.starts_with(name), "{cfg}: {e}");
    }
    assert!(message(SecRun::new(js("{}"), v(f64::NAN)).err().unwrap()).starts_with("seed:"));
    let e = message(SecRun::new(js(r#"{"agent": {"memory": {"beta": 1.5}}}"#), v(1.0)).err().unwrap());
    assert!(e.contains("[0, 1]"), "the range is named: {e}");

    let mut run = SecRun::new(js(r#"{"task": "object-permanence", "t": 300}"#), v(3.0)).unwrap();
    run.run_decisions(v(100)).unwrap();
    let before: serde_json::Value = serde_wasm_bindgen::from_value(run.config().unwrap()).unwrap();
    for (cfg, name) in bad {
        let e = message(run.configure(js(cfg)).err().unwrap_or_else(|| panic!("{cfg} was accepted")));
        assert!(e.starts_with(name), "{cfg}: {e}");
    }
    assert!(message(run.run_decisions(v(0)).err().unwrap()).starts_with("decisions:"));
    assert!(message(run.memory_map(v("q")).err().unwrap()).starts_with("which:"));
    assert!(message(run.top_down(v(8)).err().unwrap()).starts_with("size:"));
    let after: serde_json::Value = serde_wasm_bindgen::from_value(run.config().unwrap()).unwrap();
    assert_eq!(before, after, "a refused configuration changed nothing");
    let view: serde_json::Value = serde_wasm_bindgen::from_value(run.view().unwrap()).unwrap();
    assert!(view["step"].as_u64().unwrap() > 0, "the run kept its state: {view}");
    run.run_decisions(v(10)).unwrap();
}

/// What `SecRun.configure` answered: "live" or "restart".
fn applied(answer: Result<JsValue, JsError>) -> String {
    let v: serde_json::Value = serde_wasm_bindgen::from_value(answer.unwrap()).unwrap();
    v["applied"].as_str().unwrap().to_string()
}

#[wasm_bindgen_test]
fn configure_changes_only_the_fields_it_names() {
    models();
    use sec_playground::web::SecRun;
    let mut run =
        SecRun::new(js(r#"{"task": "object-permanence", "t": 300, "agent": {"memory": {"alpha": 0.05}}}"#), v(2.0))
            .unwrap();
    let config = |run: &SecRun| -> serde_json::Value { serde_wasm_bindgen::from_value(run.config().unwrap()).unwrap() };
    let before = config(&run);
    let answer: serde_json::Value =
        serde_wasm_bindgen::from_value(run.configure(js(r#"{"agent": {"memory": {"tau": 0.5}}}"#)).unwrap()).unwrap();
    assert_eq!(answer["applied"], "live");
    assert_eq!(
        answer["changed"],
        serde_json::json!([{"field": "agent.memory.tau", "from": before["agent"]["memory"]["tau"], "to": 0.5, "live": true}])
    );
    let mut expected = before.clone();
    expected["agent"]["memory"]["tau"] = 0.5.into();
    assert_eq!(config(&run), expected, "alpha, t and the task kept their values");
    let answer: serde_json::Value =
        serde_wasm_bindgen::from_value(run.configure(js(r#"{"t": 400, "agent": {"memory": {"beta": 0.5}}}"#)).unwrap())
            .unwrap();
    assert_eq!(answer["applied"], "restart");
    let fields: Vec<(&str, bool)> = answer["changed"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| (c["field"].as_str().unwrap(), c["live"].as_bool().unwrap()))
        .collect();
    assert_eq!(fields, [("agent.memory.beta", true), ("t", false)]);
    assert_eq!(config(&run)["agent"]["memory"]["alpha"], 0.05);
    // A whole configuration replaces: what it leaves out takes the default.
    assert_eq!(applied(run.replace_config(js(r#"{"task": "object-permanence"}"#))), "restart");
    assert_eq!(config(&run)["t"], serde_json::Value::Null);
}

#[wasm_bindgen_test]
fn live_changes_and_restarts_through_the_js_api() {
    models();
    use sec_playground::web::SecRun;
    let mut run = SecRun::new(js(r#"{"task": "object-permanence"}"#), v(2.0)).unwrap();
    for _ in 0..8 {
        run.step_episode().unwrap();
    }
    let ltm = |run: &mut SecRun| {
        let v: serde_json::Value = serde_wasm_bindgen::from_value(run.view().unwrap()).unwrap();
        v["ltm"].as_u64().unwrap()
    };
    let stored = ltm(&mut run);
    assert!(stored >= 2, "object permanence stores early: {stored}");
    let live = r#"{"task": "object-permanence", "agent": {"memory": {"alpha": 0.2, "thetaAbs": 0.9, "tau": 2}}}"#;
    assert_eq!(applied(run.configure(js(live))), "live");
    assert_eq!(ltm(&mut run), stored, "a live change keeps the memory");
    let cfg: serde_json::Value = serde_wasm_bindgen::from_value(run.config().unwrap()).unwrap();
    assert_eq!(cfg["agent"]["memory"]["alpha"], 0.2);
    // The views: the camera, the reconstruction, the top-down map, the LTM heat map.
    assert_eq!(run.observation().length(), 84 * 84 * 4);
    assert_eq!(run.reconstruction().length(), 84 * 84 * 4);
    assert_eq!(run.top_down(v(64)).unwrap().length(), 64 * 64 * 4);
    run.step_decision().unwrap();
    let rows = ltm(&mut run);
    assert_eq!(run.memory_map(v("t")).unwrap().length() as u64, rows * run.stm_length() as u64);
    let restart = r#"{"task": "detour", "agent": {"memory": {"n": 20}}}"#;
    assert_eq!(applied(run.configure(js(restart))), "restart");
    assert_eq!((ltm(&mut run), run.stm_length(), run.seed()), (0, 20, 2.0), "a new run with the same seed");
}

#[wasm_bindgen_test]
fn models_are_registered_and_checked() {
    use sec_playground::web::{has_model, register_model};
    models();
    assert!(has_model(v("detour")).unwrap());
    let mut bad = include_bytes!("../assets/encoders/detour.secae").to_vec();
    bad[1000] ^= 1;
    let e = message(register_model(u8s(&bad)).err().unwrap());
    assert!(e.starts_with("weights:") && e.contains("checksum"), "{e}");
    let e = message(register_model(u8s(b"SECMEMRY not weights")).err().unwrap());
    assert!(e.starts_with("weights:") && e.contains("magic"), "{e}");
    assert!(has_model(v("detour")).unwrap(), "a refused file leaves the registered model");
    // A sound file of non-finite weights (issue 20: an infinite bias made every embedding
    // infinite) is refused by its tensor's name, and the registered model stays.
    let mut w = sec_playground::encoder::bundled::autoencoder("detour").unwrap().to_weights();
    w.tensors[1].data[0] = f32::INFINITY;
    let e = message(register_model(u8s(&w.to_bytes(sec_playground::encoder::DType::F32))).err().unwrap());
    assert!(e.starts_with(&format!("{}:", w.tensors[1].name)) && e.contains("inf"), "{e}");
    assert!(has_model(v("detour")).unwrap());
}

/// What the comparison's pool does between two time slices: a run written as a checkpoint in
/// one worker and resumed in another plays the golden log's episodes on, bit for bit.
#[wasm_bindgen_test]
fn a_run_checkpointed_and_resumed_through_the_js_api_plays_the_golden_log_on() {
    models();
    use sec_playground::experiment::EpisodeMetrics;
    use sec_playground::web::SecRun;
    let golden: Vec<EpisodeMetrics> =
        include_str!("golden/run-untrained.txt").lines().take(12).map(|l| serde_json::from_str(l).unwrap()).collect();
    let config = r#"{"task": "object-permanence"}"#;
    let mut run = SecRun::new(js(config), v(2.0)).unwrap();
    assert!(run.can_checkpoint());
    let mut got: Vec<EpisodeMetrics> = (0..5).map(|_| metrics(run.step_episode().unwrap())).collect();
    // In the middle of an episode: refused, and the run plays on.
    while !run.mid_episode() {
        run.step_decision().unwrap();
    }
    assert!(message(run.checkpoint().err().unwrap()).contains("between two episodes"));
    got.push(metrics(run.step_episode().unwrap()));
    assert!(!run.mid_episode());
    let bytes = run.checkpoint().unwrap();
    // Refused by name: another seed, a claim above the caller's count, a changed byte, no bytes.
    let refused = |r: Result<SecRun, JsError>| message(r.err().expect("refused"));
    assert!(refused(SecRun::resume(js(config), v(3.0), u8s(&bytes), v(6.0))).contains("seed"));
    assert!(refused(SecRun::resume(js(config), v(2.0), u8s(&bytes), v(5.0))).contains("6 claimed"));
    let mut changed = bytes.clone();
    changed[bytes.len() / 2] ^= 1;
    assert!(refused(SecRun::resume(js(config), v(2.0), u8s(&changed), v(6.0))).contains("checksum"));
    assert!(refused(SecRun::resume(js(config), v(2.0), v("SECCKPT4"), v(6.0))).starts_with("checkpoint:"));
    assert!(refused(SecRun::resume(js(config), v(2.0), u8s(&bytes), v(-1.0))).starts_with("max_episodes:"));
    let mut resumed = SecRun::resume(js(config), v(2.0), u8s(&bytes), v(6.0)).unwrap();
    while got.len() < 12 {
        got.extend(
            serde_wasm_bindgen::from_value::<Vec<EpisodeMetrics>>(resumed.run_decisions(v(41)).unwrap()).unwrap(),
        );
    }
    assert_eq!(&got[..12], &golden[..]);
    // MFEC's buffers are not written: it says so, and a checkpoint is refused by name.
    let mfec = SecRun::new(js(r#"{"task": "object-permanence", "kind": "mfec"}"#), v(2.0)).unwrap();
    assert!(!mfec.can_checkpoint());
    let e = message(mfec.checkpoint().err().unwrap());
    assert!(e.contains("does not checkpoint"), "{e}");
}

#[wasm_bindgen_test]
fn memory_files_and_driving_through_the_js_api() {
    use sec_playground::web::SecRun;
    models();
    let mut a = SecRun::new(js(r#"{"task": "object-permanence"}"#), v(2.0)).unwrap();
    while metrics(a.step_episode().unwrap()).ltm < 2 {}
    let file = a.save_memory().unwrap();
    // The untrained encoder is the seed's: another seed's run refuses the file, a run of the same
    // seed (or, with the trained perception, of any seed) takes it.
    let mut other = SecRun::new(js(r#"{"task": "object-permanence"}"#), v(8.0)).unwrap();
    let e = message(other.load_memory(u8s(&file)).err().unwrap());
    assert!(e.starts_with("memory:") && e.contains("another encoder"), "{e}");
    let trained = r#"{"task": "object-permanence", "perception": "trained"}"#;
    let mut t = SecRun::new(js(trained), v(2.0)).unwrap();
    while metrics(t.step_episode().unwrap()).ltm < 1 {}
    SecRun::new(js(trained), v(9.0)).unwrap().load_memory(u8s(&t.save_memory().unwrap())).unwrap();
    let mut b = SecRun::new(js(r#"{"task": "object-permanence"}"#), v(2.0)).unwrap();
    assert_eq!(b.load_memory(u8s(&file)).unwrap(), metrics_ltm(&mut a));
    assert_eq!(b.save_memory().unwrap(), file);
    // Corrupt and foreign files: refused, the run unchanged and still running.
    let mut corrupt = file.clone();
    corrupt[file.len() - 30] ^= 4;
    assert!(message(b.load_memory(u8s(&corrupt)).err().unwrap()).contains("checksum"));
    let mut c = SecRun::new(js(r#"{"task": "detour"}"#), v(1.0)).unwrap();
    let e = message(c.load_memory(u8s(&file)).err().unwrap());
    assert!(e.starts_with("memory:") && e.contains("object-permanence"), "{e}");
    assert_eq!(b.save_memory().unwrap(), file);
    // null, undefined or a string for bytes: refused by name, the run unchanged.
    for bad in [wasm_bindgen::JsValue::NULL, wasm_bindgen::JsValue::UNDEFINED, v("SECMEMRY")] {
        let e = message(b.load_memory(bad).err().unwrap());
        assert!(e.starts_with("bytes:") && e.contains("is not a Uint8Array"), "{e}");
    }
    assert_eq!(b.save_memory().unwrap(), file);
    b.step_episode().unwrap();
    // A person drives: actions are checked; the episode is marked.
    assert!(message(b.set_driver(v(9.0), true).err().unwrap()).contains("0..=8"));
    assert!(message(b.set_driver(v(1.5), true).err().unwrap()).contains("action"));
    b.set_driver(v(3.0), false).unwrap();
    let m = metrics(b.step_episode().unwrap());
    assert!(m.human);
    b.set_driver(JsValue::NULL, false).unwrap();
    assert!(!metrics(b.step_episode().unwrap()).human);
}

fn metrics_ltm(run: &mut sec_playground::web::SecRun) -> u32 {
    let v: serde_json::Value = serde_wasm_bindgen::from_value(run.view().unwrap()).unwrap();
    v["ltm"].as_u64().unwrap() as u32
}

/// Issue 20's JS reproducers: values of the wrong type, NaN, wrap-around and a throwing config
/// are refused by name, and the run or env is as it was.
#[wasm_bindgen_test]
fn bad_js_arguments_are_refused_by_name_and_leave_the_state_as_it_was() {
    use sec_playground::web::{Encoder, SecRun};
    models();
    let refused = |e: Result<(), wasm_bindgen::JsError>, name: &str| {
        let m = message(e.err().unwrap_or_else(|| panic!("{name}: accepted")));
        assert!(m.starts_with(&format!("{name}:")), "{m}");
        assert!(m.len() < 500, "a message of {} bytes", m.len());
    };
    // Numbers where strings are expected, strings, null and booleans where numbers are.
    refused(ArenaEnv::new(v(5), v(1), None).map(drop), "task");
    refused(ArenaEnv::from_yaml(v("a"), v(5), v(1), None).map(drop), "source");
    refused(Encoder::new(v(5)).map(drop), "task");
    for seed in [JsValue::NULL, v(true), v("5"), js_sys::Array::new().into(), v(f64::NAN), v(f64::INFINITY), v(-1)] {
        refused(ArenaEnv::new(v("detour"), seed, None).map(drop), "seed");
    }
    let mut env = ArenaEnv::new(v("detour"), v(1), Some(v(50))).unwrap();
    let before = env.observation();
    refused(env.step(v(2f64.powi(32) + 3.0)).map(drop), "action");
    refused(env.step(v("3")).map(drop), "action");
    refused(env.step_held(v(3), v(-1)).map(drop), "k");
    refused(env.step_held(v(3), v("5")).map(drop), "k");
    refused(env.top_down(v(f64::NAN)).map(drop), "size");
    assert_eq!(env.observation(), before, "refused steps move nothing");
    let mut run = SecRun::new(js(r#"{"task": "object-permanence"}"#), v(2)).unwrap();
    refused(run.memory_map(v(5)).map(drop), "which");
    refused(run.run_decisions(v(2f64.powi(32) + 1.0)).map(drop), "decisions");
    refused(run.run_decisions(v(-5)).map(drop), "decisions");
    // NaN in a config is refused, not turned into null (a default: the gate off).
    let nan = js_sys::eval("({agent: {gate: NaN}})").unwrap();
    let m = message(SecRun::new(nan, v(1)).err().unwrap());
    assert!(m.starts_with("agent.gate:") && m.contains("NaN"), "{m}");
    // A config whose getter throws is an error; the run is not left borrowed.
    let throwing = js_sys::eval("({get agent() { throw new Error('boom') }})").unwrap();
    let m = message(run.configure(throwing).err().unwrap());
    assert!(m.starts_with("config:") && m.contains("boom"), "{m}");
    run.run_decisions(v(10)).unwrap();
    assert_eq!(
        applied(run.configure(js(r#"{"task": "object-permanence", "agent": {"memory": {"alpha": 0.02}}}"#))),
        "live"
    );
}

/// After a refused deep-YAML file (which overflowed the wasm stack and trapped every later
/// call), a new env and a new run still work.
#[wasm_bindgen_test]
fn a_deeply_nested_yaml_file_is_refused_and_the_module_keeps_working() {
    use sec_playground::web::SecRun;
    models();
    let deep = format!("arenas:\n  0: !Arena\n    items:\n    {}x\n", "- ".repeat(3_600));
    let m = message(ArenaEnv::from_yaml(v("deep"), v(deep), v(1), None).err().unwrap());
    assert!(m.contains("yaml") && m.contains("deeper than"), "{m}");
    let mut env = ArenaEnv::new(v("detour"), v(1), None).unwrap();
    env.step(v(3)).unwrap();
    let mut run = SecRun::new(js(r#"{"task": "object-permanence"}"#), v(2)).unwrap();
    run.run_decisions(v(5)).unwrap();
}

#[wasm_bindgen_test]
fn the_agent_table_crosses_to_js_as_the_core_declares_it() {
    let table: serde_json::Value = serde_wasm_bindgen::from_value(sec_playground::web::agents().unwrap()).unwrap();
    assert_eq!(table, serde_json::to_value(sec_playground::agent::AGENTS).unwrap());
    assert!(table.as_array().unwrap().iter().any(|a| a["key"] == "sec" && a["hasMemory"] == true));
}

#[wasm_bindgen_test]
fn the_task_table_crosses_to_js_as_the_core_declares_it() {
    let table: serde_json::Value = serde_wasm_bindgen::from_value(sec_playground::web::tasks().unwrap()).unwrap();
    assert_eq!(table, serde_json::to_value(sec_playground::arena::TASKS).unwrap());
    assert_eq!(table.as_array().unwrap().len(), TASK_NAMES.len());
}

/// The wasm similarity kernels (simd128's four couplets side by side, and f64 once the LTM has
/// been through forgetting) give the bits of numpy's pairwise sum of one couplet at a time, for
/// rows that are a multiple of four and rows whose last block overlaps. No golden run reaches
/// forgetting, so this is what ties wasm's f64 similarity to the native one.
#[wasm_bindgen_test]
fn the_simd128_similarity_kernels_sum_in_numpys_order() {
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use sec_playground::arena::Action;
    use sec_playground::encoder::EMBEDDING;
    use sec_playground::memory::{pairwise20, Couplet, Forgetting, Memory, MemoryConfig};
    let mut r = ChaCha8Rng::seed_from_u64(54);
    for n in [4, 13, 50] {
        let cfg =
            MemoryConfig { n, m: 3, forgetting: Forgetting::Fifo, sequential_bias: false, ..MemoryConfig::default() };
        let mut mem = Memory::new(cfg).unwrap();
        let mut rows: Vec<Vec<[f32; EMBEDDING]>> = Vec::new();
        for stores in 0..3 {
            let row: Vec<[f32; EMBEDDING]> = (0..n).map(|_| std::array::from_fn(|_| r.gen_range(-1.0..4.0))).collect();
            for x in &row {
                mem.update(Couplet { embedding: *x, action: Action::RIGHT });
            }
            mem.store(1.0, &mut ChaCha8Rng::seed_from_u64(1));
            rows.push(row);
            if stores == 2 {
                rows.remove(0); // m = 3 is full: FIFO forgot the oldest, and the LTM is now f64
            }
            for _ in 0..10 {
                let q: [f32; EMBEDDING] = std::array::from_fn(|_| r.gen_range(-1.0..4.0));
                mem.retrieve(&q, &mut ChaCha8Rng::seed_from_u64(2));
                let want: Vec<f64> = rows
                    .iter()
                    .flatten()
                    .map(|x| {
                        if stores == 2 {
                            1.0 - pairwise20(|k| (q[k] as f64 - x[k] as f64).abs()) / EMBEDDING as f64
                        } else {
                            (1.0 - pairwise20(|k| (q[k] - x[k]).abs()) / EMBEDDING as f32) as f64
                        }
                    })
                    .collect();
                assert_eq!(mem.biased_similarity(), want, "n = {n}, after {} stores", stores + 1);
            }
        }
    }
}

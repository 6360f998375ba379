//! Runs of an arena file (`RunConfig::arena`): an Olympics arena played by SEC with the untrained
//! encoder and no gate, deterministic, and every part that needs a trained model refused by name.
#![cfg(not(target_arch = "wasm32"))]

use sec_playground::agent::SecConfig;
use sec_playground::encoder::PerceptionKind;
use sec_playground::experiment::{Run, RunConfig};

const FILE: &str = "01-01-01.yaml";

fn corpus(file: &str) -> String {
    let path = format!("{}/assets/arenas/competition/{file}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(path).expect("the corpus is committed")
}

fn arena_config() -> RunConfig {
    RunConfig::default().with_arena("01-01-01", &corpus(FILE)).expect("a loadable Olympics arena")
}

fn log(cfg: &RunConfig, seed: u64, n: usize) -> Vec<String> {
    let mut run = Run::new(cfg.clone(), seed).unwrap();
    (0..n).map(|_| run.episode().to_json()).collect()
}

#[test]
fn an_olympics_arena_runs_sec_with_the_untrained_encoder_and_no_gate() {
    let cfg = arena_config();
    assert_eq!(cfg.task, "01-01-01");
    assert_eq!(cfg.perception, PerceptionKind::Untrained);
    assert_eq!(cfg.section::<SecConfig>().gate, None);
    assert_eq!(cfg.t, None, "the file's own limit");
    let mut run = Run::new(cfg, 1).unwrap();
    assert!(run.encoder().is_none(), "no model was trained on an Olympics arena");
    // The goal is 2 m ahead: the random walk finds it, and SEC stores those episodes.
    let goals: usize = (0..60).map(|_| usize::from(run.episode().goal)).sum();
    assert!(goals > 0, "no goal in 60 episodes");
    let ltm = run.inspect().memory.expect("SEC has a memory").len();
    assert!(ltm > 0, "{goals} goals but no sequence stored");
    assert_eq!(run.gate_mse(), None);
    // The file's own limit: t 250 in the file.
    assert_eq!(run.env().t(), 250);
}

#[test]
fn an_arena_files_run_is_a_function_of_its_configuration_and_seed() {
    let cfg = arena_config();
    let a = log(&cfg, 7, 5);
    assert_eq!(a, log(&cfg, 7, 5));
    assert_ne!(a, log(&cfg, 8, 5));
    // Its JSON carries the file, so a configuration read back plays the same run.
    let json = serde_json::to_string(&cfg).unwrap();
    let back = RunConfig::from_json(&json).unwrap();
    assert_eq!(back, cfg);
    assert_eq!(log(&back, 7, 5), a);
    // And a configuration without one writes no `arena` (the committed runs' identities).
    assert!(!serde_json::to_string(&RunConfig::default()).unwrap().contains("arena"));
}

#[test]
fn what_an_arena_file_has_no_model_for_is_refused_by_name() {
    let field = |cfg: RunConfig| cfg.validate().unwrap_err().field;
    let cfg = arena_config();
    let mut trained = cfg.clone();
    trained.perception = PerceptionKind::Trained;
    assert_eq!(field(trained), "perception");
    let mut gated = cfg.clone();
    gated.section_mut::<SecConfig>().gate = Some(0.01);
    assert_eq!(field(gated), "agent.gate");
    for name in ["double-t-maze", "", " x", &"a".repeat(201)] {
        let mut named = cfg.clone();
        named.task = name.to_string();
        assert_eq!(field(named), "task", "{name:?}");
    }
    // A file that is not an arena: the loader's error, under `arena`.
    let e = RunConfig::default().with_arena("x", "arenas: 3").unwrap_err();
    assert!(e.field.starts_with("arena"), "{e}");
    // A gate on an agent without one (MFEC) is not its concern.
    let json = serde_json::json!({"task": "x", "arena": corpus(FILE), "kind": "mfec"});
    assert!(RunConfig::from_json(&json.to_string()).is_ok());
}

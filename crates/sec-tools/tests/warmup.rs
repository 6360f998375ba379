//! The page's warm-up memories (assets/warm-up/) are the reference runs' own: the double T-maze's
//! is made again here, byte for byte, by replaying its seed against the committed log; every
//! file loads into a run of its reference configuration with the LTM size its run logged.

use sec_playground::experiment::{Run, RunConfig};
use sec_tools::runner::{read_run_text, run_path};
use sec_tools::warmup::{snapshot, Entry};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn index() -> BTreeMap<String, Entry> {
    let text = std::fs::read_to_string(root().join("assets/warm-up/index.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

#[test]
fn every_warm_up_memory_holds_what_its_reference_run_logged() {
    let index = index();
    assert_eq!(
        index.keys().map(String::as_str).collect::<Vec<_>>(),
        ["cylinder", "detour", "double-t-maze", "object-permanence"],
        "one warm-up memory per task of experiment 1"
    );
    for (task, e) in &index {
        let dir = root().join("results/experiments").join(&e.run);
        let cfg = RunConfig::from_json(&std::fs::read_to_string(dir.join("config.json")).unwrap()).unwrap();
        assert_eq!(&cfg.task, task);
        let log = read_run_text(&run_path(&dir, "", e.seed)).unwrap();
        let line: serde_json::Value = serde_json::from_str(log.lines().nth(e.episodes - 1).unwrap()).unwrap();
        assert_eq!(line["ltm"].as_u64().unwrap() as usize, e.sequences, "{task}: the log's LTM size");
        let bytes = std::fs::read(root().join("assets/warm-up").join(&e.file)).unwrap();
        let mut run = Run::new(cfg, e.seed).unwrap();
        assert_eq!(run.load_memory(&bytes).unwrap(), e.sequences, "{task}: sequences loaded");
        // A memory of the reference run acts at once: the contextual layer takes part of the first episode.
        let m = run.episode();
        assert!(m.contextual_share > 0.0, "{task}: memory acted in no decision of the first episode");
    }
}

#[test]
fn the_double_t_maze_warm_up_is_made_again_byte_for_byte() {
    let e = &index()["double-t-maze"];
    let (bytes, made) = snapshot(&root().join("results/experiments").join(&e.run), e.seed, e.episodes).unwrap();
    assert_eq!(bytes, std::fs::read(root().join("assets/warm-up").join(&e.file)).unwrap());
    assert_eq!(Entry { file: e.file.clone(), ..made }, *e);
}

#[test]
fn a_snapshot_that_does_not_replay_its_log_is_refused() {
    let dir = std::env::temp_dir().join(format!("sec-warmup-test-{}", std::process::id()));
    let cond = dir.join("exp1/object-permanence/SEC");
    std::fs::create_dir_all(&cond).unwrap();
    let src = root().join("results/experiments/exp1/object-permanence/SEC");
    std::fs::copy(src.join("config.json"), cond.join("config.json")).unwrap();
    // The committed log with its second episode's reward changed.
    let log = read_run_text(&run_path(&src, "", 1)).unwrap();
    let mut lines: Vec<String> = log.lines().take(3).map(String::from).collect();
    let mut second: serde_json::Value = serde_json::from_str(&lines[1]).unwrap();
    second["decisions"] = serde_json::json!(second["decisions"].as_u64().unwrap() + 1);
    lines[1] = second.to_string();
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    std::io::Write::write_all(&mut gz, (lines.join("\n") + "\n").as_bytes()).unwrap();
    std::fs::write(run_path(&cond, "", 1), gz.finish().unwrap()).unwrap();
    let err = snapshot(&cond, 1, 3).unwrap_err();
    assert!(err.contains("episode 1 replays differently"), "{err}");
    let err = snapshot(&cond, 1, 4).unwrap_err();
    assert!(err.contains("3 episodes logged, fewer than the 4 asked for"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

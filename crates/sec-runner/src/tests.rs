//! The runner's tests across its parts: resuming, copying, replacing a shorter log, verifying,
//! shards preparing one folder together.

use crate::layout::*;
use crate::plan::*;
use crate::play::*;
use crate::verify::*;
use flate2::write::GzEncoder;
use indicatif::ProgressBar;
use sec_dqn::DqnConfig;
use sec_playground::experiment::AgentKind;
use sec_playground::experiment::RunConfig;
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("sec-runner-test-{}-{name}", std::process::id()));
    let _ = fs::remove_dir_all(&d);
    fs::create_dir_all(d.join("c/dqn")).unwrap();
    d
}

#[test]
fn an_interrupted_run_resumes_from_its_checkpoint_to_the_same_log() {
    sec_dqn::register();
    let dqn = DqnConfig { random_decisions: 10, batch_size: 4, replay_size: 30, ..DqnConfig::default() };
    let config =
        RunConfig { task: "object-permanence".into(), kind: AgentKind::Dqn, t: Some(60), ..RunConfig::default() }
            .with_section(dqn);
    let job =
        Job { condition: "c/dqn".into(), config, seed: 2, agents: Some(sec_dqn::factory), legacy_checkpoint: false };
    let bar = ProgressBar::hidden();
    let whole = dir("whole");
    run_job(&job, &whole, 6, 0, &bar).unwrap();
    let expected = read_run_text(&run_path(&whole, "c/dqn", 2)).unwrap();

    // Killed after episode 5 with the checkpoint of episode 4: the fifth is played again.
    let cut = dir("cut");
    play(&job, &cut, 6, 2, 5, &bar).unwrap();
    let ckpt = checkpoint_path(&cut, "c/dqn", 2);
    assert!(ckpt.exists(), "a checkpoint was left");
    let part = run_path(&cut, "c/dqn", 2).with_extension("part");
    assert_eq!(fs::read_to_string(&part).unwrap().lines().count(), 5);
    // Resumed after the checkpoint's four episodes (the log's head is the one it continues),
    // not restarted; the fifth line is played again.
    let (_, played, kept) = start(&job, &part, &ckpt, false).unwrap();
    let text = fs::read_to_string(&part).unwrap();
    assert_eq!((played, kept as usize), (4, text.split_inclusive('\n').take(4).map(str::len).sum()));
    // A log whose head was edited is not the one the checkpoint continues: it is not resumed.
    let (first, rest) = text.split_once('\n').unwrap();
    fs::write(&part, format!("{}\n{rest}", first.replacen("{", "{\"mark\":1,", 1))).unwrap();
    assert_eq!(start(&job, &part, &ckpt, false).unwrap().1, 0, "an edited log restarts the run");
    fs::write(&part, &text).unwrap();
    run_job(&job, &cut, 6, 2, &bar).unwrap();
    let log = read_run_text(&run_path(&cut, "c/dqn", 2)).unwrap();
    assert_eq!(log, expected);
    let mut left: Vec<_> = fs::read_dir(cut.join("c/dqn")).unwrap().map(|e| e.unwrap().file_name()).collect();
    left.sort();
    assert_eq!(left, ["seed-2.jsonl.gz", "seed-2.manifest.json"], "a finished run leaves only its log and manifest");

    // A corrupt checkpoint is not used: the run starts again, to the same log.
    let bad = dir("bad");
    play(&job, &bad, 6, 2, 3, &bar).unwrap();
    fs::write(checkpoint_path(&bad, "c/dqn", 2), b"SECCKPT1garbage").unwrap();
    run_job(&job, &bad, 6, 2, &bar).unwrap();
    assert_eq!(read_run_text(&run_path(&bad, "c/dqn", 2)).unwrap(), expected);

    // A checkpoint whose claim is edited (its checksum recomputed) against a log of three:
    // ten million is refused before any replay (no reset is played), one (the state is of
    // episode two's end) by the log's digest; either way the run starts again.
    let forge = |name: &str, episodes: u64| {
        let d = dir(name);
        play(&job, &d, 6, 2, 3, &bar).unwrap();
        let ckpt = checkpoint_path(&d, "c/dqn", 2);
        let bytes = fs::read(&ckpt).unwrap();
        let hlen = u32::from_le_bytes(bytes[8..12].try_into().unwrap()) as usize;
        let mut h: serde_json::Value = serde_json::from_slice(&bytes[12..12 + hlen]).unwrap();
        assert_eq!(h["episodes"], 2);
        h["episodes"] = episodes.into();
        let json = serde_json::to_vec(&h).unwrap();
        let mut out = bytes[..8].to_vec();
        out.extend_from_slice(&(json.len() as u32).to_le_bytes());
        out.extend_from_slice(&json);
        out.extend_from_slice(&bytes[12 + hlen..bytes.len() - 8]);
        let sum = sec_playground::render::fnv1a(&out);
        out.extend_from_slice(&sum.to_le_bytes());
        fs::write(&ckpt, out).unwrap();
        let part = run_path(&d, "c/dqn", 2).with_extension("part");
        let (_, played, kept) = start(&job, &part, &ckpt, false).unwrap();
        assert_eq!((played, kept), (0, 0), "a claim of {episodes}: not resumed");
        run_job(&job, &d, 6, 2, &bar).unwrap();
        assert_eq!(read_run_text(&run_path(&d, "c/dqn", 2)).unwrap(), expected);
        d
    };
    let forged = forge("forged", 10_000_000);
    let below = forge("below", 1);
    for d in [whole, cut, bad, forged, below] {
        fs::remove_dir_all(d).unwrap();
    }
}

/// A job whose configuration, seed and length equal a finished run's elsewhere is copied,
/// and the copy is what playing it gives; any other job is played.
#[test]
fn identical_finished_runs_are_copied_not_played() {
    let root = dir("reuse");
    let config = RunConfig { task: "object-permanence".into(), t: Some(40), ..RunConfig::default() };
    let write_config = |d: &Path, c: &RunConfig| {
        fs::create_dir_all(d).unwrap();
        fs::write(d.join("config.json"), serde_json::to_string(c).unwrap()).unwrap();
    };
    let bar = ProgressBar::hidden();
    let first =
        Job { condition: "g/a".into(), config: config.clone(), seed: 3, agents: None, legacy_checkpoint: false };
    write_config(&root.join("e1/g/a"), &config);
    run_job(&first, &root.join("e1"), 4, 0, &bar).unwrap();

    let same = Job { condition: "h/b".into(), ..first.clone() };
    let other = Job { config: RunConfig { t: Some(41), ..config.clone() }, condition: "h/c".into(), ..first.clone() };
    let longer = Job { condition: "h/d".into(), ..first.clone() };
    let (e2, e3) = (root.join("e2"), root.join("e3"));
    for (d, c) in [(e2.join("h/b"), &config), (e2.join("h/c"), &other.config), (e3.join("h/b"), &config)] {
        write_config(&d, c);
    }
    let finished = Finished::scan(&root);
    assert!(finished.find(&same, &e2, 4).is_some());
    assert!(finished.find(&other, &e2, 4).is_none(), "another configuration");
    assert!(finished.find(&Job { seed: 4, ..same.clone() }, &e2, 4).is_none(), "another seed");
    assert!(finished.find(&longer, &e2, 5).is_none(), "a longer run than any finished");
    assert!(finished.find(&longer, &e2, 3).is_some(), "a shorter run is a finished one's head");
    assert!(finished.find(&first, &root.join("e1"), 4).is_none(), "not its own file");
    // An interrupted play of the job leaves a log and a checkpoint that the copy removes.
    play(&same, &e2, 4, 1, 2, &bar).unwrap();
    assert_eq!(fs::read_dir(e2.join("h/b")).unwrap().count(), 3);
    let (made, copied, skipped) = run_all(&[same.clone(), other.clone()], &e2, 4, 0, 1, Some(&finished)).unwrap();
    let left: Vec<_> = fs::read_dir(e2.join("h/b")).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(left.len(), 3, "config.json, the log and its manifest (copied from): {left:?}");
    assert_eq!((made, copied, skipped), (1, 1, 0));
    let copy = fs::read(run_path(&e2, "h/b", 3)).unwrap();
    assert_eq!(copy, fs::read(run_path(&root.join("e1"), "g/a", 3)).unwrap());

    // Played instead (--reuse no), the same job writes the same log.
    assert_eq!(run_all(&[same], &e3, 4, 0, 1, None).unwrap(), (1, 0, 0));
    assert_eq!(read_run_text(&run_path(&e3, "h/b", 3)).unwrap(), read_run_text(&run_path(&e2, "h/b", 3)).unwrap());
    fs::remove_dir_all(root).unwrap();
}

/// A longer run of a finished job re-plays it and replaces the shorter log only when that log
/// is its head; a doctored shorter log stops the job and both logs are kept.
#[test]
fn a_longer_run_replaces_a_shorter_log_only_when_it_is_its_head() {
    let out = dir("longer");
    let config = RunConfig { task: "object-permanence".into(), t: Some(40), ..RunConfig::default() };
    let job =
        Job { condition: "c/dqn".into(), config, seed: 5, agents: Some(sec_dqn::factory), legacy_checkpoint: false };
    let bar = ProgressBar::hidden();
    run_job(&job, &out, 3, 0, &bar).unwrap();
    let short = read_run_text(&run_path(&out, "c/dqn", 5)).unwrap();
    run_job(&job, &out, 5, 0, &bar).unwrap();
    let long = read_run_text(&run_path(&out, "c/dqn", 5)).unwrap();
    assert_eq!(long.lines().count(), 5);
    assert_eq!(first_difference(&short, &long), None);

    // Episode 2 of the shorter log doctored: the 6-episode run is refused.
    let mut lines: Vec<String> = short.lines().map(String::from).collect();
    lines[1] = lines[1].replacen("\"episode\":", "\"episode\": ", 1);
    assert_ne!(lines[1], short.lines().nth(1).unwrap(), "the doctoring changed the line");
    let doctored = lines.join("\n") + "\n";
    let path = run_path(&out, "c/dqn", 5);
    let mut gz = GzEncoder::new(Vec::new(), flate2::Compression::fast());
    gz.write_all(doctored.as_bytes()).unwrap();
    fs::write(&path, gz.finish().unwrap()).unwrap();
    let e = run_job(&job, &out, 6, 0, &bar).unwrap_err();
    assert!(e.contains("at episode 2") && e.contains("both are kept"), "{e}");
    assert_eq!(read_run_text(&path).unwrap(), doctored, "the shorter log is kept");
    assert_eq!(fs::read_to_string(path.with_extension("part")).unwrap().lines().count(), 6);
    fs::remove_dir_all(out).unwrap();
}

/// `verify` passes on runs of one configuration and seed where the shorter is the longer's
/// head, and names the pair when a log is doctored.
#[test]
fn verify_finds_a_doctored_log() {
    let root = dir("verify");
    let config = RunConfig { task: "object-permanence".into(), t: Some(40), ..RunConfig::default() };
    let bar = ProgressBar::hidden();
    for (exp, n) in [("e1", 5), ("e2", 3)] {
        let d = root.join(exp).join("g/a");
        fs::create_dir_all(&d).unwrap();
        fs::write(d.join("config.json"), serde_json::to_string(&config).unwrap()).unwrap();
        let job =
            Job { condition: "g/a".into(), config: config.clone(), seed: 2, agents: None, legacy_checkpoint: false };
        run_job(&job, &root.join(exp), n, 0, &bar).unwrap();
    }
    let v = verify(&root).unwrap();
    assert_eq!((v.runs, v.pairs, v.failures.len()), (2, 1, 0), "{v:?}");
    let short = run_path(&root.join("e2"), "g/a", 2);
    let text = read_run_text(&short).unwrap().replacen("\"goal\":false", "\"goal\":true", 1);
    write_gzip(&short, text.as_bytes()).unwrap();
    let v = verify(&root).unwrap();
    assert_eq!(v.failures.len(), 1, "{v:?}");
    assert!(v.failures[0].contains("differ at episode 1"), "{}", v.failures[0]);
    fs::remove_dir_all(root).unwrap();
}

/// Shards of one grid started at once write and read the same manifests: none may see
/// another's half-written file (which read as "another configuration" and stopped a shard).
#[test]
fn shards_started_together_all_prepare_their_directory() {
    let out = dir("shards");
    let conditions = (0..4)
        .map(|i| ManifestCondition {
            name: format!("g/c{i}"),
            paper_total: None,
            config: RunConfig { t: Some(100 + i), ..RunConfig::default() },
            plan: None,
        })
        .collect();
    let manifest = ExperimentManifest { experiment: "x".into(), episodes: 3, seeds: vec![1, 2], conditions };
    let failures: Vec<String> = std::thread::scope(|s| {
        let shards: Vec<_> = (0..4)
            .map(|_| s.spawn(|| (0..100).filter_map(|_| prepare(&out, &manifest).err()).collect::<Vec<_>>()))
            .collect();
        shards.into_iter().flat_map(|h| h.join().unwrap()).collect()
    });
    assert_eq!(failures, Vec::<String>::new());
    let names: Vec<_> = fs::read_dir(out.join("g/c0")).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names, ["config.json"], "no temporary file is left");
    fs::remove_dir_all(out).unwrap();
}

//! The experiment runner end to end: runs, resumes, shards, reports and refuses bad input.

use std::path::{Path, PathBuf};
use std::process::Command;

fn cli(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_sec-experiment")).args(args).output().unwrap();
    (out.status.success(), String::from_utf8_lossy(&out.stdout).into(), String::from_utf8_lossy(&out.stderr).into())
}

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sec-experiment-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn files(dir: &Path) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for cond in ["object-permanence/SEC", "object-permanence/NSEC", "object-permanence/reactive"] {
        for seed in 1..=2 {
            let p = sec_tools::runner::run_path(&dir.join("smoke"), cond, seed);
            out.push((format!("{cond} {seed}"), sec_tools::runner::read_run_text(&p).unwrap_or_default()));
        }
    }
    out
}

#[test]
fn runs_resume_shard_and_report() {
    let (a, b) = (temp("whole"), temp("shards"));
    let run = |dir: &Path, extra: &[&str]| {
        let mut args =
            vec!["run", "smoke", "--seeds", "2", "--episodes", "3", "--jobs", "2", "--out", dir.to_str().unwrap()];
        args.extend_from_slice(extra);
        cli(&args)
    };
    let (ok, _, err) = run(&a, &[]);
    assert!(ok, "{err}");
    assert!(err.contains("6 runs made, 0 copied from identical finished runs, 0 already there"), "{err}");
    let whole = files(&a);
    assert!(whole.iter().all(|(_, text)| text.lines().count() == 3), "every run has its 3 episodes");
    // Resuming makes nothing new.
    let (ok, _, err) = run(&a, &[]);
    assert!(ok && err.contains("0 runs made, 0 copied from identical finished runs, 6 already there"), "{err}");
    // Two shards make disjoint halves of the same files, bit for bit.
    let (ok1, _, e1) = run(&b, &["--shard", "1/2"]);
    let (ok2, _, e2) = run(&b, &["--shard", "2/2"]);
    assert!(ok1 && ok2 && e1.contains("3 runs made") && e2.contains("3 runs made"), "{e1}{e2}");
    assert_eq!(files(&b), whole);
    // The report: the table, the CSV and the plots.
    let (ok, md, err) = cli(&["report", "smoke", "--out", a.to_str().unwrap()]);
    assert!(ok, "{err}");
    assert!(md.contains("| SEC | 2 |") && md.contains("| NSEC | 2 |"), "{md}");
    for f in ["report.md", "summary.csv", "plots/object-permanence-reward.png", "plots/object-permanence-entropy.svg"] {
        assert!(a.join("smoke").join(f).exists(), "{f}");
    }
    let png = std::fs::read(a.join("smoke/plots/object-permanence-reward.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    // A changed configuration under the same name is refused.
    std::fs::write(a.join("smoke/object-permanence/SEC/config.json"), "{}\n").unwrap();
    let (ok, _, err) = run(&a, &[]);
    assert!(!ok && err.contains("holds runs of another configuration"), "{err}");
    let _ = std::fs::remove_dir_all(&a);
    let _ = std::fs::remove_dir_all(&b);
}

#[test]
fn record_then_trace_reproduces_the_runs_decisions() {
    let dir = temp("trace");
    std::fs::create_dir_all(&dir).unwrap();
    let cfg = dir.join("c.json");
    std::fs::write(&cfg, r#"{"task":"object-permanence","t":250}"#).unwrap();
    let (events, trace) = (dir.join("events.jsonl"), dir.join("trace.jsonl"));
    let (c, e, t) = (cfg.to_str().unwrap(), events.to_str().unwrap(), trace.to_str().unwrap());
    let (ok, _, err) = cli(&["record", "--config", c, "--seed", "4", "--episodes", "3", "--events", e]);
    assert!(ok, "{err}");
    let episodes: Vec<serde_json::Value> = err.lines().map(|l| serde_json::from_str(l).unwrap()).collect();
    let (ok, _, err) = cli(&["trace", "--config", c, "--seed", "4", "--events", e, "--trace", t]);
    assert!(ok, "{err}");
    let lines: Vec<serde_json::Value> =
        std::fs::read_to_string(&trace).unwrap().lines().map(|l| serde_json::from_str(l).unwrap()).collect();
    let decisions: u64 = episodes.iter().map(|m| m["decisions"].as_u64().unwrap()).sum();
    assert_eq!(lines.len() as u64, decisions);
    assert!(err.contains(&format!("{decisions} decisions traced")));
    for key in ["action", "layer", "t", "selected", "q", "p", "entropy", "ltm"] {
        assert!(lines[0].get(key).is_some(), "{key}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_input_is_refused_by_name() {
    let err = |args: &[&str]| {
        let (ok, _, e) = cli(args);
        assert!(!ok, "{args:?} should fail");
        e
    };
    assert!(err(&["run", "exp9"]).contains(
        "experiment: 'exp9' is not one of exp1, exp2, exp3, exp4, presets, heading, perception, textured, smoke"
    ));
    assert!(err(&["run", "smoke", "--episodes", "0"]).contains("--episodes: '0' is not a whole number in 1..=1000000"));
    assert!(err(&["run", "smoke", "--shard", "3/2"]).contains("--shard: '3/2' is not i/N"));
    assert!(err(&["run", "smoke", "--seeds", "5..2"]).contains("--seeds: '5..2'"));
    assert!(err(&["run", "smoke", "--sedes", "2"]).contains("unknown option --sedes"));
    let dir = temp("bad");
    std::fs::create_dir_all(&dir).unwrap();
    let cfg = dir.join("c.json");
    std::fs::write(&cfg, r#"{"agent":{"memory":{"tau":-1}}}"#).unwrap();
    let e = err(&["run", "--config", cfg.to_str().unwrap(), "--name", "a/b", "--out", dir.to_str().unwrap()]);
    assert!(e.contains("tau"), "{e}");
    // A type error names the field as well as the line and column.
    std::fs::write(&cfg, r#"{"agent":{"memory":{"tau":"x"}}}"#).unwrap();
    let e = err(&["run", "--config", cfg.to_str().unwrap(), "--name", "a/b", "--out", dir.to_str().unwrap()]);
    assert!(e.contains("agent.memory.tau: invalid type") && e.contains("line 1"), "{e}");
    let e = err(&["run", "smoke", "--checkpoint-every", "-1"]);
    assert!(e.contains("--checkpoint-every"), "{e}");
    let e = err(&["run", "smoke", "--reuse", "maybe", "--out", dir.to_str().unwrap()]);
    assert!(e.contains("--reuse: 'maybe' is not yes or no"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A named pipe with no writer, a directory or a device as `--config` is refused by kind before
/// any read (a pipe blocked `open` itself before); so are the trace's events.
#[cfg(unix)]
#[test]
fn text_inputs_are_regular_files_only() {
    let dir = temp("fifo");
    std::fs::create_dir_all(&dir).unwrap();
    let pipe = dir.join("p");
    assert!(Command::new("mkfifo").arg(&pipe).status().unwrap().success());
    let p = pipe.to_str().unwrap();
    let cfg = dir.join("c.json");
    std::fs::write(&cfg, r#"{"task": "object-permanence"}"#).unwrap();
    let c = cfg.to_str().unwrap();
    let cases: [(&[&str], &str); 5] = [
        (&["run", "--config", p, "--name", "a/b", "--out", dir.to_str().unwrap()], "a named pipe"),
        (&["config", "--config", p], "a named pipe"),
        (&["config", "--config", dir.to_str().unwrap()], "a directory"),
        (&["config", "--config", "/dev/zero"], "a device"),
        (&["trace", "--config", c, "--seed", "1", "--events", p], "a named pipe"),
    ];
    for (args, kind) in cases {
        let (ok, _, err) = cli(args);
        assert!(!ok && err.contains(kind) && err.contains("not a regular file"), "{args:?}: {err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `parameters` is the table the page builds its controls from, per agent: the same JSON as the
/// core's, and readable text.
#[test]
fn parameters_lists_the_pages_settings_per_agent() {
    use sec_playground::experiment::settings::params_for;
    for agent in [None, Some("sec"), Some("reactive"), Some("dqn")] {
        let mut args = vec!["parameters", "--json"];
        if let Some(a) = agent {
            args.extend(["--agent", a]);
        }
        let (ok, out, err) = cli(&args);
        assert!(ok, "{err}");
        let got: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert_eq!(got, serde_json::to_value(params_for(agent).unwrap()).unwrap(), "{agent:?}");
    }
    let (_, sec, _) = cli(&["parameters", "--agent", "sec"]);
    let alpha = sec.lines().find(|l| l.starts_with("alpha ")).expect("alpha is SEC's");
    assert!(alpha.contains("[0, 1]") && alpha.contains("live"), "{alpha}");
    let (_, reactive, _) = cli(&["parameters", "--agent", "reactive"]);
    assert!(!reactive.lines().any(|l| l.starts_with("alpha ")) && reactive.contains("task "), "{reactive}");
    let (ok, _, err) = cli(&["parameters", "--agent", "nope"]);
    assert!(!ok && err.contains("--agent: 'nope' is not one of sec, "), "{err}");
}

/// `--set` changes the fields it names; the others keep the file's values (never the defaults),
/// and `config` says what changed and whether it acts live.
#[test]
fn set_changes_only_the_fields_it_names() {
    let dir = temp("set");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("c.json");
    std::fs::write(&file, r#"{"task": "object-permanence", "t": 300, "agent": {"memory": {"alpha": 0.05}}}"#).unwrap();
    let f = file.to_str().unwrap();
    let (ok, base, err) = cli(&["config", "--config", f]);
    assert!(ok && err.is_empty(), "{err}");
    let (ok, out, err) = cli(&["config", "--config", f, "--set", r#"{"agent": {"memory": {"tau": 0.5}}}"#]);
    assert!(ok, "{err}");
    let mut expected: serde_json::Value = serde_json::from_str(&base).unwrap();
    let from = expected["agent"]["memory"]["tau"].clone();
    expected["agent"]["memory"]["tau"] = 0.5.into();
    assert_eq!(serde_json::from_str::<serde_json::Value>(&out).unwrap(), expected, "alpha, t and the task kept");
    assert_eq!(err.trim(), format!("agent.memory.tau: {from} -> 0.5 (live)"));
    let (_, _, err) = cli(&["config", "--config", f, "--set", r#"{"t": 400}"#]);
    assert_eq!(err.trim(), "t: 300 -> 400 (needs a restart)");
    let (ok, _, err) = cli(&["config", "--config", f, "--set", r#"{"agent": {"memory": {"tua": 1}}}"#]);
    assert!(!ok && err.contains("--set: agent.memory") && err.contains("tua"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn runs_of_parts_of_an_experiment_add_up_in_its_report() {
    let dir = temp("only");
    let out = dir.to_str().unwrap();
    for only in ["object-permanence/SEC", "object-permanence/NSEC"] {
        let (ok, _, err) = cli(&["run", "smoke", "--only", only, "--seeds", "1", "--episodes", "2", "--out", out]);
        assert!(ok && err.contains("1 runs made"), "{err}");
    }
    let (ok, md, err) = cli(&["report", "smoke", "--out", out]);
    assert!(ok, "{err}");
    assert!(md.contains("| SEC | 1 |") && md.contains("| NSEC | 1 |") && !md.contains("| reactive |"), "{md}");
    // An item is a whole name or a group: `object-permanence/SE` names nothing.
    let (ok, _, err) = cli(&["run", "smoke", "--only", "object-permanence/SE", "--out", out]);
    assert!(!ok && err.contains("matches no condition"), "{err}");
    let (ok, _, err) = cli(&["run", "smoke", "--only", "cylinder/", "--out", out]);
    assert!(!ok && err.contains("--only: 'cylinder/' matches no condition of smoke"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The committed orderings table is what `sec-experiment orderings` makes of the committed runs,
/// and REPRODUCTION.md quotes it as it is. (It reads the working tree: while a grid is running
/// here, its new runs make it fail until `sec-experiment orderings` is run and the table quoted.)
#[test]
fn the_committed_orderings_are_regenerated_from_the_committed_runs() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = temp("orderings");
    let (ok, md, err) = cli(&[
        "orderings",
        "--out",
        root.join("results/experiments").to_str().unwrap(),
        "--trained",
        root.join("results/experiments-trained").to_str().unwrap(),
        "--authors",
        root.join("results/authors").to_str().unwrap(),
        "--to",
        dir.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert_eq!(md, std::fs::read_to_string(root.join("results/orderings.md")).unwrap());
    let reproduction = std::fs::read_to_string(root.join("REPRODUCTION.md")).unwrap();
    assert!(reproduction.contains(&md), "REPRODUCTION.md quotes results/orderings.md");
    // The textured grid's column: experiment 1's double T-maze tested, the other experiments not
    // in it.
    let row = |start: &str| md.lines().find(|l| l.starts_with(start)).unwrap_or_default().to_string();
    let cells = |r: String| r.split(" | ").map(str::to_string).collect::<Vec<_>>();
    assert!(cells(row("| exp1 double-t-maze | SEC > NSEC |"))[4].contains("p "), "{md}");
    assert_eq!(cells(row("| exp2 | SEC > NSEC at m=125 |"))[4], "-", "{md}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every JSON file under `dir` with `key` removed wherever it holds `default`, and each
/// manifest's hash made of that JSON: what a version without the setting wrote.
fn strip_default(dir: &Path, key: &str, default: &serde_json::Value) -> usize {
    fn strip(v: &mut serde_json::Value, key: &str, default: &serde_json::Value) -> usize {
        match v {
            serde_json::Value::Object(m) => {
                let mut n = usize::from(m.get(key) == Some(default));
                if n == 1 {
                    m.remove(key);
                }
                n += m.values_mut().map(|x| strip(x, key, default)).sum::<usize>();
                n
            }
            serde_json::Value::Array(a) => a.iter_mut().map(|x| strip(x, key, default)).sum(),
            _ => 0,
        }
    }
    let mut n = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            n += strip_default(&path, key, default);
        } else if path.extension().is_some_and(|e| e == "json") {
            let mut v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
            let k = strip(&mut v, key, default);
            if k > 0 && v.get("configHash").is_some() {
                // A manifest's hash as that older version wrote it: of the JSON without the key.
                let json = serde_json::to_string(&v["config"]).unwrap();
                v["configHash"] = format!("{:016x}", sec_playground::render::fnv1a(json.as_bytes())).into();
            }
            if k > 0 {
                std::fs::write(&path, serde_json::to_string_pretty(&v).unwrap()).unwrap();
                n += k;
            }
        }
    }
    n
}

fn copy_tree(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let path = entry.unwrap().path();
        let target = to.join(path.file_name().unwrap());
        if path.is_dir() {
            copy_tree(&path, &target);
        } else {
            std::fs::copy(&path, &target).unwrap();
        }
    }
}

/// A setting added with a default leaves the committed results valid: their manifests,
/// `experiment.json` and `config.json` files, as written before the setting existed (here the
/// start heading, removed wherever it holds its default), still pass `verify`, and `report` and
/// `orderings` make the committed tables from them. Manifests compare parsed configurations, not
/// hashes of their JSON.
#[test]
fn results_written_before_a_setting_existed_still_verify_and_report() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = temp("older");
    for sub in ["experiments", "experiments-trained"] {
        copy_tree(&root.join("results").join(sub), &dir.join(sub));
    }
    let stripped = strip_default(&dir, "startHeading", &serde_json::Value::from("random"));
    assert!(stripped > 233, "the start heading removed from {stripped} configurations");
    let (ok, _, err) = cli(&["verify", "--out", dir.join("experiments").to_str().unwrap()]);
    assert!(ok, "{err}");
    let to = dir.join("reports");
    let (ok, md, err) =
        cli(&["report", "exp1", "--out", dir.join("experiments").to_str().unwrap(), "--to", to.to_str().unwrap()]);
    assert!(ok && !err.contains("gap"), "{err}");
    assert_eq!(md, std::fs::read_to_string(root.join("results/experiments/exp1/report.md")).unwrap());
    let (ok, md, err) = cli(&[
        "orderings",
        "--out",
        dir.join("experiments").to_str().unwrap(),
        "--trained",
        dir.join("experiments-trained").to_str().unwrap(),
        "--authors",
        root.join("results/authors").to_str().unwrap(),
        "--to",
        to.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert_eq!(md, std::fs::read_to_string(root.join("results/orderings.md")).unwrap());
    let _ = std::fs::remove_dir_all(&dir);
}

/// The committed comparison with the authors' runs is what `sec-experiment versus-authors` makes
/// of the committed runs and results/authors/, and REPRODUCTION.md quotes it as it is (like the
/// orderings, this reads the working tree).
#[test]
fn the_committed_comparison_with_the_authors_is_regenerated_from_the_committed_runs() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = temp("versus-authors");
    let (ok, md, err) = cli(&[
        "versus-authors",
        "--out",
        root.join("results/experiments").to_str().unwrap(),
        "--authors",
        root.join("results/authors").to_str().unwrap(),
        "--to",
        dir.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let file = std::fs::read_to_string(dir.join("versus-authors.md")).unwrap();
    assert_eq!(file, std::fs::read_to_string(root.join("results/versus-authors.md")).unwrap());
    let reproduction = std::fs::read_to_string(root.join("REPRODUCTION.md")).unwrap();
    let quoted = sec_tools::quote::quoted(&reproduction, "versus-authors").expect("REPRODUCTION.md quotes it");
    assert_eq!(quoted.trim_end(), md.trim_end());
    assert!(md.contains("| double-t-maze/MFEC-ae |") && md.contains("| forgetting/NSEC-rwd |"), "{md}");
    assert!(md.contains("**exp1 with the textured renderer**"), "the textured runs get their table: {md}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The textured grid's verdict (results/PROTOCOL.md, 2026-12-06) is what `sec-experiment surfaces`
/// makes of the committed runs, and REPRODUCTION.md quotes it as it is; with the textured SEC runs
/// cut to 19 the block is incomplete and nothing is decided.
#[test]
fn the_textured_grids_verdict_is_regenerated_from_the_committed_runs() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = temp("surfaces");
    let args = |out: &Path| {
        cli(&[
            "surfaces",
            "--out",
            out.to_str().unwrap(),
            "--authors",
            root.join("results/authors").to_str().unwrap(),
            "--to",
            dir.to_str().unwrap(),
        ])
    };
    let (ok, md, err) = args(&root.join("results/experiments"));
    assert!(ok, "{err}");
    assert_eq!(md, std::fs::read_to_string(root.join("results/surfaces.md")).unwrap());
    let reproduction = std::fs::read_to_string(root.join("REPRODUCTION.md")).unwrap();
    let quoted = sec_tools::quote::quoted(&reproduction, "surfaces").expect("REPRODUCTION.md quotes it");
    assert_eq!(quoted.trim_end(), md.trim_end());
    assert!(md.contains("**Decision: "), "{md}");

    let partial = dir.join("partial");
    for exp in ["exp1", "textured"] {
        copy_tree(&root.join("results/experiments").join(exp), &partial.join(exp));
    }
    std::fs::remove_file(partial.join("textured/double-t-maze/SEC/seed-20.jsonl.gz")).unwrap();
    let (ok, md, err) = args(&partial);
    assert!(ok, "{err}");
    assert!(md.contains("not complete (textured: SEC 19 of 20; flat: complete)") && !md.contains("Decision"), "{md}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `verify` passes on the committed runs, and fails, naming the file, on a copy of two of them
/// (one configuration and seed) where the shorter is doctored.
#[test]
fn verify_passes_on_the_committed_runs_and_fails_on_a_doctored_log() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let results = root.join("results/experiments");
    let (ok, out, err) = cli(&["verify", "--out", results.to_str().unwrap()]);
    assert!(ok, "{err}");
    assert!(out.contains("pairs of one configuration and seed agree"), "{out}");

    // exp1's SEC seed 1 and its copy as experiment 3's default, the copy cut and then doctored.
    let dir = temp("verify");
    let from = [("exp1", "double-t-maze/SEC"), ("exp3", "value-function/SEC-default")];
    for (exp, cond) in from {
        let d = dir.join(exp).join(cond);
        std::fs::create_dir_all(&d).unwrap();
        std::fs::copy(results.join(exp).join(cond).join("config.json"), d.join("config.json")).unwrap();
    }
    let text =
        sec_tools::runner::read_run_text(&sec_tools::runner::run_path(&results.join("exp1"), from[0].1, 1)).unwrap();
    let head: String = text.split_inclusive('\n').take(300).collect();
    std::fs::write(dir.join("exp1").join(from[0].1).join("seed-1.jsonl.gz"), gzip(&text)).unwrap();
    let short = dir.join("exp3").join(from[1].1).join("seed-1.jsonl.gz");
    std::fs::write(&short, gzip(&head)).unwrap();
    let (ok, out, err) = cli(&["verify", "--out", dir.to_str().unwrap()]);
    assert!(ok, "{err}");
    assert!(out.contains("2 runs") && out.contains("the 1 pairs"), "{out}");
    let doctored = head.replacen("\"episode\":120,", "\"episode\":121,", 1);
    assert_ne!(doctored, head);
    std::fs::write(&short, gzip(&doctored)).unwrap();
    let (ok, _, err) = cli(&["verify", "--out", dir.to_str().unwrap()]);
    assert!(!ok, "a doctored log fails");
    assert!(err.contains("differ at episode 121") && err.contains("1 of 1 pairs of runs differ"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

fn gzip(text: &str) -> Vec<u8> {
    use std::io::Write;
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    gz.write_all(text.as_bytes()).unwrap();
    gz.finish().unwrap()
}

/// The page's committed reference curves are what `sec-experiment reference` makes of the
/// committed runs (like the orderings, this reads the working tree).
#[test]
fn the_committed_reference_curves_are_regenerated_from_the_committed_runs() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = temp("reference");
    let (ok, _, err) =
        cli(&["reference", "--out", root.join("results/experiments").to_str().unwrap(), "--to", dir.to_str().unwrap()]);
    assert!(ok, "{err}");
    let committed = root.join("assets/reference");
    let index = std::fs::read_to_string(dir.join("index.json")).unwrap();
    assert_eq!(index, std::fs::read_to_string(committed.join("index.json")).unwrap());
    let listed: serde_json::Value = serde_json::from_str(&index).unwrap();
    let refs = listed["references"].as_array().unwrap();
    assert!(!refs.is_empty());
    for r in refs {
        let (exp, cond) = r["reference"].as_str().unwrap().split_once(':').unwrap();
        let file = format!("{exp}/{cond}.json");
        assert_eq!(
            std::fs::read_to_string(dir.join(&file)).unwrap(),
            std::fs::read_to_string(committed.join(&file)).unwrap(),
            "{file}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every table REPRODUCTION.md quotes from an experiment's report (`<!-- EXPERIMENT/GROUP: ... -->`)
/// is that group's table in the report `sec-experiment report` makes of the committed runs, and
/// the committed report.md is that report; the perception table is matching.md's (whose walk
/// embeddings take too long for a debug test to redo). Like the orderings, this reads the
/// working tree.
#[test]
fn every_table_reproduction_quotes_is_regenerated_from_the_committed_runs() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let out = root.join("results/experiments");
    let page = std::fs::read_to_string(root.join("REPRODUCTION.md")).unwrap();
    let keys = sec_tools::quote::keys(&page);
    assert!(keys.len() >= 6, "{keys:?}");
    let mut reports = std::collections::BTreeMap::new();
    // The orderings and the comparison with the authors have tests of their own.
    for key in keys.iter().filter(|k| !["orderings", "versus-authors", "surfaces"].contains(&k.as_str())) {
        let quoted = sec_tools::quote::quoted(&page, key).unwrap();
        if key == "perception/matching" {
            let md = std::fs::read_to_string(out.join("perception/matching.md")).unwrap();
            assert!(md.contains(quoted.trim_end()), "{key}: REPRODUCTION.md differs from matching.md");
            continue;
        }
        let (exp, group) = key.split_once('/').unwrap();
        let md = reports.entry(exp.to_string()).or_insert_with(|| {
            let to = temp(&format!("report-{exp}"));
            let (ok, md, err) = cli(&["report", exp, "--out", out.to_str().unwrap(), "--to", to.to_str().unwrap()]);
            assert!(ok, "{err}");
            let committed = std::fs::read_to_string(out.join(exp).join("report.md")).unwrap();
            assert_eq!(md, committed, "results/experiments/{exp}/report.md is not what its runs make");
            let _ = std::fs::remove_dir_all(&to);
            md
        });
        // The group's section: from its heading to the next one.
        let section = md.split("\n## ").find_map(|s| s.strip_prefix(&format!("{group}\n"))).unwrap_or_default();
        assert!(section.contains(quoted.trim_end()), "{key}: REPRODUCTION.md's table is not the report's");
    }
}

/// Every figure the docs and the committed reports link to is there (a report once linked
/// `untrained-x0.5-reward.svg` while the plot was written as `untrained-x0.svg`).
#[test]
fn every_figure_the_docs_and_reports_show_exists() {
    fn markdown(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                markdown(&path, out);
            } else if path.extension().is_some_and(|e| e == "md") {
                out.push(path);
            }
        }
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut docs: Vec<PathBuf> =
        ["README.md", "REPRODUCTION.md", "BENCHMARKS.md"].iter().map(|f| root.join(f)).collect();
    markdown(&root.join("docs"), &mut docs);
    markdown(&root.join("results"), &mut docs);
    let (mut figures, mut missing) = (0, Vec::new());
    for doc in &docs {
        let text = std::fs::read_to_string(doc).unwrap();
        for link in text.split("](").skip(1).filter_map(|rest| rest.split(')').next()) {
            if link.contains("://") || !(link.ends_with(".svg") || link.ends_with(".png")) {
                continue;
            }
            figures += 1;
            if !doc.parent().unwrap().join(link).is_file() {
                missing.push(format!("{}: {link}", doc.strip_prefix(&root).unwrap().display()));
            }
        }
    }
    assert!(figures > 20, "only {figures} figures found: is the link pattern still right?");
    assert!(missing.is_empty(), "figures linked but not there: {missing:#?}");
}

#[test]
fn the_cli_lists_the_core_agent_table() {
    let (ok, out, err) = cli(&["agents"]);
    assert!(ok, "{err}");
    let rows: Vec<Vec<&str>> = out.lines().skip(1).map(|l| l.split('\t').collect()).collect();
    assert_eq!(rows.len(), sec_playground::agent::AGENTS.len());
    for (row, a) in rows.iter().zip(sec_playground::agent::AGENTS) {
        assert_eq!((row[0], row[5]), (a.key, a.label));
        assert_eq!(row[4].contains("native-only"), a.native_only, "{row:?}");
    }
    assert!(!cli(&["agents", "x"]).0, "agents takes no argument");
}

#[test]
fn reports_refuse_an_incomplete_or_inconsistent_folder_unless_partial() {
    let dir = temp("partial");
    let out = dir.to_str().unwrap();
    let (ok, _, err) = cli(&["run", "smoke", "--seeds", "2", "--episodes", "2", "--jobs", "2", "--out", out]);
    assert!(ok, "{err}");
    let (ok, _, err) = cli(&["report", "smoke", "--out", out]);
    assert!(ok, "a whole folder reports: {err}");
    // A third seed asked and not made: the plan in experiment.json now names it.
    let (ok, _, err) = cli(&[
        "run",
        "smoke",
        "--seeds",
        "3..3",
        "--episodes",
        "2",
        "--only",
        "object-permanence/SEC",
        "--out",
        out,
        "--shard",
        "2/2",
    ]);
    assert!(ok && err.contains("0 runs made"), "{err}");
    for args in [
        vec!["report", "smoke", "--out", out],
        vec!["orderings", "--out", out, "--to", out],
        vec!["reference", "--out", out, "--to", out],
    ] {
        let (ok, _, err) = cli(&args);
        assert!(
            !ok && err.contains("object-permanence/SEC seed 3: 0 of 2 episodes") && err.contains("--partial"),
            "{args:?}: {err}"
        );
    }
    let (ok, md, err) = cli(&["report", "smoke", "--out", out, "--partial"]);
    assert!(ok && md.contains("| SEC | 2 |") && err.contains("1 gap(s)"), "{err}");
    // A run whose manifest names another configuration is a gap too.
    let (ok, _, _) =
        cli(&["run", "smoke", "--seeds", "3..3", "--episodes", "2", "--only", "object-permanence/SEC", "--out", out]);
    assert!(ok);
    assert!(cli(&["report", "smoke", "--out", out]).0, "whole again");
    let mf = dir.join("smoke/object-permanence/SEC/seed-3.manifest.json");
    let text = std::fs::read_to_string(&mf).unwrap();
    std::fs::write(&mf, text.replacen("\"tau\": 0.9", "\"tau\": 0.5", 1)).unwrap();
    let (ok, _, err) = cli(&["report", "smoke", "--out", out]);
    assert!(!ok && err.contains("seed 3: its manifest names another configuration"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The frame-match table docs/ARENAS.md quotes is what `sec-experiment frame-match` makes of the
/// committed real frames (searching next to the poses results/frame-match.md found: the full
/// search renders every pose of the task and takes half a minute a frame), and results/ holds it.
#[test]
fn the_frame_match_table_arenas_quotes_is_regenerated_from_the_reference_frames() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = temp("frame-match");
    std::fs::create_dir_all(&dir).unwrap();
    let committed = std::fs::read_to_string(root.join("results/frame-match.md")).unwrap();
    std::fs::write(dir.join("frame-match.md"), &committed).unwrap();
    let frames = root.join("tests/reference-frames");
    let (ok, md, err) =
        cli(&["frame-match", "--frames", frames.to_str().unwrap(), "--to", dir.to_str().unwrap(), "--near-quoted"]);
    assert!(ok, "{err}");
    assert_eq!(md, committed, "results/frame-match.md is not what the reference frames make");
    let page = std::fs::read_to_string(root.join("docs/ARENAS.md")).unwrap();
    let quoted = sec_tools::quote::quoted(&page, "frame-match").expect("docs/ARENAS.md quotes it");
    assert!(md.contains(quoted.trim_end()), "docs/ARENAS.md's frame-match table is not the report's");
    // Three frames, two surfaces each.
    assert_eq!(quoted.lines().filter(|l| l.contains(" | textured | ")).count(), 3, "{quoted}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The arenas table docs/ARENAS.md quotes is what `sec-experiment arenas` makes of the committed
/// Olympics corpus, results/ holds it and its per-file CSV, and the counts add up.
#[test]
fn the_arenas_table_arenas_quotes_is_regenerated_from_the_corpus() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = temp("arenas");
    let corpus = root.join("assets/arenas/competition");
    let index = dir.join("olympics.json");
    let (ok, md, err) =
        cli(&["arenas", corpus.to_str().unwrap(), "--to", dir.to_str().unwrap(), "--index", index.to_str().unwrap()]);
    assert!(ok, "{err}");
    assert_eq!(
        std::fs::read_to_string(&index).unwrap(),
        std::fs::read_to_string(root.join("assets/arenas/olympics.json")).unwrap(),
        "assets/arenas/olympics.json (the arena page's menu) is not what the corpus makes"
    );
    let committed = std::fs::read_to_string(root.join("results/arenas.md")).unwrap();
    // The command line names the folder as given.
    assert_eq!(md.replace(corpus.to_str().unwrap(), "assets/arenas/competition"), committed);
    assert_eq!(
        std::fs::read_to_string(dir.join("arenas.csv")).unwrap(),
        std::fs::read_to_string(root.join("results/arenas.csv")).unwrap()
    );
    let page = std::fs::read_to_string(root.join("docs/ARENAS.md")).unwrap();
    let quoted = sec_tools::quote::quoted(&page, "arenas").expect("docs/ARENAS.md quotes it");
    assert!(md.contains(quoted.trim_end()), "docs/ARENAS.md's arenas table is not the report's");
    // Ten categories of 90, and each row's loads plus refused make its files.
    let all = quoted.lines().find(|l| l.starts_with("| all |")).unwrap();
    let cells: Vec<usize> = all.split('|').skip(2).take(6).map(|c| c.trim().parse().unwrap()).collect();
    assert_eq!((cells[0], cells[1] + cells[5]), (900, 900), "{all}");
    assert_eq!(quoted.lines().filter(|l| l.contains(" | 90 | ")).count(), 10, "{quoted}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The aliasing table docs/ARENAS.md quotes is what `sec-experiment aliasing` measures.
#[test]
fn the_aliasing_table_arenas_quotes_is_regenerated() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = temp("aliasing");
    let (ok, md, err) = cli(&["aliasing", "--to", dir.to_str().unwrap()]);
    assert!(ok, "{err}");
    assert_eq!(md, std::fs::read_to_string(root.join("results/aliasing.md")).unwrap());
    let page = std::fs::read_to_string(root.join("docs/ARENAS.md")).unwrap();
    let quoted = sec_tools::quote::quoted(&page, "aliasing").expect("docs/ARENAS.md quotes it");
    assert!(md.contains(quoted.trim_end()), "docs/ARENAS.md's aliasing table is not what the command measures");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every figure REPRODUCTION.md's prose writes with three decimals is one its generated tables or
/// the page's reference index (assets/reference/index.json, made from the committed runs) hold:
/// a sentence left from an earlier grid fails here once its table moves on. p values (`p 0.034`,
/// `p = 7.5e-5`, `p 0.002-0.041`) are left out: the orderings table's are corrected, and the
/// prose quotes uncorrected ones too.
#[test]
fn every_three_decimal_figure_in_reproductions_prose_is_in_a_generated_table() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let page = std::fs::read_to_string(root.join("REPRODUCTION.md")).unwrap();
    let mut prose = page.clone();
    let mut tables = String::new();
    for key in sec_tools::quote::keys(&page) {
        let quoted = sec_tools::quote::quoted(&page, &key).unwrap();
        tables += quoted;
        prose = prose.replacen(quoted, "", 1);
    }
    fn numbers(v: &serde_json::Value, out: &mut Vec<String>) {
        match v {
            serde_json::Value::Number(n) => out.push(format!("{:.3}", n.as_f64().unwrap())),
            serde_json::Value::Array(a) => a.iter().for_each(|x| numbers(x, out)),
            serde_json::Value::Object(o) => o.values().for_each(|x| numbers(x, out)),
            _ => {}
        }
    }
    let index: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(root.join("assets/reference/index.json")).unwrap()).unwrap();
    let mut indexed = Vec::new();
    numbers(&index, &mut indexed);
    // The prose's figures: maximal runs of digits and dots, p values skipped.
    let chars: Vec<char> = prose.chars().collect();
    let (mut checked, mut missing, mut i) = (0, Vec::new(), 0);
    while i < chars.len() {
        let standalone = i == 0 || !chars[i - 1].is_alphanumeric();
        for lead in ["p = ", "p "] {
            let l: Vec<char> = lead.chars().collect();
            if standalone && chars[i..].starts_with(&l) {
                i += l.len();
                while i < chars.len() && (chars[i].is_ascii_digit() || ".e-".contains(chars[i])) {
                    i += 1;
                }
            }
        }
        if i < chars.len() && chars[i].is_ascii_digit() {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            let run: String = chars[start..i].iter().collect::<String>().trim_end_matches('.').to_string();
            if run.split_once('.').is_some_and(|(_, d)| d.len() == 3 && d.chars().all(|c| c.is_ascii_digit())) {
                checked += 1;
                if !tables.contains(&run) && !indexed.contains(&run) {
                    missing.push(run);
                }
            }
        } else {
            i += 1;
        }
    }
    assert!(checked > 20, "only {checked} figures found: is the scan still right?");
    assert!(missing.is_empty(), "REPRODUCTION.md's prose quotes figures no generated table holds: {missing:?}");
}

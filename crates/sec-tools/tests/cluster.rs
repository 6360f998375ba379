//! The grid on a cluster: Slurm array tasks take the same shards as `--shard`, the sbatch script
//! runs them, every run gets a manifest, and `merge` brings shard folders together, refusing by
//! name a differing duplicate, a configuration mismatch and a manifest of another configuration,
//! and listing missing seeds.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_sec-experiment");

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sec-cluster-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn run(out: &Path, extra: &[&str], env: &[(&str, &str)]) -> (bool, String) {
    let mut cmd = Command::new(BIN);
    cmd.args(["run", "smoke", "--seeds", "3", "--episodes", "3", "--jobs", "2", "--out", out.to_str().unwrap()]);
    cmd.args(extra);
    for var in ["SLURM_ARRAY_TASK_ID", "SLURM_ARRAY_TASK_COUNT", "SLURM_ARRAY_TASK_MIN"] {
        cmd.env_remove(var);
    }
    cmd.envs(env.iter().copied());
    let o = cmd.output().unwrap();
    (o.status.success(), String::from_utf8_lossy(&o.stderr).into_owned())
}

/// Every run log under `root`, by path relative to it.
fn logs(root: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).into_iter().flatten().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.to_string_lossy().ends_with(".jsonl.gz") {
                out.insert(p.strip_prefix(root).unwrap().display().to_string(), std::fs::read(&p).unwrap());
            }
        }
    }
    out
}

fn merge(sources: &[&Path], into: &Path) -> (bool, String) {
    let mut cmd = Command::new(BIN);
    cmd.arg("merge").args(sources).args(["--into", into.to_str().unwrap()]);
    let o = cmd.output().unwrap();
    (o.status.success(), format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr)))
}

#[test]
fn slurm_array_tasks_take_the_shards_and_merge_to_the_whole_grid() {
    let whole = temp("whole");
    assert!(run(&whole, &[], &[]).0);
    // The runs' manifests name their configuration, seed, kernel and times.
    let m: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(whole.join("smoke/object-permanence/SEC/seed-2.manifest.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(m["seed"], 2);
    assert_eq!(m["episodes"], 3);
    assert_eq!(m["configHash"].as_str().unwrap().len(), 16);
    assert!(["avx2", "scalar"].contains(&m["kernel"].as_str().unwrap()));
    assert!(m["wallSeconds"].as_f64().unwrap() >= 0.0 && m["end"].as_u64() >= m["start"].as_u64());
    // Array task 0 of --array=0-2 is shard 1/3, through the variables and through the sbatch script.
    let (shard, slurm, script) = (temp("shard"), temp("slurm"), temp("script"));
    assert!(run(&shard, &["--shard", "1/3"], &[]).0);
    let vars = [("SLURM_ARRAY_TASK_ID", "0"), ("SLURM_ARRAY_TASK_COUNT", "3"), ("SLURM_ARRAY_TASK_MIN", "0")];
    let (ok, err) = run(&slurm, &[], &vars);
    assert!(ok, "{err}");
    assert!(err.contains("shard 1/3"), "{err}");
    assert_eq!(logs(&slurm), logs(&shard));
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let o = Command::new("bash")
        .arg(root.join("scripts/slurm-grid.sh"))
        .envs(vars)
        .env("EXPERIMENT", "smoke")
        .env("SEEDS", "3")
        .env("EPISODES", "3")
        .env("BIN", BIN)
        .env("OUT", &script)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(logs(&script), logs(&shard));
    // --shard wins over the variables; a bad variable is named.
    let (ok, err) = run(&temp("wins"), &["--shard", "2/3"], &vars);
    assert!(ok && err.contains("shard 2/3"), "{err}");
    let (ok, err) = run(
        &temp("bad"),
        &[],
        &[("SLURM_ARRAY_TASK_ID", "7"), ("SLURM_ARRAY_TASK_COUNT", "3"), ("SLURM_ARRAY_TASK_MIN", "1")],
    );
    assert!(!ok && err.contains("SLURM_ARRAY_TASK_ID 7 is not among the 3 tasks"), "{err}");
    // The other two shards, then merge: the whole grid, byte for byte.
    let (s2, s3) = (temp("s2"), temp("s3"));
    assert!(
        run(&s2, &[], &[("SLURM_ARRAY_TASK_ID", "2"), ("SLURM_ARRAY_TASK_COUNT", "3"), ("SLURM_ARRAY_TASK_MIN", "1")])
            .0
    );
    assert!(run(&s3, &["--shard", "3/3"], &[]).0);
    let partial = temp("partial");
    let (ok, out) = merge(&[&slurm, &s2], &partial);
    assert!(ok, "{out}");
    assert!(out.contains("runs missing or short") && out.contains("seed 3: 0 of 3 episodes"), "{out}");
    let merged = temp("merged");
    let (ok, out) = merge(&[&slurm, &s2, &s3], &merged);
    assert!(ok && out.contains("complete"), "{out}");
    assert_eq!(logs(&merged), logs(&whole));
    // Merging again changes nothing.
    let (ok, out) = merge(&[&s3], &merged);
    assert!(ok && out.contains("0 runs copied"), "{out}");
}

#[test]
fn merge_refuses_a_differing_duplicate_and_another_configuration_by_name() {
    let (a, b) = (temp("a"), temp("b"));
    assert!(run(&a, &["--shard", "1/1"], &[]).0);
    assert!(run(&b, &["--shard", "1/1"], &[]).0);
    let run_b = b.join("smoke/object-permanence/NSEC/seed-2.jsonl.gz");
    let text = sec_tools::runner::read_run_text(&run_b).unwrap();
    let changed = text.replacen("\"episode\":1", "\"episode\":1 ", 1);
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    std::io::Write::write_all(&mut gz, changed.as_bytes()).unwrap();
    std::fs::write(&run_b, gz.finish().unwrap()).unwrap();
    let target = temp("target");
    let (ok, out) = merge(&[&a, &b], &target);
    assert!(!ok && out.contains("smoke/object-permanence/NSEC seed 2") && out.contains("differ at episode 2"), "{out}");
    assert!(!target.join("smoke").exists(), "nothing written before the check");
    // Another configuration under the same name.
    let c = temp("c");
    assert!(run(&c, &["--shard", "1/1"], &[]).0);
    let cfg = c.join("smoke/experiment.json");
    let text = std::fs::read_to_string(&cfg).unwrap().replacen("\"tau\": 0.9", "\"tau\": 0.5", 1);
    std::fs::write(&cfg, text).unwrap();
    let (ok, out) = merge(&[&a, &c], &temp("target2"));
    assert!(!ok && out.contains("has another configuration"), "{out}");
    // A run whose manifest names another configuration (compared parsed; the hash is a name).
    let d = temp("d");
    assert!(run(&d, &["--shard", "1/1"], &[]).0);
    let mf = d.join("smoke/object-permanence/SEC/seed-1.manifest.json");
    let text = std::fs::read_to_string(&mf).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let hash = v["configHash"].as_str().unwrap().to_string();
    std::fs::write(&mf, text.replace(&hash, "0123456789abcdef")).unwrap();
    assert!(merge(&[&d], &temp("target3")).0, "a stale hash of the same configuration is not another configuration");
    std::fs::write(&mf, text.replacen("\"tau\": 0.9", "\"tau\": 0.5", 1)).unwrap();
    let (ok, out) = merge(&[&d], &temp("target4"));
    assert!(!ok && out.contains("seed-1.jsonl.gz: its manifest names configuration"), "{out}");
}

#[test]
fn a_config_file_that_is_endless_or_binary_is_refused_by_name() {
    let dir = temp("config");
    std::fs::create_dir_all(&dir).unwrap();
    let binary = dir.join("binary.json");
    std::fs::write(&binary, [0x7bu8, 0xff, 0xfe, 0x00]).unwrap();
    let large = dir.join("large.json");
    std::fs::write(&large, vec![b' '; (1 << 20) + 1]).unwrap();
    for (path, want) in [
        ("/dev/zero", "/dev/zero is a device, not a regular file"),
        (large.to_str().unwrap(), "is larger than 1048576 bytes"),
        (binary.to_str().unwrap(), "is not UTF-8 text"),
    ] {
        let o = Command::new(BIN).args(["run", "--config", path, "--name", "a/b", "--out"]).arg(&dir).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains("--config: ") && err.contains(want), "{path}: {err}");
    }
}

//! Checking a results tree: which runs its manifest asked for are missing or short (`gaps`), and
//! whether every finished log is what its configuration and seed make (`verify` replays them).

use crate::layout::{finished_episodes, finished_runs, read_run_text, run_path, same_dir};
use crate::plan::{ExperimentManifest, Job};
use sec_playground::experiment::RunConfig;
use std::fs;
use std::path::{Path, PathBuf};

/// What keeps the experiment folder `dir` from being complete and consistent, one line each: a
/// condition's planned run missing or short of its episodes, a run whose manifest names another
/// configuration or seed, a condition whose `config.json` is another configuration. Empty when
/// the folder is whole. The reports refuse a folder with gaps unless told `--partial`.
pub fn gaps(dir: &Path) -> Result<Vec<String>, String> {
    let path = dir.join("experiment.json");
    let text = fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let manifest: ExperimentManifest = serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut out = Vec::new();
    for c in &manifest.conditions {
        let config = dir.join(&c.name).join("config.json");
        if let Ok(text) = fs::read_to_string(&config) {
            if !serde_json::from_str::<RunConfig>(&text).is_ok_and(|o| o.same_run(&c.config)) {
                out.push(format!("{}: config.json is another configuration than experiment.json's", c.name));
            }
        }
        for (seed, log) in finished_runs(&dir.join(&c.name)) {
            if let Some(m) = crate::manifest::read(&log)? {
                // The configurations as parsed, defaults filled in: a setting added since the
                // manifest was written takes its default on both sides (a hash of the JSON would
                // differ).
                if !m.config.same_run(&c.config) || m.seed != seed {
                    out.push(format!("{} seed {seed}: its manifest names another configuration or seed", c.name));
                }
            }
        }
        if let Some(plan) = &c.plan {
            for &seed in &plan.seeds {
                let have = finished_episodes(&run_path(dir, &c.name, seed));
                if have < plan.episodes {
                    out.push(format!("{} seed {seed}: {have} of {} episodes", c.name, plan.episodes));
                }
            }
        }
    }
    Ok(out)
}

/// The first episode (1-based) at which `shorter` is not the head of `longer`, line for line, or
/// `None` when it is (an equal or longer `shorter` differs where `longer` ends).
pub fn first_difference(shorter: &str, longer: &str) -> Option<usize> {
    let mut long = longer.lines();
    for (i, line) in shorter.lines().enumerate() {
        if long.next() != Some(line) {
            return Some(i + 1);
        }
    }
    None
}

/// Every finished run under `root` (experiment directories and their condition directories, as
/// `run` writes them), by configuration: a run is a pure function of (configuration, seed), so a
/// job whose configuration, seed and length equal a finished run's has its log already. Several
/// experiments share conditions (exp1's double T-maze SEC is exp2's m = 500, exp3's default,
/// exp4's no forgetting and the perception experiment's untrained x1).
pub struct Finished {
    dirs: Vec<(PathBuf, RunConfig)>,
}

impl Finished {
    /// Reads every `config.json` under `root`; a file that does not parse is passed over.
    pub fn scan(root: &Path) -> Finished {
        fn walk(dir: &Path, depth: usize, dirs: &mut Vec<(PathBuf, RunConfig)>) {
            if let Ok(text) = fs::read_to_string(dir.join("config.json")) {
                if let Ok(config) = serde_json::from_str::<RunConfig>(&text) {
                    dirs.push((dir.to_path_buf(), config));
                }
            }
            if depth == 0 {
                return;
            }
            let Ok(entries) = fs::read_dir(dir) else { return };
            let mut subdirs: Vec<PathBuf> =
                entries.filter_map(|e| e.ok()).map(|e| e.path()).filter(|p| p.is_dir()).collect();
            subdirs.sort();
            for d in subdirs {
                walk(&d, depth - 1, dirs);
            }
        }
        let mut dirs = Vec::new();
        // root / experiment / group / model: three levels below the root.
        walk(root, 3, &mut dirs);
        Finished { dirs }
    }

    /// A finished log of at least `episodes` episodes of `job`'s configuration and seed outside
    /// `job`'s own directory under `out` (the shortest there is): its first `episodes` lines are
    /// the job's log.
    pub fn find(&self, job: &Job, out: &Path, episodes: usize) -> Option<PathBuf> {
        let own = out.join(&job.condition);
        self.dirs
            .iter()
            .filter(|(dir, config)| config.same_run(&job.config) && !same_dir(dir, &own))
            .map(|(dir, _)| dir.join(format!("seed-{}.jsonl.gz", job.seed)))
            .map(|path| (finished_episodes(&path), path))
            .filter(|(n, _)| *n >= episodes)
            .min_by_key(|(n, _)| *n)
            .map(|(_, path)| path)
    }
}

/// What `verify` found: the runs it read, the pairs of one configuration and seed it compared,
/// and each pair whose shorter log is not the longer one's head.
#[derive(Debug, Default)]
pub struct Verified {
    /// Finished runs read.
    pub runs: usize,
    /// Pairs of runs of one configuration and seed compared.
    pub pairs: usize,
    /// One line per pair whose shorter log is not the longer one's head.
    pub failures: Vec<String>,
}

/// Checks every finished run under `root` against every other of the same configuration and seed
/// (several experiments share conditions, and a longer run of a condition replaces a shorter
/// one): a run is a pure function of (configuration, seed), so the shorter log must be the
/// longer one's head, line for line.
pub fn verify(root: &Path) -> Result<Verified, String> {
    let finished = Finished::scan(root);
    let mut by_run: std::collections::BTreeMap<(String, u64), Vec<PathBuf>> = Default::default();
    for (dir, config) in &finished.dirs {
        let key = serde_json::to_string(config).expect("configurations serialise");
        for (seed, path) in finished_runs(dir) {
            by_run.entry((key.clone(), seed)).or_default().push(path);
        }
    }
    let mut v = Verified::default();
    for paths in by_run.values() {
        v.runs += paths.len();
        let mut logs: Vec<(String, &PathBuf)> =
            paths.iter().map(|p| read_run_text(p).map(|t| (t, p))).collect::<Result<_, _>>()?;
        logs.sort_by_key(|(t, p)| (t.lines().count(), (*p).clone()));
        for pair in logs.windows(2) {
            let ((short, a), (long, b)) = (&pair[0], &pair[1]);
            v.pairs += 1;
            if let Some(line) = first_difference(short, long) {
                v.failures.push(format!(
                    "{} ({} episodes) is not the head of {} ({} episodes): they differ at episode {line}",
                    a.display(),
                    short.lines().count(),
                    b.display(),
                    long.lines().count()
                ));
            }
        }
    }
    Ok(v)
}

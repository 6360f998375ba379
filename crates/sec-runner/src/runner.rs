//! Runs a grid of (condition, seed) jobs on all cores and streams each run's episodes as JSON
//! lines to `OUT/<condition>/seed-<seed>.jsonl.part`; a finished run is gzipped to
//! `seed-<seed>.jsonl.gz` (about a sixth of the size, so the runs themselves can be committed and
//! every report regenerated from them).
//!
//! Resumable: a finished run is a complete `.jsonl.gz` file and is skipped; an unfinished one is
//! a `.part` file, continued from its `.ckpt` checkpoint where its agent writes them (SEC, NSEC,
//! DQN and ERLAM), and started again otherwise (MFEC, the reactive walk) (runs are deterministic, so either
//! way nothing differs but the time spent).
//! `--shard i/N` takes every N-th job, so shards on several machines write disjoint files into
//! copies of the same tree, which merge by copying.

use flate2::read::GzDecoder;
use flate2::write::GzEncoder;
use indicatif::{ProgressBar, ProgressStyle};
use sec_playground::experiment::checkpoint::ResumeCheck;
use sec_playground::experiment::presets::Condition;
use sec_playground::experiment::{AgentFactory, Run, RunConfig};
use sec_playground::seed::MAX_SEED;
use std::fs;
use std::io::{BufWriter, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// The most episodes a run may ask for.
pub const MAX_EPISODES: usize = 1_000_000;
/// The default number of episodes between a run's checkpoints.
pub const CHECKPOINT_EVERY: usize = 50;

/// `episodes` when in 1..=MAX_EPISODES, else an error naming it.
pub fn check_episodes(episodes: usize) -> Result<usize, String> {
    if (1..=MAX_EPISODES).contains(&episodes) {
        Ok(episodes)
    } else {
        Err(format!("episodes: {episodes} is out of range 1..={MAX_EPISODES}"))
    }
}

/// The experiment folders under `root` (those with an `experiment.json`), by name; none when
/// `root` cannot be read.
pub fn experiment_dirs(root: &Path) -> Vec<PathBuf> {
    let mut dirs: Vec<PathBuf> = fs::read_dir(root)
        .into_iter()
        .flatten()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.join("experiment.json").is_file())
        .collect();
    dirs.sort();
    dirs
}

/// One run to make.
#[derive(Clone, Debug)]
pub struct Job {
    /// Its condition's name, `GROUP/MODEL`: the folder its log goes to.
    pub condition: String,
    /// The configuration it runs.
    pub config: RunConfig,
    /// Its seed.
    pub seed: u64,
    /// The agents a native crate builds (`sec_dqn::factory`), or `None`.
    pub agents: Option<AgentFactory>,
    /// Whether an interrupted run resumes from a checkpoint of an earlier format (`ResumeCheck::legacy`:
    /// `--legacy-checkpoint`); otherwise such a run starts again.
    pub legacy_checkpoint: bool,
}

/// What an experiment directory holds besides the runs: written by `run`, read by `report`.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct Manifest {
    /// The experiment's name (a preset's, or `custom`).
    pub experiment: String,
    /// The most episodes any `run` into the folder asked for.
    pub episodes: usize,
    /// Every seed any `run` into the folder asked for.
    pub seeds: Vec<u64>,
    /// Its conditions.
    pub conditions: Vec<ManifestCondition>,
}

/// One condition of an experiment folder.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct ManifestCondition {
    /// `GROUP/MODEL`.
    pub name: String,
    /// The paper's total reward for it, where the paper gives one.
    pub paper_total: Option<f64>,
    /// Its configuration.
    pub config: RunConfig,
    /// The runs asked of it, over every `run` into the folder (absent in folders written before
    /// plans were recorded: those are checked for consistency only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plan: Option<Plan>,
}

/// What was asked of one condition: its seeds, and the episodes each run must reach.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Plan {
    /// The seeds asked for.
    pub seeds: Vec<u64>,
    /// The episodes each run must reach.
    pub episodes: usize,
}

impl Plan {
    /// Both plans' seeds, and the longer of their runs.
    fn union(&self, other: &Plan) -> Plan {
        let mut seeds = self.seeds.clone();
        seeds.extend(other.seeds.iter().filter(|s| !self.seeds.contains(s)));
        seeds.sort_unstable();
        Plan { seeds, episodes: self.episodes.max(other.episodes) }
    }
}

/// The shard a Slurm array task runs: task `SLURM_ARRAY_TASK_ID` of `SLURM_ARRAY_TASK_COUNT`
/// (counted from `SLURM_ARRAY_TASK_MIN`, so `--array=0-3` and `--array=1-4` both give shards
/// 1/4..4/4), or None outside an array job. `var` reads the environment.
pub fn slurm_shard(var: impl Fn(&str) -> Option<String>) -> Result<Option<(usize, usize)>, String> {
    let Some(id) = var("SLURM_ARRAY_TASK_ID") else { return Ok(None) };
    let number = |name: &str, v: Option<String>| -> Result<usize, String> {
        let v = v.ok_or(format!("{name} is not set, but SLURM_ARRAY_TASK_ID is"))?;
        v.trim().parse().map_err(|_| format!("{name}: '{v}' is not a whole number"))
    };
    let id = number("SLURM_ARRAY_TASK_ID", Some(id))?;
    let count = number("SLURM_ARRAY_TASK_COUNT", var("SLURM_ARRAY_TASK_COUNT"))?;
    let min = number("SLURM_ARRAY_TASK_MIN", var("SLURM_ARRAY_TASK_MIN"))?;
    if id < min || id - min >= count || count == 0 {
        return Err(format!(
            "SLURM_ARRAY_TASK_ID {id} is not among the {count} tasks from SLURM_ARRAY_TASK_MIN {min} (a contiguous --array=A-B)"
        ));
    }
    Ok(Some((id - min + 1, count)))
}

/// `i/N` with 1 <= i <= N.
pub fn parse_shard(s: &str) -> Result<(usize, usize), String> {
    let err = || format!("--shard: '{s}' is not i/N with 1 <= i <= N");
    let (i, n) = s.split_once('/').ok_or_else(err)?;
    let (i, n): (usize, usize) = (i.parse().map_err(|_| err())?, n.parse().map_err(|_| err())?);
    if i == 0 || i > n {
        return Err(err());
    }
    Ok((i, n))
}

/// `A..B` (inclusive), `A,B,C` or a count `N` (1..=N).
pub fn parse_seeds(s: &str) -> Result<Vec<u64>, String> {
    let err = || format!("--seeds: '{s}' is not N, A..B or a list A,B,C of seeds (0..={MAX_SEED})");
    let seeds: Vec<u64> = if let Some((a, b)) = s.split_once("..") {
        let (a, b): (u64, u64) = (a.parse().map_err(|_| err())?, b.parse().map_err(|_| err())?);
        if a > b {
            return Err(err());
        }
        (a..=b).collect()
    } else if s.contains(',') {
        s.split(',').map(|x| x.trim().parse().map_err(|_| err())).collect::<Result<_, _>>()?
    } else {
        let n: u64 = s.parse().map_err(|_| err())?;
        (1..=n).collect()
    };
    if seeds.is_empty() || seeds.len() > 10_000 || seeds.iter().any(|&x| x > MAX_SEED) {
        return Err(err());
    }
    Ok(seeds)
}

/// The file of one finished run.
pub fn run_path(out: &Path, condition: &str, seed: u64) -> PathBuf {
    out.join(condition).join(format!("seed-{seed}.jsonl.gz"))
}

/// A run file's text: gzipped (`.gz`) or plain.
pub fn read_run_text(path: &Path) -> Result<String, String> {
    let bytes = fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    if path.extension().is_some_and(|e| e == "gz") {
        let mut text = String::new();
        GzDecoder::new(&bytes[..]).read_to_string(&mut text).map_err(|e| format!("{}: {e}", path.display()))?;
        Ok(text)
    } else {
        String::from_utf8(bytes).map_err(|e| format!("{}: {e}", path.display()))
    }
}

/// Lines in a finished run file (0 if there is none or it is unreadable).
pub fn finished_episodes(path: &Path) -> usize {
    read_run_text(path).map(|t| t.lines().count()).unwrap_or(0)
}

/// Writes `path` through a temporary file of this process's own beside it and a rename, so that a
/// reader (a shard started at the same moment, a resumed run, a report) finds the old file or the
/// new one whole, never part of one, whenever the writer is interrupted.
fn write_atomically(path: &Path, write: impl FnOnce(&mut dyn Write) -> Result<(), String>) -> Result<(), String> {
    static WRITES: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let n = WRITES.fetch_add(1, Ordering::Relaxed);
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(format!(".tmp-{}-{n}", std::process::id()));
    let tmp = path.with_file_name(name);
    let err = |e: std::io::Error| format!("{}: {e}", tmp.display());
    let mut w = BufWriter::new(fs::File::create(&tmp).map_err(err)?);
    let written = write(&mut w).and_then(|()| w.flush().map_err(err));
    drop(w);
    if let Err(e) = written {
        let _ = fs::remove_file(&tmp);
        return Err(e);
    }
    fs::rename(&tmp, path).map_err(|e| format!("{}: {e}", path.display()))
}

/// [`write_atomically`] of a text.
fn write_text_atomically(path: &Path, text: &str) -> Result<(), String> {
    write_atomically(path, |w| w.write_all(text.as_bytes()).map_err(|e| format!("{}: {e}", path.display())))
}

/// Writes the manifest and each condition's `config.json`, refusing to mix configurations: a
/// directory that holds runs of another configuration under the same name is an error.
pub fn prepare(out: &Path, manifest: &Manifest) -> Result<(), String> {
    for c in &manifest.conditions {
        let dir = out.join(&c.name);
        fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        let path = dir.join("config.json");
        let text = serde_json::to_string_pretty(&c.config).expect("configurations serialise") + "\n";
        // Compared as configurations, so a file written before a new field (with its default)
        // was added still matches.
        let same = |old: &str| serde_json::from_str::<RunConfig>(old).is_ok_and(|o| o == c.config);
        match fs::read_to_string(&path) {
            Ok(old) if !same(&old) => {
                return Err(format!(
                    "{} holds runs of another configuration of '{}'; use another --out or remove it",
                    path.display(),
                    c.name
                ))
            }
            Ok(_) => {}
            Err(_) => write_text_atomically(&path, &text)?,
        }
    }
    // Runs of other conditions or seeds made earlier into the same directory stay listed.
    let path = out.join("experiment.json");
    let mut merged = manifest.clone();
    if let Ok(old) = fs::read_to_string(&path) {
        let old: Manifest = serde_json::from_str(&old).map_err(|e| format!("{}: {e}", path.display()))?;
        let mut conditions = old.conditions;
        for c in &manifest.conditions {
            match conditions.iter_mut().find(|o| o.name == c.name) {
                Some(o) => {
                    // The runs asked before stay asked.
                    let plan = match (&o.plan, &c.plan) {
                        (Some(a), Some(b)) => Some(a.union(b)),
                        (a, b) => b.clone().or_else(|| a.clone()),
                    };
                    *o = ManifestCondition { plan, ..c.clone() };
                }
                None => conditions.push(c.clone()),
            }
        }
        let mut seeds = old.seeds;
        seeds.extend(manifest.seeds.iter().filter(|s| !seeds.contains(s)).copied().collect::<Vec<_>>());
        seeds.sort_unstable();
        merged = Manifest { conditions, seeds, episodes: old.episodes.max(manifest.episodes), ..merged };
    }
    let text = serde_json::to_string_pretty(&merged).expect("manifests serialise") + "\n";
    write_text_atomically(&path, &text)
}

/// The jobs of `conditions` x `seeds`, seed by seed (every condition's seed 1, then seed 2, ...)
/// so that an interrupted grid has runs of every condition to compare, keeping shard `shard` of
/// `of`.
pub fn jobs(
    conditions: &[Condition],
    seeds: &[u64],
    (shard, of): (usize, usize),
    agents: Option<AgentFactory>,
) -> Vec<Job> {
    let all = seeds.iter().flat_map(|&seed| {
        conditions.iter().map(move |c| Job {
            condition: c.name.clone(),
            config: c.config.clone(),
            seed,
            agents,
            legacy_checkpoint: false,
        })
    });
    all.enumerate().filter(|(i, _)| i % of == shard - 1).map(|(_, j)| j).collect()
}

/// The conditions named by one of `only`'s comma-separated items: a whole name
/// (`double-t-maze/ERLAM`, not `double-t-maze/ERLAM-raw` too) or a group ending in `/`; all of
/// them without `only`. An item that matches nothing is refused, naming the experiment.
pub fn select(experiment: &str, conditions: Vec<Condition>, only: Option<&str>) -> Result<Vec<Condition>, String> {
    let Some(only) = only else { return Ok(conditions) };
    let named = |name: &str, item: &str| name == item || (item.ends_with('/') && name.starts_with(item));
    let keep: Vec<Condition> =
        conditions.into_iter().filter(|c| only.split(',').any(|p| named(&c.name, p.trim()))).collect();
    if keep.is_empty() {
        return Err(format!("--only: '{only}' matches no condition of {experiment} (see `sec-experiment list`)"));
    }
    Ok(keep)
}

/// The experiment folder's manifest (`experiment.json`) for these runs.
pub fn manifest(experiment: &str, episodes: usize, seeds: &[u64], conditions: &[Condition]) -> Manifest {
    Manifest {
        experiment: experiment.to_string(),
        episodes,
        seeds: seeds.to_vec(),
        conditions: conditions
            .iter()
            .map(|c| ManifestCondition {
                name: c.name.clone(),
                paper_total: c.paper_total,
                config: c.config.clone(),
                plan: Some(Plan { seeds: seeds.to_vec(), episodes }),
            })
            .collect(),
    }
}

/// What keeps the experiment folder `dir` from being complete and consistent, one line each: a
/// condition's planned run missing or short of its episodes, a run whose manifest names another
/// configuration or seed, a condition whose `config.json` is another configuration. Empty when
/// the folder is whole. The reports refuse a folder with gaps unless told `--partial`.
pub fn gaps(dir: &Path) -> Result<Vec<String>, String> {
    let path = dir.join("experiment.json");
    let text = fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let manifest: Manifest = serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut out = Vec::new();
    for c in &manifest.conditions {
        let config = dir.join(&c.name).join("config.json");
        if let Ok(text) = fs::read_to_string(&config) {
            if serde_json::from_str::<RunConfig>(&text).ok().as_ref() != Some(&c.config) {
                out.push(format!("{}: config.json is another configuration than experiment.json's", c.name));
            }
        }
        for (seed, log) in finished_runs(&dir.join(&c.name)) {
            if let Some(m) = crate::manifest::read(&log)? {
                // The configurations as parsed, defaults filled in: a setting added since the
                // manifest was written takes its default on both sides (a hash of the JSON would
                // differ).
                if m.config != c.config || m.seed != seed {
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

/// Where an interrupted run's checkpoint lies, beside its `.part` file.
pub fn checkpoint_path(out: &Path, condition: &str, seed: u64) -> PathBuf {
    run_path(out, condition, seed).with_extension("ckpt")
}

/// The run to continue, the episodes it has played and the length in bytes of their lines at
/// the head of its `.part` file: from the checkpoint an interrupted run left (any lines written
/// after it are played again), or a fresh run (0, 0).
fn start(job: &Job, part: &Path, ckpt: &Path, legacy: bool) -> Result<(Run, usize, u64), String> {
    if let (Ok(bytes), Ok(text)) = (fs::read(ckpt), fs::read_to_string(part)) {
        // The log bounds what the checkpoint may claim, and its head must be the lines the
        // checkpoint was written after (`ResumeCheck`): a count edited above or below is refused
        // before anything is replayed. Whole lines only: a last line cut by the interruption
        // does not count.
        let whole = text.split_inclusive('\n').take_while(|l| l.ends_with('\n')).count();
        let check = ResumeCheck { max_episodes: whole as u64, log: Some(&text), legacy };
        match Run::resume(job.config.clone(), job.seed, job.agents, &mut bytes.as_slice(), &check) {
            Ok(run) => {
                let played = run.env().episode() as usize;
                eprintln!("{}: resumed after episode {played}", ckpt.display());
                let kept = text.split_inclusive('\n').take(played).map(|l| l.len() as u64).sum();
                return Ok((run, played, kept));
            }
            Err(e) => eprintln!("{}: not resumed ({e}); the run starts again", ckpt.display()),
        }
    }
    let run =
        Run::with_agents(job.config.clone(), job.seed, job.agents).map_err(|e| format!("{}: {e}", job.condition))?;
    Ok((run, 0, 0))
}

/// Writes the run's checkpoint in place of the last (an interruption leaves the previous one
/// whole).
fn save_checkpoint(run: &Run, ckpt: &Path) -> Result<(), String> {
    write_atomically(ckpt, |w| run.save_checkpoint(w).map_err(|e| format!("{}: {e}", ckpt.display())))
}

/// Plays one job's episodes into `<file>.part`, up to `stop` of them (`episodes` but in tests),
/// with a checkpoint every `every` episodes (0: none) when the agent can write one. A resumed
/// run's file is cut after the lines its checkpoint continues and appended to, never rewritten,
/// so a second interruption, however early, still finds them.
fn play(job: &Job, out: &Path, episodes: usize, every: usize, stop: usize, bar: &ProgressBar) -> Result<(), String> {
    let path = run_path(out, &job.condition, job.seed);
    let (part, ckpt) = (path.with_extension("part"), checkpoint_path(out, &job.condition, job.seed));
    let (mut run, played, kept) = start(job, &part, &ckpt, job.legacy_checkpoint)?;
    let err = |e: std::io::Error| format!("{}: {e}", part.display());
    let file = fs::OpenOptions::new().write(true).create(true).truncate(false).open(&part).map_err(err)?;
    file.set_len(kept).map_err(err)?;
    let mut w = BufWriter::new(file);
    w.seek(SeekFrom::End(0)).map_err(err)?;
    bar.inc(played as u64);
    for i in played..stop.min(episodes) {
        let m = run.episode();
        writeln!(w, "{}", m.to_json()).map_err(err)?;
        bar.inc(1);
        let n = i + 1;
        if every > 0 && n % every == 0 && n < episodes && run.can_checkpoint() {
            // The log first: a checkpoint never runs ahead of the lines it continues.
            w.flush().map_err(err)?;
            save_checkpoint(&run, &ckpt)?;
        }
    }
    w.flush().map_err(err)
}

/// Plays one job's `episodes` (resuming an interrupted run from its checkpoint), then gzips the
/// log into place and removes the checkpoint. A shorter finished log of the job is replaced only
/// when it is the new log's head, line for line: a run is a pure function of (configuration,
/// seed), so a difference means one of them is wrong, and both are kept for a look.
fn run_job(job: &Job, out: &Path, episodes: usize, every: usize, bar: &ProgressBar) -> Result<(), String> {
    let path = run_path(out, &job.condition, job.seed);
    let shorter = read_run_text(&path).ok().filter(|t| !t.is_empty());
    let clock = crate::manifest::Clock::start();
    play(job, out, episodes, every, episodes, bar)?;
    let part = path.with_extension("part");
    let text = fs::read(&part).map_err(|e| format!("{}: {e}", part.display()))?;
    if let Some(old) = shorter {
        let new = String::from_utf8_lossy(&text);
        if let Some(line) = first_difference(&old, &new) {
            return Err(format!(
                "{}: the new {episodes}-episode log differs from the finished {}-episode log {} at episode {line}; \
                 both are kept",
                part.display(),
                old.lines().count(),
                path.display()
            ));
        }
    }
    write_gzip(&path, &text)?;
    crate::manifest::write(&path, &clock.finish(&job.config, job.seed, episodes))?;
    remove_leftovers(&path, &checkpoint_path(out, &job.condition, job.seed))
}

/// Makes one run of an experiment folder `out` (as `run_all` does, without its progress bar):
/// nothing when its log already has `episodes`, else it plays (from its checkpoint when an
/// interrupted run left one). Returns whether it played. A Ray task or a Slurm job calls this.
pub fn run_one(job: &Job, out: &Path, episodes: usize, every: usize) -> Result<bool, String> {
    check_episodes(episodes)?;
    if finished_episodes(&run_path(out, &job.condition, job.seed)) >= episodes {
        return Ok(false);
    }
    run_job(job, out, episodes, every, &ProgressBar::hidden())?;
    Ok(true)
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
            .filter(|(dir, config)| *config == job.config && !same_dir(dir, &own))
            .map(|(dir, _)| dir.join(format!("seed-{}.jsonl.gz", job.seed)))
            .map(|path| (finished_episodes(&path), path))
            .filter(|(n, _)| *n >= episodes)
            .min_by_key(|(n, _)| *n)
            .map(|(_, path)| path)
    }
}

/// The finished runs (`seed-S.jsonl.gz`) of a condition directory, by seed.
pub fn finished_runs(dir: &Path) -> std::collections::BTreeMap<u64, PathBuf> {
    let mut out = std::collections::BTreeMap::new();
    for e in fs::read_dir(dir).into_iter().flatten().flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if let Some(seed) = name.strip_prefix("seed-").and_then(|s| s.strip_suffix(".jsonl.gz")) {
            if let Ok(seed) = seed.parse() {
                out.insert(seed, e.path());
            }
        }
    }
    out
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

fn same_dir(a: &Path, b: &Path) -> bool {
    match (fs::canonicalize(a), fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

/// Copies the head of `episodes` lines of the finished log `from` into `job`'s place under `out`
/// (the file itself when it has no more), removing what an interrupted play of the job left (its
/// `.part` log and checkpoint).
fn copy_run(from: &Path, job: &Job, out: &Path, episodes: usize) -> Result<(), String> {
    let bytes = fs::read(from).map_err(|e| format!("{}: {e}", from.display()))?;
    let path = run_path(out, &job.condition, job.seed);
    let text = read_run_text(from)?;
    if text.lines().count() == episodes {
        write_atomically(&path, |w| w.write_all(&bytes).map_err(|e| format!("{}: {e}", path.display())))?;
    } else {
        let head: String = text.split_inclusive('\n').take(episodes).collect();
        write_gzip(&path, head.as_bytes())?;
    }
    let mut manifest = crate::manifest::Clock::start().finish(&job.config, job.seed, episodes);
    manifest.copied_from = Some(from.display().to_string());
    crate::manifest::write(&path, &manifest)?;
    remove_leftovers(&path, &checkpoint_path(out, &job.condition, job.seed))
}

/// Writes `text` gzipped to `path` (atomically), as every finished run is written.
fn write_gzip(path: &Path, text: &[u8]) -> Result<(), String> {
    write_atomically(path, |w| {
        let mut gz = GzEncoder::new(w, flate2::Compression::best());
        gz.write_all(text).and_then(|()| gz.finish().map(drop)).map_err(|e| format!("{}: {e}", path.display()))
    })
}

/// Removes a finished run's `.part` log and checkpoint, where there are any.
fn remove_leftovers(path: &Path, ckpt: &Path) -> Result<(), String> {
    for leftover in [&path.with_extension("part"), ckpt] {
        match fs::remove_file(leftover) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(format!("{}: {e}", leftover.display())),
            _ => {}
        }
    }
    Ok(())
}

/// Runs the unfinished `jobs` on `threads` threads with a progress bar on standard error (a line
/// per finished run when it is not a terminal), each checkpointing every `every` episodes (0:
/// never; only agents that can: SEC, DQN and ERLAM). A job that `reuse` holds a finished run of
/// is copied from it instead of played. Returns (runs made, runs copied, runs already there).
pub fn run_all(
    jobs: &[Job],
    out: &Path,
    episodes: usize,
    every: usize,
    threads: usize,
    reuse: Option<&Finished>,
) -> Result<(usize, usize, usize), String> {
    let unfinished: Vec<&Job> =
        jobs.iter().filter(|j| finished_episodes(&run_path(out, &j.condition, j.seed)) < episodes).collect();
    let skipped = jobs.len() - unfinished.len();
    let mut todo = Vec::new();
    let mut copied = 0;
    for job in unfinished {
        match reuse.and_then(|r| r.find(job, out, episodes)) {
            Some(from) => {
                copy_run(&from, job, out, episodes)?;
                eprintln!(
                    "{} seed {}: copied from {} (the same configuration and seed)",
                    job.condition,
                    job.seed,
                    from.display()
                );
                copied += 1;
            }
            None => todo.push(job),
        }
    }
    let bar = ProgressBar::new((todo.len() * episodes) as u64);
    bar.set_style(
        ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} episodes, eta {eta} {msg}")
            .expect("a valid template")
            .progress_chars("=> "),
    );
    let next = AtomicUsize::new(0);
    let errors = Mutex::new(Vec::new());
    let done = AtomicUsize::new(0);
    std::thread::scope(|s| {
        for _ in 0..threads.max(1) {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                let Some(job) = todo.get(i) else { break };
                match run_job(job, out, episodes, every, &bar) {
                    Ok(()) => {
                        let n = done.fetch_add(1, Ordering::Relaxed) + 1;
                        let line = format!("{}/{} runs: {} seed {}", n, todo.len(), job.condition, job.seed);
                        if bar.is_hidden() {
                            eprintln!("{line}");
                        } else {
                            bar.set_message(line);
                        }
                    }
                    Err(e) => errors.lock().expect("no thread panicked holding it").push(e),
                }
            });
        }
    });
    bar.finish();
    let errors = errors.into_inner().expect("no thread panicked holding it");
    if let Some(e) = errors.first() {
        return Err(format!("{} run(s) failed; the first: {e}", errors.len()));
    }
    Ok((todo.len(), copied, skipped))
}

#[cfg(test)]
mod tests {
    use super::*;
    use sec_playground::agent::dqn::DqnConfig;
    use sec_playground::experiment::AgentKind;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("sec-runner-test-{}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&d);
        fs::create_dir_all(d.join("c/dqn")).unwrap();
        d
    }

    #[test]
    fn an_interrupted_run_resumes_from_its_checkpoint_to_the_same_log() {
        let dqn = DqnConfig { random_decisions: 10, batch_size: 4, replay_size: 30, ..DqnConfig::default() };
        let config = RunConfig {
            task: "object-permanence".into(),
            kind: AgentKind::Dqn,
            t: Some(60),
            dqn,
            ..RunConfig::default()
        };
        let job = Job {
            condition: "c/dqn".into(),
            config,
            seed: 2,
            agents: Some(sec_dqn::factory),
            legacy_checkpoint: false,
        };
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
        assert_eq!(
            left,
            ["seed-2.jsonl.gz", "seed-2.manifest.json"],
            "a finished run leaves only its log and manifest"
        );

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
        let other =
            Job { config: RunConfig { t: Some(41), ..config.clone() }, condition: "h/c".into(), ..first.clone() };
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
        let job = Job {
            condition: "c/dqn".into(),
            config,
            seed: 5,
            agents: Some(sec_dqn::factory),
            legacy_checkpoint: false,
        };
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
            let job = Job {
                condition: "g/a".into(),
                config: config.clone(),
                seed: 2,
                agents: None,
                legacy_checkpoint: false,
            };
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
        let manifest = Manifest { experiment: "x".into(), episodes: 3, seeds: vec![1, 2], conditions };
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
}

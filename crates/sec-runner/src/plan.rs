//! What a grid is: its jobs (condition, configuration, seed), the experiment's manifest of
//! conditions and plans (`experiment.json`), shards (`--shard i/N`, Slurm arrays) and seeds.

use sec_playground::experiment::presets::Condition;
use sec_playground::experiment::{AgentFactory, RunConfig};
use sec_playground::seed::MAX_SEED;

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
pub struct ExperimentManifest {
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
    pub(crate) fn union(&self, other: &Plan) -> Plan {
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
pub fn experiment_manifest(
    experiment: &str,
    episodes: usize,
    seeds: &[u64],
    conditions: &[Condition],
) -> ExperimentManifest {
    ExperimentManifest {
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

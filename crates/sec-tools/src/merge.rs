//! `sec-experiment merge SRC... --into DIR`: result folders from several machines (shards, Slurm
//! array tasks, Ray workers) into one, checked before anything is written. Refused, by name: an
//! experiment whose condition has another configuration in another folder, a run whose manifest
//! names another configuration than its condition's, and two logs of one run that differ (a
//! shorter log that is the longer's head is no conflict: the longer is kept, as `run` does). After
//! the merge the seeds the experiments list that are missing or short are reported.

use crate::manifest::{self, config_hash};
use crate::runner::{
    experiment_dirs, finished_runs, first_difference, prepare, read_run_text, run_path, ExperimentManifest,
};
use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};

/// What a merge did and what the merged folder still lacks.
#[derive(Debug, Default)]
pub struct Merged {
    /// Runs copied into the target.
    pub copied: usize,
    /// Runs already there with the same log (or a longer one).
    pub kept: usize,
    /// "EXPERIMENT/GROUP/MODEL seed S: N of E episodes" for each run the experiments list that
    /// the merged folder lacks or holds shorter.
    pub missing: Vec<String>,
}

fn experiments(root: &Path) -> Result<Vec<(String, ExperimentManifest)>, String> {
    let mut out = Vec::new();
    for dir in experiment_dirs(root) {
        let path = dir.join("experiment.json");
        let text = fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let m: ExperimentManifest = serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        out.push((dir.file_name().map_or_else(String::new, |n| n.to_string_lossy().into_owned()), m));
    }
    Ok(out)
}

/// Merges every experiment under each of `sources` into `into` (see the module's doc).
pub fn merge(sources: &[PathBuf], into: &Path) -> Result<Merged, String> {
    // Every folder's experiments, the target's first: their conditions must agree.
    let mut folders = vec![into.to_path_buf()];
    folders.extend(sources.iter().cloned());
    let mut merged: BTreeMap<String, ExperimentManifest> = BTreeMap::new();
    let mut seen: BTreeMap<(String, String), (String, PathBuf)> = BTreeMap::new();
    for folder in &folders {
        for (name, m) in experiments(folder)? {
            for c in &m.conditions {
                let hash = config_hash(&c.config);
                match seen.get(&(name.clone(), c.name.clone())) {
                    Some((h, first)) if *h != hash => {
                        return Err(format!(
                            "{name}/{}: {} has another configuration ({hash}) than {} ({h}); not merged",
                            c.name,
                            folder.display(),
                            first.display()
                        ))
                    }
                    Some(_) => {}
                    None => {
                        seen.insert((name.clone(), c.name.clone()), (hash, folder.clone()));
                    }
                }
            }
            let entry = merged
                .entry(name.clone())
                .or_insert_with(|| ExperimentManifest { conditions: Vec::new(), ..m.clone() });
            entry.episodes = entry.episodes.max(m.episodes);
            for s in &m.seeds {
                if !entry.seeds.contains(s) {
                    entry.seeds.push(*s);
                }
            }
            entry.seeds.sort_unstable();
            for c in m.conditions {
                if !entry.conditions.iter().any(|o| o.name == c.name) {
                    entry.conditions.push(c);
                }
            }
        }
    }
    // Every run: the longest log of each, every other its head; its manifest its condition's.
    let mut plan: Vec<(PathBuf, PathBuf)> = Vec::new();
    let mut result = Merged::default();
    for (name, m) in &merged {
        for c in &m.conditions {
            let hash = config_hash(&c.config);
            let mut by_seed: BTreeMap<u64, Vec<PathBuf>> = BTreeMap::new();
            for folder in &folders {
                for (seed, path) in finished_runs(&folder.join(name).join(&c.name)) {
                    if let Some(mf) = manifest::read(&path)? {
                        // Parsed configurations, defaults filled in (a setting added since takes its
                        // default on both sides).
                        if !mf.config.same_run(&c.config) || mf.seed != seed {
                            return Err(format!(
                                "{}: its manifest names configuration {} seed {}, not {name}/{}'s {hash} seed {seed}; not merged",
                                path.display(),
                                config_hash(&mf.config),
                                mf.seed,
                                c.name
                            ));
                        }
                    }
                    by_seed.entry(seed).or_default().push(path);
                }
            }
            for (seed, paths) in by_seed {
                let mut logs: Vec<(String, PathBuf)> =
                    paths.into_iter().map(|p| read_run_text(&p).map(|t| (t, p))).collect::<Result<_, _>>()?;
                logs.sort_by_key(|(t, _)| std::cmp::Reverse(t.lines().count()));
                let (longest, from) = &logs[0];
                for (other, path) in &logs[1..] {
                    if let Some(line) = first_difference(other, longest) {
                        return Err(format!(
                            "{name}/{} seed {seed}: {} and {} differ at episode {line} (a run is a pure function of its \
                             configuration and seed: one of them is wrong); not merged",
                            c.name,
                            path.display(),
                            from.display()
                        ));
                    }
                }
                let target = run_path(&into.join(name), &c.name, seed);
                if *from == target || read_run_text(&target).is_ok_and(|t| t == *longest) {
                    result.kept += 1;
                } else {
                    plan.push((from.clone(), target));
                }
            }
        }
    }
    // Checked: now write.
    for (name, m) in &merged {
        prepare(&into.join(name), m)?;
    }
    for (from, target) in &plan {
        fs::copy(from, target).map_err(|e| format!("{} -> {}: {e}", from.display(), target.display()))?;
        let mf = manifest::manifest_path(from);
        if mf.exists() {
            let to = manifest::manifest_path(target);
            fs::copy(&mf, &to).map_err(|e| format!("{} -> {}: {e}", mf.display(), to.display()))?;
        }
        result.copied += 1;
    }
    for (name, m) in &merged {
        for c in &m.conditions {
            for &seed in &m.seeds {
                let have = read_run_text(&run_path(&into.join(name), &c.name, seed)).map_or(0, |t| t.lines().count());
                if have < m.episodes {
                    result.missing.push(format!("{name}/{} seed {seed}: {have} of {} episodes", c.name, m.episodes));
                }
            }
        }
    }
    Ok(result)
}

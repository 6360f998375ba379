//! Warm-up memories for the page's "Skip the warm-up": the memory a reference run had after its
//! first episodes, as a memory file (`memory::file`), so a student can start from a learned SEC.
//!
//! A snapshot is made by replaying one seed of a finished reference run (its `config.json` and
//! seed), checking every replayed episode against the committed log line for line before the file
//! is written: a snapshot that is not the reference run's memory cannot be made. The folder's
//! `index.json` tells the page, per task, which run, seed and episode count each file holds.

use crate::runner::{read_run_text, run_path};
use sec_playground::experiment::{Run, RunConfig};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fs;
use std::path::Path;

/// One snapshot as the page's index lists it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct Entry {
    /// The memory file, relative to the index.
    pub file: String,
    /// The reference condition the run belongs to (`exp1/double-t-maze/SEC`).
    pub run: String,
    /// Its seed.
    pub seed: u64,
    /// Episodes played before the memory was taken.
    pub episodes: usize,
    /// Sequences in the LTM then (the log's `ltm` of the last episode).
    pub sequences: usize,
    /// The run's 20-episode mean reward at that point, for the page's notice.
    pub mean_reward: f64,
}

/// The memory of `seed` of the reference runs in `condition_dir` (`OUT/EXPERIMENT/GROUP/MODEL`)
/// after `episodes` episodes, with its index entry (`file` left empty). Every replayed episode
/// must equal the committed log's.
pub fn snapshot(condition_dir: &Path, seed: u64, episodes: usize) -> Result<(Vec<u8>, Entry), String> {
    let config_path = condition_dir.join("config.json");
    let text = fs::read_to_string(&config_path).map_err(|e| format!("{}: {e}", config_path.display()))?;
    let cfg = RunConfig::from_json(&text).map_err(|e| format!("{}: {e}", config_path.display()))?;
    let log_path = run_path(condition_dir, "", seed);
    let log = read_run_text(&log_path)?;
    let lines: Vec<&str> = log.lines().collect();
    if lines.len() < episodes {
        return Err(format!(
            "{}: {} episodes logged, fewer than the {episodes} asked for",
            log_path.display(),
            lines.len()
        ));
    }
    let mut run = Run::new(cfg, seed).map_err(|e| format!("{}: {e}", config_path.display()))?;
    let mut last = None;
    let mut rewards = Vec::with_capacity(episodes);
    for (i, want) in lines[..episodes].iter().enumerate() {
        let m = run.episode();
        let got = m.to_json();
        if got != *want {
            return Err(format!(
                "{}: episode {i} replays differently from the log (this build does not make the reference run)\n  log:    {want}\n  replay: {got}",
                log_path.display()
            ));
        }
        rewards.push(m.reward);
        last = Some(m);
    }
    let last = last.ok_or("--episodes must be at least 1")?;
    let bytes = run.save_memory().map_err(|e| e.to_string())?;
    let window = &rewards[rewards.len().saturating_sub(20)..];
    // EXPERIMENT/GROUP/MODEL: the folder's last three parts.
    let parts: Vec<String> = condition_dir.iter().map(|p| p.to_string_lossy().into_owned()).collect();
    let run_name = parts[parts.len().saturating_sub(3)..].join("/");
    let entry = Entry {
        file: String::new(),
        run: run_name,
        seed,
        episodes,
        sequences: last.ltm,
        mean_reward: window.iter().sum::<f64>() / window.len() as f64,
    };
    Ok((bytes, entry))
}

/// Writes the snapshot as `to` and records it under `task` in the `index.json` beside it (other
/// tasks' entries are kept). Returns the entry.
pub fn write(condition_dir: &Path, seed: u64, episodes: usize, to: &Path) -> Result<Entry, String> {
    let (bytes, mut entry) = snapshot(condition_dir, seed, episodes)?;
    let text = fs::read_to_string(condition_dir.join("config.json")).map_err(|e| e.to_string())?;
    let task = RunConfig::from_json(&text).map_err(|e| e.to_string())?.task;
    let dir = to.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    fs::write(to, &bytes).map_err(|e| format!("{}: {e}", to.display()))?;
    entry.file = to.file_name().and_then(|f| f.to_str()).ok_or("--to needs a file name")?.to_string();
    let index_path = dir.join("index.json");
    let mut index: BTreeMap<String, Entry> = match fs::read_to_string(&index_path) {
        Ok(t) => serde_json::from_str(&t).map_err(|e| format!("{}: {e}", index_path.display()))?,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => BTreeMap::new(),
        Err(e) => return Err(format!("{}: {e}", index_path.display())),
    };
    index.insert(task, entry.clone());
    let json = serde_json::to_string_pretty(&index).expect("the index serialises") + "\n";
    fs::write(&index_path, json).map_err(|e| format!("{}: {e}", index_path.display()))?;
    Ok(entry)
}

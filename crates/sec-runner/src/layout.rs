//! Where a grid's files go and how they are written: `OUT/<condition>/seed-<seed>.jsonl.part`
//! while a run plays, `seed-<seed>.jsonl.gz` when it is finished (about a sixth of the size, so the
//! runs themselves can be committed), its `.ckpt` checkpoint beside; every write atomic (a
//! temporary file renamed), so an interrupted writer leaves the old file or the new one.

use crate::plan::{ExperimentManifest, ManifestCondition};
use flate2::read::GzDecoder;
use flate2::write::GzEncoder;
use sec_playground::experiment::RunConfig;
use std::fs;
use std::io::{BufWriter, Read, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;

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
pub(crate) fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> Result<(), String>,
) -> Result<(), String> {
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
pub(crate) fn write_text_atomically(path: &Path, text: &str) -> Result<(), String> {
    write_atomically(path, |w| w.write_all(text.as_bytes()).map_err(|e| format!("{}: {e}", path.display())))
}

/// Writes the manifest and each condition's `config.json`, refusing to mix configurations: a
/// directory that holds runs of another configuration under the same name is an error.
pub fn prepare(out: &Path, manifest: &ExperimentManifest) -> Result<(), String> {
    for c in &manifest.conditions {
        let dir = out.join(&c.name);
        fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        let path = dir.join("config.json");
        let text = serde_json::to_string_pretty(&c.config).expect("configurations serialise") + "\n";
        // Compared as configurations, so a file written before a new field (with its default)
        // was added still matches.
        let same = |old: &str| serde_json::from_str::<RunConfig>(old).is_ok_and(|o| o.same_run(&c.config));
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
        let old: ExperimentManifest = serde_json::from_str(&old).map_err(|e| format!("{}: {e}", path.display()))?;
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
        merged = ExperimentManifest { conditions, seeds, episodes: old.episodes.max(manifest.episodes), ..merged };
    }
    let text = serde_json::to_string_pretty(&merged).expect("manifests serialise") + "\n";
    write_text_atomically(&path, &text)
}

/// Where an interrupted run's checkpoint lies, beside its `.part` file.
pub fn checkpoint_path(out: &Path, condition: &str, seed: u64) -> PathBuf {
    run_path(out, condition, seed).with_extension("ckpt")
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

pub(crate) fn same_dir(a: &Path, b: &Path) -> bool {
    match (fs::canonicalize(a), fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

/// Writes `text` gzipped to `path` (atomically), as every finished run is written.
pub(crate) fn write_gzip(path: &Path, text: &[u8]) -> Result<(), String> {
    write_atomically(path, |w| {
        let mut gz = GzEncoder::new(w, flate2::Compression::best());
        gz.write_all(text).and_then(|()| gz.finish().map(drop)).map_err(|e| format!("{}: {e}", path.display()))
    })
}

/// Removes a finished run's `.part` log and checkpoint, where there are any.
pub(crate) fn remove_leftovers(path: &Path, ckpt: &Path) -> Result<(), String> {
    for leftover in [&path.with_extension("part"), ckpt] {
        match fs::remove_file(leftover) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(format!("{}: {e}", leftover.display())),
            _ => {}
        }
    }
    Ok(())
}

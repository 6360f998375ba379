//! A run's manifest, `seed-S.manifest.json` beside its log: what made it (configuration and its
//! hash, seed, episodes, the tools' version and git commit, the kernel path) and where and how long
//! (host, start and end, wall and CPU seconds), so a merged results folder can say which binary and
//! configuration produced each file.

use sec_playground::experiment::RunConfig;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::time::{Instant, SystemTime, UNIX_EPOCH};

/// One run's record.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct RunManifest {
    /// FNV-1a 64 of the configuration's JSON as the writing version serialised it, hex: a name
    /// to show, not to compare (a setting added later changes the JSON, not the configuration:
    /// readers compare `config`, parsed with defaults filled in).
    pub config_hash: String,
    /// The configuration the run was made with.
    pub config: RunConfig,
    /// Its seed.
    pub seed: u64,
    /// The episodes its log holds.
    pub episodes: usize,
    /// The runner's package version (sec-runner).
    pub version: String,
    /// The git commit the binary was built from (`unknown` outside a checkout).
    pub git_commit: String,
    /// The kernels the run used: `avx2` or `scalar` (the bits are the same).
    pub kernel: String,
    /// The machine's name (`HOSTNAME`, else `/etc/hostname`; `unknown`).
    pub host: String,
    /// When the run started, in Unix seconds.
    pub start: u64,
    /// When it ended, in Unix seconds.
    pub end: u64,
    /// Seconds from start to end.
    pub wall_seconds: f64,
    /// CPU time of the thread that played the run (Linux; None elsewhere).
    pub cpu_seconds: Option<f64>,
    /// Set when the log was copied from an identical finished run rather than played.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub copied_from: Option<String>,
}

/// The manifest's path beside a run's log `seed-S.jsonl.gz`.
pub fn manifest_path(log: &Path) -> PathBuf {
    let name = log.file_name().and_then(|n| n.to_str()).unwrap_or_default();
    log.with_file_name(format!("{}.manifest.json", name.trim_end_matches(".jsonl.gz")))
}

/// The configuration's hash as manifests hold it.
pub fn config_hash(config: &RunConfig) -> String {
    let json = serde_json::to_string(config).expect("configurations serialise");
    format!("{:016x}", sec_playground::render::fnv1a(json.as_bytes()))
}

fn unix_now() -> u64 {
    SystemTime::now().duration_since(UNIX_EPOCH).map_or(0, |d| d.as_secs())
}

/// This thread's CPU seconds so far (Linux's schedstat), or None.
fn thread_cpu_seconds() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: u64 = text.split_whitespace().next()?.parse().ok()?;
    Some(ns as f64 / 1e9)
}

fn host() -> String {
    std::env::var("HOSTNAME")
        .ok()
        .filter(|h| !h.is_empty())
        .or_else(|| std::fs::read_to_string("/etc/hostname").ok().map(|h| h.trim().to_string()))
        .filter(|h| !h.is_empty())
        .unwrap_or_else(|| "unknown".into())
}

/// Started when a run starts playing; `finish` makes its manifest.
pub struct Clock {
    start: u64,
    wall: Instant,
    cpu: Option<f64>,
}

impl Clock {
    /// Starts timing the run this thread is about to play.
    pub fn start() -> Clock {
        Clock { start: unix_now(), wall: Instant::now(), cpu: thread_cpu_seconds() }
    }

    /// The manifest of a run of `config` and `seed` with `episodes`, played since `start`.
    pub fn finish(self, config: &RunConfig, seed: u64, episodes: usize) -> RunManifest {
        RunManifest {
            config_hash: config_hash(config),
            config: config.clone(),
            seed,
            episodes,
            version: env!("CARGO_PKG_VERSION").into(),
            git_commit: env!("SEC_GIT_COMMIT").into(),
            kernel: sec_playground::kernel_path().into(),
            host: host(),
            start: self.start,
            end: unix_now(),
            wall_seconds: self.wall.elapsed().as_secs_f64(),
            cpu_seconds: thread_cpu_seconds().zip(self.cpu).map(|(now, then)| now - then),
            copied_from: None,
        }
    }
}

/// Writes `manifest` beside the log `log`.
pub fn write(log: &Path, manifest: &RunManifest) -> Result<(), String> {
    let path = manifest_path(log);
    let text = serde_json::to_string_pretty(manifest).expect("manifests serialise") + "\n";
    std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))
}

/// The manifest beside `log`, if there is one (an unreadable one is an error).
pub fn read(log: &Path) -> Result<Option<RunManifest>, String> {
    let path = manifest_path(log);
    match std::fs::read_to_string(&path) {
        Ok(text) => serde_json::from_str(&text).map(Some).map_err(|e| format!("{}: {e}", path.display())),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(format!("{}: {e}", path.display())),
    }
}

//! The page's reference curves: the committed long runs of each condition reduced to what the
//! compare chart draws (per episode, the mean across seeds of each seed's 20-episode trailing mean,
//! and its standard error), sampled so a file stays small. One JSON file per condition,
//! `<to>/<experiment>/<group>/<model>.json`, and `<to>/index.json` listing them with their mean
//! reward per episode and the paper's total (over 5000 episodes, where it gives one), which the
//! page's captions quote; the page fetches the curves its presets name.

use crate::report::{load, ConditionRuns, WINDOW};
use sec_playground::experiment::settings::to_settings;
use sec_playground::experiment::EpisodeMetrics;
use serde_json::{json, Value};
use std::fs;
use std::path::Path;

/// Most points per curve; in between the page interpolates linearly (the curves are 20-episode
/// means, smooth at this resolution).
const POINTS: usize = 250;

/// What a curve plots of an episode.
type Metric = fn(&EpisodeMetrics) -> f64;

/// The metrics the compare chart offers.
const METRICS: [(&str, Metric); 3] =
    [("reward", |m| m.reward), ("entropy", |m| m.entropy), ("decisions", |m| m.decisions as f64)];

/// Rounds to 4 significant digits, enough for a chart, and what keeps the files small.
fn round(x: f64) -> Value {
    if x == 0.0 || !x.is_finite() {
        return json!(0.0);
    }
    let digits = 3 - x.abs().log10().floor() as i32;
    let k = 10f64.powi(digits.max(0));
    json!((x * k).round() / k)
}

/// The episodes sampled: every `step`-th from 0, and always the last.
fn sampled(len: usize) -> Vec<usize> {
    let step = len.div_ceil(POINTS).max(1);
    let mut at: Vec<usize> = (0..len).step_by(step).collect();
    if at.last() != Some(&(len - 1)) {
        at.push(len - 1);
    }
    at
}

fn condition_json(experiment: &str, c: &ConditionRuns) -> Value {
    let len = c.runs[0].len();
    let at = sampled(len);
    let mut metrics = serde_json::Map::new();
    for (name, f) in METRICS {
        let (mean, se) = c.curve(f);
        metrics.insert(
            name.into(),
            json!({
                "mean": at.iter().map(|&i| round(mean[i])).collect::<Vec<_>>(),
                "se": at.iter().map(|&i| round(se[i])).collect::<Vec<_>>(),
            }),
        );
    }
    let mut settings = to_settings(&c.condition.config, 0);
    settings.remove("seed");
    json!({
        "experiment": experiment,
        "condition": c.condition.name,
        "settings": settings,
        "seeds": c.seeds,
        "episodes": len,
        "window": WINDOW,
        "at": at,
        "metrics": metrics,
    })
}

/// Writes the reference files of every experiment under `out` into `to`; returns a summary.
pub fn references(out: &Path, to: &Path) -> Result<String, String> {
    let mut index = Vec::new();
    let mut entries: Vec<_> = fs::read_dir(out).map_err(|e| format!("{}: {e}", out.display()))?.flatten().collect();
    entries.sort_by_key(|e| e.file_name());
    for entry in entries {
        let dir = entry.path();
        if !dir.join("experiment.json").exists() {
            continue;
        }
        let experiment = entry.file_name().to_string_lossy().to_string();
        let (_, conditions) = load(&dir)?;
        for c in &conditions {
            let path = to.join(&experiment).join(format!("{}.json", c.condition.name));
            fs::create_dir_all(path.parent().expect("a condition has a folder"))
                .map_err(|e| format!("{}: {e}", path.display()))?;
            let text = serde_json::to_string(&condition_json(&experiment, c)).expect("JSON values serialise");
            fs::write(&path, text + "\n").map_err(|e| format!("{}: {e}", path.display()))?;
            // The numbers the page's captions quote: declared here (the paper's, in the presets)
            // and measured here (ours), never typed again in the page.
            let episodes: usize = c.runs.iter().map(Vec::len).sum();
            let reward: f64 = c.runs.iter().flatten().map(|m| m.reward).sum();
            index.push(json!({
                "reference": format!("{experiment}:{}", c.condition.name),
                "seeds": c.seeds.len(),
                "episodes": c.runs[0].len(),
                // Six significant digits: the captions divide these, so the curves' four would show.
                "meanReward": format!("{:.6e}", reward / episodes as f64).parse::<f64>().expect("a number"),
                "paperTotal": c.condition.paper_total,
            }));
        }
    }
    let summary = format!("{} reference curves", index.len());
    let text = serde_json::to_string_pretty(&json!({ "window": WINDOW, "references": index })).expect("serialise");
    fs::write(to.join("index.json"), text + "\n").map_err(|e| format!("{}: {e}", to.display()))?;
    Ok(summary)
}

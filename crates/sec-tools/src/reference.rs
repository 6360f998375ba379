//! The page's reference curves: the committed long runs of each condition reduced to what the
//! compare chart draws (per episode, the mean across seeds of each seed's 20-episode trailing mean,
//! and its standard error), sampled so a file stays small. One JSON file per condition,
//! `<to>/<experiment>/<group>/<model>.json`, and `<to>/index.json` listing them with their mean
//! reward per episode and the paper's total (over 5000 episodes, where it gives one), and the
//! other numbers the page's captions quote (`facts`): the captions are templates over this file,
//! so no measured number is typed in the page. The page fetches the curves its presets name.

use crate::authors::{load_authors, LearnedBar};
use crate::report::{load, ConditionRuns, WINDOW};
use crate::runner::experiment_dirs;
use crate::stats::mean;
use sec_playground::agent::SecConfig;
use sec_playground::experiment::settings::to_settings;
use sec_playground::experiment::AgentKind;
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

/// Rounds for the index: four decimals, what the captions show at most.
fn dec4(x: f64) -> Value {
    if x.is_finite() {
        json!((x * 1e4).round() / 1e4)
    } else {
        Value::Null
    }
}

/// Six significant digits: the captions divide these, so the curves' four would show.
fn sig6(x: f64) -> Value {
    json!(format!("{x:.6e}").parse::<f64>().expect("a number"))
}

/// The episodes at which a caption quotes the curve (the 20-episode trailing mean across runs).
const CURVE_AT: [usize; 3] = [100, 200, 2000];
/// The prefixes over which a caption compares runs of different lengths (DQN's 1000 episodes).
const OVER: [usize; 2] = [1000, 2000];

/// What the captions quote of a condition beyond its mean: each run's reward per episode (seed
/// order), runs that learned (above the reactive walk's bar in its task), the authors' runs where
/// their notebooks keep them, the episode each run's LTM filled (SEC's kinds), the curve at a few
/// episodes and at the end, the last 10 % (mean, and per run with the first 90 %) and the mean
/// over a prefix.
fn facts(c: &ConditionRuns, bar: Option<LearnedBar>, authors: Option<(&[f64], usize)>) -> Value {
    let len = c.runs[0].len();
    let per_run: Vec<f64> = c.totals().iter().map(|t| t / len as f64).collect();
    let mut f = serde_json::Map::new();
    f.insert("runs".into(), json!(per_run.iter().map(|&v| dec4(v)).collect::<Vec<_>>()));
    if let Some(bar) = bar {
        f.insert("learned".into(), json!(bar.count(&per_run)));
        f.insert("learnedBar".into(), dec4(bar.per_episode));
    }
    if let Some((totals, episodes)) = authors {
        f.insert("authorsRuns".into(), json!(totals.iter().map(|t| dec4(t / episodes as f64)).collect::<Vec<_>>()));
    }
    if c.condition.config.kind == AgentKind::Sec {
        let m = c.condition.config.section::<SecConfig>().memory.m;
        let full: Vec<Option<usize>> = c.runs.iter().map(|r| r.iter().position(|e| e.ltm >= m)).collect();
        f.insert("ltmFull".into(), json!(full));
    }
    let (curve, _) = c.curve(|m| m.reward);
    let mut at = serde_json::Map::new();
    for e in CURVE_AT.into_iter().filter(|&e| e < len) {
        at.insert(e.to_string(), dec4(curve[e]));
    }
    at.insert("end".into(), dec4(curve[len - 1]));
    f.insert("curveAt".into(), Value::Object(at));
    let late = c.span_means(0.9, 1.0, |m| m.reward);
    f.insert("late".into(), dec4(mean(&late)));
    // Per run (seed order), over the last 10 % and the first 90 %: whether a run learned only
    // near its end.
    f.insert("lateRuns".into(), json!(late.iter().map(|&v| dec4(v)).collect::<Vec<_>>()));
    let early = c.span_means(0.0, 0.9, |m| m.reward);
    f.insert("earlyRuns".into(), json!(early.iter().map(|&v| dec4(v)).collect::<Vec<_>>()));
    let mut over = serde_json::Map::new();
    for n in OVER.into_iter().filter(|&n| n < len) {
        over.insert(n.to_string(), dec4(mean(&c.totals_over(n)) / n as f64));
    }
    f.insert("over".into(), Value::Object(over));
    Value::Object(f)
}

/// The tests of the paper's claims on our runs (the `code` tree of `orderings.csv`, which
/// `sec-experiment orderings` writes): family, ordering, verdict, ratio and corrected p.
fn claims(csv: &str) -> Result<Vec<Value>, String> {
    let mut out = Vec::new();
    for line in csv.lines().skip(1) {
        // family,"ordering",paper,tree,verdict,ratio,p: the ordering is quoted; the verdict may
        // hold commas, the fields around it do not.
        let bad = || format!("orderings.csv: '{line}' is not family,\"ordering\",paper,tree,verdict,ratio,p");
        let (family, rest) = line.split_once(",\"").ok_or_else(bad)?;
        let (ordering, rest) = rest.split_once("\",").ok_or_else(bad)?;
        let mut head = rest.splitn(3, ',');
        let (_paper, tree, rest) = (head.next(), head.next().ok_or_else(bad)?, head.next().ok_or_else(bad)?);
        let mut tail = rest.rsplitn(3, ',');
        let (p, ratio, verdict) = (tail.next(), tail.next().ok_or_else(bad)?, tail.next().ok_or_else(bad)?);
        if tree != "code" {
            continue;
        }
        let number = |s: Option<&str>| s.and_then(|s| s.parse::<f64>().ok()).map_or(Value::Null, sig6);
        out.push(json!({
            "family": family,
            "ordering": ordering,
            "verdict": verdict,
            "ratio": number(Some(ratio)),
            "p": number(p),
        }));
    }
    Ok(out)
}

/// Writes the reference files of every experiment under `out` into `to`; returns a summary. The
/// authors' numbers come from `authors/` beside `out`, and the claims' tests from
/// `orderings.csv` beside it, when they are there (`scripts/results.sh` writes it first).
pub fn references(out: &Path, to: &Path) -> Result<String, String> {
    let authors_dir = out.parent().map(|p| p.join("authors")).filter(|d| d.is_dir());
    let authors = match &authors_dir {
        Some(d) => load_authors(d)?,
        None => Vec::new(),
    };
    // The learned bar of each task (it loads exp1's reactive runs).
    let mut bars = std::collections::HashMap::new();
    let mut index = Vec::new();
    fs::read_dir(out).map_err(|e| format!("{}: {e}", out.display()))?;
    for dir in experiment_dirs(out) {
        let experiment = dir.file_name().map_or_else(String::new, |n| n.to_string_lossy().into_owned());
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
            let task = &c.condition.config.task;
            let bar = *bars.entry(task.clone()).or_insert_with(|| LearnedBar::of(out, "exp1", task));
            let theirs = authors
                .iter()
                .filter(|a| a.experiment == experiment)
                .flat_map(|a| {
                    a.runs.iter().filter(|r| r.condition == c.condition.name).map(|r| (r.totals.as_slice(), a.episodes))
                })
                .next();
            let mut entry = json!({
                "reference": format!("{experiment}:{}", c.condition.name),
                "seeds": c.seeds.len(),
                "episodes": c.runs[0].len(),
                "meanReward": sig6(reward / episodes as f64),
                "paperTotal": c.condition.paper_total,
            });
            if let (Value::Object(e), Value::Object(f)) = (&mut entry, facts(c, bar, theirs)) {
                e.extend(f);
            }
            index.push(entry);
        }
    }
    let summary = format!("{} reference curves", index.len());
    let orderings = match out.parent().map(|p| p.join("orderings.csv")).filter(|p| p.is_file()) {
        Some(path) => claims(&fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?)?,
        None => Vec::new(),
    };
    let index = json!({ "window": WINDOW, "references": index, "orderings": orderings });
    let text = serde_json::to_string_pretty(&index).expect("serialise");
    fs::write(to.join("index.json"), text + "\n").map_err(|e| format!("{}: {e}", to.display()))?;
    Ok(summary)
}

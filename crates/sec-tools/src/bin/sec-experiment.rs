//! The experiment runner: the paper's experiments (or any configuration) x seeds on all cores,
//! resumable and shardable, a report of the paper's measures with plots, and the trace command.
//!
//!   sec-experiment run EXPERIMENT [--seeds 20|1..20|1,5,9] [--episodes 5000] [--jobs N]
//!                      [--shard i/N] [--out results/experiments] [--only GROUP/MODEL,...]
//!                      [--checkpoint-every 50]
//!   sec-experiment run --config FILE.json --name GROUP/MODEL [same options]
//!   sec-experiment report EXPERIMENT [--out results/experiments] [--to OUT/EXPERIMENT]
//!                         [--quote REPRODUCTION.md]
//!   sec-experiment orderings [--out results/experiments] [--trained results/experiments-trained]
//!                            [--authors results/authors] [--to results] [--quote REPRODUCTION.md]
//!   sec-experiment matching [--out results/experiments] [--frames 2000] [--seeds 3]
//!                           [--quote REPRODUCTION.md]
//!   sec-experiment frame-match [--frames tests/reference-frames] [--to results] [--near-quoted]
//!                              [--quote docs/ARENAS.md]
//!   sec-experiment aliasing [--frames 2000] [--seeds 3] [--to results] [--quote docs/ARENAS.md]
//!   sec-experiment arenas [assets/arenas/competition] [--steps 2500] [--to results] [--quote docs/ARENAS.md]
//!                         [--index assets/arenas/olympics.json]
//!   sec-experiment reference [--out results/experiments] [--to assets/reference]
//!   sec-experiment versus-authors [--out results/experiments] [--authors results/authors] [--to results]
//!                                 [--quote REPRODUCTION.md]
//!   sec-experiment surfaces [--out results/experiments] [--authors results/authors] [--to results]
//!                           [--quote REPRODUCTION.md]
//!   sec-experiment verify [--out results/experiments]
//!   sec-experiment merge SRC... --into DIR
//!   sec-experiment warm-up --from OUT/EXPERIMENT/GROUP/MODEL --seed S --episodes N --to FILE.secmem
//!   sec-experiment list
//!   sec-experiment agents
//!   sec-experiment record --config FILE.json --seed S --episodes N --events OUT.jsonl
//!   sec-experiment trace --config FILE.json --seed S --events IN.jsonl [--trace OUT.jsonl]
//!
//! Runs go to `OUT/EXPERIMENT/<group>/<model>/seed-S.jsonl.gz`, one JSON line per episode; a SEC,
//! DQN or ERLAM run in progress keeps a checkpoint `seed-S.jsonl.ckpt` beside its log and resumes from it.

use sec_playground::agent::SecConfig;
use sec_playground::experiment::presets::{self, Condition, EXPERIMENTS};
use sec_playground::experiment::trace::trace;
use sec_playground::experiment::{AgentKind, Run, RunConfig};
use sec_playground::seed::MAX_SEED;
use sec_tools::runner;
use std::collections::HashMap;
use std::io::{BufReader, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

const USAGE: &str = "usage:
  sec-experiment run EXPERIMENT [--seeds N|A..B|A,B,C] [--episodes N] [--jobs N] [--shard i/N] [--out DIR]
                     [--only GROUP/MODEL,GROUP/,...] [--checkpoint-every N] [--reuse yes|no]
                     [--legacy-checkpoint]
  sec-experiment run --config FILE.json|--arena FILE.yaml [--set JSON] --name GROUP/MODEL [the same options]
  sec-experiment parameters [--agent KEY] [--json]   (the settings the page's controls are built
                         from: key, symbol, range, live or restart, group, help; --agent one
                         agent's, a key of `agents`)
  sec-experiment config [--config FILE.json] [--arena FILE.yaml] [--set JSON]   (the whole
                         configuration they make, on standard output; each field --set changed, and
                         whether it acts live, on standard error. --set '{\"agent\": {\"memory\":
                         {\"tau\": 0.5}}}' changes only the fields it names; --arena plays an
                         Animal-AI arena file, named by its stem, with the untrained encoder and no
                         gate; record, trace and run --config take both too)
  sec-experiment report EXPERIMENT [--out DIR] [--to DIR] [--quote PAGE.md] [--partial]
  sec-experiment orderings [--out DIR] [--trained DIR] [--authors DIR] [--to DIR] [--quote PAGE.md] [--partial]
  sec-experiment matching [--out DIR] [--frames N] [--seeds N|A..B|A,B,C] [--quote PAGE.md]
  sec-experiment frame-match [--frames DIR] [--to DIR] [--near-quoted] [--quote PAGE.md]
                             (our flat and textured frames against the real v1 frames, each at the
                              pose that fits it best; --near-quoted searches only next to the poses
                              DIR/frame-match.md found)
  sec-experiment aliasing [--frames N] [--seeds N|A..B|A,B,C] [--to DIR] [--quote PAGE.md]
                          (how often views repeat with each surface: the identical-view share,
                           matching breadth and distance, distinct frames per decision)
  sec-experiment arenas [DIR] [--steps N] [--to DIR] [--quote PAGE.md] [--index FILE.json]
                        (every Animal-AI arena file of DIR, default the Olympics corpus
                         assets/arenas/competition: which load, run N random env steps (2500)
                         cleanly and behave as in v1, and what the refused ones need, per category;
                         DIR/arenas.md and arenas.csv under --to, default results; --index the
                         arena page's menu, assets/arenas/olympics.json)
  sec-experiment reference [--out DIR] [--to DIR] [--partial]   (the page's reference curves)
  sec-experiment versus-authors [--out DIR] [--authors DIR] [--to DIR] [--quote PAGE.md]
                                (our runs against the authors' per-run results, results/authors/)
  sec-experiment surfaces [--out DIR] [--authors DIR] [--to DIR] [--quote PAGE.md]
                          (the textured double T-maze against the flat one and the authors': the
                           tests, predictions and default rule of results/PROTOCOL.md, 2026-12-06)
  sec-experiment verify [--out DIR]   (every shorter run is the head of the longer runs of its
                                       configuration and seed)
  sec-experiment merge SRC... --into DIR   (result folders of several machines into one, checked
                                            first; reports the seeds still missing)
  sec-experiment warm-up --from OUT/EXPERIMENT/GROUP/MODEL --seed S --episodes N --to FILE.secmem
                         (the memory seed S of those runs had after N episodes, replayed and checked
                          against its log, for the page's Skip the warm-up; recorded in index.json
                          beside FILE)
  sec-experiment list
  sec-experiment agents   (the agent table: key, RunConfig kind and section, what each can do)
  sec-experiment record --config FILE.json --seed S --episodes N --events OUT.jsonl
  sec-experiment trace --config FILE.json --seed S --events IN.jsonl [--trace OUT.jsonl]
defaults: --seeds 1..20, --episodes 5000, --jobs all cores, --shard 1/1 (in a Slurm array job:
  task SLURM_ARRAY_TASK_ID of SLURM_ARRAY_TASK_COUNT), --out results/experiments,
  --checkpoint-every 50 (episodes; 0: never; SEC, DQN and ERLAM runs resume from it mid-run, if
  its log holds the lines it continues; --legacy-checkpoint resumes from one of an earlier format,
  which otherwise starts the run again),
  --reuse yes (a run whose configuration, seed and episodes equal a finished run's under --out is
  copied from it, not played again: runs are deterministic; no plays every run),
  --to OUT/EXPERIMENT for report; --quote rewrites the page's quotes of the tables made, each between
  '<!-- KEY: COMMAND -->' and '<!-- /KEY -->' (KEY: orderings, EXPERIMENT/GROUP, perception/matching,
  versus-authors, surfaces)";

fn main() -> ExitCode {
    // A reader that stops early (`| head`) ends the process as it ends any Unix tool, instead of
    // a panic in the middle of a print (Rust ignores SIGPIPE by default).
    #[cfg(unix)]
    // SAFETY: restoring the default disposition of one signal before any thread starts.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    // DQN's and ERLAM's sections checked, filled in and written in full from here on.
    sec_dqn::register();
    let args: Vec<String> = std::env::args().skip(1).collect();
    match dispatch(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("sec-experiment: {e}");
            ExitCode::from(2)
        }
    }
}

/// `--key value` options after the positional arguments; every key must be one of `allowed`.
/// Options that take no value.
const SWITCHES: [&str; 4] = ["partial", "near-quoted", "legacy-checkpoint", "json"];

/// Refuses (unless `partial`) to report on experiment folders with gaps (`runner::gaps`: planned
/// runs missing or short, runs of another configuration); with `partial` it says what is missing
/// and goes on.
fn check_whole(dirs: &[PathBuf], partial: bool) -> Result<(), String> {
    let mut gaps = Vec::new();
    for dir in dirs {
        let name = dir.file_name().map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        gaps.extend(runner::gaps(dir)?.into_iter().map(|g| format!("{name}/{g}")));
    }
    if gaps.is_empty() {
        return Ok(());
    }
    let shown: Vec<&str> = gaps.iter().take(5).map(String::as_str).collect();
    let more =
        if gaps.len() > shown.len() { format!("; and {} more", gaps.len() - shown.len()) } else { String::new() };
    if partial {
        eprintln!("partial: {} gap(s): {}{more}", gaps.len(), shown.join("; "));
        return Ok(());
    }
    Err(format!(
        "the runs are incomplete or inconsistent ({} gap(s): {}{more}); finish them, or pass --partial to report on what is there",
        gaps.len(),
        shown.join("; ")
    ))
}

fn options<'a>(args: &'a [String], allowed: &[&str]) -> Result<(Vec<&'a str>, HashMap<&'a str, &'a str>), String> {
    let (mut pos, mut opts) = (Vec::new(), HashMap::new());
    let mut i = 0;
    while i < args.len() {
        let a = args[i].as_str();
        if let Some(key) = a.strip_prefix("--") {
            if !allowed.contains(&key) {
                return Err(format!("unknown option --{key} (allowed: --{})", allowed.join(", --")));
            }
            if SWITCHES.contains(&key) {
                opts.insert(key, "yes");
                i += 1;
                continue;
            }
            let v = args.get(i + 1).ok_or(format!("--{key} needs a value"))?;
            opts.insert(key, v.as_str());
            i += 2;
        } else {
            pos.push(a);
            i += 1;
        }
    }
    Ok((pos, opts))
}

fn number<T: std::str::FromStr + PartialOrd + std::fmt::Display>(
    key: &str,
    v: &str,
    lo: T,
    hi: T,
) -> Result<T, String> {
    match v.parse::<T>() {
        Ok(n) if n >= lo && n <= hi => Ok(n),
        _ => Err(format!("--{key}: '{v}' is not a whole number in {lo}..={hi}")),
    }
}

/// The configuration of `--config FILE` (the defaults without one, where `optional`), playing
/// the arena file of `--arena FILE.yaml` (`RunConfig::with_arena`, named by the file's stem), with
/// the fields of `--set JSON` changed (`RunConfig::patched`: the others keep the file's values).
fn read_config(o: &HashMap<&str, &str>, command: &str, optional: bool) -> Result<RunConfig, String> {
    let cfg = match o.get("config") {
        Some(path) => {
            let text = sec_playground::util::read_text_file(Path::new(path), "--config")?;
            // The field is named as well as the line and column (`agent.memory.tau: invalid type ...`).
            RunConfig::from_json(&text).map_err(|e| format!("--config {path}: {e}"))?
        }
        None if optional => RunConfig::default(),
        None => return Err(format!("{command} needs --config")),
    };
    let cfg = match o.get("arena") {
        Some(path) => {
            let yaml = sec_playground::util::read_text_file(Path::new(path), "--arena")?;
            let name = Path::new(path).file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
            cfg.with_arena(&name, &yaml).map_err(|e| format!("--arena {path}: {e}"))?
        }
        None => cfg,
    };
    let cfg = match o.get("set") {
        Some(patch) => cfg.patched(patch).map_err(|e| format!("--set: {e}"))?,
        None => cfg,
    };
    // Building a run checks what only a run can (the task's model; DQN's settings).
    Run::with_agents(cfg.clone(), 0, Some(sec_dqn::factory)).map_err(|e| format!("--config: {e}"))?;
    Ok(cfg)
}

/// `parameters`: the settings table the page builds its controls from (for one agent with
/// `--agent`), one setting a line, or as JSON with `--json`.
fn parameters_cmd(args: &[String]) -> Result<(), String> {
    let (pos, o) = options(args, &["agent", "json"])?;
    if let Some(p) = pos.first() {
        return Err(format!("parameters takes no argument '{p}'\n{USAGE}"));
    }
    let params =
        sec_playground::experiment::settings::params_for(o.get("agent").copied()).map_err(|e| format!("--{e}"))?;
    if o.contains_key("json") {
        println!("{}", serde_json::to_string_pretty(&params).expect("the table serialises"));
        return Ok(());
    }
    use sec_playground::experiment::settings::Kind;
    for p in &params {
        let range = match &p.kind {
            Kind::Number { min, max, min_open, auto, .. } => {
                format!("{}{min}, {max}]{}", if *min_open { "(" } else { "[" }, if *auto { " or auto" } else { "" })
            }
            Kind::Integer { min, max } => format!("{min}..={max}"),
            Kind::Choice { options } => options.join(" | "),
            Kind::Switch => "0 | 1".into(),
        };
        let live = if p.live { "live" } else { "restart" };
        println!("{:<16} {:<10} {:<32} {:<8} {:<10} {}", p.key, p.symbol, range, live, p.group, p.help);
    }
    Ok(())
}

/// `config`: the whole configuration `--config` and `--set` make, as JSON on standard output,
/// and each field `--set` changed on standard error.
fn config_cmd(args: &[String]) -> Result<(), String> {
    let (pos, o) = options(args, &["config", "arena", "set"])?;
    if let Some(p) = pos.first() {
        return Err(format!("config takes no argument '{p}'\n{USAGE}"));
    }
    let base: HashMap<&str, &str> = o.iter().filter(|(k, _)| **k != "set").map(|(k, v)| (*k, *v)).collect();
    let before = read_config(&base, "config", true)?;
    let after = read_config(&o, "config", true)?;
    for c in before.changes(&after) {
        eprintln!("{}: {} -> {} ({})", c.field, c.from, c.to, if c.live { "live" } else { "needs a restart" });
    }
    println!("{}", serde_json::to_string_pretty(&after).expect("configurations serialise"));
    Ok(())
}

/// The core's agent table as text, one agent per line.
fn agent_table() -> String {
    let mut out = String::from("key\tkind\tsection\treads\tcan\tlabel\n");
    for a in sec_playground::agent::AGENTS {
        let kind = serde_json::to_value(a.kind).expect("kinds serialise");
        let reads = serde_json::to_value(a.reads).expect("reads serialise");
        let can: Vec<&str> = [
            (a.has_memory, "memory"),
            (a.has_gate, "gate"),
            (a.can_be_driven, "driven"),
            (a.native_only, "native-only"),
        ]
        .iter()
        .filter(|(on, _)| *on)
        .map(|(_, name)| *name)
        .collect();
        let can = if can.is_empty() { "-".to_string() } else { can.join(",") };
        out += &format!(
            "{}\t{}\t{}\t{}\t{can}\t{}\n",
            a.key,
            kind.as_str().unwrap_or_default(),
            a.section.map_or("-", |s| s.key),
            reads.as_str().unwrap_or_default(),
            a.label
        );
    }
    out
}

fn dispatch(args: &[String]) -> Result<(), String> {
    let Some(cmd) = args.first() else { return Err(USAGE.into()) };
    let rest = &args[1..];
    match cmd.as_str() {
        "run" => run(rest),
        "report" => report(rest),
        "orderings" => {
            let (pos, o) = options(rest, &["out", "trained", "authors", "to", "quote", "partial"])?;
            if !pos.is_empty() {
                return Err(format!("orderings takes no positional argument\n{USAGE}"));
            }
            let dir = |k: &str, d: &str| PathBuf::from(o.get(k).copied().unwrap_or(d));
            check_whole(&runner::experiment_dirs(&dir("out", "results/experiments")), o.contains_key("partial"))?;
            let md = sec_tools::orderings::orderings(
                &dir("out", "results/experiments"),
                &dir("trained", "results/experiments-trained"),
                &dir("authors", "results/authors"),
                &dir("to", "results"),
            )?;
            if let Some(page) = o.get("quote") {
                sec_tools::quote::quote_required(Path::new(page), "orderings", &md)?;
            }
            print!("{md}");
            Ok(())
        }
        "agents" => {
            if !rest.is_empty() {
                return Err(format!("agents takes no argument\n{USAGE}"));
            }
            print!("{}", agent_table());
            Ok(())
        }
        "list" => {
            for (name, what) in EXPERIMENTS {
                println!("{name}: {what}");
                for c in presets::experiment(name).map_err(|e| e.to_string())? {
                    println!("  {}", c.name);
                }
            }
            Ok(())
        }
        "matching" => {
            let (_, o) = options(rest, &["out", "frames", "seeds", "quote"])?;
            let frames = number("frames", o.get("frames").copied().unwrap_or("2000"), 100usize, 20_000)?;
            let seeds = runner::parse_seeds(o.get("seeds").copied().unwrap_or("3"))?;
            let out = PathBuf::from(o.get("out").copied().unwrap_or("results/experiments"));
            let (md, table) = sec_tools::matching::report(&out.join("perception"), frames, &seeds)?;
            if let Some(page) = o.get("quote") {
                sec_tools::quote::quote_into(Path::new(page), "perception/matching", &table)?;
            }
            print!("{md}");
            Ok(())
        }
        "frame-match" => {
            let (pos, o) = options(rest, &["frames", "to", "quote", "near-quoted"])?;
            if let Some(p) = pos.first() {
                return Err(format!("frame-match takes no argument '{p}'\n{USAGE}"));
            }
            let frames = PathBuf::from(o.get("frames").copied().unwrap_or("tests/reference-frames"));
            let to = PathBuf::from(o.get("to").copied().unwrap_or("results"));
            let report = to.join("frame-match.md");
            let around = if o.contains_key("near-quoted") {
                let text = std::fs::read_to_string(&report).map_err(|e| format!("{}: {e}", report.display()))?;
                sec_tools::frame_match::poses_of(&text)
            } else {
                Vec::new()
            };
            let matches = sec_tools::frame_match::compare(&frames, &around)?;
            let table = sec_tools::frame_match::table(&matches);
            let md = format!("{}\n{table}", sec_tools::frame_match::PREAMBLE);
            std::fs::create_dir_all(&to).map_err(|e| format!("{}: {e}", to.display()))?;
            std::fs::write(&report, &md).map_err(|e| format!("{}: {e}", report.display()))?;
            let rows = to.join("frame-match-rows.csv");
            std::fs::write(&rows, sec_tools::frame_match::rows_csv(&matches))
                .map_err(|e| format!("{}: {e}", rows.display()))?;
            if let Some(page) = o.get("quote") {
                sec_tools::quote::quote_required(Path::new(page), "frame-match", &table)?;
            }
            print!("{md}");
            Ok(())
        }
        "arenas" => {
            let (pos, o) = options(rest, &["steps", "to", "quote", "index"])?;
            if pos.len() > 1 {
                return Err(format!("arenas takes one folder, not {}\n{USAGE}", pos.len()));
            }
            let dir = PathBuf::from(pos.first().copied().unwrap_or(sec_tools::arenas::CORPUS));
            let steps = number("steps", o.get("steps").copied().unwrap_or("2500"), 0u64, 1_000_000)?;
            let results = sec_tools::arenas::survey_dir(&dir, steps)?;
            let table = sec_tools::arenas::table(&results, steps);
            let to = PathBuf::from(o.get("to").copied().unwrap_or("results"));
            std::fs::create_dir_all(&to).map_err(|e| format!("{}: {e}", to.display()))?;
            let md = format!(
                "# The Animal-AI Olympics arenas, loaded and run\n\n`sec-experiment arenas {}`\n\n{table}",
                dir.display()
            );
            std::fs::write(to.join("arenas.md"), &md).map_err(|e| format!("{}: {e}", to.display()))?;
            std::fs::write(to.join("arenas.csv"), sec_tools::arenas::rows_csv(&results))
                .map_err(|e| format!("{}: {e}", to.display()))?;
            if let Some(page) = o.get("quote") {
                sec_tools::quote::quote_required(Path::new(page), "arenas", &table)?;
            }
            if let Some(index) = o.get("index") {
                std::fs::write(index, sec_tools::arenas::index_json(&results)).map_err(|e| format!("{index}: {e}"))?;
            }
            print!("{md}");
            Ok(())
        }
        "aliasing" => {
            let (pos, o) = options(rest, &["frames", "seeds", "to", "quote"])?;
            if let Some(p) = pos.first() {
                return Err(format!("aliasing takes no argument '{p}'\n{USAGE}"));
            }
            let frames = number("frames", o.get("frames").copied().unwrap_or("2000"), 100usize, 20_000)?;
            let seeds = runner::parse_seeds(o.get("seeds").copied().unwrap_or("3"))?;
            let rows = sec_tools::matching::aliasing(frames, &seeds)?;
            let table = sec_tools::matching::aliasing_table(&rows, frames, &seeds);
            if let Some(page) = o.get("quote") {
                sec_tools::quote::quote_required(Path::new(page), "aliasing", &table)?;
            }
            let md = format!("# How often views repeat, by surface\n\n{table}");
            if let Some(to) = o.get("to") {
                let to = PathBuf::from(to);
                std::fs::create_dir_all(&to).map_err(|e| format!("{}: {e}", to.display()))?;
                std::fs::write(to.join("aliasing.md"), &md).map_err(|e| format!("{}: {e}", to.display()))?;
            }
            print!("{md}");
            Ok(())
        }
        "reference" => {
            let (pos, o) = options(rest, &["out", "to", "partial"])?;
            if !pos.is_empty() {
                return Err(format!("reference takes no positional argument\n{USAGE}"));
            }
            let dir = |k: &str, d: &str| PathBuf::from(o.get(k).copied().unwrap_or(d));
            check_whole(&runner::experiment_dirs(&dir("out", "results/experiments")), o.contains_key("partial"))?;
            println!(
                "{}",
                sec_tools::reference::references(&dir("out", "results/experiments"), &dir("to", "assets/reference"))?
            );
            Ok(())
        }
        "versus-authors" => {
            let (pos, o) = options(rest, &["out", "authors", "to", "quote"])?;
            if !pos.is_empty() {
                return Err(format!("versus-authors takes no positional argument\n{USAGE}"));
            }
            let dir = |k: &str, d: &str| PathBuf::from(o.get(k).copied().unwrap_or(d));
            let md = sec_tools::authors::versus_authors(
                &dir("out", "results/experiments"),
                &dir("authors", "results/authors"),
                &dir("to", "results"),
            )?;
            if let Some(page) = o.get("quote") {
                sec_tools::quote::quote_required(Path::new(page), "versus-authors", &md)?;
            }
            print!("{md}");
            Ok(())
        }
        "surfaces" => {
            let (pos, o) = options(rest, &["out", "authors", "to", "quote"])?;
            if !pos.is_empty() {
                return Err(format!("surfaces takes no positional argument\n{USAGE}"));
            }
            let dir = |k: &str, d: &str| PathBuf::from(o.get(k).copied().unwrap_or(d));
            let md = sec_tools::surfaces::surfaces(
                &dir("out", "results/experiments"),
                &dir("authors", "results/authors"),
                &dir("to", "results"),
            )?;
            if let Some(page) = o.get("quote") {
                sec_tools::quote::quote_required(Path::new(page), "surfaces", &md)?;
            }
            print!("{md}");
            Ok(())
        }
        "verify" => {
            let (pos, o) = options(rest, &["out"])?;
            if !pos.is_empty() {
                return Err(format!("verify takes no positional argument\n{USAGE}"));
            }
            let out = PathBuf::from(o.get("out").copied().unwrap_or("results/experiments"));
            let v = runner::verify(&out)?;
            for f in &v.failures {
                eprintln!("{f}");
            }
            if !v.failures.is_empty() {
                return Err(format!("{} of {} pairs of runs differ", v.failures.len(), v.pairs));
            }
            println!(
                "{} runs under {}: every one of the {} pairs of one configuration and seed agrees (the shorter is the longer's head)",
                v.runs,
                out.display(),
                v.pairs
            );
            Ok(())
        }
        "merge" => {
            let (pos, o) = options(rest, &["into"])?;
            let into = o.get("into").ok_or("merge needs --into DIR")?;
            if pos.is_empty() {
                return Err(format!("merge needs at least one SRC folder\n{USAGE}"));
            }
            let sources: Vec<PathBuf> = pos.iter().map(PathBuf::from).collect();
            for s in &sources {
                if !s.is_dir() {
                    return Err(format!("merge: {} is not a folder", s.display()));
                }
            }
            let m = sec_tools::merge::merge(&sources, Path::new(into))?;
            println!("{into}: {} runs copied, {} already there", m.copied, m.kept);
            if m.missing.is_empty() {
                println!("complete: every seed of every condition its experiments list, at full length");
            } else {
                println!("{} runs missing or short:", m.missing.len());
                for line in &m.missing {
                    println!("  {line}");
                }
            }
            Ok(())
        }
        "warm-up" => {
            let (pos, o) = options(rest, &["from", "seed", "episodes", "to"])?;
            if !pos.is_empty() {
                return Err(format!("warm-up takes no positional argument\n{USAGE}"));
            }
            let from = o.get("from").ok_or("warm-up needs --from OUT/EXPERIMENT/GROUP/MODEL")?;
            let seed = number("seed", o.get("seed").ok_or("warm-up needs --seed")?, 0u64, MAX_SEED)?;
            let episodes = number("episodes", o.get("episodes").ok_or("warm-up needs --episodes")?, 1usize, 1_000_000)?;
            let to = o.get("to").ok_or("warm-up needs --to FILE.secmem")?;
            let e = sec_tools::warmup::write(Path::new(from), seed, episodes, Path::new(to))?;
            println!(
                "{to}: {} after {} episodes of seed {}: {} sequences in the LTM, 20-episode mean reward {:.3}",
                e.run, e.episodes, e.seed, e.sequences, e.mean_reward
            );
            Ok(())
        }
        "record" => record(rest),
        "config" => config_cmd(rest),
        "parameters" => parameters_cmd(rest),
        "trace" => trace_cmd(rest),
        "-h" | "--help" | "help" => {
            println!("{USAGE}");
            Ok(())
        }
        other => Err(format!("unknown command '{other}'\n{USAGE}")),
    }
}

fn run(args: &[String]) -> Result<(), String> {
    let (pos, o) = options(
        args,
        &[
            "seeds",
            "episodes",
            "jobs",
            "shard",
            "out",
            "config",
            "name",
            "only",
            "checkpoint-every",
            "reuse",
            "legacy-checkpoint",
            "set",
            "arena",
        ],
    )?;
    let seeds = runner::parse_seeds(o.get("seeds").copied().unwrap_or("1..20"))?;
    let episodes = number("episodes", o.get("episodes").copied().unwrap_or("5000"), 1usize, runner::MAX_EPISODES)?;
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let jobs = match o.get("jobs") {
        Some(v) => number("jobs", v, 1usize, 4096)?,
        None => cores,
    };
    // --shard wins; else a Slurm array task's own share; else the whole grid.
    let shard = match o.get("shard") {
        Some(s) => runner::parse_shard(s)?,
        None => runner::slurm_shard(|k| std::env::var(k).ok())?.unwrap_or((1, 1)),
    };
    let every = runner::CHECKPOINT_EVERY.to_string();
    let every =
        number("checkpoint-every", o.get("checkpoint-every").copied().unwrap_or(&every), 0usize, runner::MAX_EPISODES)?;
    let reuse = match o.get("reuse").copied().unwrap_or("yes") {
        "yes" => true,
        "no" => false,
        other => return Err(format!("--reuse: '{other}' is not yes or no")),
    };
    let out = PathBuf::from(o.get("out").copied().unwrap_or("results/experiments"));
    let custom = o.get("config").or(o.get("arena"));
    let (experiment, conditions): (String, Vec<Condition>) = match (pos.as_slice(), custom) {
        ([name], None) => (name.to_string(), presets::experiment(name).map_err(|e| e.to_string())?),
        ([], Some(_)) => {
            let name = o.get("name").ok_or("--config and --arena need --name GROUP/MODEL")?;
            if !name.contains('/') || name.split('/').any(|p| p.is_empty() || p == ".." || p == ".") {
                return Err(format!("--name: '{name}' is not GROUP/MODEL"));
            }
            (
                "custom".into(),
                vec![Condition { name: name.to_string(), config: read_config(&o, "run", true)?, paper_total: None }],
            )
        }
        _ => return Err(format!("run takes one EXPERIMENT or --config\n{USAGE}")),
    };
    let conditions = runner::select(&experiment, conditions, o.get("only").copied())?;
    let dir = out.join(&experiment);
    runner::prepare(&dir, &runner::experiment_manifest(&experiment, episodes, &seeds, &conditions))?;
    let mut jobs_list = runner::jobs(&conditions, &seeds, shard, Some(sec_dqn::factory));
    let legacy = o.contains_key("legacy-checkpoint");
    jobs_list.iter_mut().for_each(|j| j.legacy_checkpoint = legacy);
    eprintln!(
        "{experiment}: {} conditions x {} seeds, shard {}/{}: {} runs of {episodes} episodes on {jobs} threads into {}",
        conditions.len(),
        seeds.len(),
        shard.0,
        shard.1,
        jobs_list.len(),
        dir.display()
    );
    let t0 = std::time::Instant::now();
    let finished = reuse.then(|| runner::Finished::scan(&out));
    let (made, copied, skipped) = runner::run_all(&jobs_list, &dir, episodes, every, jobs, finished.as_ref())?;
    eprintln!(
        "{made} runs made, {copied} copied from identical finished runs, {skipped} already there, in {:.0} s",
        t0.elapsed().as_secs_f64()
    );
    Ok(())
}

fn report(args: &[String]) -> Result<(), String> {
    let (pos, o) = options(args, &["out", "to", "quote", "partial"])?;
    let [name] = pos.as_slice() else { return Err(format!("report takes one EXPERIMENT\n{USAGE}")) };
    let out = PathBuf::from(o.get("out").copied().unwrap_or("results/experiments"));
    if out.join(name).join("experiment.json").is_file() {
        check_whole(&[out.join(name)], o.contains_key("partial"))?;
    }
    let to = o.get("to").map_or_else(|| out.join(name), PathBuf::from);
    let what = EXPERIMENTS.iter().find(|(n, _)| n == name).map_or("custom runs", |(_, w)| w);
    let report = sec_tools::report::report(&out.join(name), &to, what)?;
    if let Some(page) = o.get("quote") {
        for (key, table) in &report.tables {
            sec_tools::quote::quote_into(Path::new(page), key, table)?;
        }
    }
    print!("{}", report.md);
    Ok(())
}

fn record(args: &[String]) -> Result<(), String> {
    let (_, o) = options(args, &["config", "arena", "set", "seed", "episodes", "events"])?;
    let cfg = read_config(&o, "record", false)?;
    if cfg.kind != AgentKind::Sec {
        return Err("--config: record and trace are for SEC (kind \"sec\")".into());
    }
    let seed = number("seed", o.get("seed").ok_or("record needs --seed")?, 0u64, MAX_SEED)?;
    let episodes = number("episodes", o.get("episodes").copied().unwrap_or("10"), 1usize, 100_000)?;
    let path = o.get("events").ok_or("record needs --events")?;
    let mut run = Run::new(cfg, seed).map_err(|e| e.to_string())?;
    run.record_events();
    let file = std::fs::File::create(path).map_err(|e| format!("--events {path}: {e}"))?;
    let mut w = BufWriter::new(file);
    for _ in 0..episodes {
        let m = run.episode();
        for e in run.take_events() {
            writeln!(w, "{}", serde_json::to_string(&e).expect("events serialise"))
                .map_err(|e| format!("--events {path}: {e}"))?;
        }
        eprintln!("{}", m.to_json());
    }
    w.flush().map_err(|e| format!("--events {path}: {e}"))
}

fn trace_cmd(args: &[String]) -> Result<(), String> {
    let (_, o) = options(args, &["config", "arena", "set", "seed", "events", "trace"])?;
    let cfg = read_config(&o, "trace", false)?;
    let seed = number("seed", o.get("seed").ok_or("trace needs --seed")?, 0u64, MAX_SEED)?;
    let input = o.get("events").ok_or("trace needs --events")?;
    let reader = BufReader::new(sec_playground::util::open_regular_file(Path::new(input), "--events")?);
    let n = match o.get("trace") {
        Some(path) => {
            let file = std::fs::File::create(Path::new(path)).map_err(|e| format!("--trace {path}: {e}"))?;
            trace(cfg.section::<SecConfig>(), Some(cfg.perception), seed, reader, BufWriter::new(file))
        }
        None => trace(
            cfg.section::<SecConfig>(),
            Some(cfg.perception),
            seed,
            reader,
            BufWriter::new(std::io::stdout().lock()),
        ),
    }
    .map_err(|e| format!("--events {input}: {e}"))?;
    eprintln!("{n} decisions traced");
    Ok(())
}

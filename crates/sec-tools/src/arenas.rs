//! The arenas report (`sec-experiment arenas DIR`): every Animal-AI arena file of a folder (the
//! Olympics corpus, `assets/arenas/competition/`) loaded, run with random actions, and counted per
//! category: which load, which behave as in v1 (loaded, no panic or non-finite number in the run,
//! and no feature the simulator ignores), and what the refused ones need (`arena::survey`).

use sec_playground::arena::survey::{features, Feature};
use sec_playground::arena::{yaml, Action, Task};
use sec_playground::env::{Env, EnvConfig};
use std::collections::{BTreeMap, BTreeSet};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

/// The committed corpus: the 900 arenas of the Animal-AI Olympics (its PROVENANCE.md).
pub const CORPUS: &str = "assets/arenas/competition";

/// The Olympics' ten categories, by the first two digits of a file's name.
pub const CATEGORIES: [&str; 10] = [
    "food",
    "preferences",
    "static obstacles",
    "avoidance",
    "spatial reasoning",
    "generalisation",
    "internal models",
    "object permanence",
    "advanced preferences",
    "causal reasoning",
];

/// What became of one file.
#[derive(Clone, Debug)]
pub struct FileResult {
    /// The file's name.
    pub name: String,
    /// Its category's number (1-10), from the name; 0 when the name has none.
    pub category: usize,
    /// The features it uses that the simulator lacks or ignores.
    pub needs: BTreeSet<Feature>,
    /// Why it was refused (by the loader or the env), if it was.
    pub refused: Option<String>,
    /// What the loader changed to read it as v1 does (a size clamped).
    pub warnings: Vec<String>,
    /// What went wrong in its random run (a panic, a non-finite number), if anything.
    pub run_error: Option<String>,
    /// Env steps its random run took.
    pub steps: u64,
}

impl FileResult {
    /// Loaded: the loader and the env took it.
    pub fn loaded(&self) -> bool {
        self.refused.is_none()
    }

    /// Behaves as in v1: loaded and its run clean.
    pub fn behaves_as_v1(&self) -> bool {
        self.loaded() && self.run_error.is_none()
    }
}

/// Loads and runs every `.yml`/`.yaml` file of `dir`, in name order: `steps` env steps of random
/// actions (drawn from a ChaCha stream of the file's index), reset at each episode's end.
pub fn survey_dir(dir: &Path, steps: u64) -> Result<Vec<FileResult>, String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.file_name().to_string_lossy().into_owned()))
        .filter(|n| n.ends_with(".yml") || n.ends_with(".yaml"))
        .collect();
    names.sort();
    if names.is_empty() {
        return Err(format!("{}: no .yml or .yaml file", dir.display()));
    }
    names
        .iter()
        .enumerate()
        .map(|(i, name)| {
            let src = std::fs::read_to_string(dir.join(name)).map_err(|e| format!("{name}: {e}"))?;
            Ok(survey_file(name, &src, steps, i as u64))
        })
        .collect()
}

/// One file: its features, whether it loads, and its random run.
pub fn survey_file(name: &str, src: &str, steps: u64, seed: u64) -> FileResult {
    let category = name.get(..2).and_then(|c| c.parse::<usize>().ok()).filter(|c| (1..=10).contains(c)).unwrap_or(0);
    let mut out = FileResult {
        name: name.to_string(),
        category,
        needs: features(src).unwrap_or_default(),
        refused: None,
        warnings: Vec::new(),
        run_error: None,
        steps: 0,
    };
    let env = yaml::load_task(name, src).map_err(|e| e.to_string()).and_then(|task: Task| {
        out.warnings = task.warnings.clone();
        Env::new(EnvConfig::new(task), seed).map_err(|e| e.to_string())
    });
    let mut env = match env {
        Ok(env) => env,
        Err(e) => {
            out.refused = Some(e);
            return out;
        }
    };
    let run = catch_unwind(AssertUnwindSafe(|| random_run(&mut env, steps, seed)));
    match run {
        Ok(Ok(n)) => out.steps = n,
        Ok(Err((n, e))) => {
            out.steps = n;
            out.run_error = Some(e);
        }
        Err(p) => {
            let message =
                p.downcast_ref::<String>().cloned().or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()));
            out.run_error = Some(format!("panic: {}", message.unwrap_or_default()));
        }
    }
    out
}

/// `steps` env steps of random actions; an error (with the steps taken) at the first
/// non-finite reward, position, velocity or heading. Every 64th step renders the camera.
fn random_run(env: &mut Env, steps: u64, seed: u64) -> Result<u64, (u64, String)> {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    for n in 0..steps {
        if env.is_over() {
            env.reset(None);
        }
        let action = Action::new(rng.gen_range(0..9)).expect("0..9 are actions");
        let out = env.advance(action, 1).map_err(|e| (n, e.to_string()))?;
        let a = &env.world().agent;
        let finite = out.reward.is_finite()
            && a.pos.is_finite()
            && a.vel.is_finite()
            && [a.y, a.vy, a.heading].iter().all(|v| v.is_finite());
        if !finite {
            return Err((n, format!("a non-finite number at step {n}: reward {}, agent {a:?}", out.reward)));
        }
        if n % 64 == 0 {
            env.observation();
        }
    }
    Ok(steps)
}

/// The report's table: per category, the files, how many load and behave as in v1, and among
/// the refused files how many need each feature (and how many need it alone); a total row.
pub fn table(results: &[FileResult], steps: u64) -> String {
    let refused_features: BTreeSet<Feature> =
        results.iter().filter(|r| !r.loaded()).flat_map(|r| r.needs.iter().cloned()).collect();
    let mut md = String::new();
    md.push_str(&format!(
        "{} files; each loaded one run for {steps} env steps of random actions. *Loads*: the loader and \
         the env take it; *as v1*: loaded and its run free of panics and non-finite numbers; *clamped*: loaded with a size clamped into its \
         object's range, as v1 does; *left out*: loaded with an object left out, its spot taken by what is placed \
         before it, as v1 does. Refused files by what they need \
         (*alone*: the only feature they need); *other*: refused files needing none of them \
         (refused for something else: its error in the CSV).\n\n",
        results.len()
    ));
    md.push_str("| category | files | loads | as v1 | clamped | left out | refused |");
    for f in &refused_features {
        md.push_str(&format!(" {} (alone) |", f.name()));
    }
    md.push_str(" other |\n|---|---:|---:|---:|---:|---:|---:|");
    for _ in &refused_features {
        md.push_str("---:|");
    }
    md.push_str("---:|\n");
    let mut groups: BTreeMap<usize, Vec<&FileResult>> = BTreeMap::new();
    for r in results {
        groups.entry(r.category).or_default().push(r);
    }
    let all: Vec<&FileResult> = results.iter().collect();
    let rows =
        groups.iter().map(|(c, rs)| (category_name(*c), rs.as_slice())).chain([("all".to_string(), all.as_slice())]);
    for (name, rs) in rows {
        let refused: Vec<&&FileResult> = rs.iter().filter(|r| !r.loaded()).collect();
        let warned =
            |what: &str| rs.iter().filter(|r| r.loaded() && r.warnings.iter().any(|w| w.contains(what))).count();
        md.push_str(&format!(
            "| {name} | {} | {} | {} | {} | {} | {} |",
            rs.len(),
            rs.iter().filter(|r| r.loaded()).count(),
            rs.iter().filter(|r| r.behaves_as_v1()).count(),
            warned("clamped to"),
            warned("left out"),
            refused.len()
        ));
        for f in &refused_features {
            let with = refused.iter().filter(|r| r.needs.contains(f)).count();
            let alone = refused.iter().filter(|r| r.needs.len() == 1 && r.needs.contains(f)).count();
            md.push_str(&format!(" {with} ({alone}) |"));
        }
        let other = refused.iter().filter(|r| r.needs.is_empty()).count();
        md.push_str(&format!(" {other} |\n"));
    }
    md
}

fn category_name(c: usize) -> String {
    match c {
        1..=10 => format!("{c:02} {}", CATEGORIES[c - 1]),
        _ => "other".into(),
    }
}

/// One line per file: name, category, loads, as v1, steps run, needs, the refusal or run error.
pub fn rows_csv(results: &[FileResult]) -> String {
    let mut csv = String::from("file,category,loads,as_v1,steps,needs,error,warnings\n");
    let quote = |s: &str| format!("\"{}\"", s.replace('"', "\"\""));
    for r in results {
        let needs: Vec<String> = r.needs.iter().map(Feature::name).collect();
        let error = r.refused.as_deref().or(r.run_error.as_deref()).unwrap_or("");
        csv.push_str(&format!(
            "{},{},{},{},{},{},{},{}\n",
            r.name,
            r.category,
            r.loaded(),
            r.behaves_as_v1(),
            r.steps,
            quote(&needs.join("; ")),
            quote(error),
            quote(&r.warnings.join("; "))
        ));
    }
    csv
}

/// The arena page's menu of the corpus (`assets/arenas/olympics.json`): the categories, and per
/// file its category, whether it loads and behaves as in v1, what it needs, and, for a file
/// refused while needing nothing the simulator lacks, why.
pub fn index_json(results: &[FileResult]) -> String {
    let files: Vec<serde_json::Value> = results
        .iter()
        .map(|r| {
            let mut f = serde_json::json!({
                "file": r.name,
                "category": r.category,
                "loads": r.loaded(),
                "asV1": r.behaves_as_v1(),
                "needs": r.needs.iter().map(Feature::name).collect::<Vec<_>>(),
                "warnings": r.warnings.len(),
            });
            if let Some(why) = r.refused.as_ref().filter(|_| r.needs.is_empty()) {
                // The loader's message names the file first; the menu already does.
                let why = why.rsplit_once("': ").map_or(why.as_str(), |(_, w)| w);
                f["refused"] = why.into();
            }
            f
        })
        .collect();
    let index = serde_json::json!({ "categories": CATEGORIES, "files": files });
    format!("{}\n", serde_json::to_string(&index).expect("plain JSON"))
}

//! The authors' own results and our runs held against them, run against run
//! (`sec-experiment versus-authors`).
//!
//! `results/authors/EXPERIMENT.json` holds what the authors' notebooks store in their printed
//! outputs (read by `scripts/authors-data.py`, each value with its repository, commit, notebook and
//! cell): per-run totals over 5000 episodes where the notebooks print them (experiment 1 in the
//! double T-maze, experiment 4), means elsewhere. A mean hides how many runs learned, so where there
//! are runs the report compares distributions: the share of runs that learned (results/PROTOCOL.md:
//! reward per episode above the reactive walk's 95th percentile), the quartiles, a Mann-Whitney U
//! test of the per-episode totals and Fisher's exact test of the learned counts.

use crate::report::{load, ConditionRuns};
use crate::stats::{fisher_exact, mann_whitney, mean, quantile};
use sec_playground::experiment::presets;
use std::fmt::Write as _;
use std::fs;
use std::path::Path;

/// The experiments the authors' notebooks hold numbers of, one file each.
pub const EXPERIMENTS: [&str; 4] = ["exp1", "exp2", "exp3", "exp4"];

/// Where the figures are, from the repository's root (`--to results`).
const FIGURES: &str = "results/versus-authors";

/// The share of the reactive walk's runs a learning run must be above (results/PROTOCOL.md).
pub const LEARNED_QUANTILE: f64 = 0.95;

/// One experiment's numbers from the authors' notebooks.
#[derive(Clone, Debug, serde::Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct AuthorsResults {
    /// The experiment's preset name (exp1, ...).
    pub experiment: String,
    /// The notebook the numbers were read from.
    pub source: Source,
    /// What the numbers are, in a sentence.
    pub note: String,
    /// The episodes of every run the numbers sum over.
    pub episodes: usize,
    /// Per-run totals, model by model.
    pub runs: Vec<AuthorsRuns>,
    /// The notebook's table of means, model by model.
    pub means: Vec<AuthorsMean>,
}

/// Where the numbers were read.
#[derive(Clone, Debug, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Source {
    /// `owner/name` on GitHub.
    pub repository: String,
    /// The commit read.
    pub commit: String,
    /// The notebook's path in the repository.
    pub notebook: String,
}

/// One model's per-run totals.
#[derive(Clone, Debug, serde::Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct AuthorsRuns {
    /// This project's condition (`group/model` of the experiment's preset).
    pub condition: String,
    /// The notebook's name for it.
    pub authors_model: String,
    /// The notebook cell whose output printed them.
    pub cell: usize,
    /// Each run's total reward, in the notebook's order.
    pub totals: Vec<f64>,
}

/// One model's mean total, with what the notebook's table gives beside it.
#[derive(Clone, Debug, serde::Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct AuthorsMean {
    /// This project's condition.
    pub condition: String,
    /// The notebook's name for it.
    pub authors_model: String,
    /// The notebook cell whose output printed it.
    pub cell: usize,
    /// The mean total.
    pub mean: f64,
    /// Its 95 % confidence interval, where the notebook gives one.
    #[serde(default)]
    pub ci95: Option<[f64; 2]>,
    /// The condition the p values test against.
    #[serde(default)]
    pub versus: Option<String>,
    /// The notebook's p value against `versus`.
    #[serde(default)]
    pub p: Option<f64>,
    /// The same, Bonferroni-corrected as the notebook did.
    #[serde(default)]
    pub p_bonferroni: Option<f64>,
}

/// Reads `dir/EXPERIMENT.json` for each of [`EXPERIMENTS`], refusing a file whose numbers are
/// not finite and non-negative or whose conditions its experiment's preset does not have.
pub fn load_authors(dir: &Path) -> Result<Vec<AuthorsResults>, String> {
    EXPERIMENTS
        .iter()
        .map(|e| {
            let path = dir.join(format!("{e}.json"));
            let text = fs::read_to_string(&path).map_err(|err| format!("{}: {err}", path.display()))?;
            let r: AuthorsResults = serde_json::from_str(&text).map_err(|err| format!("{}: {err}", path.display()))?;
            let bad = |what: String| Err(format!("{}: {what}", path.display()));
            if r.experiment != *e || r.episodes == 0 {
                return bad(format!("experiment '{}' with {} episodes", r.experiment, r.episodes));
            }
            let names: Vec<String> =
                presets::experiment(e).map_err(|err| err.to_string())?.into_iter().map(|c| c.name).collect();
            let conditions = r.runs.iter().map(|x| &x.condition).chain(r.means.iter().map(|m| &m.condition));
            if let Some(c) = conditions.into_iter().find(|c| !names.contains(c)) {
                return bad(format!("'{c}' is not a condition of {e}"));
            }
            let values = r.runs.iter().flat_map(|x| x.totals.iter()).chain(r.means.iter().map(|m| &m.mean));
            if let Some(v) = values.into_iter().find(|v| !v.is_finite() || **v < 0.0) {
                return bad(format!("{v} is not a finite, non-negative total"));
            }
            Ok(r)
        })
        .collect()
}

/// The bar a run must pass to count as learned: the reactive walk's 95th percentile of reward
/// per episode over its runs in the task.
#[derive(Clone, Copy, Debug)]
pub struct LearnedBar {
    /// The bar, in reward per episode.
    pub per_episode: f64,
    /// The reactive runs it was taken over.
    pub runs: usize,
    /// Their episodes each.
    pub episodes: usize,
}

impl LearnedBar {
    /// From the reactive walk's runs of `task` in `results/EXPERIMENT`, if there are any.
    pub fn of(results: &Path, experiment: &str, task: &str) -> Option<LearnedBar> {
        let (_, conds) = load(&results.join(experiment)).ok()?;
        LearnedBar::among(&conds, task)
    }

    /// From the reactive walk's runs of `task` among `conds`, if there are any.
    pub fn among(conds: &[ConditionRuns], task: &str) -> Option<LearnedBar> {
        let walk = conds.iter().find(|c| c.condition.name == format!("{task}/reactive"))?;
        let episodes = walk.runs[0].len();
        Some(LearnedBar {
            per_episode: quantile(&per_episode(walk), LEARNED_QUANTILE),
            runs: walk.runs.len(),
            episodes,
        })
    }

    /// How many of `per_episode` are above the bar.
    pub fn count(&self, per_episode: &[f64]) -> usize {
        per_episode.iter().filter(|&&v| v > self.per_episode).count()
    }
}

/// Each run's total divided by its episodes.
fn per_episode(c: &ConditionRuns) -> Vec<f64> {
    let n = c.runs[0].len() as f64;
    c.totals().into_iter().map(|t| t / n).collect()
}

/// A p value as the tables print it: `-` for none, 1.2e-5 below 0.001, else three decimals.
pub(crate) fn fmt_p(p: f64) -> String {
    if p.is_nan() {
        "-".into()
    } else if p < 0.001 {
        format!("{p:.1e}")
    } else {
        format!("{p:.3}")
    }
}

fn quartiles(x: &[f64]) -> String {
    format!("{:.3} / {:.3} / {:.3}", quantile(x, 0.25), quantile(x, 0.5), quantile(x, 0.75))
}

/// Our runs of each experiment, by condition, and the textured renderer's runs of experiment 1
/// (`textured`, whose conditions carry experiment 1's names; PROTOCOL.md, 2026-12-06).
struct Ours {
    experiments: Vec<(String, Vec<ConditionRuns>)>,
}

/// The folder of the textured renderer's runs of experiment 1.
pub const TEXTURED: &str = "textured";

impl Ours {
    fn load(results: &Path) -> Ours {
        let experiments = EXPERIMENTS
            .iter()
            .chain(&[TEXTURED])
            .map(|e| (e.to_string(), load(&results.join(e)).map(|(_, c)| c).unwrap_or_default()))
            .collect();
        Ours { experiments }
    }

    fn find(&self, experiment: &str, condition: &str) -> Option<&ConditionRuns> {
        let (_, conds) = self.experiments.iter().find(|(e, _)| e == experiment)?;
        conds.iter().find(|c| c.condition.name == condition)
    }
}

/// One of our conditions held against the authors' runs of it, as versus-authors tests it.
#[derive(Clone, Debug)]
pub struct Versus {
    /// Our runs' reward per episode.
    pub ours: Vec<f64>,
    /// Theirs.
    pub theirs: Vec<f64>,
    /// How many of ours and of theirs learned, when there is a bar.
    pub learned: Option<(usize, usize)>,
    /// The Mann-Whitney U test's p, corrected over the table's tests.
    pub p_mann_whitney: f64,
    /// Fisher's exact test's p of the learned counts, corrected likewise (NaN without a bar).
    pub p_fisher: f64,
}

/// `ours` against `theirs` as a table of `rows` rows tests them: two tests per row (a Mann-Whitney
/// and a Fisher test), Bonferroni-corrected over all of them.
pub fn versus(
    ours: &ConditionRuns,
    theirs: &AuthorsRuns,
    episodes: usize,
    bar: Option<LearnedBar>,
    rows: usize,
) -> Versus {
    let tests = 2.0 * rows as f64;
    let theirs_pe: Vec<f64> = theirs.totals.iter().map(|x| x / episodes as f64).collect();
    let ours_pe = per_episode(ours);
    let learned = bar.map(|b| (b.count(&ours_pe), b.count(&theirs_pe)));
    let (_, p) = mann_whitney(&ours_pe, &theirs_pe);
    let p_fisher = learned.map_or(f64::NAN, |(a, b)| fisher_exact(a, ours_pe.len() - a, b, theirs_pe.len() - b));
    Versus {
        p_mann_whitney: (p * tests).min(1.0),
        p_fisher: (p_fisher * tests).min(1.0),
        ours: ours_pe,
        theirs: theirs_pe,
        learned,
    }
}

/// Writes `versus-authors.md` and a figure per experiment with per-run totals
/// (`versus-authors/EXPERIMENT.svg|png`) into `to`, from our runs under `results` and the authors'
/// numbers under `authors`; returns the markdown. Experiment 1 gets a second table and figure for
/// the textured renderer's runs when there are any.
pub fn versus_authors(results: &Path, authors: &Path, to: &Path) -> Result<String, String> {
    let theirs = load_authors(authors)?;
    let ours = Ours::load(results);
    let figures = to.join("versus-authors");
    fs::create_dir_all(&figures).map_err(|e| format!("{}: {e}", figures.display()))?;
    let bar = LearnedBar::of(results, "exp1", "double-t-maze");
    let mut md = String::new();
    match bar {
        Some(b) => writeln!(
            md,
            "A run **learned** when its reward per episode is above R = {:.4}, the reactive walk's 95th \
             percentile in the double T-maze ({} runs x {} episodes; results/PROTOCOL.md). The authors' runs \
             are over {} episodes; ours over the episodes shown. p values are two-sided, Bonferroni-corrected \
             over every test of their table (two per row).\n",
            b.per_episode, b.runs, b.episodes, theirs[0].episodes
        ),
        None => writeln!(md, "No reactive-walk runs of the double T-maze: \"learned\" is not computed.\n"),
    }
    .unwrap();
    for t in theirs.iter().filter(|t| !t.runs.is_empty()) {
        let mut trees = vec![(t.experiment.as_str(), bar, t.experiment.clone(), t.experiment.clone(), String::new())];
        let textured = ours.experiments.iter().any(|(e, c)| e == TEXTURED && !c.is_empty());
        if t.experiment == "exp1" && textured {
            let bar = LearnedBar::of(results, TEXTURED, "double-t-maze");
            let note = match bar {
                Some(b) => format!(
                    " (our runs in `{TEXTURED}`, results/PROTOCOL.md 2026-12-06; R = {:.4}, the textured reactive \
                     walk's 95th percentile, {} runs x {} episodes)",
                    b.per_episode, b.runs, b.episodes
                ),
                None => format!(" (our runs in `{TEXTURED}`; no textured reactive walk: \"learned\" is not computed)"),
            };
            let title = format!("{} with the textured renderer", t.experiment);
            trees.push((TEXTURED, bar, format!("{}-{TEXTURED}", t.experiment), title, note));
        }
        for (experiment, bar, figure, title, note) in trees {
            table(&mut md, t, |c| ours.find(experiment, c), bar, &figures.join(&figure), (&title, &note))?;
            writeln!(md, "\n![{figure} run by run]({FIGURES}/{figure}.svg)\n").unwrap();
        }
    }
    md += "Where the notebooks keep only means (no per-run totals), ours beside theirs, per episode:\n\n\
           | experiment | condition | ours (runs x episodes) | theirs | ours / theirs |\n|---|---|---|---|---|\n";
    for t in &theirs {
        for m in t.means.iter().filter(|m| !t.runs.iter().any(|r| r.condition == m.condition)) {
            let theirs_pe = m.mean / t.episodes as f64;
            let cell = match ours.find(&t.experiment, &m.condition) {
                Some(c) => {
                    let o = mean(&per_episode(c));
                    format!("{o:.3} ({} x {}) | {theirs_pe:.3} | {:.2}", c.runs.len(), c.runs[0].len(), o / theirs_pe)
                }
                None => format!("not run | {theirs_pe:.3} | -"),
            };
            writeln!(md, "| {} | {} | {cell} |", t.experiment, m.condition).unwrap();
        }
    }
    // The file sits beside its figures' folder; the returned text links them from the repository's
    // root, where REPRODUCTION.md quotes it.
    let file = md.replace(&format!("]({FIGURES}/"), "](versus-authors/");
    fs::write(to.join("versus-authors.md"), file).map_err(|e| format!("{}: {e}", to.display()))?;
    Ok(md)
}

/// One experiment's table of our runs (found by `ours`) against the authors' per-run totals, and
/// its figure at `stem`.
fn table<'a>(
    md: &mut String,
    t: &AuthorsResults,
    ours: impl Fn(&str) -> Option<&'a ConditionRuns>,
    bar: Option<LearnedBar>,
    stem: &Path,
    (title, note): (&str, &str),
) -> Result<(), String> {
    writeln!(
        md,
        "**{title}**{note}, per-run totals from `{}` (cells {}) at {}@{}:\n",
        t.source.notebook,
        cells(t.runs.iter().map(|r| r.cell)),
        t.source.repository,
        &t.source.commit[..7]
    )
    .unwrap();
    *md += "| condition | runs: ours / theirs | episodes: ours / theirs | learned: ours / theirs | \
            ours per episode: Q1 / median / Q3 | theirs per episode: Q1 / median / Q3 | \
            Mann-Whitney p | Fisher p |\n|---|---|---|---|---|---|---|---|\n";
    let share = |n: Option<usize>, of: usize| n.map_or("-".to_string(), |n| format!("{n}/{of}"));
    let mut groups = Vec::new();
    for r in &t.runs {
        let Some(c) = ours(&r.condition) else {
            let theirs_pe: Vec<f64> = r.totals.iter().map(|x| x / t.episodes as f64).collect();
            writeln!(
                md,
                "| {} | not run / {} | - / {} | - / {} | - | {} | - | - |",
                r.condition,
                r.totals.len(),
                t.episodes,
                share(bar.map(|b| b.count(&theirs_pe)), r.totals.len()),
                quartiles(&theirs_pe)
            )
            .unwrap();
            continue;
        };
        let v = versus(c, r, t.episodes, bar, t.runs.len());
        writeln!(
            md,
            "| {} | {} / {} | {} / {} | {} / {} | {} | {} | {} | {} |",
            r.condition,
            v.ours.len(),
            v.theirs.len(),
            c.runs[0].len(),
            t.episodes,
            share(v.learned.map(|l| l.0), v.ours.len()),
            share(v.learned.map(|l| l.1), v.theirs.len()),
            quartiles(&v.ours),
            quartiles(&v.theirs),
            fmt_p(v.p_mann_whitney),
            fmt_p(v.p_fisher),
        )
        .unwrap();
        let model = r.condition.split_once('/').map_or(r.condition.as_str(), |(_, m)| m);
        groups.push((model.to_string(), [v.ours, v.theirs]));
    }
    let mark = bar.map_or((0.0, String::new()), |b| (b.per_episode, format!("R {:.3}", b.per_episode)));
    let name = stem.file_name().map_or(String::new(), |n| n.to_string_lossy().into_owned());
    crate::plot::dots(
        stem,
        &format!("{name}: reward per episode, run by run"),
        "reward per episode",
        &groups,
        ["ours", "the authors'"],
        (mark.0, &mark.1),
    )
}

/// `13` or `13, 15`: the distinct cells, in order.
fn cells(it: impl Iterator<Item = usize>) -> String {
    let mut v: Vec<usize> = it.collect();
    v.dedup();
    v.iter().map(usize::to_string).collect::<Vec<_>>().join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn committed() -> Vec<AuthorsResults> {
        load_authors(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../../results/authors")).unwrap()
    }

    /// The committed numbers agree with the paper's means that the presets (and docs/ALGORITHM.md)
    /// quote: every per-run list averages to the preset's total, every stored mean equals it.
    #[test]
    fn the_authors_numbers_agree_with_the_paper_means_the_presets_quote() {
        let mut checked = 0;
        for t in committed() {
            assert_eq!(t.source.repository, "IsmaelTito/SEC");
            assert_eq!(t.source.commit.len(), 40);
            let conditions = presets::experiment(&t.experiment).unwrap();
            let paper = |name: &str| conditions.iter().find(|c| c.name == name).and_then(|c| c.paper_total);
            for r in &t.runs {
                let total = paper(&r.condition).unwrap_or_else(|| panic!("{}: no paper total", r.condition));
                assert!((mean(&r.totals) - total).abs() < 0.01, "{}: {} vs {total}", r.condition, mean(&r.totals));
                checked += 1;
            }
            for m in &t.means {
                if let Some(total) = paper(&m.condition) {
                    assert!((m.mean - total).abs() < 0.01, "{}: {} vs {total}", m.condition, m.mean);
                    checked += 1;
                }
            }
        }
        // 12 per-run lists; 24 + 8 + 4 + 3 means with a paper total.
        assert_eq!(checked, 12 + 24 + 8 + 4 + 3);
        // The run counts the authors reported: 20 runs of SEC, NSEC and MFEC-ae, 12 of MFEC-rp,
        // 10 of DQN and ERLAM.
        let exp1 = &committed()[0];
        let runs: Vec<usize> = exp1.runs.iter().map(|r| r.totals.len()).collect();
        assert_eq!(runs, [20, 12, 20, 20, 10, 10]);
    }

    #[test]
    fn a_file_with_a_foreign_condition_or_a_negative_total_is_refused() {
        let dir = std::env::temp_dir().join(format!("sec-authors-{}", std::process::id()));
        let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../results/authors");
        for (from, to, expect) in [
            ("\"double-t-maze/SEC\"", "\"double-t-maze/SEK\"", "'double-t-maze/SEK' is not a condition of exp1"),
            ("2391.732", "-2391.732", "-2391.732 is not a finite, non-negative total"),
        ] {
            fs::create_dir_all(&dir).unwrap();
            for e in EXPERIMENTS {
                fs::copy(src.join(format!("{e}.json")), dir.join(format!("{e}.json"))).unwrap();
            }
            let text = fs::read_to_string(dir.join("exp1.json")).unwrap();
            assert!(text.contains(from));
            fs::write(dir.join("exp1.json"), text.replacen(from, to, 1)).unwrap();
            let e = load_authors(&dir).unwrap_err();
            assert!(e.contains(expect), "{e}");
        }
        fs::remove_dir_all(&dir).unwrap();
    }
}

//! Every ordering the paper reports, checked against the committed runs of three result trees side
//! by side (the code preset's, its textured-renderer runs of experiment 1 and the trained-encoder
//! runs) and against the authors' own runs
//! (`results/authors/`: their per-run totals where the notebooks keep them, else their means),
//! with the paper's numbers: the table REPRODUCTION.md opens with.
//!
//! A tree's experiment is read from its runs (`seed-*.jsonl.gz`) when it has them, else from its
//! `summary.csv` (the trained-encoder runs of an earlier round, whose runs were not kept): there
//! only the tests against each group's first model exist, so other comparisons show no p.
//!
//! Verdicts, from a two-sided Mann-Whitney U test of the run totals, Bonferroni-corrected over the
//! rows of the same family (one task of experiment 1, or one experiment): "holds" when the
//! difference goes the paper's way with p < 0.05, "reversed" when it goes the other way with
//! p < 0.05, "n.s." otherwise (the arrow says which way it leans).

use crate::report::{load, ConditionRuns};
use crate::stats::{jonckheere_decreasing, mann_whitney, mean};
use std::fmt::Write as _;
use std::fs;
use std::path::Path;

/// One condition as an ordering needs it.
#[derive(Clone, Debug)]
pub struct Arm {
    /// `GROUP/MODEL`.
    pub name: String,
    /// Its runs (seeds).
    pub runs: usize,
    /// The episodes of each run.
    pub episodes: usize,
    /// The mean reward per episode over all its runs.
    pub per_episode: f64,
    /// Per-run totals, when the runs are there.
    pub totals: Option<Vec<f64>>,
    /// Per-run rewards of each episode, when the runs are there (to cut an arm to another's
    /// length).
    pub rewards: Option<Vec<Vec<f64>>>,
    /// Per-run mean entropy over the last 10 % of the episodes, when the runs are there; else
    /// only the mean.
    pub entropy_late: Option<Vec<f64>>,
    /// The mean of `entropy_late` (or summary.csv's, when the runs are not there).
    pub entropy_late_mean: f64,
    /// The corrected and uncorrected p against the group's first model (summary.csv only).
    pub p_vs_reference: Option<f64>,
}

fn from_runs(c: &ConditionRuns) -> Arm {
    let totals = c.totals();
    let n = c.runs[0].len();
    let late = c.span_means(0.9, 1.0, |m| m.entropy);
    Arm {
        name: c.condition.name.clone(),
        runs: c.runs.len(),
        episodes: n,
        per_episode: mean(&totals) / n as f64,
        entropy_late_mean: mean(&late),
        totals: Some(totals),
        rewards: Some(c.runs.iter().map(|r| r.iter().map(|m| m.reward).collect()).collect()),
        entropy_late: Some(late),
        p_vs_reference: None,
    }
}

impl Arm {
    /// The arm over its runs' first `n` episodes (its reward only), if its runs are there and
    /// that long.
    fn cut(&self, n: usize) -> Option<Arm> {
        let rewards: Vec<Vec<f64>> = self.rewards.as_ref()?.iter().map(|r| r[..n.min(r.len())].to_vec()).collect();
        if rewards.iter().any(|r| r.len() < n) {
            return None;
        }
        let totals: Vec<f64> = rewards.iter().map(|r| r.iter().sum()).collect();
        Some(Arm {
            episodes: n,
            per_episode: mean(&totals) / n as f64,
            totals: Some(totals),
            rewards: Some(rewards),
            ..self.clone()
        })
    }
}

/// The arms of `dir/<experiment>`: from its runs, else from its summary.csv; none if neither.
pub fn arms(dir: &Path) -> Vec<Arm> {
    if let Ok((_, conds)) = load(dir) {
        if !conds.is_empty() {
            return conds.iter().map(from_runs).collect();
        }
    }
    let Ok(text) = fs::read_to_string(dir.join("summary.csv")) else { return Vec::new() };
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    fn col<'a>(head: &[&str], row: &[&'a str], name: &str) -> Option<&'a str> {
        head.iter().position(|h| *h == name).and_then(|i| row.get(i).copied())
    }
    let col = |row: &[&str], name: &str| col(&head, row, name).map(str::to_string);
    lines
        .map(|l| {
            let row: Vec<&str> = l.split(',').collect();
            let num = |name: &str| col(&row, name).and_then(|v| v.parse::<f64>().ok());
            Arm {
                name: col(&row, "condition").unwrap_or_default(),
                runs: num("runs").unwrap_or(0.0) as usize,
                episodes: num("episodes").unwrap_or(0.0) as usize,
                per_episode: num("per_episode").unwrap_or(f64::NAN),
                totals: None,
                rewards: None,
                entropy_late: None,
                entropy_late_mean: num("entropy_last10").unwrap_or(f64::NAN),
                p_vs_reference: num("p_uncorrected"),
            }
        })
        .collect()
}

/// What a row asks of two arms.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Claim {
    /// The first collects more reward than the second.
    More,
    /// The first's late entropy is lower than the second's.
    LowerEntropy,
    /// The first does not differ significantly from the second.
    Same,
    /// The first collects at least as much as the second (not significantly less).
    AtLeast,
}

/// One checked ordering in one tree.
#[derive(Clone, Debug)]
pub struct Verdict {
    /// What the table says of it ("holds", "holds by direction only, ...").
    pub text: String,
    /// The ratio of the two sides, where it compares two.
    pub ratio: Option<f64>,
    /// The test's p value, where one was run.
    pub p: Option<f64>,
}

/// The trees the table compares, in its columns' order (the CSV's `tree`).
const TREES: [&str; 4] = ["code", "textured", "trained", "authors"];

/// Permutations of the trend test's p (its resolution is 1 / 20,001).
const TREND_PERMUTATIONS: usize = 20_000;

fn find<'a>(arms: &'a [Arm], name: &str) -> Option<&'a Arm> {
    arms.iter().find(|a| a.name == name)
}

/// p (uncorrected) for a vs b: Mann-Whitney on the runs' values, or the summary's test when one
/// of them is the other's group reference (the group's first condition).
fn p_value(a: &Arm, b: &Arm, arms: &[Arm], claim: Claim) -> Option<f64> {
    let values = |x: &Arm| if claim == Claim::LowerEntropy { x.entropy_late.clone() } else { x.totals.clone() };
    if let (Some(x), Some(y)) = (values(a), values(b)) {
        return (x.len() >= 2 && y.len() >= 2).then(|| mann_whitney(&x, &y).1);
    }
    if claim == Claim::LowerEntropy {
        return None;
    }
    let group = |x: &Arm| x.name.split_once('/').map(|(g, _)| g.to_string());
    let reference = |x: &Arm| arms.iter().find(|r| group(r) == group(x)).map(|r| r.name.clone());
    if reference(a).as_deref() == Some(&b.name) {
        a.p_vs_reference
    } else if reference(b).as_deref() == Some(&a.name) {
        b.p_vs_reference
    } else {
        None
    }
}

fn verdict(arms: &[Arm], a: &str, b: &str, claim: Claim, family: usize) -> Verdict {
    let (Some(x), Some(y)) = (find(arms, a), find(arms, b)) else {
        return Verdict { text: "not run".into(), ratio: None, p: None };
    };
    let ratio = match claim {
        Claim::LowerEntropy => x.entropy_late_mean / y.entropy_late_mean,
        _ => x.per_episode / y.per_episode,
    };
    if ratio.is_nan() {
        // The authors' notebooks store no entropies.
        return Verdict { text: "no data".into(), ratio: None, p: None };
    }
    let p = p_value(x, y, arms, claim).map(|p| (p * family as f64).min(1.0));
    let paper_way = match claim {
        Claim::LowerEntropy => ratio < 1.0,
        _ => ratio > 1.0,
    };
    let lean = if ratio > 1.0 {
        ">"
    } else if ratio < 1.0 {
        "<"
    } else {
        "="
    };
    let significant = p.is_some_and(|p| p < 0.05);
    let text = match (claim, p) {
        (_, None) => format!("{lean}, no test"),
        (Claim::More | Claim::LowerEntropy, _) if significant => {
            if paper_way {
                "holds".into()
            } else {
                "reversed".into()
            }
        }
        (Claim::More | Claim::LowerEntropy, _) => format!("n.s. ({lean})"),
        (Claim::Same, _) if significant => format!("differs ({lean})"),
        (Claim::Same, _) => "holds".into(),
        (Claim::AtLeast, _) if significant && !paper_way => "reversed".into(),
        (Claim::AtLeast, _) => {
            if significant {
                "holds".into()
            } else {
                format!("holds (n.s., {lean})")
            }
        }
    };
    Verdict { text, ratio: Some(ratio), p }
}

fn fmt_p(p: Option<f64>) -> String {
    match p {
        None => "-".into(),
        Some(p) if p < 0.001 => format!("{p:.1e}"),
        Some(p) => format!("{p:.3}"),
    }
}

fn cell(v: &Verdict, what: &str) -> String {
    match v.ratio {
        Some(r) if r.is_finite() => format!("{} ({what}{r:.2}, p {})", v.text, fmt_p(v.p)),
        _ => v.text.clone(),
    }
}

/// The paper's ratio of two conditions' totals (the experiment presets hold them).
fn paper_ratio(exp: &str, a: &str, b: &str) -> String {
    let total = |name: &str| {
        sec_playground::experiment::presets::experiment(exp)
            .ok()?
            .into_iter()
            .find(|c| c.name == name)
            .and_then(|c| c.paper_total)
    };
    match (total(a), total(b)) {
        (Some(x), Some(y)) => format!("{:.2}", x / y),
        _ => "-".into(),
    }
}

/// Marks a verdict that holds while its baseline `b` lies outside the authors' own runs of it:
/// our runs' median reward per episode outside the interquartile range of theirs (where their
/// notebooks keep per-run totals). A ratio over such a baseline says more about the baseline
/// than about SEC (PROTOCOL.md, 2026-12-06).
fn mark_outside(mut v: Verdict, ours: &[Arm], authors: &[Arm], b: &str) -> Verdict {
    let per_episode =
        |a: &Arm| a.totals.as_ref().map(|t| t.iter().map(|x| x / a.episodes as f64).collect::<Vec<f64>>());
    let (Some(o), Some(t)) = (find(ours, b).and_then(per_episode), find(authors, b).and_then(per_episode)) else {
        return v;
    };
    let median = crate::stats::quantile(&o, 0.5);
    let (q1, q3) = (crate::stats::quantile(&t, 0.25), crate::stats::quantile(&t, 0.75));
    if v.text.starts_with("holds") && (median < q1 || median > q3) {
        v.text = v.text.replacen("holds", "holds, baseline outside the authors' runs", 1);
    }
    v
}

/// A tree's arms per experiment.
struct Tree {
    exp: Vec<(String, Vec<Arm>)>,
}

impl Tree {
    fn load(root: &Path) -> Tree {
        let exp = ["exp1", "exp2", "exp3", "exp4"].iter().map(|e| (e.to_string(), arms(&root.join(e)))).collect();
        Tree { exp }
    }

    /// The authors' runs (`results/authors/`): each model with per-run totals as an arm of its
    /// runs, the others as their means (a p only where the notebook's test was against the
    /// group's first condition, as the trained tree's summaries); an empty tree if there are none.
    fn authors(dir: &Path) -> Tree {
        let Ok(files) = crate::authors::load_authors(dir) else { return Tree { exp: Vec::new() } };
        let exp = files
            .into_iter()
            .map(|f| {
                let e = f.episodes as f64;
                let arm = |name: &str, runs: usize, per_episode: f64, totals: Option<Vec<f64>>| Arm {
                    name: name.to_string(),
                    runs,
                    episodes: f.episodes,
                    per_episode,
                    totals,
                    rewards: None,
                    entropy_late: None,
                    entropy_late_mean: f64::NAN,
                    p_vs_reference: None,
                };
                let mut arms: Vec<Arm> = f
                    .runs
                    .iter()
                    .map(|r| arm(&r.condition, r.totals.len(), mean(&r.totals) / e, Some(r.totals.clone())))
                    .collect();
                for m in f.means.iter().filter(|m| !f.runs.iter().any(|r| r.condition == m.condition)) {
                    arms.push(arm(&m.condition, 0, m.mean / e, None));
                }
                let group = |name: &str| name.split_once('/').map(|(g, _)| g.to_string());
                for m in &f.means {
                    let first = arms.iter().find(|a| group(&a.name) == group(&m.condition)).map(|a| a.name.clone());
                    if m.versus.is_some() && m.versus == first {
                        if let Some(a) = arms.iter_mut().find(|a| a.name == m.condition && a.totals.is_none()) {
                            a.p_vs_reference = m.p;
                        }
                    }
                }
                (f.experiment, arms)
            })
            .collect();
        Tree { exp }
    }

    /// The textured renderer's runs of experiment 1 (`ROOT/textured`, whose conditions carry
    /// experiment 1's names; results/PROTOCOL.md, 2026-12-06) as this tree's exp1.
    fn textured(root: &Path) -> Tree {
        Tree { exp: vec![("exp1".to_string(), arms(&root.join(crate::authors::TEXTURED)))] }
    }

    fn arms(&self, exp: &str) -> &[Arm] {
        self.exp.iter().find(|(e, _)| e == exp).map_or(&[], |(_, a)| a)
    }

    /// "runs x episodes" of an experiment's conditions (a range if they differ).
    fn scale(&self, exp: &str, prefix: &str) -> String {
        let arms: Vec<&Arm> = self.arms(exp).iter().filter(|a| a.name.starts_with(prefix)).collect();
        if arms.is_empty() {
            return "-".into();
        }
        let span = |f: fn(&Arm) -> usize| {
            let (lo, hi) = (arms.iter().map(|a| f(a)).min().unwrap(), arms.iter().map(|a| f(a)).max().unwrap());
            if lo == hi {
                lo.to_string()
            } else {
                format!("{lo}-{hi}")
            }
        };
        format!("{} x {}", span(|a| a.runs), span(|a| a.episodes))
    }
}

/// Writes `orderings.md` and `orderings.csv` into `out` from the trees `code` and `trained` and
/// the authors' numbers under `authors`; returns the markdown.
pub fn orderings(code: &Path, trained: &Path, authors: &Path, out: &Path) -> Result<String, String> {
    let trees = [Tree::load(code), Tree::textured(code), Tree::load(trained), Tree::authors(authors)];
    let mut rows: Vec<[String; 7]> = Vec::new();
    let mut csv = String::from("family,ordering,paper,tree,verdict,ratio,p_corrected\n");
    let mut add = |family: &str, ordering: String, paper: String, verdicts: [(Verdict, &str); 4]| {
        for (i, (v, _)) in verdicts.iter().enumerate() {
            let tree = TREES[i];
            writeln!(
                csv,
                "{family},\"{ordering}\",{paper},{tree},{},{},{}",
                v.text,
                v.ratio.map_or(String::new(), |r| r.to_string()),
                v.p.map_or(String::new(), |p| p.to_string())
            )
            .unwrap();
        }
        let [(a, wa), (mut t, wt), (b, wb), (mut c, wc)] = verdicts;
        if c.text == "not run" {
            c.text = "not stored".into();
        }
        // The textured grid runs experiment 1 only.
        if !family.starts_with("exp1") {
            t.text = "-".into();
        }
        rows.push([family.to_string(), ordering, paper, cell(&a, wa), cell(&t, wt), cell(&b, wb), cell(&c, wc)]);
    };
    for task in ["double-t-maze", "cylinder", "detour", "object-permanence"] {
        let pair = |tree: &Tree, other: &str, claim| {
            verdict(tree.arms("exp1"), &format!("{task}/SEC"), &format!("{task}/{other}"), claim, 3)
        };
        let paper = |other: &str| paper_ratio("exp1", &format!("{task}/SEC"), &format!("{task}/{other}"));
        let outside = |tree: &Tree, v: Verdict, other: &str| {
            mark_outside(v, tree.arms("exp1"), trees[3].arms("exp1"), &format!("{task}/{other}"))
        };
        for other in ["NSEC", "MFEC-ae", "MFEC-rp"] {
            add(
                &format!("exp1 {task}"),
                format!("SEC > {other}"),
                paper(other),
                [
                    (outside(&trees[0], pair(&trees[0], other, Claim::More), other), "×"),
                    (outside(&trees[1], pair(&trees[1], other, Claim::More), other), "×"),
                    (outside(&trees[2], pair(&trees[2], other, Claim::More), other), "×"),
                    (pair(&trees[3], other, Claim::More), "×"),
                ],
            );
        }
        // The deep baselines: their own family of two, SEC cut to their runs' length.
        let deep = |tree: &Tree, other: &str| {
            let arms = tree.arms("exp1");
            let (sec, dqn) = (format!("{task}/SEC"), format!("{task}/{other}"));
            let Some(baseline) = find(arms, &dqn) else { return verdict(&[], &sec, &dqn, Claim::More, 2) };
            // The authors' totals have no episodes to cut, but SEC's are as long as DQN's there.
            let same_length = || find(arms, &sec).filter(|s| s.episodes == baseline.episodes).cloned();
            let Some(cut) = find(arms, &sec).and_then(|s| s.cut(baseline.episodes)).or_else(same_length) else {
                return verdict(&[], &sec, &dqn, Claim::More, 2);
            };
            verdict(&[cut, baseline.clone()], &sec, &dqn, Claim::More, 2)
        };
        for other in ["DQN", "ERLAM"] {
            add(
                &format!("exp1 {task}"),
                format!("SEC > {other} (over {other}'s episodes)"),
                paper(other),
                [
                    (outside(&trees[0], deep(&trees[0], other), other), "×"),
                    (outside(&trees[1], deep(&trees[1], other), other), "×"),
                    (outside(&trees[2], deep(&trees[2], other), other), "×"),
                    (deep(&trees[3], other), "×"),
                ],
            );
        }
        add(
            &format!("exp1 {task}"),
            "entropy SEC < NSEC (last 10 %)".into(),
            "lower".into(),
            [
                (pair(&trees[0], "NSEC", Claim::LowerEntropy), "×"),
                (pair(&trees[1], "NSEC", Claim::LowerEntropy), "×"),
                (pair(&trees[2], "NSEC", Claim::LowerEntropy), "×"),
                (pair(&trees[3], "NSEC", Claim::LowerEntropy), "×"),
            ],
        );
    }
    let exp2 = |tree: &Tree, a: &str, b: &str, family| verdict(tree.arms("exp2"), a, b, Claim::More, family);
    add(
        "exp2",
        "SEC m=125 > NSEC m=1000".into(),
        paper_ratio("exp2", "m125/SEC", "m1000/NSEC"),
        [
            (exp2(&trees[0], "m125/SEC", "m1000/NSEC", 5), "×"),
            (exp2(&trees[1], "m125/SEC", "m1000/NSEC", 5), "×"),
            (exp2(&trees[2], "m125/SEC", "m1000/NSEC", 5), "×"),
            (exp2(&trees[3], "m125/SEC", "m1000/NSEC", 5), "×"),
        ],
    );
    for m in [125, 250, 500, 1000] {
        let (s, n) = (format!("m{m}/SEC"), format!("m{m}/NSEC"));
        add(
            "exp2",
            format!("SEC > NSEC at m={m}"),
            paper_ratio("exp2", &s, &n),
            [
                (exp2(&trees[0], &s, &n, 5), "×"),
                (exp2(&trees[1], &s, &n, 5), "×"),
                (exp2(&trees[2], &s, &n, 5), "×"),
                (exp2(&trees[3], &s, &n, 5), "×"),
            ],
        );
    }
    // The protocol's rule (a strict fall of the four ratios) and, where the runs are there, a
    // one-sided Jonckheere-Terpstra test of a falling trend on the per-seed ratios (SEC's run
    // total over NSEC's of the same seed), its p by permutation (PROTOCOL.md, 2026-12-06).
    let falling = |tree: &Tree| {
        let sizes = [125, 250, 500, 1000];
        let a = tree.arms("exp2");
        let r: Vec<f64> = sizes
            .iter()
            .filter_map(|m| {
                Some(find(a, &format!("m{m}/SEC"))?.per_episode / find(a, &format!("m{m}/NSEC"))?.per_episode)
            })
            .collect();
        let list = r.iter().map(|x| format!("{x:.2}")).collect::<Vec<_>>().join(" / ");
        let per_seed: Option<Vec<Vec<f64>>> = sizes
            .iter()
            .map(|m| {
                let (s, n) =
                    (find(a, &format!("m{m}/SEC"))?.totals.as_ref()?, find(a, &format!("m{m}/NSEC"))?.totals.as_ref()?);
                (s.len() == n.len() && s.len() >= 2).then(|| s.iter().zip(n).map(|(s, n)| s / n).collect())
            })
            .collect();
        let trend = per_seed.map(|g| jonckheere_decreasing(&g, TREND_PERMUTATIONS, 1).1);
        let falls = r.len() == 4 && r.windows(2).all(|w| w[0] > w[1]);
        let text = match (r.len() < 4, falls, trend) {
            (true, _, _) => "not run".into(),
            (_, true, Some(p)) if p < 0.05 => format!("holds ({list}; trend p {})", fmt_p(Some(p))),
            (_, true, Some(p)) => format!("holds by direction only, trend n.s. ({list}; trend p {})", fmt_p(Some(p))),
            (_, true, None) => format!("holds by direction, no test ({list})"),
            (_, false, Some(p)) => format!("does not hold ({list}; trend p {})", fmt_p(Some(p))),
            (_, false, None) => format!("does not hold ({list})"),
        };
        (Verdict { text, ratio: None, p: trend }, "")
    };
    add(
        "exp2",
        "SEC/NSEC at equal memory falls as m grows (125 / 250 / 500 / 1000)".into(),
        "2.42 / 2.00 / 1.95 / 1.64".into(),
        [falling(&trees[0]), falling(&trees[1]), falling(&trees[2]), falling(&trees[3])],
    );
    for v in ["noGi", "noDist", "noRR", "soloGi", "soloDist", "soloRR"] {
        let name = format!("value-function/SEC-{v}");
        let check = |tree: &Tree| verdict(tree.arms("exp3"), &name, "value-function/SEC-default", Claim::Same, 6);
        let paper = match v {
            "noGi" | "noDist" | "noRR" => "n.s.",
            _ => "-",
        };
        add(
            "exp3",
            format!("SEC-{v} = SEC-default"),
            paper.into(),
            [(check(&trees[0]), "×"), (check(&trees[1]), "×"), (check(&trees[2]), "×"), (check(&trees[3]), "×")],
        );
    }
    for model in ["SEC", "NSEC"] {
        for f in ["fifo", "rwd", "prior"] {
            let (a, b) = (format!("forgetting/{model}-{f}"), format!("forgetting/{model}-none"));
            let check = |tree: &Tree| verdict(tree.arms("exp4"), &a, &b, Claim::AtLeast, 6);
            let outside = |tree: &Tree| mark_outside(check(tree), tree.arms("exp4"), trees[3].arms("exp4"), &b);
            add(
                "exp4",
                format!("{model}-{f} >= {model}-none"),
                paper_ratio("exp4", &a, &b),
                [
                    (outside(&trees[0]), "×"),
                    (outside(&trees[1]), "×"),
                    (outside(&trees[2]), "×"),
                    (check(&trees[3]), "×"),
                ],
            );
        }
    }
    let mut md = String::from(
        "| experiment | ordering (the paper's) | paper: ratio | untrained encoder, the code preset | the same, textured renderer | trained encoder | the authors' runs |\n|---|---|---|---|---|---|---|\n",
    );
    for r in &rows {
        writeln!(md, "| {} |", r.join(" | ")).unwrap();
    }
    let mut scales = String::from("\nRuns x episodes per condition:");
    for (e, prefix) in [("exp1", "double-t-maze/"), ("exp1", "detour/"), ("exp2", ""), ("exp3", ""), ("exp4", "")] {
        let label = if prefix.is_empty() { e.to_string() } else { format!("{e} {}", prefix.trim_end_matches('/')) };
        let textured = if e == "exp1" { format!(", {} (textured)", trees[1].scale(e, prefix)) } else { String::new() };
        write!(
            scales,
            " {label} {} (untrained){textured}, {} (trained);",
            trees[0].scale(e, prefix),
            trees[2].scale(e, prefix)
        )
        .unwrap();
    }
    scales.pop();
    md += &scales;
    md += ". The authors' runs: their per-run totals over 5000 episodes where their notebooks keep them \
           (experiment 1 in the double T-maze, experiment 4), else their means, tested only where the \
           notebook tested against the same condition (results/authors/).\n";
    fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    fs::write(out.join("orderings.md"), &md).map_err(|e| format!("{}: {e}", out.display()))?;
    fs::write(out.join("orderings.csv"), csv).map_err(|e| format!("{}: {e}", out.display()))?;
    Ok(md)
}

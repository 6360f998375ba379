//! The textured renderer against the flat one in the double T-maze: the tests, predictions and
//! default rule results/PROTOCOL.md's addendum of 2026-12-06 stated before the textured runs
//! (`sec-experiment surfaces`).
//!
//! Our own runs first: two-sided Mann-Whitney U tests of SEC's, NSEC's and MFEC-ae's per-run
//! totals, textured against flat, and Fisher's exact test of MFEC-ae's learned counts (each
//! surface's bar from its own reactive walk), Bonferroni-corrected over the four. Then the rule
//! for the code preset's default, from versus-authors' comparisons of each surface with the
//! authors' runs (its tests, corrected as its tables correct them). The decision is taken on the
//! complete block only.

use crate::authors::{fmt_p, load_authors, versus, LearnedBar, Versus, TEXTURED};
use crate::report::{load, ConditionRuns};
use crate::stats::{fisher_exact, mann_whitney, mean, quantile};
use std::fmt::Write as _;
use std::fs;
use std::path::Path;

/// The task the block runs.
const TASK: &str = "double-t-maze";

/// The block the decision waits for: each model's runs and episodes (PROTOCOL.md, 2026-12-06).
const BLOCK: [(&str, usize); 5] = [("SEC", 20), ("NSEC", 20), ("MFEC-ae", 10), ("MFEC-rp", 10), ("reactive", 10)];

/// The episodes of every run of the block.
const EPISODES: usize = 5000;

/// The tests of the first table, which the correction counts.
const TESTS: f64 = 4.0;

/// One surface's runs of the block.
struct Surface {
    conds: Vec<ConditionRuns>,
    bar: Option<LearnedBar>,
}

impl Surface {
    fn load(dir: &Path) -> Surface {
        let conds = load(dir).map(|(_, c)| c).unwrap_or_default();
        let bar = LearnedBar::among(&conds, TASK);
        Surface { conds, bar }
    }

    fn find(&self, model: &str) -> Option<&ConditionRuns> {
        self.conds.iter().find(|c| c.condition.name == format!("{TASK}/{model}"))
    }

    /// Reward per episode of each run of `model` (empty when it has none).
    fn per_episode(&self, model: &str) -> Vec<f64> {
        self.find(model).map_or(Vec::new(), |c| {
            let n = c.runs[0].len() as f64;
            c.totals().iter().map(|t| t / n).collect()
        })
    }

    /// What the block still lacks, as `MODEL runs of N`.
    fn missing(&self) -> Vec<String> {
        BLOCK
            .iter()
            .filter_map(|&(model, runs)| {
                let have = self.find(model).map_or(0, |c| c.runs.iter().filter(|r| r.len() >= EPISODES).count());
                (have < runs).then(|| format!("{model} {have} of {runs}"))
            })
            .collect()
    }
}

fn summary(x: &[f64]) -> String {
    format!("{} x {}, {:.3} ({:.3}-{:.3})", x.len(), EPISODES, quantile(x, 0.5), quantile(x, 0.25), quantile(x, 0.75))
}

fn way(textured: f64, flat: f64) -> &'static str {
    if textured > flat {
        "higher"
    } else if textured < flat {
        "lower"
    } else {
        "equal"
    }
}

/// Writes `surfaces.md` into `to` from the flat runs (`results/exp1`) and the textured ones
/// (`results/textured`) and the authors' numbers under `authors`; returns the markdown.
pub fn surfaces(results: &Path, authors: &Path, to: &Path) -> Result<String, String> {
    let flat = Surface::load(&results.join("exp1"));
    let textured = Surface::load(&results.join(TEXTURED));
    let theirs = load_authors(authors)?;
    let exp1 = theirs.iter().find(|t| t.experiment == "exp1").ok_or("the authors' exp1.json is missing")?;
    let mut md = String::new();
    let missing = textured.missing();
    if !missing.is_empty() || !flat.missing().is_empty() {
        writeln!(
            md,
            "The double T-maze's textured block is not complete (textured: {}; flat: {}): the protocol \
             decides on the complete block only, so nothing is tested yet.",
            if missing.is_empty() { "complete".into() } else { missing.join(", ") },
            if flat.missing().is_empty() { "complete".into() } else { flat.missing().join(", ") }
        )
        .unwrap();
        return write(to, md);
    }
    let (bf, bt) = (flat.bar.expect("a complete block has its walk"), textured.bar.expect("likewise"));

    // Our runs, textured against flat.
    md += "Textured against flat, our runs of the double T-maze (results/PROTOCOL.md, 2026-12-06): runs x \
           episodes, median reward per episode (Q1-Q3); two-sided tests, Bonferroni-corrected over the four. \
           A run learned when its reward per episode is above its surface's R, the 95th percentile of that \
           surface's reactive walk.\n\n\
           | model | flat | textured | textured / flat, medians | test | corrected p |\n|---|---|---|---|---|---|\n";
    let mut p = std::collections::BTreeMap::new();
    let mut ratio = std::collections::BTreeMap::new();
    for model in ["SEC", "NSEC", "MFEC-ae"] {
        let (f, t) = (flat.per_episode(model), textured.per_episode(model));
        let r = quantile(&t, 0.5) / quantile(&f, 0.5);
        let q = (mann_whitney(&t, &f).1 * TESTS).min(1.0);
        writeln!(md, "| {model} | {} | {} | {r:.3} | Mann-Whitney | {} |", summary(&f), summary(&t), fmt_p(q)).unwrap();
        p.insert(model, q);
        ratio.insert(model, r);
    }
    let (f, t) = (flat.per_episode("MFEC-ae"), textured.per_episode("MFEC-ae"));
    let (lf, lt) = (bf.count(&f), bt.count(&t));
    let q_learned = (fisher_exact(lt, t.len() - lt, lf, f.len() - lf) * TESTS).min(1.0);
    writeln!(
        md,
        "| MFEC-ae learned | {lf}/{} (R {:.4}) | {lt}/{} (R {:.4}) | - | Fisher | {} |",
        f.len(),
        bf.per_episode,
        t.len(),
        bt.per_episode,
        fmt_p(q_learned)
    )
    .unwrap();

    // The predictions.
    let med = |s: &Surface, m: &str| quantile(&s.per_episode(m), 0.5);
    let sec_nsec = |s: &Surface| mean(&s.per_episode("SEC")) / mean(&s.per_episode("NSEC"));
    let verdict = |holds: bool, went: String| if holds { format!("holds ({went})") } else { format!("fails: {went}") };
    let one = verdict(
        med(&textured, "SEC") > med(&flat, "SEC") && p["SEC"] < 0.05,
        format!("textured SEC {} than flat, p {}", way(med(&textured, "SEC"), med(&flat, "SEC")), fmt_p(p["SEC"])),
    );
    let went = match lt.cmp(&lf) {
        std::cmp::Ordering::Equal => format!("as many learned runs as flat ({lt} each)"),
        o => format!("{} learned runs ({lt} against {lf})", if o.is_gt() { "more" } else { "fewer" }),
    };
    let two = verdict(lt > lf && q_learned < 0.05, format!("{went}, p {}", fmt_p(q_learned)));
    let three = verdict(
        ratio["SEC"] > ratio["NSEC"] && p["SEC"] < 0.05,
        format!(
            "SEC/NSEC {} ({:.3} against {:.3}); textured over flat, medians: SEC {:.3}, NSEC {:.3}; SEC's p {}",
            way(sec_nsec(&textured), sec_nsec(&flat)),
            sec_nsec(&textured),
            sec_nsec(&flat),
            ratio["SEC"],
            ratio["NSEC"],
            fmt_p(p["SEC"])
        ),
    );
    md += "\n| prediction | verdict |\n|---|---|\n";
    writeln!(md, "| 1. textured SEC's median per episode above flat SEC's | {one} |").unwrap();
    writeln!(md, "| 2. textured MFEC-ae learns in more runs than flat | {two} |").unwrap();
    writeln!(md, "| 3. SEC/NSEC (per-episode means) above flat's, NSEC gaining less than SEC | {three} |").unwrap();

    // The rule for the default, from versus-authors' comparisons.
    let against = |s: &Surface, model: &str| -> Result<Versus, String> {
        let r = exp1.runs.iter().find(|r| r.condition == format!("{TASK}/{model}"));
        let c = s.find(model);
        match (c, r) {
            (Some(c), Some(r)) => Ok(versus(c, r, exp1.episodes, s.bar, exp1.runs.len())),
            _ => Err(format!("no runs of {TASK}/{model} on one side (ours or the authors')")),
        }
    };
    let theirs_median = |model: &str| -> Result<f64, String> { Ok(quantile(&against(&flat, model)?.theirs, 0.5)) };
    let share = |v: &Versus| v.learned.map_or(f64::NAN, |(a, _)| a as f64 / v.ours.len() as f64);
    let (sf, st) = (against(&flat, "SEC")?, against(&textured, "SEC")?);
    let (mf, mt) = (against(&flat, "MFEC-ae")?, against(&textured, "MFEC-ae")?);
    let nt = against(&textured, "NSEC")?;
    let target_sec = theirs_median("SEC")?;
    let theirs_share = mf.learned.map_or(f64::NAN, |(_, b)| b as f64 / mf.theirs.len() as f64);
    let gap = |x: f64, y: f64| (x - y).abs();
    let a = gap(quantile(&st.ours, 0.5), target_sec) < gap(quantile(&sf.ours, 0.5), target_sec);
    let b = gap(share(&mt), theirs_share) < gap(share(&mf), theirs_share);
    let c = nt.p_mann_whitney >= 0.05;
    let yes = |x: bool| if x { "met" } else { "not met" };
    let learned = |v: &Versus| v.learned.map_or("-".into(), |(a, _)| format!("{a}/{}", v.ours.len()));
    md += "\nThe rule for the code preset's default (versus-authors, each surface's table corrected as it is \
           there):\n\n| rule | the authors' | flat | textured | |\n|---|---|---|---|---|\n";
    writeln!(
        md,
        "| (a) SEC's median per episode closer to the authors' | {target_sec:.3} | {:.3} (off by {:.3}) | {:.3} (off by {:.3}) | {} |",
        quantile(&sf.ours, 0.5),
        gap(quantile(&sf.ours, 0.5), target_sec),
        quantile(&st.ours, 0.5),
        gap(quantile(&st.ours, 0.5), target_sec),
        yes(a)
    )
    .unwrap();
    writeln!(
        md,
        "| (b) MFEC-ae's learned share closer to the authors' | {} | {} | {} | {} |",
        mf.learned.map_or("-".into(), |(_, b)| format!("{b}/{}", mf.theirs.len())),
        learned(&mf),
        learned(&mt),
        yes(b)
    )
    .unwrap();
    writeln!(
        md,
        "| (c) textured NSEC does not differ from the authors' (corrected p >= 0.05) | {:.3} | - | {:.3}, p {} | {} |",
        quantile(&nt.theirs, 0.5),
        quantile(&nt.ours, 0.5),
        fmt_p(nt.p_mann_whitney),
        yes(c)
    )
    .unwrap();
    let failed: Vec<&str> = [(a, "(a)"), (b, "(b)"), (c, "(c)")].iter().filter(|x| !x.0).map(|x| x.1).collect();
    if failed.is_empty() {
        md += "\n**Decision: `textured` becomes the code preset's default**; `flat` stays a named perception.\n";
    } else {
        writeln!(
            md,
            "\n**Decision: `flat` stays the code preset's default** (not met: {}); `textured` stays a named \
             perception.",
            failed.join(", ")
        )
        .unwrap();
    }
    write(to, md)
}

fn write(to: &Path, md: String) -> Result<String, String> {
    fs::create_dir_all(to).map_err(|e| format!("{}: {e}", to.display()))?;
    fs::write(to.join("surfaces.md"), &md).map_err(|e| format!("{}: {e}", to.display()))?;
    Ok(md)
}

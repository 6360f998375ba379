//! Aggregates an experiment directory's JSON lines into the paper's measures: total reward over
//! the episodes, final-episode reward, entropy early and late, Mann-Whitney tests against each
//! group's first model, the SEC/NSEC memory-ratio matrix of figure 6, and the learning curves.

use crate::plot::{self, Series};
use crate::runner::{ExperimentManifest, ManifestCondition};
use crate::stats::{ci95, mann_whitney, mean, moving_mean, sd, se};
use sec_playground::agent::SecConfig;
use sec_playground::experiment::EpisodeMetrics;
use sec_playground::memory::Forgetting;
use std::fmt::Write as _;
use std::fs;
use std::path::Path;

/// The curves' window, as in the paper's figures.
pub const WINDOW: usize = 20;

/// The finished runs of one condition, cut to a common length.
pub struct ConditionRuns {
    /// The condition, as the experiment's manifest holds it.
    pub condition: ManifestCondition,
    /// The seeds of its finished runs.
    pub seeds: Vec<u64>,
    /// Each run's episodes, seed by seed.
    pub runs: Vec<Vec<EpisodeMetrics>>,
}

impl ConditionRuns {
    /// `GROUP` of `GROUP/MODEL`.
    pub fn group(&self) -> &str {
        self.condition.name.split_once('/').map_or("", |(g, _)| g)
    }

    /// `MODEL` of `GROUP/MODEL`.
    pub fn model(&self) -> &str {
        self.condition.name.split_once('/').map_or(&self.condition.name, |(_, m)| m)
    }

    /// Per run: the tables' reward summed over the episodes.
    pub fn totals(&self) -> Vec<f64> {
        self.totals_over(usize::MAX)
    }

    /// Per run: the reward summed over its first `n` episodes (all of them if it has fewer).
    pub fn totals_over(&self, n: usize) -> Vec<f64> {
        self.runs.iter().map(|r| r.iter().take(n).map(|m| m.reward).sum()).collect()
    }

    /// Per run: the mean of `f` over the episodes in [from, to) (fractions of the run).
    pub fn span_means(&self, from: f64, to: f64, f: impl Fn(&EpisodeMetrics) -> f64) -> Vec<f64> {
        self.runs
            .iter()
            .map(|r| {
                let (a, b) = ((r.len() as f64 * from) as usize, ((r.len() as f64 * to) as usize).max(1));
                r[a..b].iter().map(&f).sum::<f64>() / (b - a) as f64
            })
            .collect()
    }

    /// The fresh-only entropy over the last 10% of the episodes, pooled over the runs' episodes
    /// that computed one (NaN if none did).
    pub fn fresh_entropy_late(&self) -> f64 {
        let v: Vec<f64> = self
            .runs
            .iter()
            .flat_map(|r| r[(r.len() as f64 * 0.9) as usize..].iter().filter_map(|m| m.entropy_fresh))
            .collect();
        if v.is_empty() {
            f64::NAN
        } else {
            mean(&v)
        }
    }

    /// Mean and standard error across runs of the windowed curve of `f`.
    pub fn curve(&self, f: impl Fn(&EpisodeMetrics) -> f64) -> (Vec<f64>, Vec<f64>) {
        let smoothed: Vec<Vec<f64>> =
            self.runs.iter().map(|r| moving_mean(&r.iter().map(&f).collect::<Vec<_>>(), WINDOW)).collect();
        let len = smoothed.iter().map(Vec::len).min().unwrap_or(0);
        let at = |i: usize| smoothed.iter().map(|s| s[i]).collect::<Vec<_>>();
        ((0..len).map(|i| mean(&at(i))).collect(), (0..len).map(|i| se(&at(i))).collect())
    }
}

fn read_run(path: &Path) -> Result<Vec<EpisodeMetrics>, String> {
    let text = crate::runner::read_run_text(path)?;
    text.lines()
        .enumerate()
        .map(|(i, l)| serde_json::from_str(l).map_err(|e| format!("{} line {}: {e}", path.display(), i + 1)))
        .collect()
}

/// Loads the manifest and every finished run, each condition cut to `episodes` (or the shortest
/// of its runs).
pub fn load(dir: &Path) -> Result<(ExperimentManifest, Vec<ConditionRuns>), String> {
    let path = dir.join("experiment.json");
    let text =
        fs::read_to_string(&path).map_err(|e| format!("{}: {e} (run `sec-experiment run` first)", path.display()))?;
    let manifest: ExperimentManifest = serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut out = Vec::new();
    for c in &manifest.conditions {
        let (mut seeds, mut runs) = (Vec::new(), Vec::new());
        for &seed in &manifest.seeds {
            let p = crate::runner::run_path(dir, &c.name, seed);
            if p.exists() {
                seeds.push(seed);
                runs.push(read_run(&p)?);
            }
        }
        let len = runs.iter().map(Vec::len).min().unwrap_or(0).min(manifest.episodes);
        for r in &mut runs {
            r.truncate(len);
        }
        if len > 0 {
            out.push(ConditionRuns { condition: c.clone(), seeds, runs });
        }
    }
    Ok((manifest, out))
}

fn fmt_p(p: f64) -> String {
    if p < 0.001 {
        format!("{p:.1e}")
    } else {
        format!("{p:.3}")
    }
}

/// An experiment's report: the whole text and each group's table on its own (what a page quotes
/// under `EXPERIMENT/GROUP`, crate::quote).
pub struct Report {
    /// `report.md`'s text.
    pub md: String,
    /// Each group's name and table.
    pub tables: Vec<(String, String)>,
}

/// Writes `report.md`, `summary.csv` and the plots of the runs in `dir` into `to` (`dir` itself
/// but in tests).
pub fn report(dir: &Path, to: &Path, description: &str) -> Result<Report, String> {
    let (manifest, conds) = load(dir)?;
    if conds.is_empty() {
        return Err(format!("{}: no finished runs yet", dir.display()));
    }
    let mut md = String::new();
    let mut tables = Vec::new();
    let mut csv = String::from(
        "condition,runs,episodes,total_mean,total_ci95,per_episode,paper_total,paper_per_episode,last10_per_episode,final_mean,final_sd,entropy_first10,entropy_last10,entropy_fresh_last10,ltm_end,p_vs_reference,p_uncorrected\n",
    );
    writeln!(md, "# {}: {description}\n", manifest.experiment).unwrap();
    let fewest = conds.iter().map(|c| c.runs[0].len()).min().unwrap_or(0);
    let most = conds.iter().map(|c| c.runs[0].len()).max().unwrap_or(0);
    let episodes = if fewest == most { fewest.to_string() } else { format!("{fewest}-{most}") };
    writeln!(
        md,
        "Runs per condition: up to {} (seeds {:?}); episodes per run: {episodes} (the paper: 20 x 5000). \
         Reward is R_ep when positive, else 0; totals are summed over the run's episodes and the paper's are \
         over 5000, so compare the per-episode columns; the paper's final-episode reward (section 9) is for episode 5000. Entropy (bits) is the authors' stale-inclusive mean \
         per episode, averaged over the first and last 10% of the run; p is a two-sided Mann-Whitney U test \
         of the run totals against the group's first model (shown when both have at least 2 runs; over the \
         first episodes both have when their runs differ in length), \
         Bonferroni-corrected over the comparisons made within the group (a group is one figure or table of \
         the paper: a task, a memory size); summary.csv also has it uncorrected. Curves: {WINDOW}-episode \
         window, mean and standard error across runs.\n",
        manifest.seeds.len(),
        manifest.seeds,
    )
    .unwrap();
    let groups: Vec<String> = conds.iter().fold(Vec::new(), |mut g, c| {
        if !g.iter().any(|x| x == c.group()) {
            g.push(c.group().to_string());
        }
        g
    });
    fs::create_dir_all(to.join("plots")).map_err(|e| format!("{}: {e}", to.display()))?;
    for group in &groups {
        let members: Vec<&ConditionRuns> = conds.iter().filter(|c| c.group() == group).collect();
        let reference = members[0];
        // One run has no spread and no test, so a condition of one run (a sensitivity row, a
        // baseline still running) widens no one's correction.
        let tested_against_reference = |c: &ConditionRuns| c.runs.len() >= 2 && reference.runs.len() >= 2;
        let tested = members[1..].iter().filter(|c| tested_against_reference(c)).count();
        let bonferroni = tested.max(1) as f64;
        writeln!(md, "## {group}\n").unwrap();
        let table_start = md.len();
        writeln!(md, "| model | runs | total reward (95% CI) | per episode | paper: total (per episode) | last 10% per episode | final episode (sd) | entropy first 10% -> last 10% (fresh) | LTM at end | p vs {} |", reference.model()).unwrap();
        writeln!(md, "|---|---|---|---|---|---|---|---|---|---|").unwrap();
        for c in &members {
            let n = c.runs[0].len();
            let totals = c.totals();
            let finals: Vec<f64> = c.runs.iter().map(|r| r.last().map_or(0.0, |m| m.reward)).collect();
            let late = mean(&c.span_means(0.9, 1.0, |m| m.reward));
            let h0 = mean(&c.span_means(0.0, 0.1, |m| m.entropy));
            let h1 = mean(&c.span_means(0.9, 1.0, |m| m.entropy));
            let hf = c.fresh_entropy_late();
            let ltm = mean(&c.runs.iter().map(|r| r.last().map_or(0.0, |m| m.ltm as f64)).collect::<Vec<_>>());
            // One run has no spread and no test.
            let spread = |m: f64, h: f64, digits: usize| {
                if c.runs.len() < 2 {
                    format!("{m:.digits$}")
                } else {
                    format!("{m:.digits$} ± {h:.digits$}")
                }
            };
            // Runs of different lengths (DQN's 1000 episodes against SEC's 2000) are compared
            // over the episodes both have.
            let common = n.min(reference.runs[0].len());
            let raw = if std::ptr::eq(*c, reference) || !tested_against_reference(c) {
                None
            } else {
                Some(mann_whitney(&c.totals_over(common), &reference.totals_over(common)).1)
            };
            let p = raw.map(|p| (p * bonferroni).min(1.0));
            let paper = c.condition.paper_total;
            writeln!(
                md,
                "| {} | {} | {} | {:.3} | {} | {late:.3} | {} | {:.3} -> {:.3} ({}) | {:.0} | {} |",
                c.model(),
                c.runs.len(),
                spread(mean(&totals), ci95(&totals), 1),
                mean(&totals) / n as f64,
                paper.map_or("-".into(), |t| format!("{t:.1} ({:.3})", t / 5000.0)),
                spread(mean(&finals), sd(&finals), 3),
                h0,
                h1,
                if hf.is_nan() { "-".into() } else { format!("{hf:.3}") },
                ltm,
                p.map_or("-".into(), fmt_p),
            )
            .unwrap();
            writeln!(
                csv,
                "{},{},{n},{},{},{},{},{},{late},{},{},{h0},{h1},{},{ltm},{},{}",
                c.condition.name,
                c.runs.len(),
                mean(&totals),
                num(ci95(&totals)),
                mean(&totals) / n as f64,
                paper.map_or(String::new(), |t| t.to_string()),
                paper.map_or(String::new(), |t| (t / 5000.0).to_string()),
                mean(&finals),
                num(sd(&finals)),
                num(hf),
                p.map_or(String::new(), |p| p.to_string()),
                raw.map_or(String::new(), |p| p.to_string()),
            )
            .unwrap();
        }
        tables.push((format!("{}/{group}", manifest.experiment), md[table_start..].to_string()));
        let stem = group.replace('/', "-");
        let reward: Vec<Series> = members.iter().map(|c| series(c, |m| m.reward)).collect();
        let entropy: Vec<Series> = members.iter().map(|c| series(c, |m| m.entropy)).collect();
        plot::curves(
            &to.join("plots").join(format!("{stem}-reward")),
            &format!("{group}: reward"),
            "reward per episode",
            &reward,
        )?;
        plot::curves(
            &to.join("plots").join(format!("{stem}-entropy")),
            &format!("{group}: entropy"),
            "entropy (bits)",
            &entropy,
        )?;
        writeln!(md, "\n![{group} reward](plots/{stem}-reward.svg) ![{group} entropy](plots/{stem}-entropy.svg)\n")
            .unwrap();
    }
    if manifest.experiment == "exp2" {
        md += &memory_ratios(&conds);
    }
    let pairs = forgetting_pairs(&conds);
    if !pairs.is_empty() {
        md += "## same-seeds\n\n";
        md += FORGETTING_PAIRS_NOTE;
        let table_start = md.len();
        md += &pairs;
        tables.push((format!("{}/same-seeds", manifest.experiment), md[table_start..].to_string()));
    }
    fs::write(to.join("report.md"), &md).map_err(|e| format!("{}: {e}", to.display()))?;
    fs::write(to.join("summary.csv"), csv).map_err(|e| format!("{}: {e}", to.display()))?;
    Ok(Report { md, tables })
}

fn series(c: &ConditionRuns, f: impl Fn(&EpisodeMetrics) -> f64) -> Series {
    let (mean, se) = c.curve(f);
    Series { label: c.model().to_string(), mean, se }
}

/// Figure 6: SEC's total at each capacity over NSEC's at each capacity.
fn memory_ratios(conds: &[ConditionRuns]) -> String {
    let pick = |model: &str| -> Vec<(&str, f64)> {
        conds.iter().filter(|c| c.model() == model).map(|c| (c.group(), mean(&c.totals()))).collect()
    };
    let (sec, nsec) = (pick("SEC"), pick("NSEC"));
    let mut md = String::from("## Memory ratios (figure 6)\n\nSEC's mean total at the row's capacity over NSEC's at the column's (the paper: 2.4 / 2.0 / 1.9 / 1.6 on the diagonal, 1.2 for SEC 125 over NSEC 1000).\n\n| SEC \\ NSEC |");
    for (g, _) in &nsec {
        write!(md, " {g} |").unwrap();
    }
    md += "\n|---|";
    md += &"---|".repeat(nsec.len());
    md += "\n";
    for (gs, s) in &sec {
        write!(md, "| {gs} |").unwrap();
        for (_, n) in &nsec {
            write!(md, " {:.2} |", s / n).unwrap();
        }
        md += "\n";
    }
    md
}

const FORGETTING_PAIRS_NOTE: &str = "The same seed with and without forgetting. Forgetting acts only once the LTM is full, and a run is a pure function of its \
configuration and seed, so a run with forgetting and the run of the same seed without it are the same run until the \
LTM fills. What forgetting changes is what comes after: per seed, the reward per episode from the episode in which the run \
without forgetting first held m sequences (episodes counted from 1) to the run's end. A run whose LTM never filled has nothing after and counts for \
neither side. Descriptive only: the protocol's test is the table's Mann-Whitney over the whole runs.\n\n";

/// Each condition with forgetting against the condition of its group that differs from it only
/// in having none, over the seeds both have: the table of FORGETTING_PAIRS_NOTE, or nothing if
/// there is no such pair.
fn forgetting_pairs(conds: &[ConditionRuns]) -> String {
    let mut md = String::new();
    for c in conds {
        let memory = &c.condition.config.section::<SecConfig>().memory;
        if memory.forgetting == Forgetting::None {
            continue;
        }
        let mut without = c.condition.config.clone();
        without.section_mut::<SecConfig>().memory.forgetting = Forgetting::None;
        let Some(r) = conds.iter().find(|r| r.group() == c.group() && r.condition.config.same_run(&without)) else {
            continue;
        };
        let (mut fills, mut identical, mut after) = (Vec::new(), 0, [0.0, 0.0]);
        let (mut more, mut fewer, mut episodes_after) = (0, 0, 0);
        let seeds: Vec<u64> = c.seeds.iter().copied().filter(|s| r.seeds.contains(s)).collect();
        for seed in &seeds {
            fn run<'a>(x: &'a ConditionRuns, seed: &u64) -> &'a [EpisodeMetrics] {
                &x.runs[x.seeds.iter().position(|s| s == seed).unwrap()]
            }
            let (with, none) = (run(c, seed), run(r, seed));
            let fill = none.iter().position(|m| m.ltm >= memory.m).unwrap_or(none.len());
            identical += usize::from(with[..fill.min(with.len())] == none[..fill]);
            if fill == none.len() {
                continue;
            }
            fills.push(fill + 1);
            let reward = |x: &[EpisodeMetrics]| x.iter().map(|m| m.reward).sum::<f64>();
            let n = with.len().min(none.len());
            let (w, o) = (reward(&with[fill..n]), reward(&none[fill..n]));
            after[0] += o;
            after[1] += w;
            episodes_after += n - fill;
            more += usize::from(w > o);
            fewer += usize::from(w < o);
        }
        if md.is_empty() {
            md += "| model | against | seeds | LTM full in episode (runs) | identical until then | per episode from then: without -> with | with / without | seeds with more / fewer |\n";
            md += "|---|---|---|---|---|---|---|---|\n";
        }
        let filled = match (fills.iter().min(), fills.iter().max()) {
            (Some(a), Some(b)) => format!("{a}-{b} ({} of {})", fills.len(), seeds.len()),
            _ => format!("never (0 of {})", seeds.len()),
        };
        let per =
            |x: f64| if episodes_after == 0 { "-".to_string() } else { format!("{:.3}", x / episodes_after as f64) };
        let ratio = if after[0] > 0.0 { format!("{:.3}", after[1] / after[0]) } else { "-".into() };
        writeln!(
            md,
            "| {} | {} | {} | {filled} | {identical} of {} | {} -> {} | {ratio} | {more} / {fewer} |",
            c.model(),
            r.model(),
            seeds.len(),
            seeds.len(),
            per(after[0]),
            per(after[1]),
        )
        .unwrap();
    }
    md
}

/// A CSV number; empty where there is none (one run has no interval).
fn num(x: f64) -> String {
    if x.is_nan() {
        String::new()
    } else {
        x.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sec_playground::experiment::RunConfig;

    fn episode(reward: f64, ltm: usize) -> EpisodeMetrics {
        EpisodeMetrics {
            episode: 0,
            layout: String::new(),
            reward,
            raw_reward: reward,
            goal: reward > 0.0,
            env_steps: 0,
            decisions: 0,
            entropy: 0.0,
            entropy_fresh: None,
            ltm,
            contextual_share: 0.0,
            human: false,
            census: None,
        }
    }

    fn condition(name: &str, forgetting: Forgetting, runs: Vec<Vec<EpisodeMetrics>>) -> ConditionRuns {
        let mut config = RunConfig::default();
        config.section_mut::<SecConfig>().memory.m = 2;
        config.section_mut::<SecConfig>().memory.forgetting = forgetting;
        ConditionRuns {
            condition: ManifestCondition { name: name.into(), paper_total: None, config, plan: None },
            seeds: vec![1, 2],
            runs,
        }
    }

    #[test]
    fn forgetting_is_compared_with_the_same_seed_from_the_episode_the_ltm_filled() {
        // Seed 1's LTM fills in episode 2 (counted from 1); seed 2's never does.
        let none = vec![
            vec![episode(0.0, 1), episode(0.0, 2), episode(1.0, 2), episode(1.0, 2)],
            vec![episode(1.0, 0), episode(0.0, 1), episode(0.0, 1), episode(0.0, 1)],
        ];
        let mut fifo = none.clone();
        fifo[0][1].reward = 1.0;
        fifo[0][2].reward = 2.0;
        fifo[0][3].reward = 1.0;
        let conds =
            vec![condition("g/SEC-none", Forgetting::None, none), condition("g/SEC-fifo", Forgetting::Fifo, fifo)];
        let table = forgetting_pairs(&conds);
        assert!(
            table.contains("| SEC-fifo | SEC-none | 2 | 2-2 (1 of 2) | 2 of 2 | 0.667 -> 1.333 | 2.000 | 1 / 0 |"),
            "{table}"
        );
        // A run that differs before the LTM fills is not the same run: the comparison says so.
        let mut early = conds[1].runs.clone();
        early[1][0].reward = 0.0;
        let conds = vec![conds.into_iter().next().unwrap(), condition("g/SEC-fifo", Forgetting::Fifo, early)];
        assert!(forgetting_pairs(&conds).contains("| 1 of 2 |"));
        // No condition without forgetting to compare with: no table.
        assert!(forgetting_pairs(&conds[1..]).is_empty());
    }
}

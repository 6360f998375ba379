//! Why perception decides SEC's advantage over NSEC: which views each perception's embeddings
//! let match, measured over a reactive walk of the double T-maze, joined with the SEC/NSEC ratio
//! and contextual share the `perception` experiment measured with each.
//!
//! Without the bias a stored couplet is selected when G = 1 - MAE exceeds theta_abs 0.98 and
//! theta_prop 0.995 times the best G. Applying that rule with the walk's other views as the
//! memory (views fewer than 25 decisions apart excluded), the **matching breadth** (the effective
//! matching radius) is how many of the walk's views a view selects, and the distances say how far
//! from the view those are. A broad match lets NSEC act on memories of other places; the bias then
//! narrows recall to the successors of what was just recalled.

use crate::orderings::{arms, Arm};
use crate::plot;
use crate::stats::{mean, spearman};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use sec_playground::agent::Reactive;
use sec_playground::arena::Task;
use sec_playground::encoder::{Perception, PerceptionKind, Scratch, EMBEDDING, IMAGE};
use sec_playground::env::{Env, EnvConfig};
use sec_playground::experiment::presets;
use sec_playground::render::Surface;
use std::fmt::Write as _;
use std::fs;
use std::path::Path;

/// Frames closer than this many decisions in the walk are not compared (near copies).
const EXCLUDE: usize = 25;
/// theta_abs 0.98 at T = 1.
const RADIUS_MAE: f64 = 0.02;
/// theta_prop 0.995.
const THETA_PROP: f64 = 0.995;
/// Matched views farther apart than this (metres) count as another place.
const FAR: f64 = 5.0;

/// One perception's matching over the walks, pooled over seeds.
#[derive(Clone, Debug)]
pub struct Matching {
    /// The perception's name (trained, untrained x1, ...).
    pub arm: String,
    /// Median and 90 % quantile of each view's nearest-neighbour MAE.
    pub nn: [f64; 2],
    /// Every view's nearest-neighbour MAE, ascending.
    pub nn_all: Vec<f64>,
    /// Share of views with an identical embedding elsewhere in the walk (nearest-neighbour MAE 0).
    pub identical: f64,
    /// Share of views that select at least one other view.
    pub matched_views: f64,
    /// Views selected per view, mean.
    pub matches_per_view: f64,
    /// Median and 90 % quantile of the arena distance between a view and those it selects (m).
    pub radius: [f64; 2],
    /// Share of selected views farther than `FAR`.
    pub far: f64,
}

/// One view of a walk: the image, where it was taken, its frame's hash and its episode.
struct View {
    image: Vec<f32>,
    at: (f64, f64),
    hash: u64,
    episode: u32,
}

/// `frames` decisions of the reactive walk (4 env steps each) from `seed`, drawn with `surface`.
fn walk(task: &str, surface: Surface, frames: usize, seed: u64) -> Vec<View> {
    let task = Task::preset(task).expect("a task preset");
    let mut env = Env::new(EnvConfig { surface, ..EnvConfig::new(task) }, seed).expect("a preset's env");
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut reactive = Reactive::new(&mut rng);
    let mut out = Vec::with_capacity(frames);
    let mut episode = 0;
    while out.len() < frames {
        if env.is_over() {
            env.reset(None);
            episode += 1;
        }
        let a = reactive.step(&mut rng);
        env.advance(a, 4).expect("the episode is not over");
        let mut image = vec![0.0; IMAGE];
        env.observation().to_rgb_f32(&mut image);
        let p = env.world().agent.pos;
        out.push(View { image, at: (p.x as f64, p.y as f64), hash: env.observation().hash(), episode });
    }
    out
}

fn mae(a: &[f32; EMBEDDING], b: &[f32; EMBEDDING]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs() as f64).sum::<f64>() / EMBEDDING as f64
}

fn quantile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

/// One perception's matching over `walks` (one per seed), the perception made per seed.
fn measure(
    arm: &str,
    walks: &[(Vec<View>, u64)],
    perception: impl Fn(u64) -> Result<Perception, String>,
) -> Result<Matching, String> {
    let (mut nn, mut dist) = (Vec::new(), Vec::new());
    let (mut matched, mut views, mut pairs) = (0usize, 0usize, 0usize);
    for (walk, seed) in walks {
        let p = perception(*seed)?;
        let mut s = Scratch::default();
        let e: Vec<[f32; EMBEDDING]> = walk
            .iter()
            .map(|v| {
                let mut e = [0.0; EMBEDDING];
                p.embed(&v.image, &mut s, &mut e);
                e
            })
            .collect();
        let mut row = vec![0.0; e.len()];
        for i in 0..e.len() {
            for (j, r) in row.iter_mut().enumerate() {
                *r = if i.abs_diff(j) > EXCLUDE { mae(&e[i], &e[j]) } else { f64::INFINITY };
            }
            let best = row.iter().copied().fold(f64::INFINITY, f64::min);
            // NSEC's selection over the walk's other views: G = 1 - MAE above theta_abs and
            // above theta_prop times the best G.
            let gmax = 1.0 - best;
            let mut any = false;
            for (j, &m) in row.iter().enumerate() {
                if m < RADIUS_MAE && 1.0 - m > THETA_PROP * gmax {
                    any = true;
                    pairs += 1;
                    let ((xi, zi), (xj, zj)) = (walk[i].at, walk[j].at);
                    dist.push(((xi - xj).powi(2) + (zi - zj).powi(2)).sqrt());
                }
            }
            nn.push(best);
            matched += any as usize;
            views += 1;
        }
    }
    nn.sort_by(f64::total_cmp);
    dist.sort_by(f64::total_cmp);
    Ok(Matching {
        arm: arm.to_string(),
        nn: [quantile(&nn, 0.5), quantile(&nn, 0.9)],
        identical: nn.iter().filter(|&&v| v == 0.0).count() as f64 / nn.len().max(1) as f64,
        matched_views: matched as f64 / views as f64,
        matches_per_view: pairs as f64 / views as f64,
        radius: [quantile(&dist, 0.5), quantile(&dist, 0.9)],
        far: dist.iter().filter(|&&d| d > FAR).count() as f64 / dist.len().max(1) as f64,
        nn_all: nn,
    })
}

/// The matching of every arm of the `perception` experiment.
pub fn matching(frames: usize, seeds: &[u64]) -> Result<Vec<Matching>, String> {
    let arms = presets::experiment("perception").map_err(|e| e.to_string())?;
    let walks: Vec<_> = seeds.iter().map(|&s| (walk("double-t-maze", Surface::Flat, frames, s), s)).collect();
    let mut out = Vec::new();
    for c in arms.iter().filter(|c| c.name.ends_with("/SEC")) {
        out.push(measure(c.name.trim_end_matches("/SEC"), &walks, |seed| {
            Perception::new(c.config.perception, &c.config.task, c.config.scale_override(), seed)
                .map_err(|e| e.to_string())
        })?);
    }
    Ok(out)
}

/// How much each surface aliases views: the matching of the code preset's perception (the
/// untrained encoder at its raw scale) over reactive walks of the double T-maze drawn with that
/// surface, and the distinct frames per decision within an episode of the walk.
pub fn aliasing(frames: usize, seeds: &[u64]) -> Result<Vec<(Surface, Matching, [f64; 3])>, String> {
    let mut out = Vec::new();
    for (name, surface) in Surface::ALL {
        let walks: Vec<_> = seeds.iter().map(|&s| (walk("double-t-maze", surface, frames, s), s)).collect();
        let m = measure(name, &walks, |seed| {
            Perception::new(PerceptionKind::Untrained, "double-t-maze", None, seed).map_err(|e| e.to_string())
        })?;
        // Distinct frames per decision, per episode of each walk (the last, unfinished one left
        // out), averaged over episodes.
        let (mut shares, mut distinct, mut lengths) = (Vec::new(), Vec::new(), Vec::new());
        for (w, _) in &walks {
            let last = w.last().map_or(0, |v| v.episode);
            for e in 0..last {
                let mut hashes: Vec<u64> = w.iter().filter(|v| v.episode == e).map(|v| v.hash).collect();
                let n = hashes.len();
                hashes.sort_unstable();
                hashes.dedup();
                shares.push(hashes.len() as f64 / n as f64);
                distinct.push(hashes.len() as f64);
                lengths.push(n as f64);
            }
        }
        out.push((surface, m, [mean(&distinct), mean(&lengths), mean(&shares)]));
    }
    Ok(out)
}

/// The aliasing table (markdown): one row per surface.
pub fn aliasing_table(rows: &[(Surface, Matching, [f64; 3])], frames: usize, seeds: &[u64]) -> String {
    let mut md = format!(
        "{frames} views of a reactive walk of the double T-maze (one every 4 env steps) per seed, seeds {seeds:?}, \
         each drawn with the surface and embedded by the code preset's perception (the untrained encoder drawn from \
         the seed, raw scale); views fewer than {EXCLUDE} decisions apart are not compared. Identical view: the share \
         of views whose nearest other view has an embedding MAE of 0. Matching breadth: views a view selects by \
         NSEC's rule (G = 1 - MAE above 0.98 and 0.995 times the best G). Distinct frames: per finished episode of \
         the walk, its distinct frames, its decisions and their ratio, means over episodes.\n\n\
         | surface | identical view | views selecting one | matching breadth (views selected) | their distance median / 90 % (m) | selected > {FAR} m away | distinct frames per episode / decisions | distinct per decision |\n\
         |---|---|---|---|---|---|---|---|\n"
    );
    for (s, m, distinct) in rows {
        writeln!(
            md,
            "| {} | {:.1} % | {:.1} % | {:.1} | {:.1} / {:.1} | {:.1} % | {:.1} / {:.1} | {:.3} |",
            s.name(),
            100.0 * m.identical,
            100.0 * m.matched_views,
            m.matches_per_view,
            m.radius[0],
            m.radius[1],
            100.0 * m.far,
            distinct[0],
            distinct[1],
            distinct[2]
        )
        .unwrap();
    }
    md
}

/// Writes `matching.md`, `matching.csv` and `plots/ratio-vs-breadth.{svg,png}` into
/// `dir` (the `perception` experiment's directory), joining the distributions with the runs
/// there; returns the markdown and the part of it a page quotes (the table and the verdict on
/// the protocol's prediction).
pub fn report(dir: &Path, frames: usize, seeds: &[u64]) -> Result<(String, String), String> {
    let m = matching(frames, seeds)?;
    let runs = arms(dir);
    let arm = |label: &str, model: &str| runs.iter().find(|a| a.name == format!("{label}/{model}"));
    let mut md = format!(
        "# Perception and matching\n\n{frames} views of a reactive walk of the double T-maze (one every 4 env steps) per \
         seed, seeds {seeds:?} pooled (the untrained encoder is drawn from the seed), embedded by each perception of \
         the `perception` experiment. Each view selects the walk's other views (fewer than {EXCLUDE} decisions apart \
         excluded) as NSEC would select stored couplets: G = 1 - MAE above 0.98 and above 0.995 times the best G. \
         Matching breadth (the effective matching radius): the views a view selects, mean; their distance: the \
         median (and 90 %) arena distance between a view and the views it selects. Runs: runs x episodes of each of SEC and \
         NSEC (\"SEC / NSEC x episodes\" while the two differ). SEC, NSEC: mean reward per episode of the \
         `perception` experiment's runs; contextual share: the share of decisions the contextual layer took over \
         each run's last 10 % of episodes, mean over runs.\n\n"
    );
    let mut table = format!(
        "| perception | NN MAE median / 90 % | identical view (NN MAE 0) | views selecting one | matching breadth (views selected) | their distance median / 90 % (m) | selected > {FAR} m away | runs | SEC | NSEC | SEC/NSEC | contextual share SEC / NSEC |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|\n"
    );
    let mut csv = String::from(
        "perception,nn_median,nn_q90,identical,matched_views,matches_per_view,radius_median,radius_q90,far_share,runs,sec,nsec,ratio,ctx_sec,ctx_nsec\n",
    );
    let mut points = Vec::new();
    let loaded = crate::report::load(dir).ok();
    let ctx = |name: &str| -> Option<f64> {
        let c = loaded.as_ref()?.1.iter().find(|c| c.condition.name == name)?;
        Some(mean(&c.span_means(0.9, 1.0, |m| m.contextual_share)))
    };
    for x in &m {
        let (s, n) = (arm(&x.arm, "SEC"), arm(&x.arm, "NSEC"));
        let ratio = s.zip(n).map(|(s, n)| s.per_episode / n.per_episode);
        let (cs, cn) = (ctx(&format!("{}/SEC", x.arm)), ctx(&format!("{}/NSEC", x.arm)));
        let f = |v: Option<f64>, d: usize| v.map_or("-".to_string(), |v| format!("{v:.d$}"));
        writeln!(
            table,
            "| {} | {:.4} / {:.4} | {:.1} % | {:.1} % | {:.1} | {:.1} / {:.1} | {:.1} % | {} | {} | {} | {} | {} / {} |",
            x.arm,
            x.nn[0],
            x.nn[1],
            100.0 * x.identical,
            100.0 * x.matched_views,
            x.matches_per_view,
            x.radius[0],
            x.radius[1],
            100.0 * x.far,
            runs_column(s, n),
            f(s.map(|a| a.per_episode), 3),
            f(n.map(|a| a.per_episode), 3),
            f(ratio, 2),
            f(cs, 2),
            f(cn, 2),
        )
        .unwrap();
        let o = |v: Option<f64>| v.map_or(String::new(), |v| v.to_string());
        writeln!(
            csv,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            x.arm,
            x.nn[0],
            x.nn[1],
            x.identical,
            x.matched_views,
            x.matches_per_view,
            x.radius[0],
            x.radius[1],
            x.far,
            s.map_or(0, |a| a.runs),
            o(s.map(|a| a.per_episode)),
            o(n.map(|a| a.per_episode)),
            o(ratio),
            o(cs),
            o(cn)
        )
        .unwrap();
        if let Some(r) = ratio.filter(|_| x.matches_per_view > 0.0) {
            points.push((x.arm.clone(), x.matches_per_view, r));
        }
    }
    if points.len() == m.len() && points.len() > 2 {
        let counts: Vec<usize> =
            m.iter().flat_map(|x| ["SEC", "NSEC"].map(|model| arm(&x.arm, model).map_or(0, |a| a.runs))).collect();
        let (fewest, most) = (counts.iter().min().unwrap(), counts.iter().max().unwrap());
        let runs = if fewest == most { format!("{fewest}") } else { format!("{fewest}-{most}") };
        table += &prediction(&points, &runs);
    }
    md += &table;
    fs::create_dir_all(dir.join("plots")).map_err(|e| format!("{}: {e}", dir.display()))?;
    let samples: Vec<(String, Vec<f64>)> = m.iter().map(|x| (x.arm.clone(), x.nn_all.clone())).collect();
    // Up to past the broadest 90 % quantile, and past the matching radius in any case.
    let xmax = m.iter().map(|x| x.nn[1]).fold(2.0 * RADIUS_MAE, f64::max) * 1.25;
    plot::distributions(
        &dir.join("plots").join("nearest-neighbour-mae"),
        "Each view's nearest other view of the walk, by perception",
        "nearest-neighbour MAE of the embeddings",
        &samples,
        xmax,
        (RADIUS_MAE, " theta_abs 0.98: MAE 0.02"),
    )?;
    md += "\n![The nearest-neighbour MAE's distribution by perception](plots/nearest-neighbour-mae.svg)\n";
    if !points.is_empty() {
        plot::scatter(
            &dir.join("plots").join("ratio-vs-breadth"),
            "SEC/NSEC against the matching breadth",
            "matching breadth: views of the walk a view selects without the bias (log scale)",
            "SEC / NSEC reward",
            &points,
        )?;
        md += "\n![SEC/NSEC against the matching breadth](plots/ratio-vs-breadth.svg)\n";
    }
    fs::write(dir.join("matching.md"), &md).map_err(|e| format!("{}: {e}", dir.display()))?;
    fs::write(dir.join("matching.csv"), csv).map_err(|e| format!("{}: {e}", dir.display()))?;
    Ok((md, table))
}

/// The table's runs column: "runs x episodes", with SEC's and NSEC's counts apart while they differ
/// (a partial grid).
fn runs_column(sec: Option<&Arm>, nsec: Option<&Arm>) -> String {
    match (sec, nsec) {
        (Some(s), Some(n)) if s.runs != n.runs => format!("{} / {} x {}", s.runs, n.runs, s.episodes),
        (Some(a), _) | (None, Some(a)) => format!("{} x {}", a.runs, a.episodes),
        (None, None) => "-".into(),
    }
}

/// The verdict on the prediction results/PROTOCOL.md states before the `perception` runs: SEC/NSEC
/// falls as the matching breadth falls, failing where the ratios' order differs from the
/// breadths' and counted a failure where Spearman's correlation of the two is below 0.7.
/// `runs`: how many runs each of SEC and NSEC has per arm ("6", or "2-3" while the grid is partial).
fn prediction(points: &[(String, f64, f64)], runs: &str) -> String {
    let (breadth, ratio): (Vec<f64>, Vec<f64>) = points.iter().map(|p| (p.1, p.2)).unzip();
    let rho = spearman(&breadth, &ratio);
    let mut by_breadth: Vec<&(String, f64, f64)> = points.iter().collect();
    by_breadth.sort_by(|a, b| b.1.total_cmp(&a.1));
    let same_order = by_breadth.windows(2).all(|w| w[0].2 >= w[1].2);
    let order: Vec<String> = by_breadth.iter().map(|p| format!("{} {:.2}", p.0, p.2)).collect();
    let verdict = match (same_order, rho >= 0.7) {
        (true, _) => "holds: the ratios fall in the order of the breadths",
        (false, true) => {
            "mixed: the ratios do not fall in the order of the breadths (the stated order fails), but Spearman's \
             rho is not below 0.7 (the stated threshold passes)"
        }
        (false, false) => "fails: Spearman's correlation is below 0.7",
    };
    format!(
        "\n**The protocol's prediction** (SEC/NSEC falls as the matching breadth falls; fails below a Spearman \
         correlation of 0.7): {verdict}. Spearman's rho of breadth and SEC/NSEC over the {} arms ({runs} runs each of SEC \
         and NSEC): {rho:.2}. SEC/NSEC from the broadest to the narrowest matching: {}.\n",
        points.len(),
        order.join(", ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arms(ratios: &[f64]) -> Vec<(String, f64, f64)> {
        let breadths = [475.0, 153.0, 96.0, 91.0, 77.0];
        ratios.iter().zip(breadths).enumerate().map(|(i, (&r, b))| (format!("a{i}"), b, r)).collect()
    }

    #[test]
    fn the_prediction_is_judged_by_order_then_by_spearman() {
        assert!(prediction(&arms(&[2.0, 1.6, 1.3, 1.1, 1.1]), "6").contains(": holds: the ratios fall"));
        // One neighbouring pair swapped: rho 0.9.
        let one_swap = prediction(&arms(&[2.0, 1.3, 1.6, 1.1, 1.0]), "6");
        assert!(
            one_swap.contains(": mixed: the ratios do not fall in the order of the breadths")
                && one_swap.contains("rho of breadth and SEC/NSEC over the 5 arms (6 runs each of SEC and NSEC): 0.90"),
            "{one_swap}"
        );
        assert!(prediction(&arms(&[1.0, 1.6, 1.3, 1.1, 2.0]), "6").contains("fails"));
    }

    #[test]
    fn the_runs_column_shows_both_counts_while_they_differ() {
        let arm = |runs| Arm {
            name: String::new(),
            runs,
            episodes: 2000,
            per_episode: 1.0,
            totals: None,
            rewards: None,
            entropy_late: None,
            entropy_late_mean: 0.0,
            p_vs_reference: None,
        };
        assert_eq!(runs_column(Some(&arm(6)), Some(&arm(6))), "6 x 2000");
        assert_eq!(runs_column(Some(&arm(3)), Some(&arm(2))), "3 / 2 x 2000");
        assert_eq!(runs_column(None, Some(&arm(2))), "2 x 2000");
        assert_eq!(runs_column(None, None), "-");
    }
}

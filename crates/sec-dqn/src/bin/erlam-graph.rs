//! What the graph in an ERLAM run's checkpoint holds, the values its network is pulled toward:
//! `erlam-graph RUN.jsonl.ckpt` (a run in progress keeps its checkpoint next to its log).
//! REPRODUCTION.md quotes it.

use sec_dqn::graph::Census;
use sec_playground::experiment::checkpoint::Header;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [path] = args.as_slice() else {
        eprintln!("usage: erlam-graph RUN.jsonl.ckpt");
        std::process::exit(2);
    };
    if let Err(e) = report(path) {
        eprintln!("erlam-graph: {path}: {e}");
        std::process::exit(1);
    }
}

fn report(path: &str) -> Result<(), String> {
    let mut input = std::io::BufReader::new(std::fs::File::open(path).map_err(|e| e.to_string())?);
    let header = Header::read(&mut input).map_err(|e| e.to_string())?;
    let c = sec_dqn::checkpoint::graph(&header.config, &mut input)?.census();
    let share = |k: usize| 100.0 * k as f64 / c.nodes.max(1) as f64;
    let q = |p| Census::quantile(&c.values, p).unwrap_or(0.0);
    let h = |p| Census::quantile(&c.hops, p).unwrap_or(0);
    let above = c.values.iter().filter(|&&v| v > c.max_reward).count();
    println!("{} seed {}, after {} episodes: {} nodes", header.config.task, header.seed, header.episodes, c.nodes);
    println!("  a value link for the node's own action: {} ({:.1} %)", c.valued, share(c.valued));
    println!(
        "  rewarded: {} (largest reward {:.3}); terminal with a successor: {}",
        c.rewarded, c.max_reward, c.rewarded_linked
    );
    println!(
        "  graph value, quantiles 5/25/50/75/95 %: {:.3} {:.3} {:.3} {:.3} {:.3}; above the largest reward: {} ({:.1} %)",
        q(0.05),
        q(0.25),
        q(0.5),
        q(0.75),
        q(0.95),
        above,
        share(above)
    );
    println!(
        "  with a path to a rewarded node: {} ({:.1} %), links 5/25/50/75/95 %: {} {} {} {} {}",
        c.hops.len(),
        share(c.hops.len()),
        h(0.05),
        h(0.25),
        h(0.5),
        h(0.75),
        h(0.95)
    );
    Ok(())
}

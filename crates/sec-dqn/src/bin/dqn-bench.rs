//! DQN's speed on one core: the network's decision (one frame's Q) and a training step (batch 32,
//! online and target networks, backward, RMSprop), and the multiply-adds per second they reach.
//! `cargo run --release -p sec-dqn --bin dqn-bench` (BENCHMARKS.md has the numbers).
//! `dqn-bench --graph RUN.jsonl.ckpt` times a value propagation of the graph an ERLAM run's
//! checkpoint holds (a real graph, whose merged states form long chains) instead.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use sec_dqn::graph::{Graph, Pending};
use sec_dqn::Dqn;
use sec_dqn::DqnConfig;
use sec_dqn::ErlamConfig;
use sec_playground::agent::controller::{Controller, Step};
use sec_playground::experiment::checkpoint::Header;
use std::time::Instant;

/// Multiply-adds of one frame's forward pass: the three convolutions and the two dense layers.
const FORWARD_MACS: f64 = (20.0 * 20.0 * 32.0 * 192.0)
    + (9.0 * 9.0 * 64.0 * 512.0)
    + (7.0 * 7.0 * 64.0 * 576.0)
    + (3136.0 * 512.0)
    + (512.0 * 9.0);

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let [flag, path] = args.as_slice() {
        if flag == "--graph" {
            if let Err(e) = real_graph(path) {
                eprintln!("dqn-bench: {path}: {e}");
                std::process::exit(1);
            }
            return;
        }
    }
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let mut dqn = Dqn::new(DqnConfig::default(), 1, &mut rng).expect("the defaults are valid");
    for k in 0..64u32 {
        let frame = vec![(k % 200) as f32 / 255.0; 84 * 84 * 3];
        let step = Step {
            reward: -0.001,
            episode_reward: -0.1,
            good_goal: false,
            goal_event: false,
            decides: true,
            done: false,
        };
        dqn.on_step(&step, Some(&frame), &mut rng);
    }
    let img = vec![0.3f32; 84 * 84 * 3];
    let n = 200;
    dqn.q(&img);
    let t0 = Instant::now();
    for _ in 0..n {
        std::hint::black_box(dqn.q(&img));
    }
    let decide = t0.elapsed().as_secs_f64() / n as f64;
    dqn.train_step(&mut rng);
    let steps = 30;
    let t0 = Instant::now();
    for _ in 0..steps {
        std::hint::black_box(dqn.train_step(&mut rng));
    }
    let train = t0.elapsed().as_secs_f64() / steps as f64;
    // A training step: the online forward and its backward (about twice a forward) and the
    // target's forward, each over the batch.
    let train_macs = FORWARD_MACS * 32.0 * 4.0;
    println!(
        "decision (one frame's Q): {:.2} ms, {:.0}/s, {:.2} GMAC/s",
        decide * 1e3,
        1.0 / decide,
        FORWARD_MACS / decide / 1e9
    );
    println!(
        "training step (batch 32): {:.1} ms, {:.1}/s, {:.2} GMAC/s",
        train * 1e3,
        1.0 / train,
        train_macs / train / 1e9
    );
    // The authors' schedule: 250 decisions and 62.5 training steps per 1000-step episode.
    let episode = 250.0 * decide + 62.5 * train;
    println!(
        "a 1000-step double T-maze episode: about {:.1} s of network time; 1000 episodes: {:.0} min",
        episode,
        episode * 1000.0 / 60.0
    );
    erlam_graph(&mut rng);
}

/// ERLAM's graph work near its capacity: adding a 250-transition episode (the k-d tree rebuilt,
/// the merges, the evictions) and a value propagation, with random 20-number embeddings (frames
/// left empty: the graph only moves them).
fn erlam_graph(rng: &mut ChaCha8Rng) {
    let cfg = ErlamConfig::default();
    let mut g = Graph::new(cfg.clone(), 0.99);
    let episode = |rng: &mut ChaCha8Rng, g: &mut Graph| {
        for i in 0..250 {
            let embedding = std::array::from_fn(|_| rng.gen_range(0.0f32..1.0));
            let reward = if i == 249 { 2.997 } else { -0.001 };
            let action = rng.gen_range(0..9);
            g.remember(Pending { embedding, state: vec![], next_state: vec![], action, reward, done: i == 249 });
        }
    };
    while g.len() < cfg.nodes - 1 {
        episode(rng, &mut g);
        g.end_episode();
    }
    let n = 20;
    let t0 = Instant::now();
    for _ in 0..n {
        episode(rng, &mut g);
        g.end_episode();
    }
    let add = t0.elapsed().as_secs_f64() / n as f64;
    let t0 = Instant::now();
    g.propagate(cfg.propagate_every);
    let propagate = t0.elapsed().as_secs_f64();
    println!(
        "ERLAM graph at {} nodes: an episode added in {:.0} ms; a propagation {:.2} s ({} sweeps)",
        g.len(),
        add * 1e3,
        propagate,
        g.last_sweeps
    );
}

/// A value propagation of the graph in an ERLAM run's checkpoint.
fn real_graph(path: &str) -> Result<(), String> {
    let mut input = std::io::BufReader::new(std::fs::File::open(path).map_err(|e| e.to_string())?);
    let header = Header::read(&mut input).map_err(|e| e.to_string())?;
    let mut g = sec_dqn::checkpoint::graph(&header.config, &mut input)?;
    // Checkpoints fall on propagation episodes, so the graph is already propagated: the run's
    // own propagation took `last_sweeps` sweeps (saved with the graph); time one sweep now.
    let run_sweeps = g.last_sweeps;
    let t0 = Instant::now();
    g.propagate(sec_dqn::config::erlam(&header.config).map_err(|e| e.to_string())?.propagate_every);
    let sweep = t0.elapsed().as_secs_f64() / g.last_sweeps as f64;
    println!(
        "ERLAM graph of {} ({} episodes, seed {}): {} nodes; the run's last propagation took {} sweeps; a sweep {:.1} ms, so about {:.2} s",
        header.config.task,
        header.episodes,
        header.seed,
        g.len(),
        run_sweeps,
        sweep * 1e3,
        sweep * run_sweeps as f64
    );
    Ok(())
}

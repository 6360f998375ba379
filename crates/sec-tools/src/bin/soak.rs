//! The soak benchmark (BENCHMARKS.md, "Soak"): one SEC run of 1,000,000 decisions with forgetting
//! on, the process's resident memory sampled every 50,000, to show that a long run in the page
//! (which runs the same core) holds its memory flat.
//!
//! `cargo run --release -p sec-tools --bin soak -- DECISIONS FORGETTING` (defaults 1000000, fifo)

use sec_playground::agent::SecConfig;
use sec_playground::experiment::{Run, RunConfig};
use sec_playground::memory::Forgetting;
use std::time::Instant;

/// Resident set size in KiB, from /proc (Linux).
fn rss_kib() -> u64 {
    let statm = std::fs::read_to_string("/proc/self/statm").unwrap_or_default();
    let pages: u64 = statm.split_whitespace().nth(1).and_then(|v| v.parse().ok()).unwrap_or(0);
    pages * 4
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let decisions: u64 = args.first().and_then(|v| v.parse().ok()).unwrap_or(1_000_000);
    let forgetting = match args.get(1).map(String::as_str) {
        None | Some("fifo") => Forgetting::Fifo,
        Some(other) => Forgetting::parse(other).unwrap_or_else(|e| {
            eprintln!("soak: {e}");
            std::process::exit(2)
        }),
    };
    let mut cfg = RunConfig { task: "object-permanence".into(), ..RunConfig::default() };
    cfg.section_mut::<SecConfig>().memory.forgetting = forgetting;
    cfg.section_mut::<SecConfig>().memory.m = 100;
    let mut run = Run::new(cfg, 1).expect("a valid configuration");
    let t0 = Instant::now();
    let (mut episodes, mut done) = (0u64, 0u64);
    println!("| decisions | episodes | LTM sequences | RSS (MiB) | seconds |");
    println!("|---:|---:|---:|---:|---:|");
    while done < decisions {
        let t = run.decision();
        done += t.decision.is_some() as u64;
        episodes += t.finished.is_some() as u64;
        if done % 50_000 == 0 && t.decision.is_some() {
            let ltm = run.inspect().memory.map_or(0, |m| m.len());
            let rss = rss_kib() as f64 / 1024.0;
            println!("| {done} | {episodes} | {ltm} | {rss:.1} | {:.0} |", t0.elapsed().as_secs_f64());
        }
    }
}

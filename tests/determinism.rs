//! A run is a pure function of (configuration, seed): the scripted run of every task must equal
//! the checked-in trace bit for bit. `tests/wasm.rs` checks the same file under Node, so native
//! and wasm agree. `SEC_UPDATE_GOLDEN=1` rewrites the trace.
#![cfg(not(target_arch = "wasm32"))]

use sec_playground::arena::trace::scripted_run;
use sec_playground::arena::TASK_NAMES;

const SEED: u64 = 7;
const STEPS: u32 = 200;

#[test]
fn scripted_runs_match_the_golden_trace() {
    let log: String = TASK_NAMES.iter().map(|t| scripted_run(t, SEED, STEPS).unwrap()).collect();
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/golden/trace.txt");
    if std::env::var("SEC_UPDATE_GOLDEN").is_ok_and(|v| v == "1") {
        std::fs::write(path, &log).unwrap();
    }
    let golden = std::fs::read_to_string(path).unwrap();
    for (i, (a, b)) in log.lines().zip(golden.lines()).enumerate() {
        assert_eq!(a, b, "trace line {} differs", i + 1);
    }
    assert_eq!(log.lines().count(), golden.lines().count());
    // The script reaches episode ends, so resets are covered too.
    assert!(golden.contains("# reset"), "the trace never resets");
}

#[test]
fn different_seeds_give_different_runs() {
    assert_ne!(scripted_run("double-t-maze", 1, 50).unwrap(), scripted_run("double-t-maze", 2, 50).unwrap());
    assert_eq!(scripted_run("cylinder", 3, 50).unwrap(), scripted_run("cylinder", 3, 50).unwrap());
}

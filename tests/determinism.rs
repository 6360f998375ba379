//! A run is a pure function of (configuration, seed): the scripted run of every task must equal
//! the checked-in trace bit for bit, drawn flat (`trace.txt`) and textured (`trace-textured.txt`).
//! `tests/wasm.rs` checks the same files under Node and the Python suite through the wheel, so
//! every target agrees; `trace-pushables.txt` is an Olympics arena whose boxes the agent pushes
//! (rapier3d's rigid bodies), checked natively and under Node. `SEC_UPDATE_GOLDEN=1` rewrites the
//! traces.
#![cfg(not(target_arch = "wasm32"))]

use sec_playground::arena::TASK_NAMES;
use sec_playground::env::trace::scripted_run;
use sec_playground::render::Surface;

const SEED: u64 = 7;
const STEPS: u32 = 200;

fn check_trace(surface: Surface, file: &str) -> String {
    let log: String = TASK_NAMES.iter().map(|t| scripted_run(t, surface, SEED, STEPS).unwrap()).collect();
    let path = format!("{}/tests/golden/{file}", env!("CARGO_MANIFEST_DIR"));
    if std::env::var("SEC_UPDATE_GOLDEN").is_ok_and(|v| v == "1") {
        std::fs::write(&path, &log).unwrap();
    }
    let golden = std::fs::read_to_string(&path).unwrap();
    for (i, (a, b)) in log.lines().zip(golden.lines()).enumerate() {
        assert_eq!(a, b, "{file}: line {} differs", i + 1);
    }
    assert_eq!(log.lines().count(), golden.lines().count());
    // The script reaches episode ends, so resets are covered too.
    assert!(golden.contains("# reset"), "the trace never resets");
    golden
}

#[test]
fn scripted_runs_match_the_golden_trace() {
    check_trace(Surface::Flat, "trace.txt");
}

#[test]
fn textured_scripted_runs_match_their_golden_trace_and_draw_other_frames() {
    let textured = check_trace(Surface::Textured, "trace-textured.txt");
    let flat = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/golden/trace.txt")).unwrap();
    // The same steps (the surface changes no physics), other frames.
    fn cols(l: &str) -> Vec<&str> {
        l.split(' ').collect()
    }
    let (mut same_steps, mut other_frames) = (0, 0);
    for (a, b) in flat.lines().zip(textured.lines()).filter(|(a, _)| !a.starts_with('#')) {
        let (a, b) = (cols(a), cols(b));
        same_steps += (a[..7] == b[..7]) as usize;
        other_frames += (a[7] != b[7]) as usize;
    }
    assert_eq!(same_steps, TASK_NAMES.len() * STEPS as usize);
    assert!(other_frames > TASK_NAMES.len() * STEPS as usize * 9 / 10, "only {other_frames} frames differ");
}

#[test]
fn different_seeds_give_different_runs() {
    let run = |task, seed| scripted_run(task, Surface::Flat, seed, 50).unwrap();
    assert_ne!(run("double-t-maze", 1), run("double-t-maze", 2));
    assert_eq!(run("cylinder", 3), run("cylinder", 3));
}

/// The Olympics arena of the pushable boxes' golden trace: a row of eight Cardbox1 between the
/// agent and the goal, which the script's forward runs push.
const PUSHABLES_FILE: &str = "03-22-01";

#[test]
fn a_scripted_run_pushing_boxes_matches_its_golden_trace() {
    let path = format!("{}/assets/arenas/competition/{PUSHABLES_FILE}.yaml", env!("CARGO_MANIFEST_DIR"));
    let task = sec_playground::arena::yaml::load_task(PUSHABLES_FILE, &std::fs::read_to_string(path).unwrap()).unwrap();
    let log = sec_playground::env::trace::scripted_task_run(task, Surface::Flat, SEED, 300).unwrap();
    let path = format!("{}/tests/golden/trace-pushables.txt", env!("CARGO_MANIFEST_DIR"));
    if std::env::var("SEC_UPDATE_GOLDEN").is_ok_and(|v| v == "1") {
        std::fs::write(&path, &log).unwrap();
    }
    assert_eq!(log, std::fs::read_to_string(&path).unwrap(), "trace-pushables.txt");
    // The script pushes boxes: their places (the columns after the frame hash) change.
    let places: std::collections::BTreeSet<&str> =
        log.lines().filter(|l| !l.starts_with('#')).flat_map(|l| l.split(' ').skip(8)).collect();
    assert!(places.len() > 8 + 20, "the boxes took {} places in 300 steps", places.len());
}

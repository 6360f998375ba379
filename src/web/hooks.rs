//! The page's test flavour only (`--features test-hooks`, built into `pkg/hooks/`): timing loops
//! for the benchmarks, the scripted determinism run and a deliberate panic for the page's error
//! path. None of it is in the published build or its `.d.ts`.

use super::run::SecRun;
use super::{args, js_err, seed_from_js};
use crate::arena::Task;
use crate::encoder::{bundled, Scratch, EMBEDDING, IMAGE};
use crate::env::{trace, Env, EnvConfig};
use crate::render::Surface;
use wasm_bindgen::prelude::*;

/// The most iterations a test-hook loop takes (a count from JS is checked like the public API's).
const MAX_LOOP: u64 = 10_000_000;

/// The scripted determinism run (see `env::trace`), for cross-target checks; `surface` is
/// "flat" (or absent) or "textured".
#[wasm_bindgen(js_name = scriptedRun)]
pub fn scripted_run(task: &str, seed: f64, steps: JsValue, surface: Option<String>) -> Result<String, JsError> {
    let steps = args::whole(&steps, "steps", 0, MAX_LOOP)? as u32;
    let surface = match surface.as_deref() {
        None => Surface::Flat,
        Some(v) => Surface::from_name(v).map_err(|e| JsError::new(&format!("surface: {e}")))?,
    };
    trace::scripted_run(task, surface, seed_from_js(&JsValue::from_f64(seed))?, steps).map_err(js_err)
}

/// Benchmark helper: `n` physics-only env steps of the shared script (see `bench/wasm-bench.mjs`).
#[wasm_bindgen(js_name = benchEnvSteps)]
pub fn bench_env_steps(task: &str, n: JsValue) -> Result<f64, JsError> {
    let n = args::whole(&n, "n", 0, MAX_LOOP)? as u32;
    let mut env = Env::new(EnvConfig::new(Task::preset(task).map_err(js_err)?), 1).map_err(js_err)?;
    Ok(trace::bench_env_steps(&mut env, n))
}

/// Benchmark helper: `n` camera renders cycling through the benchmark poses of a task.
#[wasm_bindgen(js_name = benchRenders)]
pub fn bench_renders(task: &str, n: JsValue) -> Result<u32, JsError> {
    let n = args::whole(&n, "n", 0, MAX_LOOP)? as u32;
    let worlds = trace::bench_worlds(task).map_err(js_err)?;
    let mut cam = crate::render::Camera::new();
    let mut frame = crate::render::Frame::new();
    let mut acc = 0u32;
    for i in 0..n as usize {
        cam.render(&worlds[i % worlds.len()], &mut frame);
        acc = acc.wrapping_add(frame.rgba[i % frame.rgba.len()] as u32);
    }
    Ok(acc)
}

/// Benchmark helper: `n` encodes (`decode` false) or decodes of a T-maze frame with the bundled
/// T-maze model; returns a checksum.
#[wasm_bindgen(js_name = benchAutoencoder)]
pub fn bench_autoencoder(n: JsValue, decode: bool) -> Result<f32, JsError> {
    let n = args::whole(&n, "n", 0, MAX_LOOP)? as u32;
    let mut env = Env::new(EnvConfig::new(Task::preset("double-t-maze").map_err(js_err)?), 3).map_err(js_err)?;
    let mut img = vec![0.0; IMAGE];
    env.observation().to_rgb_f32(&mut img);
    let ae = bundled::autoencoder("double-t-maze").map_err(js_err)?;
    let mut s = Scratch::default();
    let mut e = [0.0; EMBEDDING];
    let mut rec = Vec::new();
    let mut acc = 0.0;
    ae.encode(&img, &mut s, &mut e);
    for _ in 0..n {
        if decode {
            ae.decode(&e, &mut s, &mut rec);
            acc += rec[0];
        } else {
            ae.encode(&img, &mut s, &mut e);
            acc += e[0];
        }
    }
    Ok(acc)
}

/// Test hook for the page's error path: panics, which traps the wasm instance like a bug would.
#[wasm_bindgen(js_name = panicForTest)]
pub fn panic_for_test() {
    panic!("panicForTest: testing the page's error path")
}

#[wasm_bindgen]
impl SecRun {
    /// Benchmark helper: fills the LTM with `rows` sequences of real embeddings (see
    /// `experiment::fixtures::fill_ltm`), so decisions can be timed over a full memory.
    #[wasm_bindgen(js_name = benchFillMemory)]
    pub fn bench_fill_memory(&mut self, rows: JsValue) -> Result<(), JsError> {
        let rows = args::whole(&rows, "rows", 0, crate::memory::M_RANGE.1 as u64)? as usize;
        crate::experiment::fixtures::fill_ltm(self.session.run_mut(), rows);
        Ok(())
    }
}

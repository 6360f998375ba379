//! Under `wasm-pack test --node`: the wasm build reproduces the native golden trace bit for bit,
//! and the JS API refuses bad values with the parameter named.
#![cfg(target_arch = "wasm32")]

use sec_playground::arena::trace::scripted_run;
use sec_playground::arena::TASK_NAMES;
use sec_playground::web::ArenaEnv;
use wasm_bindgen_test::*;

const GOLDEN: &str = include_str!("golden/trace.txt");

#[wasm_bindgen_test]
fn wasm_matches_the_native_golden_trace() {
    let log: String = TASK_NAMES.iter().map(|t| scripted_run(t, 7, 200).unwrap()).collect();
    for (i, (a, b)) in log.lines().zip(GOLDEN.lines()).enumerate() {
        assert_eq!(a, b, "trace line {} differs between wasm and native", i + 1);
    }
    assert_eq!(log.lines().count(), GOLDEN.lines().count());
}

fn message(e: wasm_bindgen::JsError) -> String {
    let v: wasm_bindgen::JsValue = e.into();
    js_sys::Error::from(v).message().into()
}

#[wasm_bindgen_test]
fn the_js_api_validates_its_inputs() {
    assert!(message(ArenaEnv::new("nope", 1.0, None).err().unwrap()).contains("task"));
    assert!(message(ArenaEnv::new("detour", -1.0, None).err().unwrap()).starts_with("seed:"));
    assert!(message(ArenaEnv::new("detour", 0.5, None).err().unwrap()).starts_with("seed:"));
    assert!(message(ArenaEnv::new("detour", 1.0, Some(1e9)).err().unwrap()).starts_with("t:"));
    let mut env = ArenaEnv::new("detour", 1.0, Some(50.0)).unwrap();
    let e = message(env.step(9).err().unwrap());
    assert!(e.contains("action") && e.contains("0..=8"), "{e}");
    assert!(message(env.top_down(5).err().unwrap()).contains("32..=2048"));
    // A refused call changed nothing: the run goes on.
    assert!(env.step(3).is_ok());
    assert_eq!(env.observation().len(), 84 * 84 * 4);
    let e = ArenaEnv::from_yaml("x", "arenas:\n  0:\n    items:\n    - name: Ramp\n", 1.0, None).err().unwrap();
    assert!(message(e).contains("line 4"));
}

#[wasm_bindgen_test]
fn wasm_gives_the_native_golden_embedding() {
    use sec_playground::arena::{Env, EnvConfig, Task};
    use sec_playground::encoder::{Autoencoder, Scratch, EMBEDDING, IMAGE};
    let mut env = Env::new(EnvConfig::new(Task::preset("double-t-maze").unwrap()), 1).unwrap();
    let mut rgb = vec![0.0; IMAGE];
    env.observation().to_rgb_f32(&mut rgb);
    let mut e = [0.0; EMBEDDING];
    Autoencoder::glorot(1).encode(&rgb, &mut Scratch::default(), &mut e);
    let text: String = e.iter().map(|v| format!("{:08x}\n", v.to_bits())).collect();
    assert_eq!(text, include_str!("golden/embedding.txt"));
}

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
    use sec_playground::encoder::{bundled, Scratch, EMBEDDING, IMAGE};
    let mut env = Env::new(EnvConfig::new(Task::preset("double-t-maze").unwrap()), 1).unwrap();
    let mut rgb = vec![0.0; IMAGE];
    env.observation().to_rgb_f32(&mut rgb);
    let ae = bundled::autoencoder("double-t-maze").unwrap();
    let mut e = [0.0; EMBEDDING];
    ae.encode(&rgb, &mut Scratch::default(), &mut e);
    let mut rec = Vec::new();
    ae.decode(&e, &mut Scratch::default(), &mut rec);
    let bytes: Vec<u8> = rec.iter().flat_map(|v| v.to_le_bytes()).collect();
    let mut text: String = e.iter().map(|v| format!("{:08x}\n", v.to_bits())).collect();
    text += &format!("reconstruction fnv1a {:016x}\n", sec_playground::render::fnv1a(&bytes));
    assert_eq!(text, include_str!("golden/embedding.txt"));
}

#[wasm_bindgen_test]
fn the_encoder_api_embeds_and_reconstructs_an_observation() {
    use sec_playground::web::Encoder;
    assert!(message(Encoder::new("maze").err().unwrap()).contains("task"));
    let mut enc = Encoder::new("detour").unwrap();
    let mut env = ArenaEnv::new("detour", 1.0, None).unwrap();
    let obs = env.observation();
    let e = enc.encode(&obs).unwrap();
    assert_eq!(e.len(), 20);
    assert!(e.iter().any(|&v| v > 0.0));
    let rec = enc.reconstruct(&obs).unwrap();
    assert_eq!(rec.len(), obs.len());
    let mse = enc.reconstruction_mse(&obs).unwrap();
    assert!(mse > 0.0 && mse < 0.01, "a trained model reconstructs its first frame: mse {mse}");
    let err = message(enc.encode(&obs[..100]).err().unwrap());
    assert!(err.starts_with("rgba:") && err.contains("28224"), "{err}");
    assert_eq!(enc.encode(&obs).unwrap(), e, "a refused call changed nothing");
}

#[wasm_bindgen_test]
fn wasm_gives_the_native_golden_episode_log() {
    let log = sec_playground::experiment::golden_run();
    for (i, (a, b)) in log.lines().zip(include_str!("golden/run.txt").lines()).enumerate() {
        assert_eq!(a, b, "episode {} differs between wasm and native", i);
    }
    assert_eq!(log.lines().count(), include_str!("golden/run.txt").lines().count());
}

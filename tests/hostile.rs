//! Issue 20's reproducers, each refused by name with the state left as it was: weights files with
//! non-finite or huge values, a tau that made p NaN, an n x m that reserved gigabytes, a memory
//! file's reward of 1e308, and the benchmark fill that never returned. (The YAML ones are in
//! `tests/yaml.rs`; the JS API's in `tests/wasm.rs`.)
#![cfg(not(target_arch = "wasm32"))]

use sec_playground::agent::SecConfig;
use sec_playground::encoder::{bundled, DType, Weights};
use sec_playground::experiment::{Run, RunConfig};
use sec_playground::memory::{file::Identity, Memory, MemoryConfig, MAX_COUPLETS, TAU_RANGE};

fn weights() -> Weights {
    bundled::autoencoder("double-t-maze").unwrap().to_weights()
}

#[test]
fn weights_with_non_finite_or_huge_values_or_scales_are_refused() {
    let ok = weights();
    assert!(Weights::from_bytes(&ok.to_bytes(DType::F32)).is_ok());
    for bad in [f32::NAN, f32::INFINITY, -f32::INFINITY, 3e38] {
        let mut w = ok.clone();
        w.tensors[1].data[0] = bad;
        let e = Weights::from_bytes(&w.to_bytes(DType::F32)).unwrap_err();
        assert_eq!((e.file, e.field.as_str()), ("weights", w.tensors[1].name.as_str()), "{e}");
        let mut w = ok.clone();
        w.embedding_scale = bad;
        let e = Weights::from_bytes(&w.to_bytes(DType::F32)).unwrap_err();
        assert_eq!(e.field, "embeddingScale", "{e}");
    }
    // A shape whose product overflows is refused, not wrapped.
    let mut w = ok.clone();
    w.tensors[0].shape = vec![1 << 31, 1 << 31, 1 << 31];
    let e = Weights::from_bytes(&w.to_bytes(DType::F32)).unwrap_err();
    assert!(e.message.contains("overflows"), "{e}");
}

#[test]
fn tau_is_bounded_so_that_p_stays_finite_and_n_times_m_is_bounded() {
    let cfg = |f: fn(&mut MemoryConfig)| {
        let mut c = MemoryConfig::default();
        f(&mut c);
        c.validate()
    };
    assert_eq!(cfg(|c| c.tau = 2.7e-5).unwrap_err().field, "tau");
    assert_eq!(cfg(|c| c.tau = 0.0).unwrap_err().field, "tau");
    assert!(cfg(|c| c.tau = TAU_RANGE.0).is_ok());
    let e = cfg(|c| (c.n, c.m) = (1000, 100_000)).unwrap_err();
    assert_eq!(e.field, "m");
    assert!(e.message.contains(&MAX_COUPLETS.to_string()), "{e}");
    // At the bound the memory is made without reserving it: its buffers start empty.
    assert!(Memory::new(MemoryConfig { n: 1000, m: MAX_COUPLETS / 1000, ..MemoryConfig::default() }).is_ok());
    // The smallest tau over a whole run: every decision's p is finite (an entropy in the log).
    let mut run_cfg = RunConfig { task: "object-permanence".into(), ..RunConfig::default() };
    run_cfg.section_mut::<SecConfig>().memory.tau = TAU_RANGE.0;
    let mut run = Run::new(run_cfg, 2).unwrap();
    for _ in 0..20 {
        let m = run.episode();
        assert!(m.entropy.is_finite() && m.reward.is_finite(), "{m:?}");
    }
}

#[test]
fn memory_files_with_unbounded_rewards_are_refused_and_the_memory_kept() {
    let id = Identity { task: "double-t-maze".into(), model: 7 };
    let mut mem = Memory::new(MemoryConfig { n: 3, m: 4, ..MemoryConfig::default() }).unwrap();
    let mut rng = <rand_chacha::ChaCha8Rng as rand::SeedableRng>::seed_from_u64(1);
    mem.store(2.0, &mut rng);
    let good = mem.to_file(&id);
    // A file with a sound checksum whose reward is 1e308 (a memory can store any positive
    // reward; the tasks pay a few units).
    let mut huge = Memory::new(MemoryConfig { n: 3, m: 4, ..MemoryConfig::default() }).unwrap();
    huge.store(1e308, &mut rng);
    let bad = huge.to_file(&id);
    let mut target = Memory::new(MemoryConfig { n: 3, m: 4, ..MemoryConfig::default() }).unwrap();
    let e = target.load_file(&bad, &id).unwrap_err();
    assert!(e.message.contains("out of range"), "{e}");
    assert_eq!(target.len(), 0, "the memory is as it was");
    assert_eq!(target.load_file(&good, &id).unwrap(), 1);
}

#[test]
fn filling_a_forgetting_ltm_for_the_benchmarks_returns() {
    use sec_playground::memory::Forgetting;
    let mut cfg = RunConfig::default();
    cfg.section_mut::<SecConfig>().memory.forgetting = Forgetting::Fifo;
    cfg.section_mut::<SecConfig>().memory.m = 20;
    let mut run = Run::new(cfg, 1).unwrap();
    sec_playground::experiment::fixtures::fill_ltm(&mut run, 50);
    assert!(run.inspect().memory.unwrap().len() >= 19);
}

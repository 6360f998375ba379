//! Retrieval over a full LTM (issue 4 target: <= 100 us for 500 sequences x 50 couplets).
//! Run: `cargo bench --bench memory`.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use sec_playground::arena::Action;
use sec_playground::encoder::EMBEDDING;
use sec_playground::memory::{Couplet, Memory, MemoryConfig};

fn retrieval(c: &mut Criterion) {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let mut m = Memory::new(MemoryConfig::default()).unwrap();
    // Embeddings like the T-maze model's: about a fifth of the units zero, the rest up to ~1.
    let random_embedding = |rng: &mut ChaCha8Rng| -> [f32; EMBEDDING] {
        std::array::from_fn(|_| if rng.gen_bool(0.2) { 0.0 } else { rng.gen_range(0.0..1.0) })
    };
    while m.len() < 500 {
        for _ in 0..50 {
            let e = random_embedding(&mut rng);
            m.update(Couplet { embedding: e, action: Action::ALL[rng.gen_range(0..9)] });
        }
        m.store(rng.gen_range(0.5..3.0), &mut rng);
    }
    // A query next to a stored couplet, so that some couplets are selected.
    let mut q = m.ltm_embedding(250, 20);
    q[0] += 0.01;
    c.bench_function("retrieval 500x50", |b| b.iter(|| m.retrieve(black_box(&q), &mut rng)));
}

criterion_group!(benches, retrieval);

/// One full decision as a run makes it: 4 env steps (12 physics frames) with the action held, a
/// render, the encoder, retrieval over a full 500 x 50 LTM and the arbitration (issue 4 target:
/// >= 1,000 decisions/s on one core).
fn full_decision(c: &mut Criterion) {
    use sec_playground::agent::{Sec, SecConfig};
    use sec_playground::arena::Task;
    use sec_playground::encoder::{bundled, Scratch, IMAGE};
    use sec_playground::env::{Env, EnvConfig};
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let task = Task::preset("double-t-maze").unwrap();
    // t = 0: no episode limit, so the walk goes on through the maze.
    let mut env = Env::new(EnvConfig { t: Some(0), ..EnvConfig::new(task) }, 1).unwrap();
    let encoder = bundled::autoencoder("double-t-maze").unwrap();
    let (mut scratch, mut image) = (Scratch::default(), vec![0.0f32; IMAGE]);
    let mut agent = Sec::new(SecConfig::default(), &mut rng).unwrap();
    // Fill the LTM with sequences of real embeddings from a random walk.
    let mut action = Action::NOOP;
    while agent.memory().len() < 500 {
        env.advance(action, 4).unwrap();
        env.observation().to_rgb_f32(&mut image);
        let mut e = [0.0; EMBEDDING];
        encoder.encode(&image, &mut scratch, &mut e);
        let d = agent.decide(&e, 0.0, &mut rng);
        action = d.action;
        if rng.gen_bool(0.2) {
            agent.goal(rng.gen_range(0.5..3.0), &mut rng);
        }
    }
    c.bench_function("full decision, LTM 500x50", |b| {
        b.iter(|| {
            env.advance(action, 4).unwrap();
            env.observation().to_rgb_f32(&mut image);
            let mut e = [0.0; EMBEDDING];
            encoder.encode(&image, &mut scratch, &mut e);
            let d = agent.decide(black_box(&e), 0.0, &mut rng);
            action = d.action;
        })
    });
}

/// A run's decision as `Run::decision` makes it, the reconstruction gate included, over a full
/// LTM, for both perceptions: the untrained encoder's activations are denser (fewer zeros to
/// skip) and its embeddings are not the gate model's, so the gate encodes on its own. And the
/// default with the textured surface, whose frames repeat less (the frame cache and the window
/// reuse find less to reuse).
fn run_decision(c: &mut Criterion) {
    use sec_playground::encoder::PerceptionKind;
    use sec_playground::experiment::{Run, RunConfig};
    use sec_playground::render::Surface;
    for (label, perception, surface) in [
        ("untrained", PerceptionKind::Untrained, Surface::Flat),
        ("trained", PerceptionKind::Trained, Surface::Flat),
        ("untrained textured", PerceptionKind::Untrained, Surface::Textured),
    ] {
        let mut run = Run::new(RunConfig { perception, surface, ..RunConfig::default() }, 1).unwrap();
        sec_playground::experiment::fixtures::fill_ltm(&mut run, 500);
        for _ in 0..200 {
            run.decision();
        }
        c.bench_function(&format!("run decision, {label} encoder, LTM 500x50"), |b| b.iter(|| run.decision()));
    }
}

criterion_group!(decision, full_decision, run_decision);
criterion_main!(benches, decision);

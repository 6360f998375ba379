//! Encoder and decoder speed per frame (issue 3 targets: encoder <= 0.6 ms natively).
//! Run: `cargo bench --bench encoder`. Uses the bundled T-maze model and an untrained encoder.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use sec_playground::arena::Task;
use sec_playground::encoder::{bundled, Scratch, EMBEDDING, IMAGE};
use sec_playground::env::{Env, EnvConfig};

fn encoder(c: &mut Criterion) {
    let mut env = Env::new(EnvConfig::new(Task::preset("double-t-maze").unwrap()), 3).unwrap();
    let mut img = vec![0.0; IMAGE];
    env.observation().to_rgb_f32(&mut img);
    let ae = bundled::autoencoder("double-t-maze").unwrap();
    let mut s = Scratch::default();
    let mut e = [0.0; EMBEDDING];
    c.bench_function("encode", |b| b.iter(|| ae.encode(black_box(&img), &mut s, &mut e)));
    let mut rec = Vec::new();
    c.bench_function("decode", |b| b.iter(|| ae.decode(black_box(&e), &mut s, &mut rec)));
    // The code preset's perception: a Glorot-initialised encoder, whose activations have fewer
    // zeros for the sparse kernels to skip.
    use sec_playground::encoder::{Perception, PerceptionKind};
    let p = Perception::new(PerceptionKind::Untrained, "double-t-maze", None, 1).unwrap();
    c.bench_function("encode, untrained encoder", |b| b.iter(|| p.embed(black_box(&img), &mut s, &mut e)));
}

criterion_group!(benches, encoder);
criterion_main!(benches);

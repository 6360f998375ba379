//! Retrieval over a full LTM (issue 4 target: <= 100 us for 500 sequences x 50 couplets).
//! Run: `cargo bench --bench memory`.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
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
            m.update(Couplet { embedding: e, action: rng.gen_range(0..9) });
        }
        m.store(rng.gen_range(0.5..3.0), &mut rng);
    }
    // A query next to a stored couplet, so that some couplets are selected.
    let mut q = m.ltm_embedding(250, 20);
    q[0] += 0.01;
    c.bench_function("retrieval 500x50", |b| b.iter(|| m.advance(black_box(&q), &mut rng)));
}

criterion_group!(benches, retrieval);
criterion_main!(benches);

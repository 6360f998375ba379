//! Arena speed: physics env steps per second and 84x84 renders per second, per task (and the
//! pushable objects' cost in two Olympics arenas).
//! Run: `cargo bench --bench arena`. Targets (BENCHMARKS.md): >= 200,000 env steps/s and
//! >= 5,000 renders/s on one core. `bench/wasm-bench.mjs` measures the same work in Node.

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use sec_playground::arena::{Task, TASK_NAMES};
use sec_playground::env::trace::{bench_env_steps, bench_worlds};
use sec_playground::env::{Env, EnvConfig};
use sec_playground::render::{Camera, Frame, Surface};

fn env_steps(c: &mut Criterion) {
    let mut g = c.benchmark_group("env_step");
    g.throughput(Throughput::Elements(1000));
    for name in TASK_NAMES {
        let mut env = Env::new(EnvConfig::new(Task::preset(name).unwrap()), 1).unwrap();
        g.bench_function(name, |b| b.iter(|| black_box(bench_env_steps(&mut env, 1000))));
    }
    // What the pushable objects' rigid bodies cost: an Olympics arena of eight boxes the script
    // pushes, the same arena with walls in their place, and one with a U (three boxes in one body)
    // round a goal, which is then a rigid body too.
    let yaml = include_str!("../assets/arenas/competition/03-22-01.yaml");
    let u = include_str!("../assets/arenas/competition/10-04-01.yaml");
    for (label, src) in [
        ("03-22-01 boxes", yaml.to_string()),
        ("03-22-01 walls", yaml.replace("Cardbox1", "Wall")),
        ("10-04-01 U", u.to_string()),
    ] {
        let task = sec_playground::arena::yaml::load_task(label, &src).unwrap();
        let mut env = Env::new(EnvConfig::new(task), 1).unwrap();
        g.bench_function(label, |b| b.iter(|| black_box(bench_env_steps(&mut env, 1000))));
    }
    g.finish();
}

fn renders(c: &mut Criterion) {
    let mut g = c.benchmark_group("render_84x84");
    g.throughput(Throughput::Elements(1));
    // Each task flat, and the double T-maze textured (the floor's and fences' texels per pixel).
    let cases = TASK_NAMES.iter().map(|&t| (t, Surface::Flat)).chain([("double-t-maze", Surface::Textured)]);
    for (name, surface) in cases {
        let worlds = bench_worlds(name).unwrap();
        let mut cam = Camera::with_surface(surface);
        let mut frame = Frame::new();
        let mut i = 0;
        let label = sec_playground::encoder::model_name(name, surface);
        g.bench_function(&label, |b| {
            b.iter(|| {
                i = (i + 1) % worlds.len();
                cam.render(black_box(&worlds[i]), &mut frame);
                black_box(frame.rgba[0]);
            })
        });
    }
    g.finish();
}

criterion_group!(benches, env_steps, renders);
criterion_main!(benches);

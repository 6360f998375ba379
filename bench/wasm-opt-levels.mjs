// The arena build (pkg/arena/) at other wasm-opt levels, alternated in one Node process: env
// steps/s of three Olympics arenas (8,000 steps held 4 at a time without a render, then 1,000
// single steps each with its observation). Make the files from the build's input, e.g.
//   wasm-bindgen --target web --out-dir /tmp/arena target/scalar/wasm32-unknown-unknown/release/sec_playground.wasm
//   node_modules/.bin/wasm-opt -O1 /tmp/arena/sec_playground_bg.wasm -o /tmp/arena/o1.wasm
// then `node bench/wasm-opt-levels.mjs /tmp/arena/sec_playground_bg.wasm /tmp/arena/o1.wasm ...`
// (after scripts/build.sh, whose pkg/arena/ JS glue loads each).
import { readFileSync } from 'node:fs';
import { performance } from 'node:perf_hooks';

const root = new URL('..', import.meta.url).pathname;
const glue = await import(`${root}pkg/arena/sec_playground.js`);
const files = process.argv.slice(2);
if (!files.length) throw new Error('usage: node bench/wasm-opt-levels.mjs BUILD.wasm [BUILD.wasm ...]');
const yaml = (name) => readFileSync(`${root}assets/arenas/competition/${name}.yaml`, 'utf8');
const results = {};
for (let round = 0; round < 3; round++) {
  for (const f of files) {
    glue.initSync({ module: readFileSync(f) });
    for (const arena of ['03-22-01', '10-04-01', '01-01-01']) {
      const env = glue.ArenaEnv.fromYaml(arena, yaml(arena), 1);
      const t0 = performance.now();
      for (let i = 0; i < 2000; i++) {
        const r = env.stepHeld(i % 9, 4);
        if (r.terminated || r.truncated) env.reset();
      }
      const held = 8000 / ((performance.now() - t0) / 1000);
      const t1 = performance.now();
      for (let i = 0; i < 1000; i++) {
        const r = env.step(i % 9);
        env.observation();
        if (r.terminated || r.truncated) env.reset();
      }
      const rendered = 1000 / ((performance.now() - t1) / 1000);
      (results[`${f.split('/').pop()} ${arena}`] ??= []).push(`${Math.round(held)} / ${Math.round(rendered)}`);
      env.free();
    }
  }
}
console.log('env steps/s without a render / with one, rounds 1-3 (round 1 warms up)');
console.table(results);

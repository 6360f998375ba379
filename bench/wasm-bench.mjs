// Arena speed in Node, running the release wasm build (pkg/hooks: the published build plus its
// timing loops): env steps/s and 84x84 renders/s
// per task, the same work as `cargo bench --bench arena`. Run `npm run bench:wasm` after
// `scripts/build-hooks.sh`. Targets (BENCHMARKS.md): >= 2,000 renders/s.
import { readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { performance } from 'node:perf_hooks';

const root = fileURLToPath(new URL('..', import.meta.url));
const wasm = await import(`${root}pkg/hooks/sec_playground.js`);
wasm.initSync({ module: readFileSync(`${root}pkg/hooks/sec_playground_bg.wasm`) });
wasm.registerModel(readFileSync(`${root}assets/encoders/double-t-maze.secae`));

/** Best of `repeats` timings of fn(), in seconds. */
function best(fn, repeats = 5) {
  let t = Infinity;
  for (let i = 0; i < repeats; i++) {
    const t0 = performance.now();
    fn();
    t = Math.min(t, (performance.now() - t0) / 1000);
  }
  return t;
}

const rows = [];
for (const task of wasm.taskNames()) {
  wasm.benchEnvSteps(task, 20000); // warm up
  const steps = 200000;
  const ts = best(() => wasm.benchEnvSteps(task, steps));
  wasm.benchRenders(task, 200);
  const frames = 2000;
  const tr = best(() => wasm.benchRenders(task, frames));
  rows.push({ task, envStepsPerSec: Math.round(steps / ts), rendersPerSec: Math.round(frames / tr) });
}
console.log(`node ${process.version}, wasm release build`);
console.table(rows);

const n = 300;
wasm.benchAutoencoder(20, false);
const te = best(() => wasm.benchAutoencoder(n, false), 3);
wasm.benchAutoencoder(20, true);
const td = best(() => wasm.benchAutoencoder(n, true), 3);
// Multiply-adds per frame of the plain computation (docs/ENCODER.md): three convolutions and the
// Dense(20); the decoder's Dense(3872) and four convolutions over the upsampled images. The kernels
// do fewer (zero inputs skipped, the upsampling folded), so the rate printed is what a dense
// kernel would need for the same time.
const MACS = { encode: 15_318_400, decode: 16_829_824 };
const gmacs = (macs, s) => (macs / (s / n) / 1e9).toFixed(1);
console.log(
  `autoencoder (bundled T-maze model, simd128): encode ${(te / n * 1000).toFixed(3)} ms ` +
    `(${gmacs(MACS.encode, te)} G dense-equivalent multiply-adds/s), decode ${(td / n * 1000).toFixed(3)} ms ` +
    `(${gmacs(MACS.decode, td)} G/s) per frame`,
);

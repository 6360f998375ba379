// Two or more builds of pkg/hooks side by side in one Node process: their batches alternate
// (A, B, A, B, ...), so the machine's drift over minutes falls on every build alike. Each batch
// is `bench/decisions.mjs`'s: a `SecRun` (seed 1) with its LTM filled (`benchFillMemory`), 200
// decisions untimed, then 2,000 timed. Prints each build's median and best decisions/s.
//   node bench/decisions-ab.mjs <pkg-dir> <pkg-dir> [...] [--fill N] [--batches N]
// A build to compare with: `scripts/build-hooks.sh` at that commit, then copy pkg/hooks away.
import { readFileSync } from 'node:fs';
import { resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { performance } from 'node:perf_hooks';

const root = fileURLToPath(new URL('..', import.meta.url));
const args = process.argv.slice(2);
const option = (name, fallback) => {
  const i = args.indexOf(name);
  return i < 0 ? fallback : Number(args.splice(i, 2)[1]);
};
const fill = option('--fill', 500);
const batches = option('--batches', 15);
if (args.length < 2) {
  console.error('usage: node bench/decisions-ab.mjs <pkg-dir> <pkg-dir> [...] [--fill N] [--batches N]');
  process.exit(2);
}
const builds = [];
for (const dir of args.map((d) => resolve(d))) {
  const wasm = await import(`${dir}/sec_playground.js`);
  wasm.initSync({ module: readFileSync(`${dir}/sec_playground_bg.wasm`) });
  wasm.registerModel(readFileSync(`${root}assets/encoders/double-t-maze.secae`));
  builds.push({ dir, wasm, rates: [] });
}
for (let b = 0; b < batches; b++) {
  for (const build of builds) {
    const run = new build.wasm.SecRun({}, 1);
    run.benchFillMemory(fill);
    run.runDecisions(200);
    const t0 = performance.now();
    run.runDecisions(2000);
    build.rates.push(2e6 / (performance.now() - t0));
    run.free();
  }
}
for (const { dir, rates } of builds) {
  rates.sort((a, b) => a - b);
  const median = Math.round(rates[rates.length >> 1]);
  console.log(`${dir}: median ${median}, best ${Math.round(rates[rates.length - 1])} decisions/s (LTM ${fill}, ${batches} batches)`);
}

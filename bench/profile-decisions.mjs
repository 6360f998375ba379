// Where a decision's time goes as the LTM fills, profiled in Debian's Chromium (V8's sampling
// profiler through the DevTools protocol): decisions of a `SecRun` whose LTM is filled to 30, 150,
// 430 and 500 sequences (`benchFillMemory`), and each function's share of the samples.
//   node bench/profile-decisions.mjs [pkg-dir]     (about a minute)
// `pkg-dir` (default pkg/hooks, scripts/build-hooks.sh) is served and loaded. Its functions are
// named only if the wasm keeps its name section: for a named build, run wasm-pack as
// build-hooks.sh does into another folder and `wasm-opt -O3 -g` instead of `-O3`.
import { fileURLToPath } from 'node:url';
import { relative } from 'node:path';
import { openChromium, UNTHROTTLED } from './browser.mjs';

const root = fileURLToPath(new URL('..', import.meta.url));
const pkg = relative(root, process.argv[2] ?? `${root}pkg/hooks`);
const DECISIONS = 10000;

const { server, browser, base } = await openChromium(UNTHROTTLED);
try {
  const page = await browser.newPage();
  await page.goto(`${base}arena.html`);
  await page.evaluate(async ({ src, model }) => {
    window.wasm = await import(src);
    await window.wasm.default();
    window.wasm.registerModel(new Uint8Array(await (await fetch(model)).arrayBuffer()));
  }, { src: `${base}${pkg}/sec_playground.js`, model: `${base}assets/encoders/double-t-maze.secae` });
  const cdp = await page.context().newCDPSession(page);
  await cdp.send('Profiler.enable');
  await cdp.send('Profiler.setSamplingInterval', { interval: 100 });
  for (const fill of [30, 150, 430, 500]) {
    // Filled and warmed up outside the profile.
    await page.evaluate((fill) => {
      window.run?.free();
      window.run = new window.wasm.SecRun({}, 1);
      window.run.benchFillMemory(fill);
      window.run.runDecisions(500);
    }, fill);
    await cdp.send('Profiler.start');
    const ms = await page.evaluate((n) => {
      const t0 = performance.now();
      window.run.runDecisions(n);
      return performance.now() - t0;
    }, DECISIONS);
    const { profile } = await cdp.send('Profiler.stop');
    const self = new Map();
    const byId = new Map(profile.nodes.map((n) => [n.id, n]));
    for (const id of profile.samples) {
      const f = byId.get(id).callFrame;
      const name = (f.functionName || f.url || '(anonymous)').replace(/::h[0-9a-f]{16}$/, '');
      self.set(name, (self.get(name) ?? 0) + 1);
    }
    const total = profile.samples.length;
    console.log(`LTM ${fill}: ${Math.round((DECISIONS * 1000) / ms)} decisions/s while profiled, ${total} samples`);
    for (const [name, n] of [...self].sort((a, b) => b[1] - a[1]).slice(0, 10)) {
      console.log(`  ${((100 * n) / total).toFixed(1).padStart(5)} %  ${name.slice(0, 110)}`);
    }
  }
} finally {
  await browser.close();
  server.close();
}

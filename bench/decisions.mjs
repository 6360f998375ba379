// SEC decisions per second in wasm with a full LTM (500 x 50) at the default settings (and, in
// Node, with the trained encoder), in Node and in headless Chromium, and the playground page's frame rate while its worker runs at max
// speed. Targets (BENCHMARKS.md): >= 600 decisions/s, >= 50 fps. Run `npm run bench:decisions`
// after `scripts/build.sh` and `scripts/build-hooks.sh`.
import { readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { performance } from 'node:perf_hooks';
import { openChromium, UNTHROTTLED, maxSpeed } from './browser.mjs';

const root = fileURLToPath(new URL('..', import.meta.url));
const BATCHES = 11;
const DECISIONS = 2000;

/**
 * Decisions/s of a `SecRun` over a full LTM, as the best and the median of BATCHES timings of the
 * same work: each batch builds the run afresh (seed 1, LTM filled, 200 decisions untimed, which
 * also lets the engine's optimising tier take over), then times `decisions` decisions. This
 * machine's speed drifts over minutes and hours, so both numbers are reported. Self-contained:
 * it runs in Node and, as source, in the page.
 */
function measure(wasm, batches, decisions, now, config = {}, fill = 500) {
  const rates = [];
  let ltm = 0;
  for (let i = 0; i < batches; i++) {
    const run = new wasm.SecRun(config, 1);
    run.benchFillMemory(fill);
    run.runDecisions(200);
    const t0 = now();
    run.runDecisions(decisions);
    rates.push((decisions * 1000) / (now() - t0));
    ltm = run.view().ltm;
    run.free();
  }
  rates.sort((a, b) => a - b);
  return { best: Math.round(rates[rates.length - 1]), median: Math.round(rates[rates.length >> 1]), ltm };
}

const show = (r) => `best ${r.best}, median ${r.median} decisions/s over ${BATCHES} batches of ${DECISIONS} (LTM ${r.ltm} sequences)`;

// SEC_PKG names another build of pkg/hooks (say, the build before a change) to compare with;
// --node-only skips Chromium and the page.
const pkg = process.env.SEC_PKG ?? `${root}pkg/hooks`;
const wasm = await import(`${pkg}/sec_playground.js`);
wasm.initSync({ module: readFileSync(`${pkg}/sec_playground_bg.wasm`) });
wasm.registerModel(readFileSync(`${root}assets/encoders/double-t-maze.secae`));
// As the memory fills (issue 54): the rate at LTM 30, 150 and 430 sequences, then full.
for (const fill of [30, 150, 430]) {
  console.log(`node ${process.version}, LTM ${fill}: ${show(measure(wasm, BATCHES, DECISIONS, () => performance.now(), {}, fill))}`);
}
const node = measure(wasm, BATCHES, DECISIONS, () => performance.now());
console.log(`node ${process.version}: ${show(node)}`);
if (process.argv.includes('--fills-only')) process.exit(0);
// The paper preset's perception, for comparison: the trained encoder embeds and its embedding
// doubles as the gate's, where the default's untrained encoder leaves the gate its own encode.
const trained = measure(wasm, BATCHES, DECISIONS, () => performance.now(), { perception: 'trained' });
console.log(`node ${process.version}, trained encoder: ${show(trained)}`);
// The default with v1's textured floor and fences: its frames repeat less, so the frame cache and
// the window reuse find less to reuse; its gate uses the textured model.
// (A build from before the surfaces, through SEC_PKG, refuses the setting: then it is skipped.)
try {
  wasm.registerModel(readFileSync(`${root}assets/encoders/double-t-maze-textured.secae`));
  const textured = measure(wasm, BATCHES, DECISIONS, () => performance.now(), { surface: 'textured' });
  console.log(`node ${process.version}, textured surface: ${show(textured)}`);
} catch (e) {
  console.log(`node ${process.version}, textured surface: not in this build (${e.message})`);
}
if (process.argv.includes('--node-only')) process.exit(0);

const { server, browser, base } = await openChromium(UNTHROTTLED);
try {
  const page = await browser.newPage({ viewport: { width: 1300, height: 1000 } });
  await page.goto(`${base}arena.html`);
  const chrome = await page.evaluate(async ({ src, model, measureSrc, batches, decisions }) => {
    const wasm = await import(src);
    await wasm.default();
    wasm.registerModel(new Uint8Array(await (await fetch(model)).arrayBuffer()));
    const measure = new Function(`return ${measureSrc}`)();
    const fills = {};
    for (const fill of [30, 150, 430]) fills[fill] = measure(wasm, batches, decisions, () => performance.now(), {}, fill);
    return { ...measure(wasm, batches, decisions, () => performance.now()), fills };
  }, {
    src: `${base}pkg/hooks/sec_playground.js`,
    model: `${base}assets/encoders/double-t-maze.secae`,
    measureSrc: measure.toString(),
    batches: BATCHES,
    decisions: DECISIONS,
  });
  for (const [fill, r] of Object.entries(chrome.fills)) console.log(`chromium ${browser.version()}, LTM ${fill}: ${show(r)}`);
  console.log(`chromium ${browser.version()}: ${show(chrome)}`);

  // The page at max speed: count animation frames on the main thread for 5 s.
  await page.goto(`${base}#speed=max`);
  await page.waitForFunction(() => window.secPlayground?.playing);
  await maxSpeed(page);
  await page.waitForTimeout(1000);
  const fps = await page.evaluate(() => new Promise((ok) => {
    let frames = 0;
    let worst = 0;
    let last = performance.now();
    const t0 = last;
    const tick = (t) => {
      frames++;
      worst = Math.max(worst, t - last);
      last = t;
      if (t - t0 < 5000) requestAnimationFrame(tick);
      else ok({ fps: (frames * 1000) / (t - t0), worstFrameMs: worst, episodes: window.secPlayground.episodes });
    };
    requestAnimationFrame(tick);
  }));
  console.log(`page at max speed: ${fps.fps.toFixed(1)} fps, longest frame ${fps.worstFrameMs.toFixed(1)} ms, ${fps.episodes} episodes so far`);
} finally {
  await browser.close();
  server.close();
}

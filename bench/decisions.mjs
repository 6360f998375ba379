// SEC decisions per second in wasm with a full LTM (500 x 50) at the default settings, in Node
// and in headless Chromium, and the playground page's frame rate while its worker runs at max
// speed. Targets (BENCHMARKS.md): >= 600 decisions/s, >= 50 fps. Run `npm run bench:decisions`
// after `scripts/build.sh`.
import { readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { performance } from 'node:perf_hooks';
import { chromium } from 'playwright-core';
import { serve } from '../scripts/serve.mjs';

const root = fileURLToPath(new URL('..', import.meta.url));
const DECISIONS = 3000;

/** Decisions/s of `wasm` (an initialised module): best of 3 batches over a full LTM. */
function measure(wasm, decisions, now) {
  const run = new wasm.SecRun({}, 1);
  run.benchFillMemory(500);
  run.advance(200);
  let best = Infinity;
  for (let i = 0; i < 3; i++) {
    const t0 = now();
    run.advance(decisions);
    best = Math.min(best, now() - t0);
  }
  const ltm = run.view().ltm;
  run.free();
  return { decisionsPerSec: Math.round((decisions * 1000) / best), ltm };
}

const wasm = await import(`${root}pkg/sec_playground.js`);
wasm.initSync({ module: readFileSync(`${root}pkg/sec_playground_bg.wasm`) });
wasm.registerModel(readFileSync(`${root}assets/encoders/double-t-maze.secae`));
const node = measure(wasm, DECISIONS, () => performance.now());
console.log(`node ${process.version}: ${node.decisionsPerSec} decisions/s (LTM ${node.ltm} sequences)`);

const server = await serve(0);
const base = `http://127.0.0.1:${server.address().port}/`;
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
  args: ['--no-sandbox', '--disable-gpu', '--disable-background-timer-throttling', '--disable-renderer-backgrounding'],
});
try {
  const page = await browser.newPage({ viewport: { width: 1300, height: 1000 } });
  await page.goto(`${base}arena.html`);
  const chrome = await page.evaluate(async ({ src, model, decisions }) => {
    const wasm = await import(src);
    await wasm.default();
    wasm.registerModel(new Uint8Array(await (await fetch(model)).arrayBuffer()));
    const run = new wasm.SecRun({}, 1);
    run.benchFillMemory(500);
    run.advance(200);
    let best = Infinity;
    for (let i = 0; i < 3; i++) {
      const t0 = performance.now();
      run.advance(decisions);
      best = Math.min(best, performance.now() - t0);
    }
    return { decisionsPerSec: Math.round((decisions * 1000) / best), ltm: run.view().ltm };
  }, { src: `${base}pkg/sec_playground.js`, model: `${base}assets/encoders/double-t-maze.secae`, decisions: DECISIONS });
  console.log(`chromium ${browser.version()}: ${chrome.decisionsPerSec} decisions/s (LTM ${chrome.ltm} sequences)`);

  // The page at max speed: count animation frames on the main thread for 5 s.
  await page.goto(`${base}#speed=max`);
  await page.waitForFunction(() => window.secPlayground?.playing);
  await page.evaluate(() => {
    const s = document.getElementById('speed');
    s.value = String(Number(s.max));
    s.dispatchEvent(new Event('input'));
  });
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

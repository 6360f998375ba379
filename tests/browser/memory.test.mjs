// The page over a long run, in real Chromium: at max speed its JS heap grows by no more than the
// episodes it keeps for the charts and the CSV, its DOM by nothing, and its worker's wasm memory
// by nothing once the LTM is full. A short version of `bench/page-memory.mjs` (5000 episodes, a
// compare of four workers for 30 minutes), which BENCHMARKS.md reports.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { launch, pageMemory } from './harness.mjs';

let server, browser, base;
before(async () => { ({ server, browser, base } = await launch()); });
after(async () => { await browser?.close(); server?.close(); });

/** Bytes of JS heap an episode may add: its metrics in the log (a dozen fields) and a point of
 *  each chart's columns, generously. */
const PER_EPISODE = 2048;

test('at max speed the heap, the DOM and the wasm memory stay flat after the warm-up', async () => {
  const page = await browser.newPage({ viewport: { width: 1300, height: 1000 } });
  const problems = [];
  page.on('pageerror', (e) => problems.push(String(e)));
  const cdp = await page.context().newCDPSession(page);
  await cdp.send('Performance.enable');
  // The warm-up fills what a run may hold: a small LTM (m = 10), and the frame cache (its 1,024
  // frames; object permanence's run of seed 3 grows its wasm memory once, by 128 KiB, between
  // episodes 60 and 200, then not at all to episode 1,800).
  await page.goto(`${base}#task=object-permanence&m=10&seed=3`);
  await page.waitForFunction(() => window.secPlayground?.settings && window.secPlayground.view);
  await page.evaluate(() => {
    const s = document.getElementById('speed');
    s.value = s.max;
    s.dispatchEvent(new Event('input'));
  });
  const at = (n) => page.waitForFunction((n) => window.secPlayground.episodes >= n && window.secPlayground.view.ltm >= 10,
    n, { timeout: 600000, polling: 500 });
  // Five samples ten episodes apart, each figure their least: a node or listener the page adds
  // for a moment (a notice, a legend row) is not growth.
  const sample = async (from) => {
    const all = [];
    for (let i = 0; i < 5; i++) {
      await at(from + 10 * i);
      all.push(await pageMemory(page, cdp));
    }
    const least = (k) => Math.min(...all.map((m) => m[k]));
    return { ...all[0], heap: least('heap'), nodes: least('nodes'), listeners: least('listeners'), wasm: all.at(-1).wasm };
  };
  const warm = await sample(250);
  const late = await sample(warm.episodes + 300);
  const episodes = late.episodes - warm.episodes;
  const grew = late.heap - warm.heap;
  const summary = JSON.stringify({ warm, late });
  assert.ok(grew <= episodes * PER_EPISODE + (1 << 20),
    `the JS heap grew ${grew} bytes over ${episodes} episodes (${(grew / episodes).toFixed(0)} per episode): ${summary}`);
  assert.ok(Math.abs(late.nodes - warm.nodes) <= 10, `DOM nodes ${warm.nodes} -> ${late.nodes}`);
  assert.ok(late.listeners <= warm.listeners + 10, `event listeners ${warm.listeners} -> ${late.listeners}`);
  assert.equal(late.wasm, warm.wasm, `the run's wasm memory grew: ${summary}`);
  assert.deepEqual(problems, []);
  await page.close();
});

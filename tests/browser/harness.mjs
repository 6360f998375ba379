// Shared by the browser tests: a static server for the repository and Debian's Chromium driven
// by playwright-core (a test tool's own browser download does not work here).
import { mkdirSync } from 'node:fs';
import { chromium } from 'playwright-core';
import { serve } from '../../scripts/serve.mjs';

/** Where screenshots go. */
export const ARTIFACTS = new URL('../../test-artifacts/', import.meta.url);

/** Starts the server and the browser: `{server, browser, base}`; close both in `after`. */
export async function launch() {
  mkdirSync(ARTIFACTS, { recursive: true });
  const server = await serve(0);
  const base = `http://127.0.0.1:${server.address().port}/`;
  const browser = await chromium.launch({
    executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
    args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking',
      '--disable-component-update', '--disable-sync'],
  });
  return { server, browser, base };
}

/** Distinct colours on a canvas (`selector`): a blank canvas has one. */
export function colours(page, selector) {
  return page.evaluate((selector) => {
    const c = document.querySelector(selector);
    const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    const seen = new Set();
    for (let i = 0; i < d.length; i += 4) seen.add((d[i] << 16) | (d[i + 1] << 8) | d[i + 2]);
    return seen.size;
  }, selector);
}

/** Waits until the canvas `selector` shows at least `n` distinct colours (it has drawn), however
 *  long a loaded machine takes: a condition, never a time. */
export function untilColours(page, selector, n, timeout = 60000) {
  return page.waitForFunction(([selector, n]) => {
    const c = document.querySelector(selector);
    if (!c) return false;
    const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    const seen = new Set();
    for (let i = 0; i < d.length && seen.size < n; i += 4) seen.add((d[i] << 16) | (d[i + 1] << 8) | d[i + 2]);
    return seen.size >= n;
  }, [selector, n], { timeout });
}

/** Polls the async `predicate` (a check made from the test's side, such as a count of chart
 *  pixels) until it holds, failing with `what` after `timeout` ms: a condition, never a time. */
export async function until(predicate, what, timeout = 60000) {
  const end = Date.now() + timeout;
  for (;;) {
    if (await predicate()) return;
    if (Date.now() > end) throw new Error(`timed out waiting for ${what}`);
    await new Promise((r) => setTimeout(r, 50));
  }
}

/** What the page holds after a garbage collection (Chromium's DevTools protocol on `cdp`, a
 *  `page.context().newCDPSession(page)`): the page's JS heap in use and its DOM nodes, and the
 *  wasm memory of its run's worker and of each compare worker (from their last messages). The
 *  workers' own JS heaps are not counted: what they keep lives in their wasm memory. */
export async function pageMemory(page, cdp) {
  await cdp.send('HeapProfiler.collectGarbage');
  const { metrics } = await cdp.send('Performance.getMetrics');
  const metric = (name) => metrics.find((m) => m.name === name)?.value;
  const inPage = await page.evaluate(() => ({
    episodes: window.secPlayground.episodes,
    wasm: window.secPlayground.wasmBytes,
    compareWasm: window.secPlayground.compare.wasmBytes,
    compareEpisodes: window.secPlayground.compare.episodes,
  }));
  return { heap: metric('JSHeapUsedSize'), nodes: metric('Nodes'), listeners: metric('JSEventListeners'), ...inPage };
}

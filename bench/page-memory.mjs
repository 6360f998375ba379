// The page over the paper's horizon, in Debian's Chromium: what it holds while a run plays 5000
// episodes at max speed in one tab, then while a compare of four workers runs for 30 minutes.
//   npm run bench:page-memory            (after scripts/build.sh; about an hour)
//   EPISODES=1000 COMPARE_MINUTES=5 npm run bench:page-memory     (a shorter look; EPISODES=0 or
//   COMPARE_MINUTES=0 leaves that part out)
// Each sample is taken after a garbage collection (DevTools' HeapProfiler.collectGarbage): the
// page's JS heap in use and its DOM nodes (Performance.getMetrics), and the wasm memory of the
// run's worker and of each compare worker (their last messages). Flat after the warm-up means no
// leak: the heap may grow only by the episodes the page keeps for its charts and CSV.
import { launch, pageMemory } from '../tests/browser/harness.mjs';
import { maxSpeed } from './browser.mjs';

const EPISODES = Number(process.env.EPISODES ?? 5000);
const EVERY = Math.max(1, Math.round(EPISODES / 20));
const COMPARE_MINUTES = Number(process.env.COMPARE_MINUTES ?? 30);
const ARMS = 4;

const { server, browser, base } = await launch();
const mib = (b) => (b == null ? '-' : (b / 1048576).toFixed(2));
const row = (label, m, t0) => console.log([label, ((Date.now() - t0) / 60000).toFixed(1), mib(m.heap), m.nodes, m.listeners,
  mib(m.wasm), m.compareWasm.map(mib).join(' ') || '-', m.compareEpisodes.join(' ') || '-'].join('\t'));

try {
  const page = await browser.newPage({ viewport: { width: 1300, height: 1000 } });
  // The compare's pool is the machine's threads less one: say there are ARMS + 1, so that every
  // arm plays at once (one worker each) on any machine.
  await page.addInitScript((n) => Object.defineProperty(Navigator.prototype, 'hardwareConcurrency', { get: () => n }), ARMS + 1);
  const cdp = await page.context().newCDPSession(page);
  await cdp.send('Performance.enable');
  await page.goto(`${base}#task=double-t-maze`);
  await page.waitForFunction(() => window.secPlayground?.settings && window.secPlayground.view);
  await maxSpeed(page);
  console.log(`chromium ${browser.version()}; the double T-maze at max speed, ${EPISODES} episodes (code preset, m = 500)`);
  console.log(['episodes', 'minutes', 'heap MiB', 'DOM nodes', 'listeners', 'wasm MiB', 'compare wasm MiB', 'compare episodes'].join('\t'));
  const t0 = Date.now();
  for (let n = EVERY; n <= EPISODES; n += EVERY) {
    await page.waitForFunction((n) => window.secPlayground.episodes >= n, n, { timeout: 0, polling: 1000 });
    row(String(n), await pageMemory(page, cdp), t0);
  }
  // The compare: four arms (the current settings, added four times), one seed each, to a
  // horizon they do not reach in the time, while the main run keeps playing (it pauses for a
  // comparison: "Resume it").
  if (COMPARE_MINUTES > 0) {
    await page.click('#compare-clear');
    await page.selectOption('#compare-seeds', '1');
    await page.fill('#compare-episodes', '20000');
    for (let i = 0; i < ARMS; i++) await page.click('#compare-add');
    await page.click('#compare-run');
    await page.click('#main-resume');
    console.log(`compare: ${ARMS} workers for ${COMPARE_MINUTES} minutes`);
    const t1 = Date.now();
    for (let i = 1; i <= 10; i++) {
      await page.waitForTimeout((COMPARE_MINUTES * 60000) / 10);
      row(`+${i}/10`, await pageMemory(page, cdp), t1);
    }
  }
} finally {
  await browser.close();
  server.close();
}

// The page's own decision rate at max speed as its LTM fills, in Debian's Chromium:
//   node bench/page-rate.mjs [windows]      (after scripts/build.sh; 8 s a window)
// The default page (double T-maze, SEC, code preset) at max speed: after 3 s, `windows` windows
// of 8 s (default 4), each the decisions of the episodes finished in it over its time, with the
// LTM at its start and end and the page's own readout. What a student sees, views and messages
// included, where bench/decisions.mjs times the wasm alone.
import { openChromium, maxSpeed } from './browser.mjs';

const WINDOWS = Number(process.argv[2] ?? 4);
const { server, browser, base } = await openChromium();
try {
  const page = await browser.newPage({ viewport: { width: 1300, height: 1000 } });
  await page.goto(`${base}#task=double-t-maze`);
  await page.waitForFunction(() => window.secPlayground?.settings && window.secPlayground.view);
  await maxSpeed(page);
  await page.waitForTimeout(3000);
  for (let i = 0; i < WINDOWS; i++) {
    const a = await page.evaluate(() => ({ ep: window.secPlayground.episodes, t: performance.now(), ltm: window.secPlayground.view.ltm }));
    await page.waitForTimeout(8000);
    const b = await page.evaluate(() => ({ t: performance.now(), ltm: window.secPlayground.view.ltm, log: window.secPlayground.log,
      readout: window.secPlayground.rate }));
    const decisions = b.log.slice(a.ep).reduce((n, m) => n + m.decisions, 0);
    console.log(`LTM ${a.ltm}-${b.ltm}: ${((decisions * 1000) / (b.t - a.t)).toFixed(0)} decisions/s `
      + `(finished episodes), readout ${b.readout?.toFixed(0)}`);
  }
} finally {
  await browser.close();
  server.close();
}

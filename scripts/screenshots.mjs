// Regenerates the README's screenshots of the page in Debian's Chromium: a desktop window
// (1400x900) and a phone (390x844), each started from the reference run's memory ("Skip the
// warm-up") and played a few seconds at max speed, paused on a decision with the explanation open. Run `node scripts/screenshots.mjs` after
// `scripts/build.sh`; it writes docs/img/playground.png and docs/img/playground-phone.png.
import { launch } from '../tests/browser/harness.mjs';

const { server, browser, base } = await launch();
try {
  for (const [name, viewport] of [['playground', { width: 1400, height: 900 }], ['playground-phone', { width: 390, height: 844 }]]) {
    const page = await browser.newPage({ viewport });
    await page.goto(`${base}#task=object-permanence&seed=2`);
    await page.waitForFunction(() => window.secPlayground?.view);
    await page.evaluate(() => {
      const s = document.getElementById('speed');
      s.value = s.max;
      s.dispatchEvent(new Event('input'));
    });
    await page.click('#warm-up');
    await page.waitForFunction(() => document.getElementById('notice').textContent.startsWith('Warm-up skipped'));
    await page.waitForFunction(() => window.secPlayground.episodes >= 30, null, { timeout: 180000, polling: 500 });
    await page.click('#play');
    for (let i = 0; i < 300; i++) {
      await page.click('#step-decision');
      await page.waitForTimeout(10);
      if ((await page.evaluate(() => window.secPlayground.explanation))?.couplets.length) break;
    }
    await page.evaluate(() => { document.getElementById('explain').open = true; });
    await page.waitForTimeout(500);
    const path = new URL(`../docs/img/${name}.png`, import.meta.url).pathname;
    await page.screenshot({ path });
    console.log(`wrote ${path}`);
    await page.close();
  }
} finally {
  await browser.close();
  server.close();
}

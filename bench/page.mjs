// The page's weight over the wire and its time to the first camera frame, in Debian's Chromium.
//   npm run bench:page            (after scripts/build.sh)
// Weight: every response the default page (index.html) loads until its first frame, each body
// gzipped at level 9 as a static host would serve it; the scalar build's wasm, which a browser
// without SIMD loads instead of the SIMD one, is reported too. First frame: from the start of
// navigation (performance.timeOrigin) to the 'sec-playground:first-frame' mark the page sets when
// it draws its first camera image; the median of 5 cold loads (a fresh browser context each,
// cache off), on a local server, so network time is ~0 and the figure is the page's own work.
import { gzipSync } from 'node:zlib';
import { openChromium } from './browser.mjs';

const LOADS = 5;
const { server, browser, base } = await openChromium(['--no-first-run', '--disable-background-networking']);

async function load(path, wantBytes) {
  const context = await browser.newContext({ viewport: { width: 1300, height: 1000 } });
  const page = await context.newPage();
  const bodies = [];
  if (wantBytes) {
    page.on('response', async (r) => {
      try {
        const body = await r.body();
        bodies.push({ url: r.url().replace(base, ''), raw: body.length, gz: gzipSync(body, { level: 9 }).length });
      } catch { /* redirects and the like have no body */ }
    });
  }
  await page.goto(base + path);
  await page.waitForFunction(() => performance.getEntriesByName('sec-playground:first-frame').length > 0, null,
    { timeout: 30000 });
  const ms = await page.evaluate(() => performance.getEntriesByName('sec-playground:first-frame')[0].startTime);
  await page.waitForTimeout(500); // late responses (the vendored CSS, the worker's module graph)
  await context.close();
  return { ms, bodies };
}

try {
  const times = [];
  let bodies = [];
  for (let i = 0; i < LOADS; i++) {
    const r = await load('', i === 0);
    times.push(r.ms);
    if (i === 0) bodies = r.bodies;
  }
  times.sort((a, b) => a - b);
  const total = (key) => bodies.reduce((s, b) => s + b[key], 0);
  console.log('files of the default page (raw / gzip -9 bytes):');
  for (const b of bodies.sort((a, b) => b.gz - a.gz)) console.log(`  ${b.url.padEnd(48)} ${String(b.raw).padStart(9)} ${String(b.gz).padStart(9)}`);
  console.log(`page weight: ${total('raw')} bytes raw, ${total('gz')} bytes gzipped (${(total('gz') / 1048576).toFixed(2)} MiB)`);
  const scalar = await load('?wasm=scalar', true);
  const wasm = scalar.bodies.find((b) => b.url.includes('scalar/sec_playground_bg.wasm'));
  console.log(`scalar fallback wasm: ${wasm?.raw} bytes raw, ${wasm?.gz} gzipped`);
  console.log(`first camera frame: median ${times[Math.floor(LOADS / 2)].toFixed(0)} ms, min ${times[0].toFixed(0)}, max ${times.at(-1).toFixed(0)} ms (${LOADS} cold loads, chromium ${browser.version()})`);
} finally {
  await browser.close();
  server.close();
}

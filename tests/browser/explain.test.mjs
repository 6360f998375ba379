// The page explains what it shows, in real Chromium: why the reactive layer acts during the
// warm-up, a decision's couplets summing into the Q of its action grid, live views and a true
// decision rate at max speed, a phone-sized screen, the file:// message, and an embedded iframe
// that pauses while scrolled out of sight.
import { test, before, after, afterEach } from 'node:test';
import assert from 'node:assert/strict';
import { mkdirSync, writeFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { ARTIFACTS, launch } from './harness.mjs';

let server, browser, base;
before(async () => { ({ server, browser, base } = await launch()); });
after(async () => { await browser?.close(); server?.close(); });
const pages = [];
afterEach(async () => { for (const p of pages.splice(0)) if (!p.isClosed()) await p.close(); });

async function open(path, viewport = { width: 1300, height: 1000 }) {
  const page = await browser.newPage({ viewport });
  pages.push(page);
  const problems = [];
  page.on('pageerror', (e) => problems.push(String(e)));
  await page.goto(base + path);
  await page.waitForFunction(() => window.secPlayground?.settings && window.secPlayground.view);
  return { page, problems };
}

const maxSpeed = (page) => page.evaluate(() => {
  const s = document.getElementById('speed');
  s.value = s.max;
  s.dispatchEvent(new Event('input'));
});

test('the warm-up says why the reactive layer acts, and a decision explains its Q term by term', async () => {
  const { page, problems } = await open('#task=object-permanence&seed=2');
  await page.waitForFunction(() => window.secPlayground.view.layer);
  assert.match(await page.textContent('#why'), /memory holds \d of the 5 sequences SEC needs/);
  assert.notEqual(await page.textContent('#gate-mse'), '–');
  // Memory's vote is shown as such while the reactive layer acts.
  assert.match(await page.textContent('#policy-caption'), /not acted on: the reactive layer chose/);
  assert.ok(await page.$eval('.policy', (f) => f.classList.contains('not-acted')));
  // Learn at max speed until the memory can act, then pause and step until it selects.
  await maxSpeed(page);
  await page.waitForFunction(() => window.secPlayground.view.ltm >= 5, null, { timeout: 120000, polling: 250 });
  await page.click('#play');
  await page.waitForFunction(() => !window.secPlayground.playing);
  // Each step waits for its view (which carries its explanation), not for a time. A step ends at
  // the next decision or at the episode's end, which takes none (Session::step_decision): where
  // the pause left the run depends on the machine's speed, so both are waited for.
  let e = null;
  let layer = null;
  for (let i = 0; i < 400 && !(e?.couplets.length); i++) {
    const before = await page.evaluate(() => ({ d: window.secPlayground.view.decisions, ep: window.secPlayground.view.episode }));
    await page.click('#step-decision');
    await page.waitForFunction((b) => window.secPlayground.view.decisions > b.d || window.secPlayground.view.episode > b.ep, before);
    ({ e, layer } = await page.evaluate(() => ({ e: window.secPlayground.explanation, layer: window.secPlayground.view.layer })));
  }
  assert.ok(e?.couplets.length, 'memory selected couplets within 400 decisions');
  if (layer === 'C') {
    assert.match(await page.textContent('#policy-caption'), /acted on: the outlined action is drawn from it/);
    assert.ok(!(await page.$eval('.policy', (f) => f.classList.contains('not-acted'))));
  }
  // Every couplet's value adds to the Q of its action; p = Q / sum Q is the grid's.
  const q = Array(9).fill(0);
  for (const c of e.couplets) q[c.action] += c.value;
  q.forEach((v, a) => assert.ok(Math.abs(v - e.q[a]) < 1e-9 * Math.max(1, e.q[a]), `Q[${a}]: ${v} vs ${e.q[a]}`));
  const total = e.q.reduce((s, v) => s + v, 0);
  const grid = await page.$$eval('#probs tbody td', (tds) => tds.map((td) => td.textContent));
  e.q.forEach((v, a) => assert.equal(grid[a], (v / total).toFixed(2), `p of action ${a}`));
  const rows = await page.$$eval('#explain tbody tr', (trs) => trs.length);
  assert.equal(rows, Math.min(e.couplets.length, 200) + (e.couplets.length > 200 ? 1 : 0));
  const sums = await page.$$eval('#explain tfoot tr', (trs) => trs.map((tr) => Number(tr.dataset.action)));
  assert.deepEqual(sums, e.q.map((v, a) => (v > 0 ? a : -1)).filter((a) => a >= 0));
  assert.match(await page.textContent('#explain .formula'), /G \/ Gmax > θ_prop/);
  // It says first which layer acted, and "drawn from p" only when memory did.
  const formula = await page.textContent('#explain .formula');
  if (layer === 'C') assert.match(formula, /^Memory acted \(the contextual layer\).*drawn from p/);
  else assert.match(formula, /^The reactive layer acted: .*not acted on/);
  if (layer !== 'C') assert.doesNotMatch(formula, /drawn from p/);
  assert.deepEqual(problems, []);
});

test('the explanation says which layer acted: the reactive layer\'s decision shows memory\'s vote as not acted on', async () => {
  const { page, problems } = await open('#task=object-permanence');
  await page.waitForFunction(() => window.secPlayground.view.layer);
  // The panel as the page draws it, for one explanation with couplets and each layer.
  const texts = await page.evaluate(async () => {
    const { drawExplanation } = await import('./www/explain.js');
    const root = document.getElementById('explain').cloneNode(true);
    const e = {
      couplets: [{ sequence: 0, position: 3, g: 0.99, t: 1, rr: 1, d: 0.5, action: 3, value: 0.6 }],
      q: [0, 0, 0, 0.6, 0, 0, 0, 0, 0], p: [0, 0, 0, 1, 0, 0, 0, 0, 0],
      sequentialBias: true, valueFunction: 'default', thetaAbs: 0.98, thetaProp: 0.995, tau: 0.9,
    };
    const out = {};
    for (const layer of ['C', 'R', 'H']) {
      drawExplanation(root, e, layer);
      out[layer] = root.querySelector('.formula').textContent;
    }
    drawExplanation(root, { ...e, couplets: [] }, 'R');
    out.none = root.querySelector('.formula').textContent;
    return out;
  });
  assert.match(texts.C, /^Memory acted .*the action was drawn from p\.$/);
  assert.match(texts.R, /^The reactive layer acted: its walk chose the action\. Memory's vote below was not acted on\./);
  assert.match(texts.R, /the vote the reactive layer overrode\.$/);
  assert.match(texts.H, /^You acted .*the vote your driving overrode\.$/);
  for (const t of [texts.R, texts.H, texts.none]) assert.doesNotMatch(t, /drawn from p/);
  assert.match(texts.none, /^The reactive layer acted\. No stored couplet passed/);
  assert.deepEqual(problems, []);
});

test('at max speed the views keep moving and decisions/s is the true rate', async () => {
  const { page } = await open('#task=double-t-maze');
  await maxSpeed(page);
  await page.waitForFunction(() => window.secPlayground.playing);
  // The camera and the run's decision count sampled inside the page at every animation frame,
  // so what the test compares is read at the moments the page drew, whatever the machine's load.
  await page.evaluate(() => {
    const hash = () => {
      const c = document.getElementById('camera');
      const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
      let h = 0;
      for (let i = 0; i < d.length; i += 7) h = (h * 31 + d[i]) | 0;
      return h;
    };
    window.samples = { hashes: new Set(), counts: [] };
    const tick = () => {
      window.samples.hashes.add(hash());
      window.samples.counts.push({ t: performance.now(), d: window.secPlayground.view.decisions });
      requestAnimationFrame(tick);
    };
    tick();
  });
  // Frozen views never change; moving ones show several distinct images (one pair can match
  // where the agent faces a wall: views repeat in the double T-maze).
  await page.waitForFunction(() => window.samples.hashes.size >= 3, null, { timeout: 60000 });
  // The readout, its text and its window read in one evaluation (read a moment apart, they
  // belong to different views). The window is the last 3 s of the worker's own clock, so a busy
  // main thread does not bend it; against the page's frames over 5 s, counted independently, it
  // agrees within a factor of 2 (a unit or a count of views instead of decisions would not).
  await page.waitForFunction(() => {
    const c = window.samples.counts;
    return c.length > 10 && c[c.length - 1].t - c[0].t > 5000;
  }, null, { timeout: 60000 });
  const r = await page.evaluate(() => {
    const c = window.samples.counts;
    const last = c[c.length - 1];
    const first = c.find((x) => x.t >= last.t - 5000);
    const text = [...document.querySelectorAll('#status dt')]
      .find((dt) => dt.textContent === 'decisions/s').nextElementSibling.textContent;
    return {
      shown: window.secPlayground.rate, text, window: window.secPlayground.rateWindow,
      frames: ((last.d - first.d) * 1000) / (last.t - first.t),
    };
  });
  assert.equal(r.text, r.shown.toFixed(0));
  assert.ok(Math.abs(r.shown - (r.window.decisions * 1000) / r.window.ms) < 1e-9, JSON.stringify(r));
  assert.ok(r.window.ms > 2000 && r.window.ms < 6000, `about a 3 s window: ${JSON.stringify(r)}`);
  assert.ok(r.shown > r.frames / 2 && r.shown < r.frames * 2, `readout ${r.shown} vs ${r.frames} decisions/s counted`);
  // A slow speed is right too: the readout settles at 10/s once its window holds only the slow
  // decisions.
  await page.evaluate(() => {
    const s = document.getElementById('speed');
    s.value = '3'; // 10/s
    s.dispatchEvent(new Event('input'));
  });
  await page.waitForFunction(() => window.secPlayground.rate > 7 && window.secPlayground.rate < 13, null, { timeout: 60000 });
});

test('on a phone-sized screen nothing is wider than the screen and the camera comes first', async () => {
  const { page } = await open('', { width: 390, height: 844 });
  const width = await page.evaluate(() => document.documentElement.scrollWidth);
  assert.ok(width <= 390, `the document is ${width} px wide`);
  const order = await page.evaluate(() => {
    const y = (sel) => document.querySelector(sel).getBoundingClientRect().top;
    return { camera: y('#camera'), charts: y('#charts'), controls: y('#controls') };
  });
  assert.ok(order.camera < order.charts && order.charts < order.controls, `camera, charts, then controls: ${JSON.stringify(order)}`);
  // Touch targets: every visible button at least 44 px tall and wide, checkboxes with 44 px of room.
  const small = await page.evaluate(() => [...document.querySelectorAll('button, input[type=checkbox], label.file')]
    .filter((b) => b.offsetParent !== null)
    .map((b) => {
      const r = b.getBoundingClientRect();
      const m = b.type === 'checkbox' ? 16 : 0; // a box's margin counts as its target
      return { id: b.id || b.textContent.trim(), h: r.height + m, w: r.width + m };
    })
    .filter((b) => b.h < 44 || b.w < 44));
  assert.deepEqual(small, [], 'targets under 44 px');
  mkdirSync(ARTIFACTS, { recursive: true });
  await page.screenshot({ path: fileURLToPath(new URL('phone.png', ARTIFACTS)), fullPage: false });
  // The explanation, open, with the widest numbers its table shows, fits the screen.
  const table = await page.evaluate(async () => {
    const { drawExplanation } = await import('./www/explain.js');
    const details = document.getElementById('explain');
    details.open = true;
    const couplets = Array.from({ length: 12 }, (_, i) => ({
      sequence: 480 + i, position: 49, g: 0.987654, t: 1.198765, rr: 0.123456, d: 0.98, action: 8, value: 1.2345e-5,
    }));
    const q = [0, 0, 0, 0, 0, 0, 0, 0, 1.4814e-4];
    drawExplanation(details, { couplets, q, p: q.map((v) => v / 1.4814e-4), sequentialBias: true, valueFunction: 'default',
      thetaAbs: 0.98, thetaProp: 0.995, tau: 0.9 }, 'R');
    const r = details.querySelector('table').getBoundingClientRect();
    return { left: r.left, right: r.right, page: document.documentElement.scrollWidth };
  });
  assert.ok(table.left >= 0 && table.right <= 390 && table.page <= 390, `the explain table spans ${JSON.stringify(table)}`);
  // A short way to the settings, four screens down.
  const y = () => page.evaluate(() => document.getElementById('controls').getBoundingClientRect().top);
  assert.ok(await y() > 844, 'the settings start below the first screen');
  await page.click('#to-controls');
  await page.waitForFunction(() => Math.abs(document.getElementById('controls').getBoundingClientRect().top) < 5);
});

test('at 1400x900 the camera, the why-line, the action grid and the reward chart are on the first screen', async () => {
  const { page } = await open('', { width: 1400, height: 900 });
  await page.waitForFunction(() => window.secPlayground.episodes > 0, null, { timeout: 60000 });
  const boxes = await page.evaluate(() => Object.fromEntries(['#camera', '#why', '#probs', '[data-chart="reward"]'].map((sel) => {
    const r = document.querySelector(sel).getBoundingClientRect();
    return [sel, { top: Math.round(r.top), bottom: Math.round(r.bottom), height: Math.round(r.height) }];
  })));
  for (const [sel, b] of Object.entries(boxes)) {
    assert.ok(b.height > 0 && b.top >= 0 && b.top < 900, `${sel} starts on the first screen: ${JSON.stringify(b)}`);
  }
  assert.ok(boxes['#camera'].bottom <= 900 && boxes['#probs'].bottom <= 900, JSON.stringify(boxes));
  mkdirSync(ARTIFACTS, { recursive: true });
  await page.screenshot({ path: fileURLToPath(new URL('desktop-1400x900.png', ARTIFACTS)), fullPage: false });
});

test('opened from disk, the page says how to serve it', async () => {
  const page = await browser.newPage();
  pages.push(page);
  await page.goto(new URL('../../index.html', import.meta.url).href);
  assert.ok(await page.isVisible('#file-note'));
  assert.match(await page.textContent('#file-note'), /http\.server/);
  // A course page opened from disk: its element cannot start and shows the text inside its tag.
  await page.goto(new URL('../../www/examples/course.html', import.meta.url).href);
  await page.waitForSelector('#sec .sec-fallback', { state: 'visible' });
  assert.match(await page.textContent('#sec .sec-fallback'), /http\.server/);
});

test('an embedded iframe pauses while scrolled out of sight', async () => {
  mkdirSync(ARTIFACTS, { recursive: true });
  writeFileSync(new URL('iframe-host.html', ARTIFACTS), '<!doctype html><body style="margin:0">'
    + '<iframe id="f" src="/embed.html#task=detour" style="width:1200px;height:900px;border:0"></iframe>'
    + '<div style="height:4000px"></div></body>');
  const page = await browser.newPage({ viewport: { width: 1300, height: 900 } });
  pages.push(page);
  await page.goto(`${base}test-artifacts/iframe-host.html`);
  const frame = () => page.frames().find((f) => f.url().includes('embed.html'));
  await page.waitForFunction(() => true);
  await frame().waitForFunction(() => window.secPlayground?.playing, null, { timeout: 60000 });
  const step = () => frame().evaluate(() => window.secPlayground.decisions ?? window.secPlayground.view.decisions);
  await page.evaluate(() => window.scrollTo(0, 3000));
  await frame().waitForFunction(() => !window.secPlayground.playing, null, { timeout: 10000 });
  const a = await step();
  await page.waitForTimeout(1500);
  assert.equal(await step(), a, 'no decision while out of sight');
  await page.evaluate(() => window.scrollTo(0, 0));
  await frame().waitForFunction((s) => window.secPlayground.view.decisions > s, a, { timeout: 10000 });
});

test('the tour opens from #tour and walks through every stage of a decision, each on its view', async () => {
  const { page, problems } = await open('#task=object-permanence&tour');
  await page.waitForFunction(() => window.secPlayground.tour.stage === 0);
  assert.ok(await page.isVisible('#tour-box'));
  assert.ok(await page.isHidden('#error'), '`tour` is not reported as a bad setting');
  assert.equal((await page.evaluate(() => window.secPlayground.settings)).task, 'object-permanence');
  await page.waitForFunction(() => !window.secPlayground.playing && window.secPlayground.view.action != null);
  const e = await page.evaluate(() => window.secPlayground.view.embedding);
  assert.equal(e.length, 20, 'the embedding view has the decision\'s 20 numbers');
  const n = await page.evaluate(() => window.secPlayground.tour.stages);
  assert.ok(n >= 10);
  const titles = [];
  for (let i = 0; i < n; i++) {
    const s = await page.evaluate(() => ({ ...window.secPlayground.tour }));
    assert.equal(s.stage, i);
    assert.equal(s.focused.length, 1, `stage ${i + 1} highlights one view`);
    titles.push(await page.textContent('#tour-title'));
    await page.click('#tour-next');
  }
  assert.ok(await page.isHidden('#tour-box'), 'Done closes it');
  assert.equal(new Set(titles).size, n);
  assert.equal((await page.evaluate(() => window.secPlayground.tour.focused)).length, 0);
  // The button starts it again; Back goes back.
  await page.click('#tour');
  await page.click('#tour-next');
  await page.click('#tour-back');
  assert.equal(await page.evaluate(() => window.secPlayground.tour.stage), 0);
  assert.deepEqual(problems, []);
});

test('text colours pass WCAG AA contrast in the light and the dark scheme', async () => {
  for (const scheme of ['light', 'dark']) {
    const page = await browser.newPage({ colorScheme: scheme });
    pages.push(page);
    await page.goto(base);
    await page.waitForFunction(() => window.secPlayground?.view);
    const ratios = await page.evaluate(() => {
      const rgb = (s) => s.match(/[\d.]+/g).slice(0, 3).map(Number);
      const lum = (c) => {
        const [r, g, b] = c.map((v) => { const x = v / 255; return x <= 0.03928 ? x / 12.92 : ((x + 0.055) / 1.055) ** 2.4; });
        return 0.2126 * r + 0.7152 * g + 0.0722 * b;
      };
      const bg = rgb(getComputedStyle(document.body).backgroundColor);
      const ratio = (el) => {
        const a = lum(rgb(getComputedStyle(el).color));
        const b = lum(bg);
        return (Math.max(a, b) + 0.05) / (Math.min(a, b) + 0.05);
      };
      // The learning curves' lines, as their legend's markers draw them (the colour uPlot strokes).
      // A translucent colour is what it shows over the background.
      const over = (s) => {
        const [r, g, b, alpha = 1] = s.match(/[\d.]+/g).map(Number);
        return [r, g, b].map((v, i) => alpha * v + (1 - alpha) * bg[i]);
      };
      const lines = [...document.querySelectorAll('.u-legend .u-marker')].map((m) => {
        const a = lum(over(getComputedStyle(m).borderTopColor));
        const b = lum(bg);
        return (Math.max(a, b) + 0.05) / (Math.min(a, b) + 0.05);
      });
      return {
        text: ratio(document.body), help: ratio(document.querySelector('.param .help')),
        why: ratio(document.getElementById('why')), caption: ratio(document.querySelector('figcaption')),
        lines,
      };
    });
    const { lines, ...texts } = ratios;
    for (const [what, r] of Object.entries(texts)) assert.ok(r >= 4.5, `${scheme}: ${what} contrast ${r.toFixed(2)}`);
    // Lines are graphics: WCAG's 3:1 (each chart's per-episode line and its mean).
    assert.ok(lines.length >= 9, `${lines.length} lines`);
    for (const r of lines) assert.ok(r >= 3, `${scheme}: a chart line's contrast ${r.toFixed(2)}`);
  }
});

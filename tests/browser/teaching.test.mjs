// The playground for teaching, in real Chromium: compare mode and the paper's presets, driving
// with the arrow keys and recording into the LTM, CSV export, memory files (a corrupt one is
// refused and the run goes on), the <sec-playground> element twice on a course page, the iframe
// page's height messages, the self-contained build from a plain static folder, and the scalar
// fallback giving the SIMD build's episodes.
import { test, before, after, afterEach } from 'node:test';
import assert from 'node:assert/strict';
import { cpSync, mkdtempSync, readFileSync, rmSync, writeFileSync, existsSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { gunzipSync } from 'node:zlib';
import { fileURLToPath } from 'node:url';
import { ARTIFACTS, launch, until as waitUntil } from './harness.mjs';
import { serve } from '../../scripts/serve.mjs';

let server, browser, base;

before(async () => {
  ({ server, browser, base } = await launch());
});

after(async () => {
  await browser?.close();
  server?.close();
});

// A failed test must not leave its workers running under the next one.
const pages = [];
afterEach(async () => {
  for (const p of pages.splice(0)) if (!p.isClosed()) await p.close();
});

/** The threads the pages here say the machine has: a comparison's pool is one less (4), so a
 *  preset's three configurations start at once on any machine. */
const THREADS = 5;

async function newPage() {
  const page = await browser.newPage({ viewport: { width: 1300, height: 1000 }, acceptDownloads: true });
  await page.addInitScript((n) => Object.defineProperty(Navigator.prototype, 'hardwareConcurrency', { get: () => n }), THREADS);
  pages.push(page);
  return page;
}

async function open(path, problems = []) {
  const page = await newPage();
  page.on('console', (m) => { if (m.type() === 'error') problems.push(m.text()); });
  page.on('pageerror', (e) => problems.push(String(e)));
  await page.goto(base + path);
  return page;
}

const ready = (page) => page.waitForFunction(() => window.secPlayground?.settings && window.secPlayground.view);

/** Pixels of `hex` on the compare chart: opaque (lines) and translucent (bands). */
/** Polls `read` until `ok` holds of its value or `ms` pass; returns the last value read. */
async function until(read, ok, ms) {
  const end = Date.now() + ms;
  let value = await read();
  while (!ok(value) && Date.now() < end) {
    await new Promise((r) => setTimeout(r, 200));
    value = await read();
  }
  return value;
}

function armPixels(page, hex) {
  return page.evaluate((hex) => {
    const n = parseInt(hex.slice(1), 16);
    const [r, g, b] = [n >> 16, (n >> 8) & 255, n & 255];
    const cv = document.querySelector('#compare-chart canvas');
    const d = cv.getContext('2d').getImageData(0, 0, cv.width, cv.height).data;
    const out = { line: 0, band: 0 };
    for (let i = 0; i < d.length; i += 4) {
      if (Math.abs(d[i] - r) + Math.abs(d[i + 1] - g) + Math.abs(d[i + 2] - b) > 30) continue;
      if (d[i + 3] > 200) out.line++;
      else if (d[i + 3] > 20 && d[i + 3] < 90) out.band++;
    }
    return out;
  }, hex);
}

test('compare mode: a preset starts its runs; two configurations draw two series with bands', async () => {
  const problems = [];
  const page = await open('#task=object-permanence', problems);
  try {
    await ready(page);
    await page.click('#compare-exp1');
    const c = () => page.evaluate(() => ({ ...window.secPlayground.compare }));
    assert.equal((await c()).arms, 3);
    assert.ok((await c()).running);
    // The caption quotes the reference index, fetched when the preset starts.
    await page.waitForFunction(() => window.secPlayground.compare.caption !== '', null, { timeout: 20000 });
    assert.match((await c()).caption, /paper/i);
    // The preset runs what its caption says: the double T-maze, the authors' untrained encoder,
    // SEC, NSEC and MFEC.
    assert.match((await c()).caption, /untrained encoder/);
    await page.waitForFunction(() => window.secPlayground.compare.resolved.every((s) => s), null, { timeout: 60000 });
    const arms = (await c()).resolved.map((s) => [s.task, s.perception, s.agent, s.bias]);
    assert.deepEqual(arms, [
      ['double-t-maze', 'untrained', 'sec', '1'],
      ['double-t-maze', 'untrained', 'sec', '0'],
      ['double-t-maze', 'untrained', 'mfec-ae', '1'],
    ]);
    await page.waitForFunction(() => window.secPlayground.compare.drawn.series === 3, null, { timeout: 120000, polling: 500 });
    // The caption's finding in view, at most 60 words; the rest behind "more".
    const short = (await c()).captionShort;
    assert.ok(short.split(/\s+/).length <= 60 && short.length > 20, short);
    assert.ok((await c()).caption.length > short.length);
    // The x axis follows the live runs (within a factor 2), not the reference runs' thousands.
    // Read in one evaluation with the live count it follows (the two change between redraws).
    await page.waitForFunction(() => {
      const d = window.secPlayground.compare.drawn;
      return d.live >= 3 && d.x[1] >= d.live - 1 && d.x[1] <= Math.max(20, 2 * d.live);
    }, null, { timeout: 120000, polling: 500 });
    let d = (await c()).drawn;
    assert.ok(d.episodes >= 1000, 'the reference runs are longer');
    // "The reference runs' full length" shows them all.
    await page.click('#compare-full');
    await page.waitForFunction(() => window.secPlayground.compare.drawn.x[1] > 1000, null, { timeout: 5000 });
    d = (await c()).drawn;
    assert.equal(d.x[1], d.episodes - 1);
    // A drag across the chart zooms to that range; "Reset zoom" follows the live runs again.
    await page.locator('#compare-chart .u-over').scrollIntoViewIfNeeded();
    const over = await page.locator('#compare-chart .u-over').boundingBox();
    await page.mouse.move(over.x + over.width * 0.2, over.y + over.height / 2);
    await page.mouse.down();
    await page.mouse.move(over.x + over.width * 0.4, over.y + over.height / 2, { steps: 5 });
    await page.mouse.up();
    await page.waitForFunction(() => window.secPlayground.compare.drawn.x[0] > 0, null, { timeout: 5000 });
    d = (await c()).drawn;
    assert.ok(d.x[0] > 500 && d.x[1] < 2500, `zoomed to ${d.x}`);
    await page.click('#compare-full');
    await page.click('#compare-zoom-reset');
    await page.waitForFunction(() => window.secPlayground.compare.drawn.x[0] === 0, null, { timeout: 5000 });
    d = (await c()).drawn;
    assert.ok(d.x[0] === 0 && d.x[1] <= Math.max(20, 2 * d.live), JSON.stringify(d));
    // Two configurations of object permanence (goals come early) with two seeds each.
    await page.click('#compare-clear');
    await page.selectOption('#compare-seeds', '2');
    await page.click('#compare-add');
    await page.evaluate(() => { location.hash = 'task=object-permanence&bias=0'; });
    await page.waitForFunction(() => window.secPlayground.settings.bias === '0');
    await page.click('#compare-add');
    await page.click('#compare-run');
    await page.waitForFunction(() => {
      const d = window.secPlayground.compare.drawn;
      return d.series === 2 && d.bands === 2 && d.episodes >= 30;
    }, null, { timeout: 120000, polling: 500 });
    // Pixels show at the chart's next redraw, which a slow machine may take seconds to reach.
    const drawn = (a) => a.line > 30 && a.band > 100;
    const first = await until(() => armPixels(page, '#0072b2'), drawn, 20000);
    const second = await until(() => armPixels(page, '#d55e00'), drawn, 20000);
    assert.ok(first.line > 30 && second.line > 30, `lines: ${first.line}, ${second.line}`);
    assert.ok(first.band > 100 && second.band > 100, `bands: ${first.band}, ${second.band}`);
    await page.locator('#compare').screenshot({ path: fileURLToPath(new URL('compare.png', ARTIFACTS)) });
    assert.deepEqual(problems, []);
  } finally {
    await page.close();
  }
});

test('compare at the horizon: a pool of 4 plays four runs at once while the page\'s run waits', async () => {
  const problems = [];
  const page = await open('#task=object-permanence', problems);
  try {
    await ready(page);
    await page.waitForFunction(() => window.secPlayground.playing);
    assert.equal(await page.inputValue('#compare-workers'), String(THREADS - 1), 'the threads less one');
    await page.click('#compare-exp1');
    const c = () => page.evaluate(() => window.secPlayground.compare);
    // Experiment 1 to the paper's horizon: 3 configurations x 5 seeds x 5000 episodes.
    assert.equal(await page.inputValue('#compare-episodes'), '5000');
    assert.equal((await c()).jobs.length, 15);
    // The page's run pauses, with a note that says why.
    await page.waitForFunction(() => window.secPlayground.pausedForCompare && !window.secPlayground.playing);
    assert.ok(await page.locator('#main-paused').isVisible());
    const mainEpisodes = await page.evaluate(() => window.secPlayground.episodes);
    // Four runs play, the first seed of each configuration first.
    await page.waitForFunction(() => {
      const playing = window.secPlayground.compare.jobs.filter((j) => j.state === 'playing');
      return playing.length === 4 && playing.every((j) => j.episodes > 0);
    }, null, { timeout: 120000, polling: 250 });
    const first = (await c()).jobs.filter((j) => j.state === 'playing');
    assert.deepEqual(first.map((j) => j.seed), [1, 1, 1, 2]);
    // Every one of them advances, all at once (none waits for another to finish).
    await page.waitForFunction((before) => {
      const now = window.secPlayground.compare.jobs;
      return before.every((b) => now.some((j) => j.label === b.label && j.seed === b.seed && j.episodes > b.episodes + 5));
    }, first, { timeout: 120000, polling: 250 });
    assert.equal((await c()).pool, 4);
    assert.match((await c()).progress, /of 75,000 episodes .*4 playing at once/);
    assert.equal(await page.evaluate(() => window.secPlayground.episodes), mainEpisodes, 'the page\'s run stayed paused');
    // Pausing the comparison gives the machine back to the page's run.
    await page.click('#compare-run');
    await page.waitForFunction(() => !window.secPlayground.pausedForCompare && window.secPlayground.playing);
    assert.match((await c()).progress, /paused/);
    // Resumed, it pauses the page's run again; "Resume it" plays it beside the comparison.
    await page.click('#compare-run');
    await page.waitForFunction(() => window.secPlayground.pausedForCompare);
    await page.click('#main-resume');
    await page.waitForFunction(() => !window.secPlayground.pausedForCompare && window.secPlayground.playing);
    assert.ok((await c()).running);
    assert.deepEqual(problems, []);
  } finally {
    await page.close();
  }
});

test('a comparison plays its runs to their horizon, and a bad horizon is refused by name', async () => {
  const problems = [];
  const page = await open('#task=object-permanence&m=10', problems);
  try {
    await ready(page);
    await page.selectOption('#compare-workers', '1');
    await page.selectOption('#compare-seeds', '2');
    await page.click('#compare-add');
    // A non-number and an out-of-range number are refused, naming the control and its range.
    await page.fill('#compare-episodes', '');
    // What a number input holds while its text is not a number ('1e': badInput, value '').
    await page.locator('#compare-episodes').pressSequentially('1e');
    await page.click('#compare-run');
    await page.waitForFunction(() => /compare episodes: is not a number/.test(document.getElementById('error').textContent));
    assert.match(await page.locator('#error').innerText(), /10\.\.=20000/);
    await page.fill('#compare-episodes', '70000');
    await page.click('#compare-run');
    await page.waitForFunction(() => /compare episodes: 70000 is out of range 10\.\.=20000/.test(document.getElementById('error').textContent));
    assert.equal((await page.evaluate(() => window.secPlayground.compare)).running, false, 'nothing started');
    await page.fill('#compare-episodes', '60');
    await page.click('#compare-run');
    // One worker: seeds 1 and 2 to 60 episodes, then done; the page's run carries on.
    await page.waitForFunction(() => window.secPlayground.compare.jobs.every((j) => j.state === 'done'), null, { timeout: 240000, polling: 250 });
    const c = await page.evaluate(() => window.secPlayground.compare);
    assert.deepEqual(c.jobs.map((j) => [j.seed, j.episodes]), [[1, 60], [2, 60]]);
    // Its 10-sequence LTM filled early, and the chart marks the episode on its line.
    await page.waitForFunction(() => window.secPlayground.compare.drawn.fills?.some((f) => f.live));
    const fill = (await page.evaluate(() => window.secPlayground.compare.drawn.fills)).find((f) => f.live);
    const ltm = await page.evaluate(() => window.secPlayground.compare.resolved[0].m);
    assert.equal(ltm, '10');
    assert.ok(fill.episode > 0 && fill.episode < 60, JSON.stringify(fill));
    assert.equal(c.pool, 0, 'the workers are let go');
    assert.ok(!c.running);
    await page.waitForFunction(() => window.secPlayground.playing && !window.secPlayground.pausedForCompare);
    assert.match(c.progress, /120 of 120 episodes \(100 %\), 2 of 2 runs done\./);
    assert.deepEqual(problems.filter((p) => !/compare episodes/.test(p)), []);
  } finally {
    await page.close();
  }
});

test('runs take turns on a pool smaller than the plan, and the turns change no episode', async () => {
  const problems = [];
  // The test flavour's hook shortens a turn to 300 ms of play (10 s on the published page).
  const page = await open('?wasm=hooks&turn=300#task=object-permanence&m=10', problems);
  try {
    await ready(page);
    await page.selectOption('#compare-seeds', '2');
    await page.click('#compare-add');
    await page.fill('#compare-episodes', '80');
    const play = async (workers) => {
      await page.selectOption('#compare-workers', String(workers));
      await page.click('#compare-run');
      await page.waitForFunction(() => {
        const jobs = window.secPlayground.compare.jobs;
        return jobs.length === 2 && jobs.every((j) => j.state === 'done') && !window.secPlayground.compare.running;
      }, null, { timeout: 240000, polling: 250 });
      return page.evaluate(() => {
        const c = window.secPlayground.compare;
        return c.jobs.map((j, i) => ({ seed: j.seed, episodes: j.episodes, turns: j.turns, log: c.log(i) }));
      });
    };
    // One worker, two runs: they take turns, each handed over as a checkpoint and resumed.
    const shared = await play(1);
    assert.deepEqual(shared.map((j) => [j.seed, j.episodes]), [[1, 80], [2, 80]]);
    assert.ok(shared.every((j) => j.turns >= 2), `turns: ${shared.map((j) => j.turns)}`);
    // Two workers: no turns; every run's episodes are the ones it played in turns, bit for bit.
    const alone = await play(2);
    assert.deepEqual(alone.map((j) => j.turns), [1, 1]);
    assert.deepEqual(alone.map((j) => j.log.map((e) => e.episode)), [1, 2].map(() => Array.from({ length: 80 }, (_, i) => i)));
    assert.deepEqual(alone.map(({ turns, ...j }) => j), shared.map(({ turns, ...j }) => j));
    assert.deepEqual(problems, []);
  } finally {
    await page.close();
  }
});

test('a preset draws its reference runs at once, made at the settings its arms run', async () => {
  const problems = [];
  const page = await open('', problems);
  try {
    await ready(page);
    await page.click('#compare-exp1');
    // DQN, ERLAM and ERLAM-5k (native only) come as reference runs alone, those the index lists.
    const listed = await page.evaluate(async () => (await (await fetch('assets/reference/index.json')).json()).references.map((r) => r.reference));
    const natives = ['exp1:double-t-maze/DQN', 'exp1:double-t-maze/ERLAM', 'exp1:double-t-maze/ERLAM-5k'];
    assert.ok(listed.includes(natives[0]), 'DQN has committed reference runs');
    const expected = 3 + natives.filter((n) => listed.includes(n)).length;
    await page.waitForFunction((n) => window.secPlayground.compare.drawn.references === n, expected, { timeout: 30000 });
    const c = await page.evaluate(() => ({ ...window.secPlayground.compare }));
    assert.equal(c.arms, 3, 'no live run of an agent the page cannot run');
    assert.deepEqual(c.natives.map((n) => [n.label, n.seeds !== null]),
      [['DQN', true], ['ERLAM', listed.includes(natives[1])], ['ERLAM-5k', listed.includes(natives[2])]]);
    assert.match(c.referenceNote, /DQN \(\d+ seeds? × 1000 episodes\)[^.]*: reference runs only/);
    assert.match(await page.locator('#compare-arms').innerText(), /DQN\s*reference runs only \(native\)/);
    assert.equal(c.drawn.liveAtFirstReference, 0, 'the bands come before any live episode');
    // The committed runs decide the spans (the 5000-episode grid lengthens them run by run).
    const spans = [...c.references, ...c.natives].filter((r) => r?.episodes).map((r) => r.episodes);
    assert.equal(c.drawn.episodes, Math.max(...spans), 'the x axis spans the longest reference run');
    const sec = c.references[0];
    assert.ok(c.referenceNote.includes(`${sec.seeds} seeds × ${sec.episodes} episodes`), c.referenceNote);
    // Over the reference runs' whole span (the live runs' first episodes may have narrowed the x
    // axis already), at the chart's next redraw, which a slow machine may take seconds to reach.
    await page.click('#compare-full');
    await page.waitForFunction(() => window.secPlayground.compare.drawn.x[1] > 1000, null, { timeout: 5000 });
    const band = await until(async () => (await armPixels(page, '#0072b2')).band, (n) => n > 500, 20000);
    assert.ok(band > 500, `SEC's reference band is drawn (${band} band pixels)`);
    // The reference runs were made with exactly the settings the live arms run.
    await page.waitForFunction(() => window.secPlayground.compare.resolved.every((s) => s), null, { timeout: 60000 });
    const { resolved, references } = await page.evaluate(() => ({ ...window.secPlayground.compare }));
    assert.equal(references.filter((r) => r).length, 3);
    for (const [i, r] of references.entries()) {
      const { seed, ...live } = resolved[i];
      assert.deepEqual(live, r.settings, r.name);
    }
    // Experiment 1 in another task of the paper's table 1.
    await page.selectOption('#compare-task', 'detour');
    await page.waitForFunction(() => /detour/.test(window.secPlayground.compare.caption));
    await page.waitForFunction(() => window.secPlayground.compare.resolved.every((s) => s), null, { timeout: 60000 });
    assert.deepEqual((await page.evaluate(() => window.secPlayground.compare.resolved)).map((s) => s.task), ['detour', 'detour', 'detour']);
    assert.deepEqual(problems, []);
  } finally {
    await page.close();
  }
});

test('Experiment 2 marks where each memory fills and says from which episode its arms part', async () => {
  const problems = [];
  const page = await open('', problems);
  try {
    await ready(page);
    await page.click('#compare-exp2');
    const index = await page.evaluate(async () => (await (await fetch('assets/reference/index.json')).json()).references);
    const entry = (name) => index.find((r) => r.reference === name);
    const first = (name) => Math.min(...entry(name).ltmFull.filter((e) => e != null));
    await page.waitForFunction(() => window.secPlayground.compare.drawn.references === 4, null, { timeout: 30000 });
    await page.waitForFunction(() => window.secPlayground.compare.captionShort !== '');
    const c = await page.evaluate(() => window.secPlayground.compare);
    // The summary names where the reference runs of the two sizes part: the 125-sequence LTM's first fill.
    assert.ok(c.captionShort.includes(`part from episode ${first('exp2:m125/SEC')} (SEC) and ${first('exp2:m125/NSEC')} (NSEC)`),
      c.captionShort);
    // Each reference line has its fill marked (○), at its runs' median fill.
    const marks = c.drawn.fills.filter((f) => !f.live).map((f) => f.episode);
    assert.equal(marks.length, 4);
    const med = (name) => {
      const v = entry(name).ltmFull.filter((e) => e != null).sort((a, b) => a - b);
      return v[(v.length - 1) >> 1];
    };
    assert.deepEqual(marks, ['m125/SEC', 'm125/NSEC', 'm1000/SEC', 'm1000/NSEC'].map((m) => med(`exp2:${m}`)));
    assert.deepEqual(problems, []);
  } finally {
    await page.close();
  }
});

test('a preset whose reference runs are not in yet says so and draws none', async () => {
  const problems = [];
  const page = await newPage();
  page.on('pageerror', (e) => problems.push(String(e)));
  // The index as it was before experiment 3's runs: its entries taken out.
  await page.route('**/assets/reference/index.json', async (route) => {
    const response = await route.fetch();
    const json = await response.json();
    json.references = json.references.filter((r) => !r.reference.startsWith('exp3:'));
    await route.fulfill({ response, json });
  });
  try {
    await page.goto(base);
    await ready(page);
    await page.click('#compare-exp3');
    await page.waitForFunction(() => /No reference runs/.test(window.secPlayground.compare.referenceNote));
    assert.equal((await page.evaluate(() => window.secPlayground.compare.references)).filter((r) => r).length, 0);
    assert.equal((await page.evaluate(() => window.secPlayground.compare.drawn.references)), 0);
    assert.deepEqual(problems, []);
  } finally {
    await page.close();
  }
});

/** Holds the arrow keys that steer the agent to (x, z), until `done()` or `ms` pass. */
async function steer(page, x, z, done, ms) {
  const held = new Set();
  const want = async (keys) => {
    for (const k of held) if (!keys.has(k)) { await page.keyboard.up(k); held.delete(k); }
    for (const k of keys) if (!held.has(k)) { await page.keyboard.down(k); held.add(k); }
  };
  const t0 = Date.now();
  while (Date.now() - t0 < ms) {
    if (await done()) break;
    const v = await page.evaluate(() => window.secPlayground.view);
    const aim = (Math.atan2(x - v.x, z - v.z) * 180) / Math.PI;
    const diff = ((aim - v.heading + 540) % 360) - 180;
    await want(new Set(diff > 12 ? ['ArrowRight'] : diff < -12 ? ['ArrowLeft'] : ['ArrowUp']));
    await page.waitForTimeout(40);
  }
  await want(new Set());
}

test('driving: arrow keys move the agent, and a recorded rewarded episode raises the LTM by one', async () => {
  const problems = [];
  const page = await open('#task=object-permanence&seed=3', problems);
  await ready(page);
  await page.click('#record');
  await page.evaluate(() => document.activeElement?.blur()); // shortcuts act when no control has focus
  await page.keyboard.press('d');
  assert.ok(await page.evaluate(() => window.secPlayground.driving));
  // A fresh run, driven from its start at (5, 5).
  await page.keyboard.press('r');
  await page.waitForFunction(() => window.secPlayground.episodes === 0 && window.secPlayground.view.step < 8);
  const at = () => page.evaluate(() => ({ x: window.secPlayground.view.x, z: window.secPlayground.view.z }));
  const p0 = await at();
  // Held until the agent has moved (however slowly a loaded machine plays), then let go.
  await page.keyboard.down('ArrowUp');
  await page.waitForFunction((p) => Math.hypot(window.secPlayground.view.x - p.x, window.secPlayground.view.z - p.z) > 0.5,
    p0, { timeout: 60000 });
  await page.keyboard.up('ArrowUp');
  assert.equal(await page.evaluate(() => window.secPlayground.view.layer), 'H');
  // Steer to the small goal at (20, 25): the episode ends rewarded, driven, with one sequence stored.
  const rewarded = () => page.evaluate(() => window.secPlayground.log.some((m) => m.human && m.goal));
  await steer(page, 20, 25, rewarded, 180000);
  const ep = await page.evaluate(() => window.secPlayground.log.find((m) => m.human && m.goal));
  assert.ok(ep, 'the driven episode reached the goal');
  // Positive: the goal's reward, less 1/t per env step the steering took (a loaded machine's
  // steering reacts later and takes more steps, so no tighter bound holds).
  assert.ok(ep.reward > 0 && ep.reward === ep.rawReward, `reward ${ep.reward}, raw ${ep.rawReward}`);
  assert.equal(ep.ltm, 1, 'the LTM went from 0 to 1 sequence');
  // Without record the next driven episode stores nothing.
  await page.click('#record');
  await steer(page, 20, 25, () => page.evaluate(() => window.secPlayground.log.filter((m) => m.human && m.goal).length >= 2), 180000);
  const eps = await page.evaluate(() => window.secPlayground.log.filter((m) => m.human && m.goal));
  assert.equal(eps.length, 2);
  assert.equal(eps[1].ltm, 1, 'an unrecorded episode adds nothing');
  assert.deepEqual(problems, []);
  await page.close();
});

test('the drive pad moves the agent by touch, and stops when the finger lifts', async () => {
  const problems = [];
  const page = await browser.newPage({ viewport: { width: 390, height: 844 }, hasTouch: true, isMobile: true });
  pages.push(page);
  page.on('pageerror', (e) => problems.push(String(e)));
  await page.goto(`${base}#task=object-permanence&seed=3`);
  await ready(page);
  assert.equal(await page.isVisible('#drive-pad'), false, 'the pad shows only while driving');
  // Scrolled so that Drive is at the top: the pad, below the camera, would open off screen.
  await page.evaluate(() => window.scrollTo(0, document.getElementById('drive').getBoundingClientRect().top + scrollY - 4));
  await page.tap('#drive');
  await page.waitForFunction(() => window.secPlayground.driving);
  assert.equal(await page.isVisible('#drive-pad'), true);
  // It comes into view, and the notice says to touch it (not the arrow keys).
  const pad = await page.evaluate(() => document.getElementById('drive-pad').getBoundingClientRect());
  assert.ok(pad.top >= 0 && pad.bottom <= 844, `the pad is at ${pad.top}-${pad.bottom}`);
  assert.match(await page.textContent('#notice'), /touch and hold a button of the pad/);
  assert.doesNotMatch(await page.textContent('#notice'), /arrow keys/);
  const touch = await page.context().newCDPSession(page);
  const at = () => page.evaluate(() => {
    const v = window.secPlayground.view;
    return { x: v.x, z: v.z, episode: v.episode };
  });
  // A fresh run, driven from its start.
  await page.tap('#reset');
  await page.waitForFunction(() => window.secPlayground.episodes === 0 && window.secPlayground.view.step < 8);
  // Reset is at the top: back to the pad. The notice above moves the pad down: wait until the
  // pad stays put between two frames.
  await page.locator('#drive-pad').scrollIntoViewIfNeeded();
  await page.waitForFunction(() => {
    const top = document.querySelector('#drive-pad button[data-action="3"]').getBoundingClientRect().top;
    const still = top === window.padTop;
    window.padTop = top;
    return still;
  }, null, { polling: 'raf' });
  const box = await page.locator('#drive-pad button[data-action="3"]').boundingBox();
  const point = { x: box.x + box.width / 2, y: box.y + box.height / 2 };
  const p0 = await at();
  await touch.send('Input.dispatchTouchEvent', { type: 'touchStart', touchPoints: [point] });
  // Held until the person's forward has moved the agent (a condition: a loaded machine is slow).
  await page.waitForFunction((p) => {
    const v = window.secPlayground.view;
    return v.layer === 'H' && v.action === 3 && Math.hypot(v.x - p.x, v.z - p.z) > 0.5;
  }, p0, { timeout: 60000 });
  await touch.send('Input.dispatchTouchEvent', { type: 'touchEnd', touchPoints: [] });
  const p1 = await at();
  assert.equal(p1.episode, p0.episode);
  // Let go: the person's action is "stand still" (0) again, and the agent coasts to a stop.
  await page.waitForFunction(() => window.secPlayground.view.action === 0 && window.secPlayground.view.layer === 'H');
  // It comes to a stop: two positions 40 decisions apart (the run's own clock, not the wall's)
  // within 0.05 of each other.
  await waitUntil(async () => {
    const p2 = await at();
    const d2 = await page.evaluate(() => window.secPlayground.view.decisions);
    await page.waitForFunction((d) => window.secPlayground.view.decisions >= d + 40, d2, { timeout: 60000 });
    const p3 = await at();
    return p3.episode !== p2.episode || Math.hypot(p3.x - p2.x, p3.z - p2.z) < 0.05;
  }, 'the agent to stop', 120000);
  assert.deepEqual(problems, []);
});

test('"skip the warm-up" starts again from the reference run\'s memory, of the size that run logged', async () => {
  const problems = [];
  const page = await open('#seed=4', problems);
  await ready(page);
  const index = JSON.parse(readFileSync(new URL('../../assets/warm-up/index.json', import.meta.url), 'utf8'));
  const entry = index['double-t-maze'];
  // The size the reference run logged after those episodes, read from its committed log.
  const log = gunzipSync(readFileSync(new URL(`../../results/experiments/${entry.run}/seed-${entry.seed}.jsonl.gz`, import.meta.url)))
    .toString().split('\n');
  const logged = JSON.parse(log[entry.episodes - 1]).ltm;
  assert.equal(entry.sequences, logged);
  await page.evaluate(() => document.activeElement?.blur());
  await page.keyboard.press(' '); // pause: the loaded memory is what the view shows
  await page.waitForFunction(() => !window.secPlayground.playing);
  await page.click('#warm-up');
  await page.waitForFunction(() => document.getElementById('notice').textContent.startsWith('Warm-up skipped'));
  assert.match(await page.textContent('#notice'), new RegExp(`${entry.run}, seed ${entry.seed}, after ${entry.episodes} episodes \\(${logged} sequences`));
  await page.waitForFunction((n) => window.secPlayground.view.ltm === n && window.secPlayground.episodes === 0, logged);
  // The reference run's seed: the untrained encoder is drawn per seed.
  assert.equal(await page.evaluate(() => window.secPlayground.settings.seed), String(entry.seed));
  assert.match(await page.evaluate(() => location.hash), new RegExp(`seed=${entry.seed}\\b`));
  // Bad input loses nothing: with n = 40 the file (n = 50) is refused by name and the run keeps its memory.
  await page.fill('#p-n', '40');
  await page.press('#p-n', 'Enter');
  await page.waitForFunction(() => window.secPlayground.settings.n === '40');
  const ltm = await page.evaluate(() => window.secPlayground.view.ltm);
  await page.click('#warm-up');
  await page.waitForFunction(() => !document.getElementById('error').hidden);
  assert.match(await page.textContent('#error'), /n: the file's sequences have 50 couplets, this run's STM length n is 40/);
  assert.equal(await page.evaluate(() => window.secPlayground.view.ltm), ltm);
  assert.deepEqual(problems, []);
});

test('CSV export has a header and one row per episode; memory files save, load, and a corrupt one is refused', async () => {
  const problems = [];
  const page = await open('#task=object-permanence&seed=2', problems);
  await ready(page);
  await page.waitForFunction(() => window.secPlayground.view.ltm >= 2, null, { timeout: 60000 });
  await page.keyboard.press(' ');
  await page.waitForFunction(() => !window.secPlayground.playing);
  const n = await page.evaluate(() => window.secPlayground.log.length);
  const [csv] = await Promise.all([page.waitForEvent('download'), page.click('#export-csv')]);
  const text = readFileSync(await csv.path(), 'utf8').trimEnd().split('\n');
  assert.equal(text[0], 'run,seed,episode,layout,reward,rawReward,goal,envSteps,decisions,entropy,entropyFresh,ltm,contextualShare,human');
  assert.equal(text.length, n + 1, 'one row per episode');
  assert.match(text[1], /^main,2,0,8-7-\d,/);
  // Numbers rounded to 9 significant digits: a failed episode's raw reward, 1000 steps at -1/1000
  // each, is -1, not -1.0000000000000007; each equals the log's value so rounded.
  const log = await page.evaluate(() => window.secPlayground.log);
  const cols = text[0].split(',');
  for (const [i, line] of text.slice(1).entries()) {
    const row = line.split(',');
    for (const f of ['reward', 'rawReward', 'entropy', 'contextualShare']) {
      const cell = row[cols.indexOf(f)];
      assert.equal(Number(cell), Number(log[i][f].toPrecision(9)), `${f} of episode ${i}`);
      assert.ok(cell.replace(/^-?0?\.?0*|[.-]|e.*$/g, '').length <= 9, `${f} ${cell}`);
    }
  }
  const failed = log.findIndex((m) => !m.goal && m.envSteps === 1000);
  if (failed >= 0) assert.equal(text[failed + 1].split(',')[cols.indexOf('rawReward')], '-1');
  // Reward and raw are explained where they show.
  await page.click('#reward-help');
  assert.match(await page.textContent('#reward-note'), /less 1\/t for every env step.*raw.*before the floor/s);
  const [json] = await Promise.all([page.waitForEvent('download'), page.click('#export-json')]);
  const cfg = JSON.parse(readFileSync(await json.path(), 'utf8'));
  assert.equal(cfg.settings.task, 'object-permanence');
  assert.equal(cfg.config.agent.memory.alpha, 0.01);
  assert.equal(cfg.seed, 2);
  // Save the memory, then load it back.
  const ltm = await page.evaluate(() => window.secPlayground.view.ltm);
  const [mem] = await Promise.all([page.waitForEvent('download'), page.click('#save-memory')]);
  const bytes = readFileSync(await mem.path());
  assert.equal(bytes.subarray(0, 8).toString(), 'SECMEMRY');
  const dir = mkdtempSync(join(tmpdir(), 'secmem-'));
  writeFileSync(join(dir, 'good.secmem'), bytes);
  await page.setInputFiles('#load-memory', join(dir, 'good.secmem'));
  await page.waitForFunction((ltm) => document.getElementById('notice').textContent.includes(`${ltm} sequence`), ltm);
  // A corrupt file: a clear error, the run keeps its memory and goes on.
  const bad = Buffer.from(bytes);
  bad[bad.length - 40] ^= 0xff;
  writeFileSync(join(dir, 'bad.secmem'), bad);
  await page.setInputFiles('#load-memory', join(dir, 'bad.secmem'));
  await page.waitForFunction(() => !document.getElementById('error').hidden);
  assert.match(await page.textContent('#error'), /memory: checksum mismatch/);
  assert.equal(await page.textContent('#notice'), '', 'no stale "Memory loaded" next to the error');
  writeFileSync(join(dir, 'foreign.secmem'), 'name,value\nalpha,1\n');
  await page.setInputFiles('#load-memory', join(dir, 'foreign.secmem'));
  await page.waitForFunction(() => document.getElementById('error').textContent.includes('magic'));
  assert.equal(await page.evaluate(() => window.secPlayground.view.ltm), ltm);
  const before = await page.evaluate(() => window.secPlayground.episodes);
  await page.evaluate(() => document.activeElement?.blur());
  await page.keyboard.press(' ');
  await page.waitForFunction((b) => window.secPlayground.episodes > b + 1, before, { timeout: 60000 });
  rmSync(dir, { recursive: true });
  assert.deepEqual(problems, []);
  await page.close();
});

/** Waits until both elements of the course page play and returns their states. */
async function coursePage(page) {
  await page.waitForFunction(() => ['sec', 'nsec'].every((id) => document.getElementById(id).state?.view
    && document.getElementById(id).state.episodes > 0), null, { timeout: 90000, polling: 250 });
  return page.evaluate(() => ['sec', 'nsec'].map((id) => {
    const s = document.getElementById(id).state;
    return { settings: s.settings, episodes: s.episodes, playing: s.playing };
  }));
}

test('two <sec-playground> elements on a course page run their own settings; the iframe posts its height', async () => {
  const problems = [];
  const page = await newPage();
  page.on('console', (m) => { if (m.type() === 'error') problems.push(m.text()); });
  page.on('pageerror', (e) => problems.push(String(e)));
  await page.addInitScript(() => {
    window.heights = [];
    window.addEventListener('message', (e) => { if (e.data?.type === 'sec-playground:height') window.heights.push(e.data.height); });
  });
  await page.goto(`${base}www/examples/course.html`);
  // Scrolled into view in turn (an element off screen pauses).
  await page.locator('#sec').scrollIntoViewIfNeeded();
  await page.waitForFunction(() => document.getElementById('sec').state?.episodes > 0, null, { timeout: 90000 });
  await page.locator('#nsec').scrollIntoViewIfNeeded();
  // Served over HTTP, the element started: the fallback text inside its tag is not shown.
  assert.equal(await page.isVisible('#sec .sec-fallback'), false);
  const [a, b] = await coursePage(page);
  assert.equal(a.settings.bias, '1');
  assert.equal(b.settings.bias, '0');
  assert.equal(b.settings.m, '125');
  assert.equal(a.settings.m, '500');
  // Hidden controls are hidden in the second only.
  const hidden = await page.evaluate(() => ['sec', 'nsec'].map((id) => document.getElementById(id).shadowRoot
    .querySelector('.param[data-key="n"]').hidden));
  assert.deepEqual(hidden, [false, true]);
  // A key pressed in one element pauses that one only.
  await page.locator('#nsec').focus();
  await page.keyboard.press(' ');
  await page.waitForFunction(() => !document.getElementById('nsec').state.playing);
  assert.ok(await page.evaluate(() => document.getElementById('sec').state.playing !== undefined));
  // Attributes in any case or kebab form; a bad one is refused by name and a later valid one applies.
  const nsec = (f) => page.evaluate(f);
  await nsec(() => document.getElementById('nsec').setAttribute('startheading', 'sideways'));
  await page.waitForFunction(() => document.getElementById('nsec').shadowRoot.getElementById('error').textContent
    .includes('startHeading'));
  await nsec(() => document.getElementById('nsec').setAttribute('alpha', '0.2'));
  await page.waitForFunction(() => document.getElementById('nsec').state.settings.alpha === '0.2');
  await nsec(() => document.getElementById('nsec').setAttribute('start-heading', 'fixed'));
  await page.waitForFunction(() => document.getElementById('nsec').state.settings.startHeading === 'fixed');
  await nsec(() => document.getElementById('nsec').setAttribute('embeddingScale', '2'));
  await page.waitForFunction(() => document.getElementById('nsec').state.settings.embeddingScale === '2');
  // The first one, scrolled away, pauses; back on screen, it plays again.
  await page.evaluate(() => window.scrollTo(0, document.body.scrollHeight));
  await page.waitForFunction(() => !document.getElementById('sec').state.playing, null, { timeout: 10000 });
  await page.locator('#sec').scrollIntoViewIfNeeded();
  await page.waitForFunction(() => document.getElementById('sec').state.playing, null, { timeout: 10000 });
  // The iframe's page told this one its height.
  await page.waitForFunction(() => window.heights.length > 0, null, { timeout: 30000 });
  const h = await page.evaluate(() => window.heights.at(-1));
  assert.ok(h > 400, `posted height ${h}`);
  assert.equal(await page.evaluate(() => document.getElementById('frame').height), String(h));
  await page.screenshot({ path: fileURLToPath(new URL('course.png', ARTIFACTS)), fullPage: true });
  assert.deepEqual(problems, []);
  await page.close();
});

test('an element without its controls is compact, takes a new hide at once, and labels changes by their symbols', async () => {
  const problems = [];
  const page = await newPage();
  page.on('pageerror', (e) => problems.push(String(e)));
  // A course page of its own, served beside the playground.
  await page.route(`${base}compact.html`, (route) => route.fulfill({ contentType: 'text/html', body: `<!doctype html>
    <body style="margin:0;width:1200px"><script src="www/sec-playground.js"></script>
    <sec-playground id="p" task="object-permanence" hide="controls compare keepbar" autoplay></sec-playground>` }));
  await page.goto(`${base}compact.html`);
  await page.waitForFunction(() => document.getElementById('p').state?.episodes > 0, null, { timeout: 90000 });
  const shape = () => page.evaluate(() => {
    const el = document.getElementById('p');
    const r = el.shadowRoot;
    const views = r.querySelector('.views').getBoundingClientRect();
    return { height: el.getBoundingClientRect().height, views: views.width, controls: !r.getElementById('controls').hidden,
      compare: !r.getElementById('compare').hidden };
  });
  const compact = await shape();
  // The views take the width the controls left (one column), so the element stays short.
  assert.ok(compact.views > 1000, `views ${compact.views} px wide`);
  assert.ok(compact.height < 1400, `element ${compact.height} px tall`);
  assert.equal(compact.controls, false);
  // A new hide applies at once: the controls back, the compare section hidden.
  await page.evaluate(() => document.getElementById('p').setAttribute('hide', 'compare keepbar n'));
  await page.waitForFunction(() => !document.getElementById('p').shadowRoot.getElementById('controls').hidden);
  const shown = await shape();
  assert.ok(shown.views < compact.views && !shown.compare, JSON.stringify(shown));
  assert.ok(await page.evaluate(() => document.getElementById('p').shadowRoot.querySelector('.param[data-key="n"]').hidden));
  assert.ok(await page.evaluate(() => !document.getElementById('p').shadowRoot.querySelector('.param[data-key="m"]').hidden));
  // A camelCase attribute (lowercased by HTML) is named by the table's symbol.
  await page.evaluate(() => document.getElementById('p').setAttribute('thetaprop', '0.99'));
  await page.waitForFunction(() => document.getElementById('p').state.settings.thetaProp === '0.99');
  const notice = await page.evaluate(() => document.getElementById('p').shadowRoot.getElementById('notice').textContent);
  assert.match(notice, /θ_prop=0\.99/);
  assert.doesNotMatch(notice, /thetaprop/);
  assert.ok((await page.evaluate(() => document.getElementById('p').state.marks)).some((m) => /θ_prop=0\.99/.test(m.label ?? m)));
  assert.deepEqual(problems, []);
  await page.close();
});

test('opened from disk, an element without text of its own says how to serve the page', async () => {
  const page = await newPage();
  await page.goto(new URL('../../www/examples/course.html', import.meta.url).href);
  // The page's own fallback stays as written; the element without one gets the shipped text.
  await page.waitForFunction(() => document.querySelector('#nsec p'));
  assert.match(await page.textContent('#nsec'), /served over HTTP.*python3 -m http\.server/s);
  assert.equal(await page.locator('#sec p').count(), 1);
  assert.ok(await page.isVisible('#sec .sec-fallback'));
  await page.close();
});

test('the self-contained build runs from a plain static folder', async () => {
  const dist = fileURLToPath(new URL('../../dist/sec-playground', import.meta.url));
  assert.ok(existsSync(dist), 'scripts/build.sh writes dist/sec-playground');
  const dir = mkdtempSync(join(tmpdir(), 'course-'));
  cpSync(dist, join(dir, 'sec-playground'), { recursive: true });
  const own = await serve(0, '127.0.0.1', dir);
  try {
    const problems = [];
    const page = await newPage();
    page.on('console', (m) => { if (m.type() === 'error') problems.push(m.text()); });
    page.on('pageerror', (e) => problems.push(String(e)));
    await page.goto(`http://127.0.0.1:${own.address().port}/sec-playground/www/examples/course.html`);
    await page.locator('#sec').scrollIntoViewIfNeeded();
    await page.waitForFunction(() => document.getElementById('sec').state?.episodes > 0, null, { timeout: 90000 });
    await page.goto(`http://127.0.0.1:${own.address().port}/sec-playground/index.html#task=detour`);
    await ready(page);
    assert.equal(await page.evaluate(() => window.secPlayground.settings.task), 'detour');
    assert.deepEqual(problems, []);
    await page.close();
  } finally {
    own.close();
    rmSync(dir, { recursive: true });
  }
});

test('the scalar fallback build gives the same episodes as the SIMD build', async () => {
  const first = async (path) => {
    const page = await open(path);
    await ready(page);
    await page.waitForFunction(() => window.secPlayground.log.length >= 3, null, { timeout: 90000 });
    const out = await page.evaluate(() => ({ build: window.secPlayground.build, log: window.secPlayground.log.slice(0, 3) }));
    await page.close();
    return out;
  };
  const simd = await first('#task=object-permanence&seed=2');
  const scalar = await first('?wasm=scalar#task=object-permanence&seed=2');
  assert.equal(simd.build, 'simd');
  assert.equal(scalar.build, 'scalar');
  assert.deepEqual(scalar.log, simd.log);
  // And both are the native golden run's first episodes (exact numbers), with the default,
  // untrained perception.
  const golden = readFileSync(new URL('../golden/run-untrained.txt', import.meta.url), 'utf8').split('\n').slice(0, 3).map((l) => JSON.parse(l));
  assert.deepEqual(simd.log, golden);
});

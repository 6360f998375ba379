// The arena page in a real Chromium (Debian's, driven by playwright-core): it loads without
// console errors, draws both views, the arrow keys drive the agent, and bad input shows an
// error while the run goes on. Screenshots go to test-artifacts/.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { fileURLToPath } from 'node:url';
import { ARTIFACTS, launch, untilColours } from './harness.mjs';

let server, browser, page, base;
const problems = [];

before(async () => {
  ({ server, browser, base } = await launch());
  page = await browser.newPage({ viewport: { width: 1000, height: 800 } });
  page.on('console', (m) => { if (m.type() === 'error') problems.push(m.text()); });
  page.on('pageerror', (e) => problems.push(String(e)));
  await page.goto(base + 'arena.html');
  await page.waitForFunction(() => window.secPlayground?.env);
});

after(async () => {
  await browser?.close();
  server?.close();
});

test('the page loads without console errors and draws both views', async () => {
  // The T-maze start may face a fence (floor and fence only); the top-down view shows it all.
  await untilColours(page, '#camera', 2);
  await untilColours(page, '#arena', 8);
  assert.deepEqual(problems, []);
  // The canvas holds exactly what the wasm camera rendered.
  const same = await page.evaluate(() => {
    const d = document.getElementById('camera').getContext('2d').getImageData(0, 0, 84, 84).data;
    const o = window.secPlayground.env.observation();
    return d.length === o.length;
  });
  assert.ok(same);
  await page.screenshot({ path: new URL('arena-page.png', ARTIFACTS).pathname });
});

test('arrow keys drive the agent', async () => {
  await page.selectOption('#task', 'detour');
  await page.waitForFunction(() => window.secPlayground.env.taskName() === 'detour');
  const before = await page.evaluate(() => window.secPlayground.env.agent());
  await page.locator('body').click({ position: { x: 5, y: 5 } });
  // Held until the agent has moved, however slowly a loaded machine steps (60 ms a step at best).
  await page.keyboard.down('ArrowUp');
  await page.waitForFunction((z) => window.secPlayground.env.agent().z - z > 3, before.z, { timeout: 60000 });
  await page.keyboard.up('ArrowUp');
  const mid = await page.evaluate(() => window.secPlayground.env.agent());
  await page.keyboard.down('ArrowRight');
  await page.waitForFunction(() => window.secPlayground.env.agent().heading > 20, null, { timeout: 60000 });
  await page.keyboard.up('ArrowRight');
  const after = await page.evaluate(() => window.secPlayground.env.agent());
  assert.ok(after.heading > 20 && after.heading < 180, `right turned to ${after.heading}`);
  await page.screenshot({ path: new URL('arena-driven.png', ARTIFACTS).pathname });
});

test('a bad seed shows an error naming it and the run goes on', async () => {
  const steps = await page.evaluate(() => window.secPlayground.env.agent().steps);
  await page.fill('#seed', '-4');
  await page.dispatchEvent('#seed', 'change');
  const msg = await page.textContent('#error');
  assert.match(msg, /^seed: .*out of range 0\.\.=/);
  await page.waitForFunction((s) => window.secPlayground.env.agent().steps !== s, steps, { timeout: 60000 });
  // An empty field and a limit too long are the core's to refuse too, with its own ranges (the
  // page's script keeps none).
  await page.fill('#seed', '');
  await page.dispatchEvent('#seed', 'change');
  assert.match(await page.textContent('#error'), /^seed: '' \(a string\) is out of range 0\.\.=9007199254740991/);
  await page.fill('#seed', '1');
  await page.fill('#limit', '100001');
  await page.dispatchEvent('#limit', 'change');
  assert.match(await page.textContent('#error'), /^t: 100001 is out of range 0\.\.=100000 \(whole numbers\)/);
  await page.fill('#limit', '1000');
  await page.dispatchEvent('#limit', 'change');
  assert.equal(await page.isHidden('#error'), true);
  assert.deepEqual(problems, []);
});

test("a loaded YAML arena shows in the task menu, and its t does not carry over to the tasks", async () => {
  const yaml = fileURLToPath(new URL('../../assets/arenas/v1_3-4-1.yml', import.meta.url));
  await page.setInputFiles('#yaml', yaml);
  await page.waitForFunction(() => document.getElementById('task').value === '(custom)');
  assert.equal(await page.textContent('#task option[value="(custom)"]'), 'custom: v1_3-4-1.yml');
  assert.equal(await page.inputValue('#limit'), '250', "the file's t");
  assert.match(await page.textContent('#description'), /Custom arena v1_3-4-1\.yml/);
  await page.selectOption('#task', 'cylinder');
  await page.waitForFunction(() => window.secPlayground.env.taskName() === 'cylinder');
  assert.equal(await page.inputValue('#limit'), '1000', "the tasks' limit again");
  assert.equal(await page.evaluate(() => window.secPlayground.env.agent().t), 1000);
  assert.equal(await page.locator('#task option[value="(custom)"]').count(), 0, 'the file leaves the menu');
  assert.deepEqual(problems, []);
});

test('an arena file that is too large or not text is refused by name before it is read', async () => {
  const steps = await page.evaluate(() => window.secPlayground.env.agent().steps);
  await page.setInputFiles('#yaml', { name: 'huge.yaml', mimeType: 'text/yaml', buffer: Buffer.alloc((1 << 20) + 1, 0x20) });
  assert.match(await page.textContent('#error'), /^yaml: huge\.yaml is 1048577 bytes, larger than 1048576/);
  await page.setInputFiles('#yaml', { name: 'picture.yaml', mimeType: 'text/yaml', buffer: Buffer.from([0x89, 0x50, 0xff, 0xfe]) });
  await page.waitForFunction(() => document.getElementById('error').textContent.includes('picture.yaml'));
  assert.match(await page.textContent('#error'), /^yaml: picture\.yaml is not UTF-8 text/);
  // The arena goes on.
  await page.waitForFunction((s) => window.secPlayground.env.agent().steps !== s, steps, { timeout: 60000 });
  assert.deepEqual(problems, []);
});

test('the Olympics menu lists the 900 arenas by category; a category-7 arena goes dark at its blackouts', async () => {
  await page.waitForFunction(() => document.querySelectorAll('#olympics optgroup').length === 10);
  const options = await page.$$eval('#olympics option[value$=".yaml"]', (os) => os.map((o) => ({ v: o.value, off: o.disabled, t: o.textContent })));
  assert.equal(options.length, 900);
  // Every file loads in the arena build (a file that could not would say why and be disabled).
  assert.deepEqual(options.filter((o) => o.off).map((o) => o.t), []);
  // 06-11-01's rails written through their posts are left out, as v1 does, and the page says so.
  await page.selectOption('#olympics', '06-11-01.yaml');
  await page.waitForFunction(() => window.secPlayground.env.taskName() === '06-11-01.yaml');
  assert.match(await page.textContent('#description'), /As v1 does: line 110: .*its Wall .* left out, as v1 does/);
  // 07-01-01: the light switches every 20 env steps (blackouts [-20]); one env step is 60 ms here.
  await page.selectOption('#olympics', '07-01-01.yaml');
  await page.waitForFunction(() => window.secPlayground.env.taskName() === '07-01-01.yaml');
  assert.equal(await page.textContent('#task option[value="(custom)"]'), 'olympics: 07-01-01.yaml');
  // The camera's darkness and the env step, read together (the page steps in real time, so a
  // busy machine may be anywhere in the cycle): dark exactly in steps 20-39 of each 40.
  const lights = () => {
    const d = document.getElementById('camera').getContext('2d').getImageData(0, 0, 84, 84).data;
    let dark = true;
    for (let i = 0; i < d.length && dark; i += 4) dark = !(d[i] || d[i + 1] || d[i + 2]);
    return { dark, steps: window.secPlayground.env.agent().steps };
  };
  await page.waitForFunction(`(() => {
    const l = (${lights})();
    window.lightsSeen ??= new Set();
    window.lightsSeen.add(l.dark);
    return window.lightsSeen.size === 2 && !l.dark ? l : false;
  })()`, null, { timeout: 60000 });
  for (let k = 0; k < 5; k++) {
    const l = await page.evaluate(lights);
    assert.equal(l.dark, l.steps % 40 >= 20, `step ${l.steps}: ${l.dark ? 'dark' : 'lit'}`);
  }
  assert.deepEqual(problems, []);
});

test('an Olympics ramp arena: held forward, the agent climbs the ramp in front of it', async () => {
  // 05-25-01: the agent starts facing a 1 m ramp (docs/ARENAS.md section 5); the arrow key is held
  // until it stands above the floor, however slowly a loaded machine steps.
  await page.selectOption('#olympics', '05-25-01.yaml');
  await page.waitForFunction(() => window.secPlayground.env.taskName() === '05-25-01.yaml');
  const start = await page.evaluate(() => window.secPlayground.env.agent());
  assert.equal(start.y, 0, 'it starts on the floor');
  await page.locator('body').click({ position: { x: 5, y: 5 } });
  await page.keyboard.down('ArrowUp');
  await page.waitForFunction(() => window.secPlayground.env.agent().y > 0.5, null, { timeout: 60000 });
  await page.keyboard.up('ArrowUp');
  const up = await page.evaluate(() => window.secPlayground.env.agent());
  assert.ok(up.y > 0.5 && up.y < 1.0, `on the ramp, below its 0.999 top: ${up.y}`);
  assert.deepEqual(problems, []);
});

test('an Olympics arena links to the playground, where SEC learns it with the untrained encoder and no gate', async () => {
  await page.selectOption('#olympics', '05-25-01.yaml');
  await page.waitForFunction(() => window.secPlayground.env.taskName() === '05-25-01.yaml');
  assert.equal(await page.getAttribute('#learn-link', 'href'), 'index.html?arena=05-25-01');
  // A built-in task has no such link.
  await page.selectOption('#task', 'detour');
  await page.waitForFunction(() => window.secPlayground.env.taskName() === 'detour');
  assert.ok(await page.locator('#learn').isHidden());

  const pg = await browser.newPage({ viewport: { width: 1400, height: 900 } });
  const seen = [];
  pg.on('console', (m) => { if (m.type() === 'error') seen.push(m.text()); });
  pg.on('pageerror', (e) => seen.push(String(e)));
  await pg.goto(base + 'index.html?arena=05-25-01');
  // Episodes of the file's own t (500 env steps, 125 decisions) finish in the arena build.
  await pg.waitForFunction(() => window.secPlayground.episodes >= 2, null, { timeout: 120000 });
  const state = await pg.evaluate(() => ({ build: window.secPlayground.build, log: window.secPlayground.log.slice(0, 2) }));
  assert.equal(state.build, 'arena');
  for (const m of state.log) {
    assert.equal(m.layout, '05-25-01');
    assert.ok(m.envSteps <= 500, `${m.envSteps} env steps`);
  }
  assert.match(await pg.textContent('#arena-note'), /05-25-01 .*untrained encoder.*without the reconstruction gate/s);
  // What such a run has no use for is hidden: the task and encoder choices, the reconstruction,
  // the warm-up and the comparison of the paper's tasks.
  for (const sel of ['#controls .param[data-key="task"]', '#controls .param[data-key="perception"]', '#controls .param[data-key="t"]', 'figure.reconstruction', '#warm-up', '#compare']) {
    const el = pg.locator(sel).first();
    assert.ok(await el.count(), `${sel} is not on the page`);
    assert.ok(await el.isHidden(), `${sel} shows`);
  }
  await untilColours(pg, '#camera', 3);
  await pg.screenshot({ path: new URL('playground-olympics.png', ARTIFACTS).pathname });
  assert.deepEqual(seen, []);

  // A name that is not an Olympics arena's, and one shaped like it with no file, each say so.
  await pg.goto(base + 'index.html?arena=nope');
  await pg.waitForFunction(() => !document.getElementById('error').hidden);
  assert.match(await pg.textContent('#error'), /arena: 'nope' is not an Olympics arena's name/);
  await pg.goto(base + 'index.html?arena=10-99-01');
  await pg.waitForFunction(() => !document.getElementById('error').hidden);
  assert.match(await pg.textContent('#error'), /could not load: arena: assets\/arenas\/competition\/10-99-01\.yaml could not be loaded/);
  await pg.close();
});

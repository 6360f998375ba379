// The iframe protocol (docs/EMBED.md) in real Chromium, across origins: the host page is served
// from 127.0.0.1 and frames embed.html from localhost (another origin, the same server). A host
// drives the iframe (connect, configure, play, episodes, metrics, memory), a message from an
// origin the iframe was not given changes nothing, the example quiz runs to its question, and a
// sandboxed iframe works where its server allows cross-origin loading and says what it needs where
// it does not.
import { test, before, after, afterEach } from 'node:test';
import assert from 'node:assert/strict';
import { mkdirSync, writeFileSync } from 'node:fs';
import { serve } from '../../scripts/serve.mjs';
import { ARTIFACTS, launch } from './harness.mjs';

let server, browser, base, other;
before(async () => {
  ({ server, browser, base } = await launch());
  other = base.replace('127.0.0.1', 'localhost');
  mkdirSync(ARTIFACTS, { recursive: true });
});
after(async () => { await browser?.close(); server?.close(); });
const pages = [];
afterEach(async () => { for (const p of pages.splice(0)) if (!p.isClosed()) await p.close(); });

/** A host page (test-artifacts/`name`) with `body`; its script keeps every protocol message it gets
 *  in `window.got` and sends with `window.send(type, extra)` to the frame's origin. */
async function host(name, body, target) {
  writeFileSync(new URL(name, ARTIFACTS), `<!doctype html><body style="margin:0">${body}<script>
    window.got = [];
    const frame = document.querySelector('iframe');
    window.addEventListener('message', (e) => {
      if (e.source === frame.contentWindow && e.data?.protocol === 'sec-playground') window.got.push({ origin: e.origin, ...e.data });
    });
    window.send = (type, extra = {}) => frame.contentWindow.postMessage({ protocol: 'sec-playground', version: 1, type, ...extra }, ${JSON.stringify(target)});
  </script></body>`);
  const page = await browser.newPage({ viewport: { width: 1300, height: 1000 } });
  pages.push(page);
  const problems = [];
  page.on('pageerror', (e) => problems.push(String(e)));
  await page.goto(`${base}test-artifacts/${name}`);
  return { page, problems, frame: () => page.frames().find((f) => f.url().includes('embed.html')) };
}

/** The answer to the command with `id`, once it has come. */
function answer(page, id) {
  return page.waitForFunction((id) => window.got.find((m) => m.id === id && (m.type === 'result' || m.type === 'error')), id, { timeout: 60000 })
    .then((h) => h.jsonValue());
}

test('a host page on another origin drives the iframe through the protocol', async () => {
  const origin = new URL(other).origin;
  const { page, problems } = await host('protocol-host.html',
    `<iframe src="${other}embed.html?autoplay=0&hide=compare#task=object-permanence&seed=2" style="width:1200px;height:900px"></iframe>`, origin);
  // Connect (the handshake names this page) until the iframe listens: it answers with its version.
  await page.waitForFunction(() => {
    window.send('connect', { id: 'c' });
    return window.got.some((m) => m.id === 'c');
  }, null, { polling: 200, timeout: 60000 });
  const connected = await answer(page, 'c');
  assert.equal(connected.type, 'result');
  assert.equal(connected.origin, origin, 'the iframe answers from its own origin');
  const ready = await page.waitForFunction(() => window.got.find((m) => m.type === 'ready'), null, { timeout: 60000 }).then((h) => h.jsonValue());
  assert.equal(ready.version, 1);
  assert.equal(ready.settings.task, 'object-permanence');

  // A live change and a change that needs a new run, each answered with what applied.
  await page.evaluate(() => window.send('configure', { id: 1, settings: { alpha: 0.05 } }));
  const live = await answer(page, 1);
  assert.equal(live.type, 'result', JSON.stringify(live));
  assert.equal(live.value.applied, 'live');
  assert.deepEqual(live.value.changes, { alpha: '0.05' });
  await page.evaluate(() => window.send('configure', { id: 2, settings: { thetaprop: '0.99', seed: 5 } }));
  const restart = await answer(page, 2);
  assert.equal(restart.value.applied, 'restart');
  assert.deepEqual(Object.keys(restart.value.changes).sort(), ['seed', 'thetaProp'], 'changes under the table\'s keys');
  // A bad value is refused by name, and nothing changes.
  await page.evaluate(() => window.send('configure', { id: 3, settings: { tau: 'abc', alpha: 0.5 } }));
  const bad = await answer(page, 3);
  assert.equal(bad.type, 'error');
  assert.match(bad.message, /tau/);
  await page.evaluate(() => window.send('getState', { id: 4 }));
  const state = (await answer(page, 4)).value;
  assert.equal(state.settings.alpha, '0.05', 'the refused batch changed nothing');
  assert.equal(state.playing, false);

  // Play: episodes stream to the host; pause; the metrics are the rows that streamed.
  await page.evaluate(() => window.send('play', { id: 5 }));
  assert.equal((await answer(page, 5)).value.playing, true);
  await page.waitForFunction(() => window.got.filter((m) => m.type === 'episode').length >= 3, null, { timeout: 120000 });
  await page.waitForFunction(() => window.got.some((m) => m.type === 'state' && m.playing), null, { timeout: 60000 });
  await page.evaluate(() => window.send('pause', { id: 6 }));
  await answer(page, 6);
  await page.evaluate(() => window.send('getMetrics', { id: 7 }));
  const rows = (await answer(page, 7)).value;
  const streamed = await page.evaluate(() => window.got.filter((m) => m.type === 'episode').map((m) => m.row));
  assert.ok(rows.length >= 3);
  assert.deepEqual(rows.slice(0, streamed.length), streamed, 'getMetrics gives the rows the episode events carried');
  await page.evaluate(() => window.send('getMetrics', { id: 8, format: 'csv' }));
  assert.match((await answer(page, 8)).value, /^run,/m);

  // Step one decision, paused after it.
  await page.evaluate(() => window.send('step', { id: 9 }));
  const stepped = (await answer(page, 9)).value;
  assert.equal(stepped.playing, false);

  // The memory out and back in.
  await page.evaluate(() => window.send('saveMemory', { id: 10 }));
  await answer(page, 10);
  const size = await page.evaluate(() => window.got.find((m) => m.id === 10).value.byteLength);
  assert.ok(size > 100, `a memory file of ${size} bytes`);
  await page.evaluate(() => {
    const bytes = window.got.find((m) => m.id === 10).value;
    window.send('loadMemory', { id: 11, bytes });
  });
  const loaded = await answer(page, 11);
  assert.equal(loaded.type, 'result', JSON.stringify(loaded));
  assert.equal(loaded.value.sequences, stepped.ltm);

  // Unknown types and versions are refused by name.
  await page.evaluate(() => window.send('launchMissiles', { id: 12 }));
  assert.match((await answer(page, 12)).message, /unknown message type "launchMissiles" \(known: connect, play/);
  await page.evaluate(() => window.send('play', { id: 13, version: 2 }));
  assert.match((await answer(page, 13)).message, /version: 2 is not supported; this playground speaks version 1/);
  assert.deepEqual(problems, []);
});

test('a message from an origin the iframe was not given changes nothing', async () => {
  // The iframe answers https://course.example only; this page is another origin.
  const { page, frame } = await host('wrong-origin-host.html',
    `<iframe src="${other}embed.html?autoplay=0&origin=https://course.example#task=detour" style="width:1200px;height:900px"></iframe>`, '*');
  await page.waitForFunction(() => document.querySelector('iframe'));
  await frame().waitForFunction(() => window.secPlayground?.settings && window.secPlayground.view, null, { timeout: 60000 });
  const before = await frame().evaluate(() => ({ settings: window.secPlayground.settings, decisions: window.secPlayground.view.decisions }));
  const ignored = [];
  page.on('console', (m) => { if (m.text().includes('was ignored')) ignored.push(m.text()); });
  await page.evaluate(() => {
    window.send('connect', { id: 1 });
    window.send('configure', { id: 2, settings: { alpha: 0.5 } });
    window.send('play', { id: 3 });
  });
  // Each message was read and refused (the console says so), in order.
  const end = Date.now() + 60000;
  while (ignored.length < 3 && Date.now() < end) await new Promise((r) => setTimeout(r, 50));
  assert.equal(ignored.length, 3, ignored.join('\n'));
  assert.match(ignored[0], /answers https:\/\/course\.example only/);
  const after = await frame().evaluate(() => ({ settings: window.secPlayground.settings, decisions: window.secPlayground.view.decisions, playing: window.secPlayground.playing }));
  assert.deepEqual(after.settings, before.settings);
  assert.equal(after.decisions, before.decisions);
  assert.equal(after.playing, false);
  assert.deepEqual(await page.evaluate(() => window.got), [], 'no answer and no event reached this page');
});

test('the example quiz drives a playground on another origin until its LTM is full, then asks', async () => {
  const page = await browser.newPage({ viewport: { width: 1300, height: 1000 } });
  pages.push(page);
  const problems = [];
  page.on('pageerror', (e) => problems.push(String(e)));
  await page.goto(`${base}www/examples/quiz.html?playground=${encodeURIComponent(other)}`);
  await page.waitForFunction(() => document.getElementById('progress').textContent.startsWith('Connected: double-t-maze, m = 20'), null, { timeout: 60000 });
  const frame = page.frames().find((f) => f.url().includes('embed.html'));
  assert.equal(new URL(frame.url()).origin, new URL(other).origin, 'the playground is on the other origin');
  await frame.evaluate(() => {
    const s = document.getElementById('speed');
    s.value = s.max; // max speed: the quiz waits for 20 stored sequences
    s.dispatchEvent(new Event('input'));
  });
  await page.waitForFunction(() => window.secQuiz.asked, null, { timeout: 300000 });
  assert.equal(await page.isVisible('#quiz'), true);
  await frame.waitForFunction(() => !window.secPlayground.playing, null, { timeout: 60000 });
  assert.equal(await frame.evaluate(() => window.secPlayground.view.ltm), 20);
  await page.check('input[value="drop"]');
  await page.click('#answers button');
  assert.match(await page.textContent('#feedback'), /^Right/);
  assert.deepEqual(problems, []);
});

test('a sandboxed iframe runs where its server allows other origins, and says what it needs where not', async () => {
  const strict = await serve(0, '127.0.0.1', undefined, { cors: false });
  try {
    const plain = `http://localhost:${strict.address().port}/`;
    const { page, problems } = await host('sandbox-host.html', [
      `<iframe id="cors" sandbox="allow-scripts" src="${other}embed.html?autoplay=0#task=detour" style="width:1200px;height:700px"></iframe>`,
      `<iframe id="plain" sandbox="allow-scripts" src="${plain}embed.html?autoplay=0#task=detour" style="width:1200px;height:300px"></iframe>`,
      `<iframe id="none" sandbox="" src="${other}embed.html" style="width:1200px;height:300px"></iframe>`,
    ].join(''), '*');
    await page.waitForFunction(() => document.querySelectorAll('iframe').length === 3);
    const frame = (match) => page.frames().find((f) => f !== page.mainFrame() && match(f.url()));
    // Opaque origin, CORS allowed: the playground runs (its workers started from blobs).
    const cors = frame((u) => u.startsWith(`${other}embed.html?autoplay=0`));
    await cors.waitForFunction(() => window.secPlayground?.view?.embedding?.length === 20, null, { timeout: 60000 });
    assert.equal(await cors.evaluate(() => self.origin), 'null', 'the frame is sandboxed (opaque origin)');
    assert.equal(await cors.evaluate(() => window.secPlayground.settings.task), 'detour');
    // Opaque origin, no CORS: the frame says which sandbox flag (or header) it needs.
    const strictFrame = frame((u) => u.startsWith(plain));
    await strictFrame.waitForSelector('#load-note', { state: 'visible', timeout: 60000 });
    assert.match(await strictFrame.textContent('#load-note'), /without allow-same-origin.*sandbox="allow-scripts allow-same-origin".*Access-Control-Allow-Origin/s);
    // No scripts at all: the noscript text says to allow them.
    const none = frame((u) => u === `${other}embed.html`);
    assert.match(await none.textContent('noscript'), /add <code>allow-scripts<\/code>|add allow-scripts/);
    assert.deepEqual(problems, []);
  } finally {
    strict.close();
  }
});

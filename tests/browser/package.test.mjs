// The npm package (dist/sec-playground/, written by scripts/build.sh): its manifest and
// declarations against the core's settings table, and the package packed, installed into a scratch
// project, bundled by Vite and opened in Chromium, where the element learns and takes commands.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readdirSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { serve } from '../../scripts/serve.mjs';
import { manifest } from '../../scripts/custom-elements.mjs';
import { launch } from './harness.mjs';

const root = fileURLToPath(new URL('../../', import.meta.url));
const dist = `${root}dist/sec-playground/`;
const wasm = await import(`${root}pkg/sec_playground.js`);
wasm.initSync({ module: readFileSync(`${root}pkg/sec_playground_bg.wasm`) });
const params = wasm.parameters();

let server, browser, scratch;
before(async () => {
  ({ server, browser } = await launch());
  scratch = mkdtempSync(join(tmpdir(), 'sec-playground-vite-'));
});
after(async () => {
  await browser?.close();
  server?.close();
  if (scratch) rmSync(scratch, { recursive: true, force: true });
});

test('custom-elements.json lists every setting of the table with its values, default and help', () => {
  const committed = JSON.parse(readFileSync(`${root}www/custom-elements.json`, 'utf8'));
  const version = JSON.parse(readFileSync(`${root}package.json`, 'utf8')).version;
  assert.deepEqual(committed, manifest(params, wasm.parseSettings({}).settings, version),
    'www/custom-elements.json is stale: run node scripts/custom-elements.mjs');
  const attrs = committed.modules[0].declarations[0].attributes;
  for (const p of params) {
    const a = attrs.find((x) => x.fieldName === p.key);
    assert.ok(a, `${p.key} is an attribute`);
    assert.ok(a.description.startsWith(p.help), `${p.key}'s help`);
    if (p.kind.type === 'choice') for (const o of p.kind.options) assert.match(a.type.text, new RegExp(`'${o}'`), `${p.key}: ${o}`);
    if (p.kind.type === 'number') assert.match(a.description, new RegExp(`${p.kind.min}, ${p.kind.max}\\]`), `${p.key}'s range`);
  }
  assert.equal(attrs.length, params.length + 2, 'the settings, hide and autoplay');
});

test('the element\'s declarations name every setting and every value of each choice', () => {
  const dts = readFileSync(`${root}www/element.d.ts`, 'utf8');
  const body = dts.slice(dts.indexOf('export interface SecPlaygroundSettings {'), dts.indexOf('\n}\n', dts.indexOf('SecPlaygroundSettings {')));
  const declared = [...body.matchAll(/^ {2}(\w+):/gm)].map((m) => m[1]);
  assert.deepEqual(declared.sort(), params.map((p) => p.key).sort());
  for (const p of params.filter((p) => p.kind.type === 'choice')) {
    const line = body.split('\n').find((l) => l.startsWith(`  ${p.key}:`));
    for (const o of p.kind.options) assert.ok(line.includes(`'${o}'`), `${p.key}: '${o}' is declared`);
  }
});

test('the package, packed and installed, works through a Vite build in Chromium', async () => {
  const pkg = JSON.parse(readFileSync(`${dist}package.json`, 'utf8'));
  assert.equal(pkg.exports['.'].default, './www/element.js');
  assert.equal(pkg.customElements, 'www/custom-elements.json');
  const tarball = execFileSync('npm', ['pack', dist, '--pack-destination', scratch, '--silent'], { encoding: 'utf8' }).trim().split('\n').pop();
  writeFileSync(join(scratch, 'package.json'), JSON.stringify({ name: 'course', private: true, type: 'module' }));
  execFileSync('npm', ['install', '--no-save', '--no-audit', '--no-fund', '--offline', join(scratch, tarball)], { cwd: scratch, stdio: 'pipe' });
  writeFileSync(join(scratch, 'index.html'), `<!doctype html><html><head><meta charset="utf-8"><title>course</title></head><body>
    <sec-playground task="detour" seed="3" hide="compare" autoplay></sec-playground>
    <script type="module" src="./main.js"></script></body></html>`);
  writeFileSync(join(scratch, 'main.js'), `import 'sec-playground';
    import manifest from 'sec-playground/custom-elements.json';
    const el = document.querySelector('sec-playground');
    window.course = { el, episodes: [], attributes: manifest.modules[0].declarations[0].attributes.length };
    el.addEventListener('episode', (e) => window.course.episodes.push(e.detail));
  `);
  execFileSync(process.execPath, [`${root}node_modules/vite/bin/vite.js`, 'build', '--logLevel', 'warn'], { cwd: scratch, stdio: 'pipe' });
  // Vite found every file the modules address: both wasm builds, the models, the reference runs.
  const emitted = readdirSync(join(scratch, 'dist', 'assets'));
  assert.equal(emitted.filter((f) => f.endsWith('.wasm')).length, 2, emitted.join(' '));
  assert.ok(emitted.filter((f) => f.endsWith('.secae')).length >= 6, emitted.join(' '));
  assert.ok(emitted.filter((f) => f.startsWith('SEC-') && f.endsWith('.json')).length >= 10, 'the reference runs');
  const site = await serve(0, '127.0.0.1', join(scratch, 'dist'));
  try {
    const page = await browser.newPage({ viewport: { width: 1300, height: 1000 } });
    const problems = [];
    page.on('pageerror', (e) => problems.push(String(e)));
    page.on('response', (r) => { if (r.status() >= 400) problems.push(`${r.status()} ${r.url()}`); });
    await page.goto(`http://127.0.0.1:${site.address().port}/`);
    await page.waitForFunction(() => window.course?.el.state?.view?.embedding?.length === 20, null, { timeout: 60000 });
    assert.equal(await page.evaluate(() => window.course.attributes), params.length + 2);
    // Its stylesheets came with it.
    const rules = await page.evaluate(() => [...window.course.el.shadowRoot.querySelectorAll('link[rel=stylesheet]')].map((l) => l.sheet?.cssRules.length ?? 0));
    assert.equal(rules.length, 2);
    assert.ok(rules.every((n) => n > 5), `rules per stylesheet: ${rules}`);
    const applied = await page.evaluate(() => window.course.el.configure({ alpha: 0.05 }));
    assert.equal(applied.applied, 'live');
    await page.waitForFunction(() => window.course.episodes.length >= 1, null, { timeout: 120000 });
    const rows = await page.evaluate(() => window.course.el.getMetrics());
    assert.equal(rows[0].episode, 0);
    assert.deepEqual(problems, []);
    await page.close();
  } finally {
    site.close();
  }
});

// The notebook widget on a static MyST / Jupyter Book page, with no kernel: mystmd builds a page
// holding the `{anywidget}` directive (the widget's module, dist/sec-playground/widget.js, and a
// JSON model naming the settings and where a copy of the package is), and the page's widget node
// is rendered in Chromium by @myst-theme/anywidget, the renderer MyST's themes use (the themes
// themselves are downloaded from the web at build time, which the tests do not reach).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { copyFileSync, cpSync, mkdirSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { build } from 'vite';
import { serve } from '../../scripts/serve.mjs';
import { launch, until } from './harness.mjs';

const root = fileURLToPath(new URL('../../', import.meta.url));

let browser, server, base, site, scratch;
before(async () => {
  ({ browser, server, base } = await launch());
  // Under the repository, so that the page's imports resolve to its node_modules.
  mkdirSync(`${root}target`, { recursive: true });
  scratch = mkdtempSync(join(root, 'target', 'myst-test-'));
  const book = join(scratch, 'book');
  mkdirSync(join(book, 'template'), { recursive: true });
  // A local site template with no server: `myst build --site` writes the pages' content only.
  writeFileSync(join(book, 'template', 'template.yml'), 'myst: v1\nkind: site\n');
  writeFileSync(join(book, 'myst.yml'), 'version: 1\nproject:\n  title: SEC in a book\nsite:\n  template: ./template\n');
  copyFileSync(`${root}dist/sec-playground/widget.js`, join(book, 'sec-playground-widget.js'));
  writeFileSync(join(book, 'index.md'), `# Sequential Episodic Control

:::{anywidget} ./sec-playground-widget.js
{"files": "${base}dist/sec-playground/", "task": "detour", "alpha": 0.05, "seed": 4, "hide": "compare"}
:::
`);
  execFileSync(`${root}node_modules/.bin/myst`, ['build', '--site'], { cwd: book, stdio: 'pipe', env: { ...process.env, CI: 'true' } });
  // The page: the built content's widget node, rendered as the theme renders it.
  const out = join(scratch, 'site');
  const page = join(scratch, 'page');
  mkdirSync(page);
  writeFileSync(join(page, 'index.html'), '<!doctype html><meta charset="utf-8"><div id="root"></div><script type="module" src="./main.js"></script>');
  writeFileSync(join(page, 'main.js'), `import { createElement } from 'react';
import { createRoot } from 'react-dom/client';
import { ANY_RENDERERS } from '@myst-theme/anywidget';
const content = await (await fetch('/content/index.json')).json();
const find = (n) => (n?.type === 'anywidget' ? n : (n?.children ?? []).map(find).find(Boolean));
window.widgetNode = find(content.mdast);
// The renderer the themes register for the node type.
createRoot(document.getElementById('root')).render(createElement(ANY_RENDERERS.anywidget, { node: window.widgetNode }));
`);
  await build({
    root: page, configFile: false, logLevel: 'warn', build: { outDir: out, emptyOutDir: true },
    cacheDir: join(scratch, 'vite-cache'),
  });
  // The site's public files (the widget module, renamed by MyST) and its content, at the root.
  cpSync(join(book, '_build', 'site', 'public'), out, { recursive: true });
  cpSync(join(book, '_build', 'site', 'content'), join(out, 'content'), { recursive: true });
  site = await serve(0, '127.0.0.1', out);
});
after(async () => {
  await browser?.close();
  server?.close();
  site?.close();
  if (scratch) rmSync(scratch, { recursive: true, force: true });
});

test('a MyST page renders the widget with no kernel: it learns with the directive\'s settings', async () => {
  const page = await browser.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  // Every file the widget needs is found (the browser's own favicon request aside).
  page.on('response', (r) => { if (r.status() >= 400 && !r.url().endsWith('/favicon.ico')) errors.push(`${r.status()} ${r.url()}`); });
  try {
    await page.goto(`http://127.0.0.1:${site.address().port}/`);
    const node = await page.waitForFunction(() => window.widgetNode, null, { timeout: 60000 });
    const { esm, model } = await node.jsonValue();
    assert.match(esm, /^\/sec-playground-widg\w*-[0-9a-f]+\.js$/, 'MyST copied the module into the site (its name shortened and hashed)');
    assert.equal(model.task, 'detour');
    const el = () => document.querySelector('.myst-anywidget')?.shadowRoot?.querySelector('sec-playground');
    await page.waitForFunction(`(${el})()?.getState().episode >= 1`, null, { timeout: 180000 });
    const settings = await page.evaluate(`(${el})().getState().settings`);
    assert.equal(settings.task, 'detour');
    assert.equal(settings.alpha, '0.05');
    assert.equal(settings.seed, '4');
    // Its camera shows the arena (a blank canvas has one colour).
    await until(() => page.evaluate(`(() => {
      const c = (${el})().shadowRoot.querySelector('#camera');
      const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
      return new Set(d).size > 8;
    })()`), 'the camera to draw');
    // Styled: the element's style sheet came from the package's copy too.
    const display = await page.evaluate(`getComputedStyle((${el})().shadowRoot.querySelector('.playground')).display`);
    assert.notEqual(display, 'inline');
    assert.deepEqual(errors, []);
  } finally {
    await page.close();
  }
});

test('the widget module runs when a host imports it from a data: address (no address to resolve files by)', async () => {
  const page = await browser.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  try {
    await page.goto(`http://127.0.0.1:${site.address().port}/`);
    await page.evaluate(async (files) => {
      const source = await (await fetch(`${files}widget.js`)).text();
      const mod = await import(`data:text/javascript;base64,${btoa(unescape(encodeURIComponent(source)))}`);
      // The smallest model a host gives: values, change events, no kernel.
      const values = { files, task: 'cylinder', seed: 2, hide: 'compare' };
      const model = { get: (k) => values[k], set() {}, on() {}, off() {}, save_changes() {}, send() { throw new Error('no kernel'); } };
      const el = document.createElement('div');
      document.body.replaceChildren(el); // on screen (an element scrolled off it pauses)
      await mod.default.render({ model, el });
    }, `${base}dist/sec-playground/`);
    await page.waitForFunction(() => [...document.querySelectorAll('body > div > sec-playground')]
      .some((p) => p.getState().episode >= 1 && p.getState().settings.task === 'cylinder'), null, { timeout: 180000 });
    assert.deepEqual(errors, []);
  } finally {
    await page.close();
  }
});

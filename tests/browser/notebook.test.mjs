// The notebook widget (sec_playground.widget) in real JupyterLab, in Chromium: a notebook is
// opened, its cells run one by one as a user runs them, and the widget's page and the kernel are
// checked against each other. It needs the Python test venv (scripts/python-test.sh installs the
// wheel, JupyterLab and anywidget into target/py-venv; SEC_PY_VENV names another) and is skipped,
// saying so, without it. Every wait is for a condition.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { existsSync, mkdirSync, mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { launch, until, ARTIFACTS } from './harness.mjs';

const root = fileURLToPath(new URL('../../', import.meta.url));
const venv = process.env.SEC_PY_VENV ?? `${root}target/py-venv`;
const jupyter = `${venv}/bin/jupyter`;
const missing = existsSync(`${venv}/bin/jupyter-lab`) ? null
  : `JupyterLab is not in ${venv} (scripts/python-test.sh installs it with the wheel)`;

/** The notebook's cells, run in order by the test. */
const CELLS = [
  'import sec_playground\nw = sec_playground.widget(task="double-t-maze", seed=3, t=60, hide="compare")\nw',
  'w.alpha = 0.2\nw.m = 40',
  'print("episodes", len(w.episodes), w.episodes[-1]["episode"], sorted(w.episodes[-1])[:3])',
  'print("beta", w.beta)',
  'try:\n    w.tau = 1000\nexcept ValueError as e:\n    print("refused", e)',
  'w.pause()\nw.step()',
  'x = w.explain()\nprint("explained", sorted(x)[:4], len(x["p"]))',
  'w.hide = "compare charts"',
];

let browser, server, lab, scratch, url;
before(async () => {
  if (missing) return;
  ({ browser, server } = await launch());
  scratch = mkdtempSync(join(tmpdir(), 'sec-playground-lab-'));
  const notebook = {
    nbformat: 4, nbformat_minor: 5, metadata: { kernelspec: { name: 'python3', display_name: 'Python 3', language: 'python' } },
    cells: CELLS.map((source, i) => ({ cell_type: 'code', id: `c${i}`, metadata: {}, source, outputs: [], execution_count: null })),
  };
  writeFileSync(join(scratch, 'widget.ipynb'), JSON.stringify(notebook));
  for (const d of ['config', 'data', 'runtime', 'ipython', 'settings', 'workspaces']) mkdirSync(join(scratch, d));
  const env = {
    ...process.env, PATH: `${venv}/bin:/usr/bin:/bin`, HOME: scratch,
    JUPYTER_CONFIG_DIR: join(scratch, 'config'), JUPYTER_RUNTIME_DIR: join(scratch, 'runtime'),
    IPYTHONDIR: join(scratch, 'ipython'), JUPYTERLAB_SETTINGS_DIR: join(scratch, 'settings'),
    JUPYTERLAB_WORKSPACES_DIR: join(scratch, 'workspaces'),
  };
  lab = spawn(jupyter, ['lab', '--no-browser', '--ServerApp.ip=127.0.0.1', '--ServerApp.port=0',
    '--IdentityProvider.token=sec-playground-test', '--allow-root', `--ServerApp.root_dir=${scratch}`, '--LabApp.expose_app_in_browser=True',
    '--LabApp.news_url=None', '--LabApp.check_for_updates_class=jupyterlab.NeverCheckForUpdate'],
  { env, stdio: ['ignore', 'pipe', 'pipe'] });
  let log = '';
  // The server says where it listens once it does.
  url = await new Promise((ok, fail) => {
    const seen = (chunk) => {
      log += chunk;
      const m = log.match(/(http:\/\/127\.0\.0\.1:\d+\/)lab\?token=/);
      if (m) ok(m[1]);
    };
    lab.stdout.on('data', seen);
    lab.stderr.on('data', seen);
    lab.on('exit', (code) => fail(new Error(`jupyter lab exited (${code}):\n${log}`)));
  });
});
after(async () => {
  await browser?.close();
  server?.close();
  if (lab && lab.exitCode === null) {
    const exited = new Promise((ok) => lab.on('exit', ok));
    lab.kill('SIGTERM');
    await exited;
  }
  if (scratch) rmSync(scratch, { recursive: true, force: true });
});

/** Runs cell `i` of the open notebook as Shift+Enter does; resolves when it has finished, with
 * its text output. */
function runCell(page, i) {
  return page.evaluate(async (i) => {
    const panel = window.jupyterapp.shell.currentWidget;
    await panel.sessionContext.ready;
    panel.content.activeCellIndex = i;
    await window.jupyterapp.commands.execute('notebook:run-cell');
    const outputs = panel.content.widgets[i].model.outputs.toJSON();
    const text = (t) => (Array.isArray(t) ? t.join('') : t ?? '');
    return outputs.map((o) => (o.output_type === 'error' ? `${o.ename}: ${o.evalue}` : text(o.text))).join('');
  }, i);
}

/** The pixels of the widget's camera, as a string that changes when the view does. */
function camera(page) {
  return page.evaluate(() => {
    const c = document.querySelector('sec-playground')?.shadowRoot?.querySelector('#camera');
    if (!c) return null;
    const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let h = 0;
    for (let i = 0; i < d.length; i++) h = (h * 31 + d[i]) | 0;
    return new Set(d).size > 2 ? String(h) : null; // null while blank
  });
}

test('the widget learns in a JupyterLab cell, and its settings, episodes and explanation go both ways', { skip: missing ?? false, timeout: 600000 }, async () => {
  const page = await browser.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  try {
    await page.goto(`${url}lab/tree/widget.ipynb?token=sec-playground-test`);
    await page.waitForFunction((n) => window.jupyterapp?.shell.currentWidget?.content?.widgets?.length === n, CELLS.length, { timeout: 180000 });
    await page.evaluate(() => window.jupyterapp.shell.currentWidget.sessionContext.ready);

    // The cell shows the element, and its camera moves (the run plays from the wheel's wasm).
    assert.equal(await runCell(page, 0), '');
    await page.waitForFunction(() => document.querySelector('sec-playground')?.getState?.().settings !== null
      && document.querySelector('sec-playground')?.getState?.().settings?.seed === '3', null, { timeout: 180000 });
    let first = null;
    await until(async () => { first ??= await camera(page); return first !== null; }, 'a camera frame');
    await until(async () => { const now = await camera(page); return now !== null && now !== first; }, 'the camera to move');
    const pg = page.locator('sec-playground');
    assert.equal(await pg.evaluate((el) => el.getState().settings.t), '60', 'the settings from Python');

    // Python's values move the page's knobs, as one batch.
    await runCell(page, 1);
    await page.waitForFunction(() => {
      const el = document.querySelector('sec-playground');
      return el.getState().settings.alpha === '0.2' && el.getState().settings.m === '40'
        && el.shadowRoot.querySelector('#p-alpha').value === '0.2';
    }, null, { timeout: 60000 });
    // Each value went once: the page's news of the first did not send the second's old value back.
    const marks = await pg.evaluate((el) => el.state.marks.map((m) => JSON.stringify(m)));
    assert.ok(marks.length <= 2 && !marks.some((m) => m.includes('m=500')), `the chart's marks: ${marks}`);

    // Episodes come back to the kernel (between cells).
    await page.waitForFunction(() => document.querySelector('sec-playground').getState().episode >= 2, null, { timeout: 180000 });
    const out = await runCell(page, 2);
    const m = out.match(/^episodes (\d+) (\d+) \['(\w+)', '(\w+)', '(\w+)'\]/);
    assert.ok(m, `cell 2 printed: ${out}`);
    assert.ok(Number(m[1]) >= 1, 'at least one episode arrived');

    // The page's knob moves the Python trait.
    await pg.evaluate((el) => {
      const box = el.shadowRoot.querySelector('#p-beta');
      box.value = '0.3';
      box.dispatchEvent(new Event('change'));
    });
    await page.waitForFunction(() => document.querySelector('sec-playground').getState().settings.beta === '0.3', null, { timeout: 60000 });
    await until(async () => (await runCell(page, 3)).trim() === 'beta 0.3', 'the kernel to see beta = 0.3');

    // A value out of range is refused in Python, naming it, and the page keeps its value.
    const tau = await pg.evaluate((el) => el.getState().settings.tau);
    const refused = await runCell(page, 4);
    assert.match(refused, /^refused tau: .*100/, refused);
    assert.equal(await pg.evaluate((el) => el.getState().settings.tau), tau);

    // Paused and stepped from Python, the page explains the decision; the kernel reads it.
    await runCell(page, 5);
    await page.waitForFunction(() => document.querySelector('sec-playground').getState().playing === false
      && document.querySelector('sec-playground').state.explanation !== null, null, { timeout: 60000 });
    const explained = await runCell(page, 6);
    assert.match(explained, /^explained \[.*\] 9/, explained);
    await page.screenshot({ path: fileURLToPath(new URL('notebook-widget.png', ARTIFACTS)) });

    // `hide` changes after load, as the element's attribute does.
    await runCell(page, 7);
    await page.waitForFunction(() => {
      const root = document.querySelector('sec-playground').shadowRoot;
      return root.querySelector('.playground .charts, .playground #charts')?.hidden === true;
    }, null, { timeout: 60000 });
    assert.deepEqual(errors, []);
  } finally {
    await page.close();
  }
});

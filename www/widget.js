// The notebook widget's front end: an anywidget module (one ES module for JupyterLab, Notebook,
// VS Code, Colab and marimo) that shows the <sec-playground> element in a cell. The Python side is
// `sec_playground.widget(...)` (crates/sec-py/python/sec_playground/notebook.py); the module is
// bundled with its workers into one file (scripts/widget-build.mjs) that the wheel carries.
//
// The model holds one value per setting, under the settings table's keys (the element's
// attributes: task, alpha, thetaAbs...), plus `hide` and `autoplay`. With a kernel, the files
// (wasm, models, reference runs) come from it on request (no network), a change of a setting in
// Python configures the page and a change on the page goes back to Python; episodes, new runs, the
// last decision's explanation, state and errors stream back as custom messages. Without a kernel
// (a MyST / Jupyter Book page renders the module with the directive's JSON as its model), `files`
// names the address of a copy of the npm package to fetch the files from.
import './element.js';
import manifest from './custom-elements.json' with { type: 'json' };
import { provideFiles } from './files.js';

/** The settings table's keys, from the element's manifest (generated from the table). */
const KEYS = manifest.modules[0].declarations[0].attributes.map((a) => a.fieldName).filter((k) => k !== 'hide' && k !== 'autoplay');
/** Episodes go to the kernel at most this often (ms), in one message. */
const FLUSH_MS = 250;

/** Files asked of the kernel, by path (each once per page, whichever widget asks). */
const asked = new Map();
/** The widgets on the page that have a kernel; any of them can be asked for a file. */
const kernels = new Set();
let waiting = new Map();
let nextAsk = 1;

/** A file's bytes from the kernel (the Python package carries them). */
function fromKernel(path) {
  if (!asked.has(path)) {
    asked.set(path, new Promise((ok, fail) => {
      const model = [...kernels][0];
      if (!model) return fail(new Error('no kernel is connected to a widget on this page'));
      const id = nextAsk++;
      waiting.set(id, { ok, fail });
      model.send({ type: 'file', id, path });
    }));
    asked.get(path).catch(() => asked.delete(path)); // asked again next time
  }
  return asked.get(path);
}

/** The kernel's answer to `fromKernel`: `{type: 'file', id, error?}` with the bytes in `buffers`. */
function fileAnswer(msg, buffers) {
  const w = waiting.get(msg.id);
  if (!w) return;
  waiting.delete(msg.id);
  if (msg.error) return w.fail(new Error(msg.error));
  const b = buffers?.[0];
  if (!b) return w.fail(new Error(`${msg.path}: the kernel sent no bytes`));
  // ipywidgets hands buffers over as DataViews.
  w.ok(b instanceof ArrayBuffer ? b : b.buffer.slice(b.byteOffset, b.byteOffset + b.byteLength));
}

/** The model's value of a setting as an attribute's text; null when the model has none. */
function text(value) {
  if (value == null || value === '') return null;
  if (typeof value === 'boolean') return value ? '1' : '0';
  return String(value);
}

function render({ model, el }) {
  const files = model.get('files');
  const kernel = !files;
  if (kernel) {
    kernels.add(model);
    provideFiles({ get: fromKernel });
  } else {
    provideFiles({ base: new URL(files, document.baseURI).href });
  }
  const send = (msg) => {
    if (kernel) model.send(msg);
  };
  const pg = document.createElement('sec-playground');
  for (const key of KEYS) {
    const v = text(model.get(key));
    if (v != null) pg.setAttribute(key, v);
  }
  if (model.get('hide')) pg.setAttribute('hide', model.get('hide'));
  if (model.get('autoplay') ?? true) pg.setAttribute('autoplay', '');
  el.append(pg);

  // Python's values to the page: the keys changed together (one sync) go as one batch, all or
  // none, as the page's API applies them.
  let changed = new Set();
  const applyChanged = () => {
    const changes = Object.fromEntries([...changed].map((k) => [k, text(model.get(k))]).filter(([, v]) => v != null));
    changed = new Set();
    if (!Object.keys(changes).length) return;
    pg.configure(changes).catch((e) => {
      // Refused (a combination the core does not allow): the kernel hears why and gets these
      // keys' values still in force back.
      send({ type: 'error', message: String(e?.message ?? e) });
      const s = pg.getState().settings;
      if (s) send({ type: 'settings', settings: Object.fromEntries(Object.keys(changes).map((k) => [k, s[k]])) });
    });
  };
  const offs = [];
  const on = (name, f) => {
    model.on(name, f);
    offs.push(() => {
      try {
        model.off(name, f);
      } catch {
        // A static page's model (MyST) cannot unsubscribe; it goes with the page.
      }
    });
  };
  for (const key of KEYS) {
    on(`change:${key}`, () => {
      if (!changed.size) queueMicrotask(applyChanged);
      changed.add(key);
    });
  }
  on('change:hide', () => pg.setAttribute('hide', model.get('hide') ?? ''));
  on('msg:custom', (msg, buffers) => {
    if (msg?.type === 'file') fileAnswer(msg, buffers);
    else if (msg?.type === 'command') command(pg, msg, send);
  });

  // The page's news to the kernel.
  let rows = [];
  let timer = null;
  const flush = () => {
    timer = null;
    if (rows.length) send({ type: 'episodes', rows });
    rows = [];
  };
  const events = {
    ready: (d) => send({ type: 'ready', version: d.version }),
    run: () => {
      flush();
      send({ type: 'run' });
    },
    episode: (row) => {
      rows.push(row);
      timer ??= setTimeout(flush, FLUSH_MS);
    },
    // Only what changed: the kernel's other values may be on their way to the page.
    settings: (d) => send({ type: 'settings', settings: d.changes ?? {}, applied: d.applied }),
    state: (s) => send({ type: 'state', state: { ...s, settings: undefined } }),
    explanation: (x) => send({ type: 'explanation', explanation: x }),
    error: (d) => send({ type: 'error', message: d.message }),
  };
  for (const [type, f] of Object.entries(events)) {
    const h = (e) => f(e.detail);
    pg.addEventListener(type, h);
    offs.push(() => pg.removeEventListener(type, h));
  }
  return () => {
    flush();
    clearTimeout(timer);
    for (const off of offs) off();
    kernels.delete(model);
    pg.remove();
  };
}

/** Python's `widget.play()` and the like: `{type: 'command', name, args}`, answered with the
 * state (`{type: 'result', name, state}`) or the error. */
async function command(pg, { name, args = [] }, send) {
  const allowed = ['play', 'pause', 'reset', 'step'];
  try {
    if (!allowed.includes(name)) throw new Error(`unknown command '${name}' (one of ${allowed.join(', ')})`);
    const state = await pg[name](...args);
    send({ type: 'result', name, state: { ...state, settings: undefined } });
  } catch (e) {
    send({ type: 'error', message: `${name}: ${e?.message ?? e}` });
  }
}

export default { render };

// The playground's files (the wasm, the models, the reference runs, the warm-up memories, the
// style sheets) and where they come from. On a web page, from beside the modules: each call site
// names its file with a literal `new URL(..., import.meta.url)`, which bundlers (Vite) follow and
// copy. A notebook widget's module has no neighbours (the notebook loads it from a string), so the
// widget says where they are (`provideFiles`): a function that gets a file's bytes (from the
// kernel: no network), or the address of a copy of the package (a static page: MyST, Jupyter Book).
// Paths are the package's own: `pkg/sec_playground_bg.wasm`, `assets/encoders/<task>.secae`...

/** null (beside the modules), `{get(path)}` (the page's), `{base}` or `{ask: true}` (a worker's:
 * its page gets each file). */
let provided = null;
/** A worker's requests to its page, by id. */
const asked = new Map();
let nextAsk = 1;

const TYPES = { wasm: 'application/wasm', json: 'application/json', css: 'text/css' };

/**
 * Where the files come from from now on: `{get: async (path) => ArrayBuffer}` or
 * `{base: 'https://…/sec-playground/'}` (a folder holding the npm package's files).
 */
export function provideFiles(where) {
  if (where && typeof where.get !== 'function' && typeof where.base !== 'string' && where.ask !== true) {
    throw new Error('provideFiles: give {get(path)} (an async function returning the bytes) or {base} (an address)');
  }
  provided = where ?? null;
}

/** What a worker this page starts is told in its boot message (`boot.files`): null when it
 * fetches its files from beside its modules. */
export function filesForWorker() {
  if (provided?.get) return { ask: true };
  if (provided?.base) return { base: provided.base };
  return null;
}

/** Whether files come from elsewhere than beside the modules. */
export function filesProvided() {
  return provided !== null;
}

/**
 * Fetches the file at `path` (in the package); `here` returns its address beside the modules (a
 * literal `new URL(..., import.meta.url)`), used when no one provides the files. Resolves with a
 * Response (not ok for a file that is not there), as `fetch` does.
 */
export async function fetchFile(path, here) {
  if (!provided) return fetch(here());
  if (provided.base) return fetch(new URL(path, provided.base));
  let bytes;
  try {
    bytes = provided.get ? await provided.get(path) : await ask(path);
  } catch (e) {
    return new Response(null, { status: 404, statusText: `${path}: ${e?.message ?? e}` });
  }
  const type = TYPES[path.split('.').pop()] ?? 'application/octet-stream';
  return new Response(bytes, { headers: { 'Content-Type': type } });
}

/** A worker's request for a file to its page, answered by `answerFileRequest` there. */
function ask(path) {
  return new Promise((ok, fail) => {
    const id = nextAsk++;
    asked.set(id, { ok, fail });
    self.postMessage({ type: 'file', id, path });
  });
}

/**
 * In a worker: takes the page's answer to `ask` (`{type: 'file', id, bytes | error}`) before the
 * worker's message queue sees it (a handler waiting for a file holds that queue). True if it was one.
 */
export function takeFileAnswer(data) {
  if (data?.type !== 'file' || !asked.has(data.id)) return false;
  const { ok, fail } = asked.get(data.id);
  asked.delete(data.id);
  if (data.error) fail(new Error(data.error));
  else ok(data.bytes);
  return true;
}

/** On the page: answers a worker's `{type: 'file', id, path}` with the bytes, or the error. */
export async function answerFileRequest(worker, { id, path }) {
  try {
    const r = await fetchFile(path, () => { throw new Error('no file source'); });
    if (!r.ok) throw new Error(r.statusText || `HTTP ${r.status}`);
    const bytes = await r.arrayBuffer();
    worker.postMessage({ type: 'file', id, bytes }, [bytes]);
  } catch (e) {
    worker.postMessage({ type: 'file', id, error: String(e?.message ?? e) });
  }
}

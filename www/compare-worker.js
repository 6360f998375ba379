// One worker of the comparison's pool: it plays one run (a configuration and a seed) at a time,
// at full speed with no views, to its horizon, then takes the next run the page sends it.
// Episodes go out as they finish.
//
// Messages in:  {type: 'boot', wasm, files} (first), {type: 'start', settings, seed, episodes}, {type: 'play'}, {type: 'pause'},
//               {type: 'file', id, bytes | error}
// Messages out: {type: 'ready'}, {type: 'started', settings}, {type: 'episodes', list, wasmBytes},
//               {type: 'done'}, {type: 'error', message}, {type: 'file', id, path} (files.js)
import { load, ensureModel, gateModel, SecRun, parseSettings } from './wasm.js';
import { AdaptiveBatch, serveMessages, soon } from './slices.js';

/** The run in play: {run, left} (episodes still to play), or null. */
let current = null;
let playing = false;
/** Whether a slice is queued (one at a time, however often play and start come). */
let scheduled = false;
const batch = new AdaptiveBatch(16, 5000, 1);

const post = (msg) => self.postMessage(msg);

function kick() {
  if (scheduled || !playing || !current) return;
  scheduled = true;
  soon(slice);
}

function slice() {
  scheduled = false;
  if (!playing || !current) return;
  try {
    batch.fillSlice((n) => {
      if (!current) return;
      // The run plays on past an episode's end within a batch; what is past the horizon is
      // not the comparison's.
      const list = current.run.runDecisions(n).slice(0, current.left);
      current.left -= list.length;
      if (list.length) post({ type: 'episodes', list, wasmBytes: memory.buffer.byteLength });
      if (current.left === 0) {
        current.run.free();
        current = null;
        post({ type: 'done' });
      }
    });
  } catch (e) {
    playing = false;
    post({ type: 'error', message: `The simulation stopped: ${e?.message ?? e}` });
    return;
  }
  kick();
}

const handlers = {
  async start({ settings, seed, episodes }) {
    const parsed = parseSettings(settings);
    if (parsed.errors.length) throw new Error(parsed.errors.join('; '));
    await ensureModel(gateModel(parsed.config));
    current?.run.free();
    current = { run: new SecRun(parsed.config, seed), left: episodes };
    post({ type: 'started', settings: parsed.settings });
    kick();
  },
  play() {
    playing = true;
    kick();
  },
  pause() { playing = false; },
};

serveMessages(handlers, (e) => post({ type: 'error', message: String(e?.message ?? e) }));

/** The instance's memory, whose size goes out with the episodes (a leak shows). */
let memory = null;
/** The page's first message: which build (`wasm`) to load. */
handlers.boot = async ({ wasm, files }) => {
  ({ memory } = await load({ wanted: wasm, files }));
  post({ type: 'ready' });
};

// One worker of the comparison's pool: it plays one run (a configuration and a seed) at a time,
// at full speed with no views. With `turn` set, a run that can checkpoint plays for about that
// long (ms of play), then to the end of its episode, and goes back to the page as a checkpoint
// (`yield`), so that the pool's runs take turns and all move forward together; otherwise it
// plays to its horizon. Episodes go out as they finish.
//
// Messages in:  {type: 'boot', wasm, files} (first),
//               {type: 'start', settings, seed, episodes (left to play), played, checkpoint?, turn?},
//               {type: 'play'}, {type: 'pause'}, {type: 'file', id, bytes | error}
// Messages out: {type: 'ready'}, {type: 'started', settings, canCheckpoint},
//               {type: 'episodes', list, wasmBytes}, {type: 'yield', checkpoint} (an ArrayBuffer),
//               {type: 'done'}, {type: 'error', message}, {type: 'file', id, path} (files.js)
import { load, ensureModel, gateModel, SecRun, parseSettings } from './wasm.js';
import { AdaptiveBatch, serveMessages, soon } from './slices.js';

/** The run in play: {run, left (episodes still to play), turn (ms of play before it yields, or null), playedMs (ms of play so far)}, or null. */
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
    const t0 = performance.now();
    batch.fillSlice((n) => {
      if (!current) return;
      // The run plays on past an episode's end within a batch; what is past the horizon is
      // not the comparison's.
      report(current.run.runDecisions(n));
    });
    if (current?.turn != null && (current.playedMs += performance.now() - t0) >= current.turn) yieldTurn();
  } catch (e) {
    playing = false;
    post({ type: 'error', message: `The simulation stopped: ${e?.message ?? e}` });
    return;
  }
  kick();
}

/** Reports the episodes a call finished (those up to the horizon); at the horizon the run ends. */
function report(episodes) {
  const list = episodes.slice(0, current.left);
  current.left -= list.length;
  if (list.length) post({ type: 'episodes', list, wasmBytes: memory.buffer.byteLength });
  if (current.left === 0) {
    current.run.free();
    current = null;
    post({ type: 'done' });
  }
}

/** The turn is over: the run plays to its episode's end and goes back to the page as bytes. */
function yieldTurn() {
  if (current.run.midEpisode) report([current.run.stepEpisode()]);
  if (!current) return; // that episode was its last
  const bytes = current.run.checkpoint();
  current.run.free();
  current = null;
  self.postMessage({ type: 'yield', checkpoint: bytes.buffer }, [bytes.buffer]);
}

const handlers = {
  async start({ settings, seed, episodes, played = 0, checkpoint = null, turn = null }) {
    const parsed = parseSettings(settings);
    if (parsed.errors.length) throw new Error(parsed.errors.join('; '));
    await ensureModel(gateModel(parsed.config));
    current?.run.free();
    current = null;
    const run = checkpoint ? SecRun.resume(parsed.config, seed, new Uint8Array(checkpoint), played) : new SecRun(parsed.config, seed);
    current = { run, left: episodes, turn: run.canCheckpoint ? turn : null, playedMs: 0 };
    post({ type: 'started', settings: parsed.settings, canCheckpoint: run.canCheckpoint });
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

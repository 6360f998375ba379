// One configuration of a comparison: its runs (one per seed) in this worker, at full speed, with
// no views. Episodes go out as they finish, tagged with the seed.
//
// Messages in:  {type: 'start', settings, seeds}, {type: 'play'}, {type: 'pause'}
// Messages out: {type: 'started', settings}, {type: 'episodes', seed, list, wasmBytes},
//               {type: 'error', message}
import init, { ensureModel, gateModel, SecRun, parseSettings } from './wasm.js';
import { AdaptiveBatch, serveMessages } from './slices.js';

let runs = [];
let playing = false;
// Each call steps every seed, so it aims at half a slice.
const batch = new AdaptiveBatch(16, 5000, 1 / 2);

const post = (msg) => self.postMessage(msg);

function loop() {
  if (!playing || !runs.length) return;
  try {
    batch.fillSlice((n) => {
      // Round robin, so that the seeds advance together.
      for (const r of runs) {
        const list = r.run.runDecisions(n);
        if (list.length) post({ type: 'episodes', seed: r.seed, list, wasmBytes: memory.buffer.byteLength });
      }
    });
  } catch (e) {
    playing = false;
    post({ type: 'error', message: `The simulation stopped: ${e?.message ?? e}` });
    return;
  }
  setTimeout(loop, 0);
}

const handlers = {
  async start({ settings, seeds }) {
    const parsed = parseSettings(settings);
    if (parsed.errors.length) throw new Error(parsed.errors.join('; '));
    await ensureModel(gateModel(parsed.config));
    const next = seeds.map((seed) => ({ seed, run: new SecRun(parsed.config, seed) }));
    for (const r of runs) r.run.free();
    runs = next;
    post({ type: 'started', settings: parsed.settings });
  },
  play() {
    const was = playing;
    playing = true;
    if (!was) loop();
  },
  pause() { playing = false; },
};

serveMessages(handlers, (e) => post({ type: 'error', message: String(e?.message ?? e) }));

// The instance's memory, whose size goes out with the episodes (a leak shows).
const { memory } = await init();
post({ type: 'ready' });

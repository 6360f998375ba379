// One configuration of a comparison: its runs (one per seed) in this worker, at full speed, with
// no views. Episodes go out as they finish, tagged with the seed.
//
// Messages in:  {type: 'start', settings, seeds}, {type: 'play'}, {type: 'pause'}
// Messages out: {type: 'started', settings}, {type: 'episodes', seed, list}, {type: 'error', message}
import init, { ensureModel, SecRun, parseSettings } from './wasm.js';

const SLICE_MS = 12;
let runs = [];
let playing = false;
let batch = 16;

const post = (msg) => self.postMessage(msg);

function loop() {
  if (!playing || !runs.length) return;
  try {
    const t0 = performance.now();
    while (performance.now() - t0 < SLICE_MS) {
      const s0 = performance.now();
      // Round robin, so that the seeds advance together.
      for (const r of runs) {
        const list = r.run.advance(batch);
        if (list.length) post({ type: 'episodes', seed: r.seed, list });
      }
      const took = performance.now() - s0;
      batch = Math.max(1, Math.min(5000, Math.round(batch * (SLICE_MS / 2 / Math.max(took, 0.05)))));
    }
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
    await ensureModel(parsed.config.task);
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

let queue = Promise.resolve();
self.onmessage = ({ data }) => {
  queue = queue.then(() => handlers[data?.type]?.(data))
    .catch((e) => post({ type: 'error', message: String(e?.message ?? e) }));
};

await init();
post({ type: 'ready' });

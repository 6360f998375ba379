// The simulation's Web Worker: owns the wasm run, steps it in time slices so that the page stays
// smooth at any speed, and posts what the page draws. No SharedArrayBuffer: images are copied
// out of wasm memory and transferred.
//
// Any message may carry an `id`: it is then answered with {type: 'done', id, result} (or an error
// with the id) after what it posted; `set` gives {mode, changes, settings}, `saveMemory` with an
// id gives the bytes instead of posting them, `loadMemory` gives {sequences}.
// Messages in:  {type: 'boot', wasm, task, files, arena} (first), {type: 'start', settings}, {type: 'set', changes}, {type: 'play'}, {type: 'pause'},
//               {type: 'speed', value}, {type: 'step', what: 'decision' | 'episode'},
//               {type: 'reset'}, {type: 'views', camera, top, heat, hz, explain}, {type: 'drive', action, record},
//               {type: 'saveMemory'}, {type: 'loadMemory', bytes},
//               {type: 'warmUp', bytes, what}, {type: 'crash'} (a test hook), {type: 'file', id, bytes | error}
// Messages out: {type: 'ready', params, agents, defaults, build, arena}, {type: 'started', settings, errors, mode},
//               {type: 'episodes', list}, {type: 'view', ...}, {type: 'state', playing},
//               {type: 'memory', bytes}, {type: 'loaded', sequences, what}, {type: 'error', message, fatal},
//               {type: 'file', id, path} (a file it needs, where the page provides them: files.js)
import { load, build, ensureModel, gateModel, SecRun, agents, frameSize, parameters, parseSettings, applySettings, presetSettings, panicForTest, withArena } from './wasm.js';
import { fetchFile } from './files.js';
import { AdaptiveBatch, SLICE_MS, serveMessages, soon } from './slices.js';

/** Most view posts per second while watching; the page asks for fewer at max speed. */
const VIEW_HZ = 30;

let run = null;
let settings = null;
let playing = false;
let speed = Infinity; // decisions per second; Infinity is "max"
let want = { camera: true, top: 252, heat: 'g', hz: VIEW_HZ, explain: false };
// Decisions per call at max speed; each call aims at a quarter of the slice.
const batch = new AdaptiveBatch(8, 10000, 1 / 4);
let lastView = 0;
let owed = 0; // decisions owed at a watch speed
let lastTick = 0;
let dead = false; // the wasm instance trapped: only a new start can help
let driver = null; // {action, record} while a person drives; kept across new runs
let wasmMemory = null; // the instance's memory: its size goes out with each view (a leak shows)
let arena = null; // {name, yaml}: the Olympics arena file every run of this worker plays, if any

/** The Olympics corpus's file names (assets/arenas/competition/NN-NN-NN.yaml). */
const OLYMPICS_NAME = /^(0[1-9]|10)-\d\d-0[1-3]$/;

/** The run's configuration from the settings': the arena file's run when there is one. */
const configOf = (config) => (arena ? withArena(config, arena.name, arena.yaml) : config);

const post = (msg, transfer) => self.postMessage(msg, transfer ?? []);

function fail(e, fatal = false, id = undefined) {
  post({ type: 'error', message: String(e?.message ?? e), fatal, id });
}

/** Copies a view into wasm memory into a transferable buffer. */
const copy = (view) => view.slice().buffer;

function postView(force = false) {
  const now = performance.now();
  if (!run || (!force && now - lastView < 1000 / want.hz)) return;
  lastView = now;
  // `at`: when the view was taken, on the clock both threads share (epoch ms): the page's rate
  // readout counts decisions against it, so a busy main thread that handles views late does not
  // bend the rate.
  const msg = {
    type: 'view', view: run.view(), n: run.stmLength, at: performance.timeOrigin + now,
    wasmBytes: wasmMemory?.buffer.byteLength ?? null,
  };
  if (want.explain) msg.explain = run.explain();
  const transfer = [];
  if (want.camera) {
    msg.camera = copy(run.observation());
    msg.reconstruction = copy(run.reconstruction());
    msg.top = copy(run.topDown(want.top));
    msg.side = frameSize();
    transfer.push(msg.camera, msg.reconstruction, msg.top);
  }
  if (want.heat) {
    msg.heat = copy(run.memoryMap(want.heat));
    msg.selected = copy(run.selectedCouplets());
    transfer.push(msg.heat, msg.selected);
  }
  post(msg, transfer);
}

function episodes(list) {
  if (list.length) post({ type: 'episodes', list });
}

/** Runs until a slice is used up; guards every wasm call so a trap shows instead of freezing. */
function loop() {
  if (!playing || !run || dead) return;
  try {
    const t0 = performance.now();
    if (speed === Infinity) {
      const done = [];
      batch.fillSlice((n) => done.push(...run.runDecisions(n)));
      episodes(done);
      postView();
    } else {
      owed += ((t0 - lastTick) / 1000) * speed;
      lastTick = t0;
      owed = Math.min(owed, speed); // never more than a second behind
      const done = [];
      while (owed >= 1 && performance.now() - t0 < SLICE_MS) {
        const s = run.stepDecision();
        if (s.finished) done.push(s.finished);
        owed -= 1;
      }
      episodes(done);
      postView(speed <= VIEW_HZ);
    }
  } catch (e) {
    trapped(e);
    return;
  }
  if (speed === Infinity) soon(loop);
  else setTimeout(loop, Math.max(0, Math.min(1000 / speed, 1000 / VIEW_HZ)));
}

function trapped(e, id = undefined) {
  dead = true;
  playing = false;
  fail(`The simulation stopped: ${e?.message ?? e}. Reset to start again.`, true, id);
  post({ type: 'state', playing });
}

function setPlaying(p) {
  playing = p && !!run && !dead;
  // What the run stopped at goes first: once the page reads "paused", its views are final.
  if (!playing) postView(true);
  post({ type: 'state', playing });
  if (playing) {
    lastTick = performance.now();
    owed = 0;
    loop();
  }
}

/**
 * A new run (its task's model fetched first), given to `prepare` before it replaces the old one;
 * on failure (of either) the old run goes on.
 */
async function newRun(settingsConfig, seed, prepare) {
  const config = configOf(settingsConfig);
  await ensureModel(gateModel(config));
  const next = new SecRun(config, seed);
  try {
    prepare?.(next);
  } catch (e) {
    next.free();
    throw e;
  }
  if (driver) next.setDriver(driver.action, driver.record);
  run?.free();
  run = next;
  dead = false;
}

const handlers = {
  async start({ settings: raw }) {
    const parsed = parseSettings(raw ?? {});
    await newRun(parsed.config, parsed.seed);
    settings = parsed.settings;
    post({ type: 'started', settings, errors: parsed.errors, mode: 'restart', fresh: true });
    postView(true);
  },
  async set({ changes }) {
    // One batch, applied by the core as one (any order, all or none): a bad change throws,
    // naming every bad key, and nothing changes.
    const next = applySettings(settings, changes);
    const same = Object.keys(next.settings).every((k) => next.settings[k] === settings[k]);
    if (same && run && !dead) {
      // Nothing to change (e.g. the same value twice).
      return { mode: 'unchanged', changes: {}, settings };
    }
    let mode;
    if (!run || dead || next.seed !== run.seed) {
      await newRun(next.config, next.seed);
      mode = 'restart';
    } else {
      const config = configOf(next.config);
      if (gateModel(config) !== gateModel(run.config())) await ensureModel(gateModel(config));
      mode = run.replaceConfig(config).applied;
    }
    // What changed, under the table's keys (an attribute `thetaprop` is `thetaProp` here).
    const changed = Object.fromEntries(Object.entries(next.settings).filter(([k, v]) => settings?.[k] !== v));
    settings = next.settings;
    post({ type: 'started', settings, errors: [], mode, changes: changed });
    postView(true);
    return { mode, changes: changed, settings };
  },
  preset({ name }) {
    return handlers.set({ changes: presetSettings(name) });
  },
  play() { setPlaying(true); },
  pause() { setPlaying(false); },
  speed({ value }) {
    speed = value === 'max' ? Infinity : Number(value);
    if (!(speed > 0)) throw new Error(`speed: '${value}' is out of range (0, max]`);
    lastTick = performance.now();
    owed = 0;
  },
  step({ what }) {
    setPlaying(false);
    if (!run || dead) return;
    if (what === 'decision') {
      const s = run.stepDecision();
      if (s.finished) episodes([s.finished]);
    } else if (what === 'episode') {
      episodes([run.stepEpisode()]);
    } else {
      throw new Error(`step: '${what}' is not one of decision, episode`);
    }
    postView(true);
  },
  async reset() {
    const parsed = parseSettings(settings);
    await newRun(parsed.config, parsed.seed);
    post({ type: 'started', settings, errors: [], mode: 'restart' });
    postView(true);
  },
  /** A person drives (`action` 0..8) or gives the controls back (`action` null). */
  drive({ action, record }) {
    const next = action == null ? null : { action, record: !!record };
    run?.setDriver(next?.action, !!next?.record); // throws on a bad action, before anything changes
    driver = next;
  },
  config() {
    post({ type: 'config', config: run.config(), seed: run.seed });
  },
  /** The memory file: posted for the page to download, or the request's result (`id`). */
  saveMemory({ id }) {
    const bytes = run.saveMemory();
    if (id != null) return bytes.buffer;
    post({ type: 'memory', bytes: bytes.buffer }, [bytes.buffer]);
  },
  loadMemory({ bytes }) {
    const sequences = run.loadMemory(new Uint8Array(bytes));
    post({ type: 'loaded', sequences });
    postView(true);
    return { sequences };
  },
  /**
   * "Skip the warm-up": the run starts again from a reference run's memory (`what` says which),
   * with that run's seed (the untrained encoder is drawn per seed, so only its seed's embeddings
   * mean the same); a file that does not fit these settings is refused and the run goes on as it was.
   */
  async warmUp({ bytes, what }) {
    const parsed = parseSettings({ ...settings, seed: String(what.seed) });
    if (parsed.errors.length) throw new Error(parsed.errors.join('; '));
    let sequences;
    await newRun(parsed.config, parsed.seed, (next) => {
      sequences = next.loadMemory(new Uint8Array(bytes));
    });
    settings = parsed.settings;
    post({ type: 'started', settings, errors: [], mode: 'restart' });
    post({ type: 'loaded', sequences, what });
    postView(true);
  },
  /** Test hook (the test flavour only, `?wasm=hooks`): a panic in the simulation, as a bug would cause. */
  crash() {
    if (!panicForTest) throw new Error('crash: a test hook, in the test flavour only (?wasm=hooks)');
    panicForTest();
  },
  views({ camera, top, heat, hz, explain }) {
    want = {
      camera: !!camera,
      top: Number.isInteger(top) ? top : want.top,
      heat: heat === 't' || heat === 'g' ? heat : null,
      hz: Math.min(VIEW_HZ, Math.max(1, Number(hz) || VIEW_HZ)),
      explain: !!explain,
    };
    postView(true);
  },
};

// A bad value: the message names it; the run is as it was. A trap: the run is gone.
serveMessages(handlers, (e, id) => (e instanceof WebAssembly.RuntimeError ? trapped(e, id) : fail(e, false, id)));

/**
 * The page's first message: which build (`wasm`) and the first task, whose model is fetched while
 * the wasm loads. Messages after it wait until it is done (serveMessages runs them in order).
 */
handlers.boot = async ({ wasm, task, files, arena: name }) => {
  try {
    if (name != null && !OLYMPICS_NAME.test(String(name))) {
      throw new Error(`arena: '${String(name).slice(0, 40)}' is not an Olympics arena's name (01-01-01 to 10-30-03, the arena page's menu)`);
    }
    const loading = load({ wanted: wasm, task, files, arena: name != null });
    loading.catch(() => {}); // awaited below, after the file
    if (name != null) {
      const path = `assets/arenas/competition/${name}.yaml`;
      const r = await fetchFile(path, () => new URL(`../${path}`, import.meta.url));
      if (!r.ok) throw new Error(`arena: ${path} could not be loaded (${r.statusText || `HTTP ${r.status}`})`);
      arena = { name, yaml: await r.text() };
    }
    wasmMemory = (await loading).memory;
    // A file the loader refuses is refused here, naming its line and field.
    if (arena) withArena(parseSettings({}).config, arena.name, arena.yaml);
  } catch (e) {
    fail(`The simulation could not load: ${e?.message ?? e}`, true);
    dead = true;
    return;
  }
  const parsed = parseSettings({});
  post({ type: 'ready', params: parameters(), agents: agents(), defaults: parsed.settings, build, arena: arena?.name ?? null });
};

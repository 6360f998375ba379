// One playground: a simulation worker, the controls built from the core's parameter table, the
// views, the charts, driving, export and memory files, and the comparison panel. The page
// (index.html, embed.html) puts one in its document; each <sec-playground> element puts one in
// its shadow root, so several on a page share nothing.
import { buildControls, runControls, SPEEDS } from './controls.js';
import { Charts } from './charts.js';
import { Compare } from './compare.js';
import { drawRgba, drawEmbedding, drawHeat, drawHeatScale, drawProbs, drawStatus } from './views.js';
import { Tour } from './tour.js';
import { drawExplanation, whyLayer } from './explain.js';
import { keyboard } from './keys.js';
import { download, episodesCsv } from './export.js';
import { TEMPLATE } from './template.js';
import { importingWorker, sameOrigin } from './workers.js';
import { answerFileRequest, fetchFile, filesForWorker } from './files.js';

/** The version of the programmatic API and the iframe protocol (docs/EMBED.md). */
export const API_VERSION = 1;

/** Decisions per second while a person drives (the speed slider's value above it is capped). */
const DRIVE_SPEED = 8;
/** `?wasm=scalar` (the fallback build) or `?wasm=hooks` (the test flavour) in the page's address. */
const WASM = new URLSearchParams(location.search).get('wasm');

const LAYERS = { C: 'contextual (memory)', R: 'reactive (random walk)', H: 'you (driving)' };
/** View posts per second at max speed: enough to see the agent move, cheap next to the run. */
const MAX_SPEED_VIEW_HZ = 4;
/** The decisions/s readout is the rate over this window (ms). */
const RATE_WINDOW_MS = 3000;

export class Playground {
  /**
   * Builds a playground into `root` (an element or a shadow root). Options: `settings` (hash
   * keys to values), `hash` (keep the settings in the page's URL hash), `autoplay`, `hide`
   * (setting keys, or parts: runbar, keepbar, controls, views, charts, compare, or one view:
   * camera, arena, reconstruction, heat, policy), `keys` (where
   * the keyboard shortcuts listen: the window, or the element), `arena` (an Olympics arena's
   * name, `05-25-01`: every run plays that file, in the arena build).
   */
  constructor(root, { settings = {}, hash = false, autoplay = true, hide = [], keys = window, arena = null } = {}) {
    const t = document.createElement('template');
    t.innerHTML = TEMPLATE;
    root.append(t.content);
    this.root = root;
    this.$ = (id) => root.querySelector(`#${id}`);
    this.useHash = hash;
    const fromHash = hash ? readHash() : {};
    // `tour` in the address opens the guided tour; it is not a setting of the run.
    this.tourAsked = 'tour' in fromHash;
    delete fromHash.tour;
    this.initial = { ...settings, ...fromHash };
    this.hidden = hide;
    this.arena = arena;
    /** What an arena file's run has no use for (set when the worker plays one): hidden with `hide`. */
    this.arenaHides = [];
    this.worker = null;
    this.fatal = false;
    this.params = [];
    /** The core's agent table (`agents()`), from the worker. */
    this.agents = [];
    this.settings = null;
    this.controls = null;
    this.playing = false;
    this.wantPlay = autoplay;
    this.onScreen = true; // set by the element's IntersectionObserver
    this.visible = !document.hidden; // on screen and the tab shown
    this.speed = SPEEDS[Number(this.$('speed').value)];
    this.episodes = 0;
    this.log = []; // every finished episode of the current run (EpisodeMetrics)
    this.lastView = null;
    this.build = null;
    this.driving = false;
    this.keyAction = 0; // the held arrow keys' action
    this.padAction = null; // the held pad button's, which wins while held
    this.listeners = [];
    /** The API's events (`on`): ready, episode, state, error. */
    this.events = new EventTarget();
    /** The API's requests awaiting the worker's answer, by id. */
    this.pending = new Map();
    this.nextRequest = 1;
    this.started$ = new Promise((ok) => { this.whenStarted = ok; });
    // The reward curve beside the camera, unless the views are hidden (then with the other charts).
    const besideCamera = !hide.includes('views') && !hide.includes('charts');
    this.charts = new Charts(this.$('charts'), besideCamera ? { reward: this.$('chart-slot') } : {});
    this.compare = new Compare(this.$('compare'), {
      current: () => this.settings,
      agentInfo: (key) => this.agentInfo(key),
      onError: (m) => this.showError(m),
      wasm: WASM,
      onBusy: (busy) => this.compareBusy(busy),
      // Test hook (the test flavour only): `?wasm=hooks&turn=MS` shortens the runs' turns.
      turnMs: WASM === 'hooks' ? Number(new URLSearchParams(location.search).get('turn')) || undefined : undefined,
    });
    this.rate = { samples: [], perSecond: null };
    this.tour = new Tour(root, {
      onStart: () => {
        // One real decision to look at: the run pauses and steps once.
        this.setPlaying(false);
        if (this.settings) this.send({ type: 'step', what: 'decision' });
      },
      view: () => this.lastView,
    });
    this.hidden = [];
    this.setHidden(hide);
    this.wire(keys);
    this.startWorker();
  }

  /**
   * What a teacher hides: parts (runbar, keepbar, controls, views, charts, compare, or one view:
   * camera, arena, reconstruction, heat, policy) and setting keys. Again at any time (the
   * element's `hide` attribute): what was hidden before and is not listed shows again. Without
   * its controls the views take the whole width (the layout's one column).
   */
  setHidden(hide) {
    const part = (name) => (/^[a-z-]+$/i.test(name)
      ? this.root.querySelector(`.playground .${name}, .playground #${name}`) : null);
    const all = [...hide, ...this.arenaHides];
    for (const name of this.hidden) part(name)?.removeAttribute('hidden');
    for (const name of all) part(name)?.setAttribute('hidden', '');
    this.hidden = all;
    this.teacherHides = [...hide];
    this.controls?.hide(this.hidden);
  }

  /**
   * The worker plays the Olympics arena `name`: a note says what that run is (the untrained
   * encoder, no gate: no model was trained on it) with the way back, and what it has no use for
   * is hidden (the task and encoder choices, the episode limit, which is the file's own, the
   * reconstruction, the warm-up of the paper's tasks, the comparison of presets in them).
   */
  showArena(name) {
    this.arenaHides = name ? ['task', 'perception', 't', 'reconstruction', 'warm-up', 'compare'] : [];
    this.setHidden(this.teacherHides ?? []);
    const note = this.$('arena-note');
    note.hidden = !name;
    if (!name) return;
    note.querySelector('.arena-name').textContent = name;
    const category = Number(name.slice(0, 2));
    fetch(new URL('../assets/arenas/olympics.json', import.meta.url)).then((r) => r.json()).then((index) => {
      const c = index.categories?.[category - 1];
      if (c) note.querySelector('.arena-name').textContent = `${name} (category ${category}: ${c})`;
    }).catch(() => {}); // the name alone says which file it is
  }

  /** The error at the top of the page, and each refused value's next to its control. */
  showError(message) {
    const el = this.$('error');
    el.textContent = message ?? '';
    el.hidden = !message;
    this.controls?.refused(message ? message.split(/; |\. (?=[A-Z])/) : []);
    if (message) {
      this.notice(''); // a notice of what applied before is stale now
      this.emit('error', { message });
    }
  }

  notice(text) {
    this.$('notice').textContent = text;
  }

  send(msg, transfer = []) {
    this.worker.postMessage(msg, transfer);
  }

  /** A fresh simulation worker; with settings it carries on with them (after a fatal error). */
  startWorker() {
    this.worker?.terminate();
    this.fatal = false;
    for (const { fail } of this.pending.values()) fail(new Error('the simulation restarted'));
    this.pending.clear();
    this.worker = sameOrigin(import.meta.url) ? new Worker(new URL('./worker.js', import.meta.url), { type: 'module' })
      : importingWorker(new URL('./worker.js', import.meta.url));
    this.worker.onmessage = ({ data }) => this.handlers[data.type]?.call(this, data);
    this.worker.onerror = (e) => this.showError(`The simulation worker failed: ${e.message ?? 'it could not start'}`);
    // Which build, and the first task: the worker fetches its model while the wasm loads.
    this.send({
      type: 'boot', wasm: WASM, task: (this.settings ?? this.initial).task ?? 'double-t-maze', files: filesForWorker(),
      arena: this.arena,
    });
  }

  writeHash() {
    if (!this.useHash) return;
    const h = `#${new URLSearchParams(this.settings)}`;
    if (location.hash === h) return;
    try {
      history.replaceState(null, '', h);
    } catch {
      // A sandboxed frame with an opaque origin may not rewrite its address: the hash is a convenience.
    }
  }

  /** What the worker posts: every view while someone can see them, fewer at max speed, and
   * the explanation of each decision while paused or stepping. */
  views() {
    const watching = this.visible;
    const fast = this.effectiveSpeed() === 'max';
    const kind = this.$('heat-kind').value;
    drawHeatScale(this.$('heat-scale'), this.$('heat-lo'), this.$('heat-hi'), kind);
    this.send({
      type: 'views', camera: watching, top: this.$('arena').width, heat: watching ? kind : null,
      hz: fast ? MAX_SPEED_VIEW_HZ : 30, explain: watching && !this.wantPlay,
    });
  }

  /** The speed the worker runs at: the slider's, capped while a person drives. */
  effectiveSpeed() {
    if (!this.driving) return this.speed;
    return this.speed === 'max' ? DRIVE_SPEED : Math.min(this.speed, DRIVE_SPEED);
  }

  setPlaying(p) {
    this.wantPlay = p;
    if (p) this.$('main-paused').hidden = true; // the user's choice now
    this.send({ type: p && this.visible ? 'play' : 'pause' });
    this.views();
  }

  /**
   * The comparison starts playing (true) or stops (false): a playing run pauses meanwhile, with a
   * note and a button to resume it, and carries on after unless the user chose otherwise.
   */
  compareBusy(busy) {
    const note = this.$('main-paused');
    if (busy) {
      if (!this.wantPlay) return;
      this.setPlaying(false);
      note.hidden = false;
    } else if (!note.hidden) {
      note.hidden = true;
      this.setPlaying(true);
    }
  }

  /** On screen or not (the element's observer): off screen the run pauses, and carries on after. */
  setOnScreen(v) {
    this.onScreen = v;
    this.setVisible(v && !document.hidden);
  }

  setVisible(v) {
    if (v === this.visible) return;
    this.visible = v;
    this.compare.setVisible(v);
    if (!this.worker) return;
    this.send({ type: this.wantPlay && v ? 'play' : 'pause' });
    this.views();
  }

  /** Applies setting changes (hash keys to values), validated by the core like any control. */
  set(changes) {
    if (!this.settings) {
      Object.assign(this.initial, changes);
      return;
    }
    const diff = Object.fromEntries(Object.entries(changes).filter(([k, v]) => this.settings[k] !== String(v)));
    if (Object.keys(diff).length) this.send({ type: 'set', changes: diff });
  }

  setDriving(on) {
    this.driving = on;
    const b = this.$('drive');
    b.setAttribute('aria-pressed', String(on));
    b.classList.toggle('on', on);
    const pad = this.$('drive-pad');
    pad.hidden = !on;
    this.send({ type: 'speed', value: this.effectiveSpeed() });
    this.sendDriver();
    if (on) {
      // A finger drives with the pad: it comes into view, and the notice says to touch it.
      const touch = this.lastPointer === 'touch' || matchMedia('(pointer: coarse)').matches;
      this.notice((touch
        ? 'Driving: touch and hold a button of the pad under the camera (↑ forward, ↓ back, ↶ ↷ turn); '
        : 'Driving: hold the arrow keys (↑ forward, ↓ back, ← → turn) or a button of the pad under the camera; ')
        + 'nothing held: stand still. '
        + (this.$('record').checked ? 'Recording: a rewarded episode goes into the LTM.' : 'Not recording.'));
      const box = pad.getBoundingClientRect();
      if (box.top < 0 || box.bottom > innerHeight) pad.scrollIntoView({ block: 'nearest' });
      if (!this.wantPlay) this.setPlaying(true);
    } else {
      this.notice('The agent drives again.');
    }
    this.views();
  }

  sendDriver() {
    const action = this.padAction ?? this.keyAction ?? 0;
    this.send({ type: 'drive', action: this.driving ? action : null, record: this.$('record').checked });
  }

  /** The on-screen pad: a button held (mouse, pen or finger) drives with its action until let go. */
  wirePad() {
    const pad = this.$('drive-pad');
    const release = (b) => {
      b.classList.remove('held');
      if (this.padButton !== b) return;
      this.padButton = null;
      this.padAction = null;
      if (this.driving) this.sendDriver();
    };
    for (const b of pad.querySelectorAll('button')) {
      b.addEventListener('pointerdown', (e) => {
        e.preventDefault();
        b.setPointerCapture?.(e.pointerId);
        if (this.padButton) this.padButton.classList.remove('held');
        this.padButton = b;
        this.padAction = Number(b.dataset.action);
        b.classList.add('held');
        if (this.driving) this.sendDriver();
      });
      for (const type of ['pointerup', 'pointercancel', 'lostpointercapture']) b.addEventListener(type, () => release(b));
      b.addEventListener('contextmenu', (e) => e.preventDefault()); // a long touch is a hold, not a menu
    }
  }

  label(key) {
    return this.params.find((p) => p.key === key)?.symbol ?? key;
  }

  wire(keys) {
    const $ = this.$;
    $('main-resume').addEventListener('click', () => this.setPlaying(true));
    $('to-controls').addEventListener('click', () => $('controls').scrollIntoView({ block: 'start' }));
    // Whether the last press was a finger's (Drive then says to touch the pad).
    this.listen(this.root, 'pointerdown', (e) => { this.lastPointer = e.pointerType; });
    $('reward-help').addEventListener('click', () => {
      const note = $('reward-note');
      note.hidden = !note.hidden;
      $('reward-help').setAttribute('aria-expanded', String(!note.hidden));
    });
    runControls($, {
      toggle: () => this.setPlaying(!this.wantPlay),
      // A refusal shows as the page's error; the promise has nothing to add.
      step: (what) => this.step(what).catch(() => {}),
      reset: () => this.reset().catch(() => {}),
      preset: (name) => this.send({ type: 'preset', name }),
      speed: (v) => {
        this.speed = v;
        this.send({ type: 'speed', value: this.effectiveSpeed() });
        this.views();
      },
      drive: () => this.setDriving(!this.driving),
    }, { target: keys, driving: () => this.driving });
    keyboard(null, {
      target: keys,
      active: () => this.driving,
      onChange: (action) => {
        this.keyAction = action;
        if (this.driving) this.sendDriver();
      },
    });
    $('drive').addEventListener('click', () => this.setDriving(!this.driving));
    this.wirePad();
    this.listen(document, 'visibilitychange', () => this.setVisible(this.onScreen && !document.hidden));
    // Someone edits the link: apply what changed (validated by the core like any control).
    if (this.useHash) {
      this.listen(window, 'hashchange', () => {
        const h = readHash();
        if ('tour' in h) {
          delete h.tour;
          this.tour.start();
        }
        this.set(h);
      });
    }
    $('record').addEventListener('change', () => this.driving && this.setDriving(true));
    $('heat-kind').addEventListener('change', () => this.views());
    $('export-csv').addEventListener('click', () => this.exportCsv());
    $('export-json').addEventListener('click', () => this.exportJson());
    $('save-memory').addEventListener('click', () => this.send({ type: 'saveMemory' }));
    $('warm-up').addEventListener('click', () => this.skipWarmUp());
    $('load-memory').addEventListener('change', async (e) => {
      const file = e.target.files?.[0];
      e.target.value = '';
      if (!file) return;
      const bytes = await file.arrayBuffer();
      this.send({ type: 'loadMemory', bytes }, [bytes]);
    });
  }

  /**
   * "Skip the warm-up": the run starts again (same settings, the reference run's seed) from the
   * memory a native reference run of this task had after its first episodes (assets/warm-up/,
   * made and checked against that run by `sec-experiment warm-up`).
   */
  async skipWarmUp() {
    const task = this.settings?.task;
    if (!this.agentInfo()?.hasMemory) {
      this.showError(`Skip the warm-up: ${this.agentInfo()?.label ?? 'this agent'} has no memory to load; choose SEC or a SEC variant.`);
      return;
    }
    try {
      const r0 = await fetchFile('assets/warm-up/index.json', () => new URL('../assets/warm-up/index.json', import.meta.url));
      if (!r0.ok) throw new Error(`assets/warm-up/index.json: HTTP ${r0.status}`);
      const index = await r0.json();
      const entry = index[task];
      if (!entry) {
        throw new Error(`there is no warm-up memory for the task '${task}' (there is one for: ${Object.keys(index).join(', ')})`);
      }
      const r = await fetchFile(`assets/warm-up/${entry.file}`, () => new URL(`../assets/warm-up/${entry.file}`, import.meta.url));
      if (!r.ok) throw new Error(`${entry.file}: HTTP ${r.status}`);
      const bytes = await r.arrayBuffer();
      this.send({ type: 'warmUp', bytes, what: entry }, [bytes]);
    } catch (e) {
      this.showError(`Skip the warm-up: ${e.message ?? e}`);
    }
  }

  /** Adds a listener that `destroy` removes. */
  listen(target, type, f) {
    target.addEventListener(type, f);
    this.listeners.push(() => target.removeEventListener(type, f));
  }

  /** The agent table's row of `key` (the running agent's by default). */
  agentInfo(key = this.settings?.agent) {
    return this.agents?.find((a) => a.key === key);
  }

  /** After an episode a person drove with record on: what it did to SEC's memory. */
  afterDrive(m) {
    const need = (this.lastView?.minSequences ?? 5) - m.ltm;
    this.notice(m.goal
      ? `Your episode reached the goal and is stored: the LTM holds ${m.ltm} sequence${m.ltm === 1 ? '' : 's'}. `
        + (need > 0 ? `${this.agentInfo()?.label ?? 'The agent'} acts from memory once it holds ${m.ltm + need}: ${need} more to go.` : `${this.agentInfo()?.label ?? 'The agent'} can act from memory now.`)
      : 'Your episode did not reach the goal, so nothing was stored.');
  }

  exportCsv() {
    const runs = [{ name: 'main', settings: this.settings, seed: this.settings?.seed, episodes: this.log },
      ...this.compare.runs()];
    download(this.root, 'sec-episodes.csv', 'text/csv', episodesCsv(runs));
  }

  exportJson() {
    this.pendingJson = true;
    this.send({ type: 'config' });
  }

  // The programmatic API: what the element's methods, the iframe protocol (docs/EMBED.md) and
  // the notebook widget call. Settings go through the core's table as the controls' do.

  /**
   * Calls `f(detail)` on each `type` event; returns the unsubscribe. ready, episode, state and
   * error are the iframe protocol's; settings (changed by anyone: `{applied, changes, settings}`),
   * run (a new run began: its episodes count from 1 again) and explanation (the last decision's,
   * posted while paused or stepping) serve hosts that mirror the page (the notebook widget).
   */
  on(type, f) {
    const h = (e) => f(e.detail);
    this.events.addEventListener(type, h);
    return () => this.events.removeEventListener(type, h);
  }

  emit(type, detail) {
    this.events.dispatchEvent(new CustomEvent(type, { detail }));
  }

  /** Sends `msg` with a fresh id; resolves with the worker's result, rejects with its error. */
  request(msg, transfer = []) {
    return new Promise((ok, fail) => {
      const id = this.nextRequest++;
      this.pending.set(id, { ok, fail });
      this.send({ ...msg, id }, transfer);
    });
  }

  play() {
    this.setPlaying(true);
    return this.getState();
  }

  pause() {
    this.setPlaying(false);
    return this.getState();
  }

  /** A new run with the same settings (and seed). */
  async reset() {
    await this.started$;
    if (this.fatal) this.startWorker();
    else await this.request({ type: 'reset' });
    return this.getState();
  }

  /** One decision or one whole episode (`what`), paused after it. */
  async step(what = 'decision') {
    await this.started$;
    if (this.wantPlay) {
      this.wantPlay = false;
      this.views();
    }
    await this.request({ type: 'step', what });
    return this.getState();
  }

  /**
   * Applies settings (keys of the core's table, as in the URL hash) as one batch, all or none.
   * Resolves with what applied: `{applied: 'live' | 'restart' | 'unchanged', changes, settings}`
   * (`changes` under the table's keys); rejects naming each bad key and its range.
   */
  async configure(settings) {
    if (settings == null || typeof settings !== 'object' || Array.isArray(settings)) {
      throw new Error(`configure: settings must be an object of keys to values, not ${JSON.stringify(settings)}`);
    }
    await this.started$;
    const changes = Object.fromEntries(Object.entries(settings).map(([k, v]) => [k, String(v)]));
    const r = await this.request({ type: 'set', changes });
    return { applied: r.mode, changes: r.changes, settings: r.settings };
  }

  /**
   * Where the run is: `playing` (asked to play) and `running` (stepping now: not while it is off
   * screen, in a hidden tab or paused for a comparison), decisions and episodes so far, the LTM
   * and the settings.
   */
  getState() {
    const v = this.lastView;
    return {
      playing: this.wantPlay,
      running: this.playing,
      decisions: v?.decisions ?? 0,
      episode: this.episodes,
      ltm: v?.ltm ?? 0,
      capacity: v?.capacity ?? null,
      settings: this.settings ? { ...this.settings } : null,
    };
  }

  /** Every finished episode of this run: its metrics rows, or the CSV the export writes. */
  getMetrics(format = 'rows') {
    if (format === 'csv') {
      return episodesCsv([{ name: 'main', settings: this.settings, seed: this.settings?.seed, episodes: this.log }]);
    }
    if (format !== 'rows') throw new Error(`getMetrics: format '${format}' is not one of rows, csv`);
    return this.log.map((m) => ({ ...m }));
  }

  /** The run's memory file (an ArrayBuffer), as "Save memory" writes it. */
  async saveMemory() {
    await this.started$;
    return this.request({ type: 'saveMemory' });
  }

  /** Loads a memory file (ArrayBuffer or typed array); resolves with the sequences it holds. */
  async loadMemory(bytes) {
    const buffer = bytes instanceof ArrayBuffer ? bytes : ArrayBuffer.isView(bytes)
      ? bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength) : null;
    if (!buffer) throw new Error('loadMemory: bytes must be an ArrayBuffer or a typed array');
    await this.started$;
    const { sequences } = await this.request({ type: 'loadMemory', bytes: buffer });
    return { sequences };
  }

  /** What tests and the curious can read. */
  get state() {
    const me = this;
    return {
      get settings() { return me.settings; },
      get episodes() { return me.episodes; },
      get playing() { return me.playing; },
      get marks() { return me.charts.marks; },
      get points() { return me.charts.episodes.length; },
      /** Each learning curve's y axis, [min, max] by chart id. */
      get chartRanges() { return me.charts.ranges(); },
      get view() { return me.lastView; },
      get build() { return me.build; },
      /** ms from the page's start to the first camera frame drawn. */
      get firstFrame() { return me.firstFrame; },
      get driving() { return me.driving; },
      get log() { return me.log; },
      get compare() { return me.compare.state; },
      /** Whether the run is paused for the comparison (its note shows). */
      get pausedForCompare() { return !me.$('main-paused').hidden; },
      get tour() { return me.tour.state; },
      /** The last decision explained (while paused or stepping). */
      get explanation() { return me.lastExplanation ?? null; },
      /** The decisions/s readout's value. */
      get rate() { return me.rate.perSecond; },
      /** What the readout divides: decisions over ms of its window (the worker's clock). */
      get rateWindow() { return me.rate.window ?? null; },
      /** The run's worker's wasm memory in bytes, as of the last view. */
      get wasmBytes() { return me.wasmBytes ?? null; },
      /** Test hook: makes the simulation panic. */
      crash() { me.send({ type: 'crash' }); },
    };
  }

  /** Stops the workers (the element left the page). */
  destroy() {
    this.worker?.terminate();
    this.compare.stop();
    this.compare.chart.destroy();
    this.charts.destroy();
    for (const off of this.listeners) off();
  }

  /** The decision rate: decisions counted by the run over the last few seconds of views, timed
   *  by the worker when it took each view (`at`), not when this thread got round to it. */
  measureRate(v, at) {
    const now = at ?? performance.timeOrigin + performance.now();
    const s = this.rate.samples;
    if (s.length && v.decisions < s[s.length - 1].d) s.length = 0; // a new run
    s.push({ t: now, d: v.decisions });
    while (s.length > 2 && now - s[1].t > RATE_WINDOW_MS) s.shift();
    const dt = now - s[0].t;
    if (dt >= 400) {
      this.rate.perSecond = ((v.decisions - s[0].d) * 1000) / dt;
      this.rate.window = { decisions: v.decisions - s[0].d, ms: dt };
    }
  }

  status() {
    const v = this.lastView;
    if (!v) return;
    const rate = this.rate;
    drawStatus(this.$('status'), [
      ['episode', String(v.episode)],
      ['env step', String(v.step)],
      // As the charts and the CSV count it: below 0 is 0 (a failed episode); the raw sum beside it.
      ['reward', v.episodeReward < 0 ? `0 (raw ${v.episodeReward.toFixed(3)})` : v.episodeReward.toFixed(3)],
      ['LTM', v.capacity ? `${v.ltm} / ${v.capacity}` : '–'],
      ['decisions/s', !this.playing ? 'paused' : rate.perSecond == null ? '…' : rate.perSecond.toFixed(0)],
    ]);
  }
}

Playground.prototype.handlers = {
  ready(msg) {
    this.params = msg.params;
    this.agents = msg.agents;
    this.build = msg.build;
    this.showArena(msg.arena);
    this.controls ??= buildControls(this.$('controls'), this.params, (key, value) => {
      if (this.settings?.[key] !== value) this.send({ type: 'set', changes: { [key]: value } });
    });
    this.controls.hide(this.hidden);
    this.send({ type: 'speed', value: this.effectiveSpeed() });
    if (this.driving) this.sendDriver();
    this.send({ type: 'start', settings: this.settings ?? this.initial });
    this.views();
  },
  started(msg) {
    const first = this.settings === null;
    this.settings = msg.settings;
    this.controls.set(this.settings);
    this.controls.agent(this.agentInfo());
    this.writeHash();
    if (msg.errors.length) {
      this.showError(`${msg.errors.join('; ')}. Using the default for ${msg.errors.length === 1 ? 'it' : 'them'}.`);
    } else if (!first) {
      this.showError(null);
    }
    if (msg.mode === 'restart') {
      this.charts.clear();
      this.episodes = 0;
      this.log = [];
      if (!first) this.notice(msg.changes ? `New run: ${Object.keys(msg.changes).map((k) => this.label(k)).join(', ')} changed` : 'Run reset');
    } else if (msg.changes) {
      const what = Object.entries(msg.changes).map(([k, v]) => `${this.label(k)}=${v}`).join(' ');
      const ignored = Object.keys(msg.changes).filter((k) => {
        const agents = this.params.find((p) => p.key === k)?.agents ?? [];
        return agents.length && !agents.includes(this.settings.agent);
      });
      this.charts.mark(what);
      this.notice(ignored.length
        ? `Set ${what}; this agent (${this.agentInfo()?.label ?? this.settings.agent}) does not use ${ignored.map((k) => this.label(k)).join(', ')}.`
        : `Applied live: ${what}`);
    }
    if (first || msg.fresh) this.setPlaying(this.wantPlay);
    if (first) {
      this.whenStarted();
      this.emit('ready', { version: API_VERSION, settings: { ...this.settings } });
    } else {
      // Whoever changed them (a control, a shortcut, the API): a host mirrors the settings.
      this.emit('settings', { applied: msg.mode, changes: msg.changes ?? null, settings: { ...this.settings } });
    }
    if (msg.mode === 'restart') this.emit('run', { settings: { ...this.settings } });
    if (first && this.tourAsked) {
      this.tourAsked = false;
      this.tour.start();
    }
  },
  episodes({ list }) {
    this.charts.push(list);
    this.episodes += list.length;
    for (const m of list) {
      this.log.push(m);
      this.emit('episode', { ...m });
      if (m.human && this.agentInfo()?.canBeDriven && this.$('record').checked) this.afterDrive(m);
    }
  },
  view(msg) {
    const $ = this.$;
    this.lastView = msg.view;
    if (msg.camera) {
      if (!this.firstFrame) {
        this.firstFrame = performance.now();
        performance.mark('sec-playground:first-frame');
      }
      drawRgba($('camera'), new Uint8Array(msg.camera), msg.side, msg.side);
      // An arena file's run has no trained model, so no reconstruction (its figure is hidden).
      if (msg.reconstruction.byteLength) drawRgba($('reconstruction'), new Uint8Array(msg.reconstruction), msg.side, msg.side);
      drawRgba($('arena'), new Uint8Array(msg.top), $('arena').width, $('arena').width);
    }
    if (msg.heat) drawHeat($('heat'), new Float32Array(msg.heat), msg.n, new Uint32Array(msg.selected), $('heat-kind').value);
    const v = msg.view;
    this.wasmBytes = msg.wasmBytes;
    this.measureRate(v, msg.at);
    drawProbs($('probs'), v.p, v.action);
    // Memory always votes; the grid and its entropy say whether its vote was acted on.
    const memoryVotes = !!this.agentInfo()?.hasMemory && v.layer != null;
    const acted = v.layer === 'C';
    const policy = $('probs').closest('figure');
    policy.classList.toggle('not-acted', memoryVotes && !acted);
    $('policy-caption').textContent = !memoryVotes ? 'Action probabilities p (3×3 grid)'
      : acted ? "Memory's vote p (3×3 grid), acted on: the outlined action is drawn from it"
        : "Memory's vote p (3×3 grid), not acted on: the reactive layer chose the outlined action";
    drawEmbedding($('embedding'), v.embedding);
    $('entropy').textContent = `${v.entropy.toFixed(3)} bits`;
    $('entropy-meter').value = v.entropy;
    $('layer').textContent = LAYERS[v.layer] ?? '–';
    $('why').textContent = whyLayer(v, this.agentInfo());
    $('gate-mse').textContent = this.agentInfo()?.reads === 'nothing' ? '–'
      : `${v.gateMse == null ? 'not measured yet' : v.gateMse.toFixed(4)}${v.gate != null ? ` (gate ${+v.gate.toPrecision(4)})` : ''}`;
    if (msg.explain) {
      this.lastExplanation = msg.explain;
      this.emit('explanation', msg.explain);
      drawExplanation($('explain'), msg.explain, v.layer);
    }
    else if (this.wantPlay) $('explain').querySelector('.formula').textContent = 'Pause or step to see the last decision explained.';
    this.status();
  },
  state(msg) {
    this.playing = msg.playing;
    this.emit('state', this.getState());
    if (!this.playing) this.rate.samples.length = 0;
    this.$('play').textContent = this.playing ? 'Pause' : 'Play';
    this.$('play').closest('.playground').dataset.playing = this.playing;
  },
  memory({ bytes }) {
    const s = this.settings;
    download(this.root, `sec-memory-${this.arena ?? s.task}-seed${s.seed}.secmem`, 'application/octet-stream', bytes);
    this.notice(`Memory saved (${(bytes.byteLength / 1024).toFixed(0)} KB).`);
  },
  loaded({ sequences, what }) {
    this.showError(null);
    const held = `${sequences} sequence${sequences === 1 ? '' : 's'} in the LTM`;
    if (what) {
      this.notice(`Warm-up skipped: this run starts from the memory of the reference run ${what.run}, seed ${what.seed}, `
        + `after ${what.episodes} episodes (${held}; that run's 20-episode mean reward was then ${what.meanReward.toFixed(2)}). `
        + `Episodes count from 0 again, with your settings and that run's seed (the untrained encoder is drawn per seed).`);
      this.charts.mark('warm-up skipped');
    } else {
      this.notice(`Memory loaded: ${held}.`);
      this.charts.mark('memory loaded');
    }
  },
  config({ config, seed }) {
    if (!this.pendingJson) return;
    this.pendingJson = false;
    const json = JSON.stringify({ settings: this.settings, seed, config }, null, 2);
    download(this.root, `sec-config-${this.arena ?? this.settings.task}-seed${seed}.json`, 'application/json', json);
  },
  file(msg) {
    answerFileRequest(this.worker, msg);
  },
  done({ id, result }) {
    this.pending.get(id)?.ok(result);
    this.pending.delete(id);
  },
  error(msg) {
    if (this.pending.has(msg.id)) {
      this.pending.get(msg.id).fail(new Error(msg.message));
      this.pending.delete(msg.id);
    }
    this.showError(msg.message);
    this.fatal ||= msg.fatal;
    // A refused value: show the settings still in force, in the controls and the address bar.
    if (this.settings && this.controls) this.controls.set(this.settings);
    if (this.settings) this.writeHash();
  },
};

/** The URL hash as settings: `#alpha=0.01&m=500` gives {alpha: '0.01', m: '500'}. */
export function readHash() {
  return Object.fromEntries(new URLSearchParams(location.hash.slice(1)));
}

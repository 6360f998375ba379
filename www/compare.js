// The comparison panel: several configurations with the same seeds, their curves overlaid in one
// chart with standard-error bands; one-click presets for the paper's experiments 1-4. A pool of
// workers (the machine's threads less one) plays the runs, one run (configuration x seed) per
// worker at a time; the page's own run pauses meanwhile. When there are more runs than workers,
// the runs take turns (`TURN_MS` of play each, handed between workers as checkpoints), the run
// with the fewest episodes first, so every seed of every configuration moves forward together
// and the workers stay busy until the last episodes: Experiment 1's 15 runs end together instead
// of the longest starting last.
import { ARM_COLOURS, CompareChart, WINDOW } from './charts.js';
import { COMPARE_PRESETS, PRESET_BASE, exp1In, referenceMap } from './presets.js';
import { importingWorker, sameOrigin } from './workers.js';
import { answerFileRequest, fetchFile, filesForWorker } from './files.js';

/** Most configurations at once. */
const MAX_ARMS = 8;
/** Episodes a run may play (the paper's horizon is 5000). */
export const EPISODES = { min: 10, max: 20000 };
/** The seeds the paper's experiments ran here per arm (the reference runs have 10 or 20). */
const PRESET_SEEDS = 5;
/** A run's turn on a worker when runs wait for one (ms of play, then to its episode's end). */
export const TURN_MS = 10000;
/** The window over which the progress line measures its rate (ms). */
const RATE_WINDOW_MS = 30000;

/** Threads the pool may use by default: the machine's less one, for the page itself. */
export function defaultPool() {
  return Math.max(1, (navigator.hardwareConcurrency || 2) - 1);
}

/** A duration as the progress line says it. */
function duration(s) {
  if (!Number.isFinite(s)) return 'unknown';
  if (s < 90) return `${Math.max(1, Math.round(s))} s`;
  if (s < 5400) return `${Math.round(s / 60)} min`;
  return `${(s / 3600).toFixed(1)} h`;
}
const METRICS = { reward: (m) => m.reward, entropy: (m) => m.entropy, decisions: (m) => m.decisions };

let index = null;
/** The reference runs there are (`experiment:condition` names), fetched once. */
/** The reference runs there are, by `experiment:condition` name, with their numbers; fetched once. */
function referenceIndex() {
  index ??= fetchFile('assets/reference/index.json', () => new URL('../assets/reference/index.json', import.meta.url))
    .then((r) => (r.ok ? r.json() : { references: [] }))
    .then(referenceMap)
    .catch(() => referenceMap({}));
  return index;
}

/** A reference run's size, as the notes say it. */
const size = (r) => `${r.seeds.length} seed${r.seeds.length === 1 ? '' : 's'} × ${r.episodes} episodes`;

/** A line of the list: the colour, the label and what it holds. */
function item(a, text) {
  const li = document.createElement('li');
  const swatch = document.createElement('span');
  swatch.className = 'swatch';
  swatch.style.background = a.colour;
  const name = document.createElement('strong');
  name.textContent = a.label;
  const info = document.createElement('span');
  info.className = 'info';
  info.textContent = text;
  li.append(swatch, name, info);
  return li;
}

/** Episodes every seed of a configuration has finished. */
const finished = (arm) => (arm.runs.size ? Math.min(...[...arm.runs.values()].map((r) => r.length)) : 0);
/** The median of `xs`, or null for none. */
function middle(xs) {
  if (!xs.length) return null;
  const v = [...xs].sort((a, b) => a - b);
  return v[(v.length - 1) >> 1];
}

/**
 * The episode an arm's LTM filled (its `m` sequences), the median over its seeds that got there;
 * for an agent with a sequential memory (the table's `hasMemory`: `info`).
 */
function liveFill(arm, info) {
  const m = Number(arm.resolved?.m);
  if (!m || !info?.hasMemory) return null;
  return middle([...arm.runs.values()].map((eps) => eps.findIndex((e) => e.ltm >= m)).filter((i) => i >= 0));
}

/** A run of the plan, waiting to start. */
const job = (arm, seed) => ({ arm, seed, state: 'queued', checkpoint: null, played: 0, turns: 0, heldMs: 0, since: 0, checkpoints: null });

/** The waiting run with the fewest episodes played, the first in the plan among equals. */
function nextRun(jobs) {
  let best = null;
  for (const j of jobs) if (j.state === 'queued' && (!best || j.played < best.played)) best = j;
  return best;
}

/** Episodes a configuration's seeds have played, all together. */
const played = (arm) => [...arm.runs.values()].reduce((n, r) => n + r.length, 0);

export class Compare {
  constructor(root, { current, agentInfo, onError, wasm, onBusy = () => {}, turnMs = TURN_MS }) {
    this.root = root;
    this.$ = (id) => root.querySelector(`#${id}`);
    this.current = current;
    /** The agent table's row of a key. */
    this.agentInfo = agentInfo;
    this.onError = onError;
    this.wasm = wasm;
    /** A run's turn when runs wait for a worker (ms of play). */
    this.turnMs = turnMs;
    /** Called with true when the comparison starts playing, false when it stops (pause, done, clear). */
    this.onBusy = onBusy;
    this.arms = [];
    /**
     * Every run of the comparison (`job`): {arm, seed, state: 'queued' | 'playing' | 'done',
     * checkpoint, played}: the bytes of its last turn's end (an ArrayBuffer, or null: it starts
     * afresh) and the episodes they hold; its turns so far, its time on workers (`heldMs`, the
     * current turn from `since`) and whether its agent checkpoints (null until it starts).
     */
    this.jobs = [];
    /** The pool's workers: {worker, job, ready}. */
    this.pool = [];
    /** (time, episodes played) samples for the rate and the ETA. */
    this.samples = [];
    /** Agents the page cannot run (DQN, ERLAM: native, burn), shown by their reference runs. */
    this.natives = [];
    this.running = false;
    this.visible = true;
    this.title = '';
    this.chart = new CompareChart(this.$('compare-chart'));
    this.chart.watch(() => this.series());
    const $ = this.$;
    for (const name of Object.keys(COMPARE_PRESETS)) $(`compare-${name}`).addEventListener('click', () => this.preset(name));
    $('compare-add').addEventListener('click', () => this.addCurrent());
    $('compare-run').addEventListener('click', () => (this.running ? this.pause() : this.start()));
    $('compare-clear').addEventListener('click', () => this.clear());
    $('compare-full').addEventListener('change', (e) => this.chart.setFull(e.target.checked));
    $('compare-zoom-reset').addEventListener('click', () => this.chart.resetZoom());
    $('compare-metric').addEventListener('change', () => this.chart.touch());
    $('compare-task').addEventListener('change', () => this.preset('exp1'));
    const workers = $('compare-workers');
    const most = Math.max(defaultPool(), navigator.hardwareConcurrency || 1);
    workers.replaceChildren(...Array.from({ length: most }, (_, i) => new Option(String(i + 1), String(i + 1))));
    workers.value = String(defaultPool());
    workers.addEventListener('change', () => this.fillPool());
  }

  /** Runs played at once. */
  poolSize() {
    return Number(this.$('compare-workers').value) || defaultPool();
  }

  /** Episodes each run plays, or null with the error shown (naming the control and its range). */
  horizon() {
    const input = this.$('compare-episodes');
    const name = 'compare episodes';
    if (input.validity.badInput || input.value.trim() === '') {
      this.onError(`${name}: ${input.validity.badInput ? 'is not a number' : 'is empty'}; `
        + `give a whole number in ${EPISODES.min}..=${EPISODES.max}`);
      return null;
    }
    const n = Number(input.value);
    if (!Number.isInteger(n) || n < EPISODES.min || n > EPISODES.max) {
      this.onError(`${name}: ${input.value} is out of range ${EPISODES.min}..=${EPISODES.max} (whole numbers)`);
      return null;
    }
    return n;
  }

  /** The seeds every configuration runs: 1..k. */
  seeds() {
    const k = Number(this.$('compare-seeds').value);
    return Array.from({ length: k }, (_, i) => i + 1);
  }

  /** Replaces the configurations with a preset's, draws its reference runs and starts them. */
  preset(name) {
    const p = name === 'exp1' ? exp1In(this.$('compare-task').value) : { ...COMPARE_PRESETS[name], base: PRESET_BASE };
    this.clear();
    this.chart.reset();
    this.$('compare-seeds').value = String(PRESET_SEEDS);
    this.$('compare-episodes').value = '5000';
    this.title = p.title;
    this.caption('', '');
    // The captions quote the reference index's numbers (the paper's and our runs').
    referenceIndex().then((refs) => {
      if (this.title !== p.title) return; // another preset since
      if (!refs.size) {
        this.caption('The reference index (assets/reference/index.json) could not be loaded: the paper\'s and our '
          + 'numbers are in REPRODUCTION.md.', '');
        return;
      }
      this.caption(p.summary(refs), typeof p.caption === 'function' ? p.caption(refs) : p.caption);
    });
    for (const arm of p.arms) this.add(arm.label, { ...p.base, ...arm.settings }, arm.reference);
    this.natives = (p.natives ?? []).map((n, i) => ({
      label: n.label, referenceName: n.reference, reference: null,
      colour: ARM_COLOURS[(this.arms.length + i) % ARM_COLOURS.length],
    }));
    this.list();
    this.loadReferences();
    this.start();
  }

  /**
   * Fetches the reference curves the arms name (assets/reference/, made by `sec-experiment
   * reference` from the committed native runs) and says what they are.
   */
  async loadReferences() {
    const arms = this.arms.filter((a) => a.referenceName);
    const natives = this.natives;
    const note = this.$('compare-reference');
    note.textContent = arms.length || natives.length ? 'Loading the reference runs…' : '';
    // The index lists the runs there are, so a missing one is not a failed request.
    const listed = await referenceIndex();
    await Promise.all([...arms, ...natives].map(async (a) => {
      const [experiment, condition] = a.referenceName.split(':');
      if (!listed.has(a.referenceName)) return;
      a.referenceFills = listed.get(a.referenceName).ltmFull ?? [];
      try {
        // Every reference is experiment/group/arm.json: three literal levels, so that a bundler
        // (Vite) can list the files this address may name and copy them.
        const [group, arm] = condition.split('/');
        const r = await fetchFile(`assets/reference/${experiment}/${group}/${arm}.json`,
          () => new URL(`../assets/reference/${experiment}/${group}/${arm}.json`, import.meta.url));
        a.reference = r.ok ? await r.json() : null;
      } catch {
        a.reference = null;
      }
    }));
    // Unless another preset replaced these arms meanwhile.
    if (this.arms.length && arms.every((a) => this.arms.includes(a)) && natives === this.natives) {
      const have = arms.filter((a) => a.reference);
      const missing = arms.filter((a) => !a.reference).map((a) => a.label);
      const sizes = [...new Set(have.map((a) => size(a.reference)))];
      const nativesIn = natives.filter((a) => a.reference);
      const nativesOut = natives.filter((a) => !a.reference).map((a) => a.label);
      note.textContent = (have.length
        ? `Faint bands and dashed lines: the native reference runs at the same settings (${sizes.join(', ')}; `
          + 'mean of 20 episodes ± one standard error across seeds; REPRODUCTION.md). The live runs draw over them.'
        : 'No reference runs at these settings yet.')
        + (have.length && missing.length ? ` Not run yet: ${missing.join(', ')}.` : '')
        + (nativesIn.length
          ? ` ${nativesIn.map((a) => `${a.label} (${size(a.reference)})`).join(', ')}: reference runs only, as `
            + 'these agents train with burn and run natively, not in the page.'
          : '')
        + (nativesOut.length ? ` ${nativesOut.join(', ')}: reference runs still to come.` : '');
      this.list();
      this.chart.touch();
    }
  }

  /** Adds the settings in force in the playground above (its seed aside: seeds are 1..k). */
  addCurrent() {
    const s = this.current();
    if (!s) return;
    const { seed, ...settings } = s;
    const info = this.agentInfo(settings.agent);
    const name = info?.unbiasedLabel && settings.bias === '0' ? info.unbiasedLabel : info?.label ?? settings.agent;
    const label = `${name} `
      + `α=${settings.alpha} m=${settings.m} ${settings.task}`;
    this.add(label, settings);
    if (!this.title) this.title = 'Your configurations';
    if (this.jobs.length) {
      this.queue(this.arms[this.arms.length - 1]);
      if (this.running) this.fillPool();
    }
  }

  add(label, settings, referenceName = null) {
    if (this.arms.length >= MAX_ARMS) {
      this.onError(`compare: at most ${MAX_ARMS} configurations at once`);
      return;
    }
    const colour = ARM_COLOURS[this.arms.length % ARM_COLOURS.length];
    this.arms.push({ label, settings, colour, runs: new Map(), error: null, referenceName, reference: null });
    this.list();
    this.chart.touch();
  }

  /** Queues a configuration's runs, one per seed. */
  queue(arm) {
    for (const seed of this.seeds()) {
      arm.runs.set(seed, []);
      this.jobs.push(job(arm, seed));
    }
  }

  /** The runs in the order the pool takes them: every configuration's first seed, then the second, ... */
  plan() {
    this.jobs = [];
    for (const arm of this.arms) arm.runs = new Map();
    for (const seed of this.seeds()) {
      for (const arm of this.arms) {
        arm.runs.set(seed, []);
        this.jobs.push(job(arm, seed));
      }
    }
  }

  /** Starts workers up to the pool's size while runs wait. */
  fillPool() {
    if (!this.running) return;
    const waiting = this.jobs.filter((j) => j.state === 'queued').length;
    // A worker without a run is ready for one, or will be when its module has loaded.
    const free = this.pool.filter((p) => !p.job).length;
    const add = Math.min(this.poolSize() - this.pool.length, waiting - free);
    for (let i = 0; i < add; i++) this.spawn();
    for (const p of [...this.pool]) if (p.ready && !p.job) this.assign(p);
    this.list();
  }

  spawn() {
    const w = sameOrigin(import.meta.url) ? new Worker(new URL('./compare-worker.js', import.meta.url), { type: 'module' })
      : importingWorker(new URL('./compare-worker.js', import.meta.url));
    w.postMessage({ type: 'boot', wasm: this.wasm, files: filesForWorker() });
    const p = { worker: w, job: null, ready: false };
    this.pool.push(p);
    w.onmessage = ({ data }) => this.receive(p, data);
    w.onerror = (e) => {
      if (p.job) p.job.arm.error = e.message;
      this.onError(`compare: a worker failed: ${e.message}`);
      this.retire(p);
    };
  }

  /**
   * Gives a worker the waiting run with the fewest episodes (the plan's order among equals), or
   * lets it go when none waits or the pool shrank. The run takes turns while more runs are
   * unfinished than the pool has workers.
   */
  assign(p) {
    const next = nextRun(this.jobs);
    if (!next || this.pool.indexOf(p) >= this.poolSize()) {
      this.retire(p);
      return;
    }
    next.state = 'playing';
    next.turns += 1;
    next.since = performance.now();
    p.job = next;
    // What was played after the checkpoint (a worker lost mid-turn) is played again.
    const episodes = next.arm.runs.get(next.seed);
    if (episodes) episodes.length = next.played;
    const unfinished = this.jobs.filter((j) => j.state !== 'done').length;
    // The page keeps its copy of the checkpoint until the turn's end replaces it.
    p.worker.postMessage({
      type: 'start', settings: next.arm.settings, seed: next.seed, episodes: this.episodes - next.played,
      played: next.played, checkpoint: next.checkpoint, turn: unfinished > this.poolSize() ? this.turnMs : null,
    });
    if (this.running && this.visible) p.worker.postMessage({ type: 'play' });
  }

  /** A run leaves its worker (its turn's end, its horizon, an error, a lost worker). */
  release(job) {
    job.heldMs += performance.now() - job.since;
  }

  retire(p) {
    p.worker.terminate();
    if (p.job?.state === 'playing') {
      this.release(p.job);
      p.job.state = 'queued';
    }
    this.pool = this.pool.filter((q) => q !== p);
    if (this.running && this.jobs.length && this.jobs.every((j) => j.state === 'done')) this.finish();
  }

  receive(p, data) {
    const job = p.job;
    if (data.type === 'file') {
      answerFileRequest(p.worker, data);
    } else if (data.type === 'ready') {
      p.ready = true;
      this.assign(p);
    } else if (data.type === 'started') {
      job.arm.resolved = data.settings; // every setting the arm's runs use, defaults included
      job.checkpoints = data.canCheckpoint;
    } else if (data.type === 'yield') {
      this.release(job);
      job.checkpoint = data.checkpoint;
      job.played = job.arm.runs.get(job.seed)?.length ?? 0;
      job.state = 'queued';
      p.job = null;
      this.assign(p);
    } else if (data.type === 'episodes') {
      job.arm.runs.get(job.seed)?.push(...data.list);
      job.arm.wasmBytes = data.wasmBytes;
      this.chart.touch();
      this.listSoon();
    } else if (data.type === 'done') {
      this.release(job);
      job.state = 'done';
      job.checkpoint = null;
      p.job = null;
      this.assign(p);
      this.list();
    } else if (data.type === 'error') {
      if (job) {
        this.release(job);
        job.arm.error = data.message;
        job.state = 'done'; // not retried: the same configuration fails the same way
        p.job = null;
      }
      this.onError(`${job?.arm.label ?? 'compare'}: ${data.message}`);
      this.assign(p);
      this.list();
    }
  }

  start() {
    if (!this.arms.length) {
      this.onError('compare: add a configuration or pick an experiment first');
      return;
    }
    if (!this.jobs.length || this.jobs.every((j) => j.state === 'done')) {
      const episodes = this.horizon();
      if (episodes == null) return;
      this.episodes = episodes;
      this.plan();
      this.samples = [];
      this.chart.touch();
    }
    this.running = true;
    this.onBusy(true);
    for (const p of this.pool) if (this.visible) p.worker.postMessage({ type: 'play' });
    this.fillPool();
    this.$('compare-run').textContent = 'Pause';
    this.$('compare-seeds').disabled = true;
    this.$('compare-episodes').disabled = true;
    this.list();
  }

  pause() {
    this.running = false;
    for (const p of this.pool) p.worker.postMessage({ type: 'pause' });
    this.$('compare-run').textContent = 'Resume';
    this.onBusy(false);
    this.list();
  }

  /** Every run at its horizon: the pool goes, and the page's run may carry on. */
  finish() {
    this.running = false;
    for (const p of this.pool) p.worker.terminate();
    this.pool = [];
    this.$('compare-run').textContent = 'Start again';
    this.$('compare-seeds').disabled = false;
    this.$('compare-episodes').disabled = false;
    this.onBusy(false);
    this.list();
  }

  /** Off screen or in a hidden tab: the workers pause, and resume after. */
  setVisible(v) {
    this.visible = v;
    if (!this.running) return;
    for (const p of this.pool) p.worker.postMessage({ type: v ? 'play' : 'pause' });
  }

  stop() {
    for (const p of this.pool) p.worker.terminate();
    this.pool = [];
    if (this.running) this.onBusy(false);
    this.running = false;
  }

  clear() {
    this.stop();
    this.arms = [];
    this.jobs = [];
    this.natives = [];
    this.title = '';
    this.caption('', '');
    this.$('compare-reference').textContent = '';
    this.$('compare-run').textContent = 'Start';
    this.$('compare-seeds').disabled = false;
    this.$('compare-episodes').disabled = false;
    this.list();
    this.chart.touch();
  }

  /**
   * The progress line: episodes played of all the runs', the runs at a time, and the time left at
   * the rate of the last half minute.
   */
  progress() {
    if (!this.jobs.length) return '';
    const total = this.jobs.length * this.episodes;
    const done = this.arms.reduce((n, a) => n + played(a), 0);
    const now = performance.now();
    if (this.running) {
      this.samples.push([now, done]);
      while (this.samples.length > 2 && now - this.samples[0][0] > RATE_WINDOW_MS) this.samples.shift();
    }
    const [t0, d0] = this.samples[0] ?? [now, done];
    const rate = now > t0 + 1000 ? ((done - d0) * 1000) / (now - t0) : NaN;
    const runs = this.jobs.filter((j) => j.state === 'done').length;
    const head = `${this.title || 'Comparison'}: ${done.toLocaleString('en')} of ${total.toLocaleString('en')} episodes `
      + `(${Math.floor((100 * done) / total)} %), ${runs} of ${this.jobs.length} runs done`;
    if (runs === this.jobs.length) return `${head}.`;
    if (!this.running) return `${head}; paused.`;
    const playing = this.jobs.filter((j) => j.state === 'playing').length;
    return `${head}; ${playing} playing at once`
      + (rate > 0 ? `, ${Math.round(rate)} episodes/s, about ${duration((total - done) / rate)} left.` : '.');
  }

  /**
   * A preset's caption: its summary in view (two or three sentences: the finding, ours, and what
   * the live runs will show; at most presets.js's SUMMARY_WORDS words, a test checks), the details behind "more".
   */
  caption(summary, details) {
    this.$('compare-caption').textContent = summary;
    this.$('compare-more-text').textContent = details;
    this.$('compare-more').hidden = !details;
  }

  /**
   * What the chart draws: per configuration one array of values per seed, and where its LTM
   * filled (`fill`: the median episode over the seeds whose memory did, for a SEC arm).
   */
  series() {
    const f = METRICS[this.$('compare-metric').value] ?? METRICS.reward;
    const arms = this.arms.filter((a) => a.runs.size).map((a) => ({
      label: a.label, colour: a.colour, runs: [...a.runs.values()].map((eps) => eps.map(f)), fill: liveFill(a, this.agentInfo(a.resolved?.agent)),
    }));
    const metric = this.$('compare-metric').value in METRICS ? this.$('compare-metric').value : 'reward';
    const references = [...this.arms, ...this.natives].filter((a) => a.reference).map((a) => ({
      label: a.label, colour: a.colour, at: a.reference.at, episodes: a.reference.episodes,
      mean: a.reference.metrics[metric].mean, se: a.reference.metrics[metric].se,
      fill: middle((a.referenceFills ?? []).filter((e) => e != null)),
    }));
    return { title: `${this.title}: ${metric} (mean of ${WINDOW} episodes)`, arms, references };
  }

  /** For the CSV export: one entry per configuration and seed. */
  runs() {
    return this.arms.flatMap((a) => [...a.runs].map(([seed, episodes]) => ({ name: a.label, seed, episodes })));
  }

  listSoon() {
    if (this.listTimer) return;
    this.listTimer = setTimeout(() => {
      this.listTimer = null;
      this.list();
    }, 250);
  }

  /** The configurations with their colour, settings and progress, then the reference-only agents. */
  list() {
    this.$('compare-progress').textContent = this.progress();
    const ol = this.$('compare-arms');
    ol.replaceChildren(...this.arms.map((a, i) => {
      const seeds = this.jobs.filter((j) => j.arm === a);
      const done = seeds.filter((j) => j.state === 'done').length;
      const text = a.error ?? (seeds.length
        ? `${played(a).toLocaleString('en')} episodes over ${a.runs.size} seeds, ${done} at ${this.episodes}`
        : 'not started');
      const li = item(a, text);
      if (!this.running) {
        const rm = document.createElement('button');
        rm.type = 'button';
        rm.textContent = '×';
        rm.title = 'Remove';
        rm.addEventListener('click', () => {
          for (const p of this.pool.filter((q) => q.job?.arm === a)) this.retire(p);
          this.jobs = this.jobs.filter((j) => j.arm !== a);
          this.arms.splice(i, 1);
          this.list();
          this.chart.touch();
        });
        li.append(rm);
      }
      return li;
    }), ...this.natives.map((a) => item(a, a.reference
      ? `reference runs only (native): ${size(a.reference)}`
      : 'reference runs still to come')));
  }

  get state() {
    const me = this;
    return {
      get arms() { return me.arms.length; },
      get running() { return me.running; },
      get drawn() { return me.chart.drawn; },
      get episodes() { return me.arms.map(finished); },
      /** The whole caption, and the part in view before "more". */
      get caption() { return `${me.$('compare-caption').textContent} ${me.$('compare-more-text').textContent}`.trim(); },
      get captionShort() { return me.$('compare-caption').textContent; },
      get referenceNote() { return me.$('compare-reference').textContent; },
      /** Each arm's reference runs: {name, seeds, episodes, settings}, or null. */
      get references() {
        return me.arms.map((a) => (a.reference
          ? { name: a.referenceName, seeds: a.reference.seeds.length, episodes: a.reference.episodes, settings: a.reference.settings }
          : null));
      },
      /** The agents shown by their reference runs alone: {label, name, seeds, episodes} (seeds null until loaded). */
      get natives() {
        return me.natives.map((a) => ({
          label: a.label, name: a.referenceName, seeds: a.reference?.seeds.length ?? null, episodes: a.reference?.episodes ?? null,
        }));
      },
      /** Each arm's worker's wasm memory in bytes, as of its last episodes (null before). */
      get wasmBytes() { return me.arms.map((a) => a.wasmBytes ?? null); },
      /**
       * Workers in the pool, and the runs: {label, seed, state, episodes, turns, decisions and
       * reward (summed), checkpoints (whether it can take turns; null before it starts), held
       * (seconds on a worker, pauses included)}.
       */
      get pool() { return me.pool.length; },
      get jobs() {
        return me.jobs.map((j) => {
          const eps = j.arm.runs.get(j.seed) ?? [];
          return { label: j.arm.label, seed: j.seed, state: j.state, episodes: eps.length, turns: j.turns,
            decisions: eps.reduce((n, e) => n + e.decisions, 0), reward: eps.reduce((r, e) => r + e.reward, 0),
            checkpoints: j.checkpoints, held: (j.heldMs + (j.state === 'playing' ? performance.now() - j.since : 0)) / 1000 };
        });
      },
      /** The `i`th run's episodes (`EpisodeMetrics`), as its workers reported them. */
      log(i) { return me.jobs[i] ? [...(me.jobs[i].arm.runs.get(me.jobs[i].seed) ?? [])] : null; },
      get progress() { return me.$('compare-progress').textContent; },
      /** Each arm's settings as its runs use them (null until its worker has started). */
      get resolved() { return me.arms.map((a) => a.resolved ?? null); },
    };
  }
}

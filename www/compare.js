// The comparison panel: several configurations at once, each in its own worker running the
// same seeds, their curves overlaid in one chart with standard-error bands; one-click presets
// for the paper's experiments 1-4.
import { ARM_COLOURS, CompareChart, WINDOW } from './charts.js';
import { COMPARE_PRESETS, PRESET_BASE, exp1In, referenceMap } from './presets.js';

/** Most configurations at once (each is a worker). */
const MAX_ARMS = 8;
const METRICS = { reward: (m) => m.reward, entropy: (m) => m.entropy, decisions: (m) => m.decisions };

let index = null;
/** The reference runs there are (`experiment:condition` names), fetched once. */
/** The reference runs there are, by `experiment:condition` name, with their numbers; fetched once. */
function referenceIndex() {
  index ??= fetch(new URL('../assets/reference/index.json', import.meta.url))
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

export class Compare {
  constructor(root, { current, agentInfo, onError, wasm }) {
    this.root = root;
    this.$ = (id) => root.querySelector(`#${id}`);
    this.current = current;
    /** The agent table's row of a key. */
    this.agentInfo = agentInfo;
    this.onError = onError;
    this.wasm = wasm;
    this.arms = [];
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
      try {
        const r = await fetch(new URL(`../assets/reference/${experiment}/${condition}.json`, import.meta.url));
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
    if (this.running) this.launch(this.arms[this.arms.length - 1]);
  }

  add(label, settings, referenceName = null) {
    if (this.arms.length >= MAX_ARMS) {
      this.onError(`compare: at most ${MAX_ARMS} configurations at once`);
      return;
    }
    const colour = ARM_COLOURS[this.arms.length % ARM_COLOURS.length];
    this.arms.push({ label, settings, colour, worker: null, runs: new Map(), error: null, referenceName, reference: null });
    this.list();
    this.chart.touch();
  }

  launch(arm) {
    const query = new URLSearchParams({ task: arm.settings.task ?? 'double-t-maze' });
    if (this.wasm) query.set('wasm', this.wasm);
    const url = new URL(`./compare-worker.js?${query}`, import.meta.url);
    const w = new Worker(url, { type: 'module' });
    arm.worker = w;
    arm.runs = new Map(this.seeds().map((s) => [s, []]));
    arm.error = null;
    w.onmessage = ({ data }) => {
      if (data.type === 'ready') {
        w.postMessage({ type: 'start', settings: arm.settings, seeds: this.seeds() });
        if (this.running && this.visible) w.postMessage({ type: 'play' });
      } else if (data.type === 'started') {
        arm.resolved = data.settings; // every setting the arm's runs use, defaults included
      } else if (data.type === 'episodes') {
        arm.runs.get(data.seed)?.push(...data.list);
        arm.wasmBytes = data.wasmBytes;
        this.chart.touch();
        this.listSoon();
      } else if (data.type === 'error') {
        arm.error = data.message;
        this.onError(`${arm.label}: ${data.message}`);
        this.list();
      }
    };
    w.onerror = (e) => {
      arm.error = e.message;
      this.onError(`${arm.label}: the worker failed: ${e.message}`);
    };
  }

  start() {
    if (!this.arms.length) {
      this.onError('compare: add a configuration or pick an experiment first');
      return;
    }
    this.running = true;
    for (const arm of this.arms) {
      if (!arm.worker) this.launch(arm);
      else if (this.visible) arm.worker.postMessage({ type: 'play' });
    }
    this.$('compare-run').textContent = 'Pause';
    this.$('compare-seeds').disabled = true;
    this.list();
  }

  pause() {
    this.running = false;
    for (const arm of this.arms) arm.worker?.postMessage({ type: 'pause' });
    this.$('compare-run').textContent = 'Resume';
  }

  /** Off screen or in a hidden tab: the workers pause, and resume after. */
  setVisible(v) {
    this.visible = v;
    if (!this.running) return;
    for (const arm of this.arms) arm.worker?.postMessage({ type: v ? 'play' : 'pause' });
  }

  stop() {
    for (const arm of this.arms) arm.worker?.terminate();
    this.running = false;
  }

  clear() {
    this.stop();
    this.arms = [];
    this.natives = [];
    this.title = '';
    this.caption('', '');
    this.$('compare-reference').textContent = '';
    this.$('compare-run').textContent = 'Start';
    this.$('compare-seeds').disabled = false;
    this.list();
    this.chart.touch();
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

  /** What the chart draws: per configuration one array of values per seed. */
  series() {
    const f = METRICS[this.$('compare-metric').value] ?? METRICS.reward;
    const arms = this.arms.filter((a) => a.runs.size).map((a) => ({
      label: a.label, colour: a.colour, runs: [...a.runs.values()].map((eps) => eps.map(f)),
    }));
    const metric = this.$('compare-metric').value in METRICS ? this.$('compare-metric').value : 'reward';
    const references = [...this.arms, ...this.natives].filter((a) => a.reference).map((a) => ({
      label: a.label, colour: a.colour, at: a.reference.at, episodes: a.reference.episodes,
      mean: a.reference.metrics[metric].mean, se: a.reference.metrics[metric].se,
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
    const ol = this.$('compare-arms');
    ol.replaceChildren(...this.arms.map((a, i) => {
      const done = finished(a);
      const li = item(a, a.error ? a.error : a.runs.size ? `${done} episodes × ${a.runs.size} seeds` : 'not started');
      if (!this.running) {
        const rm = document.createElement('button');
        rm.type = 'button';
        rm.textContent = '×';
        rm.title = 'Remove';
        rm.addEventListener('click', () => {
          a.worker?.terminate();
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
      /** Each arm's settings as its runs use them (null until its worker has started). */
      get resolved() { return me.arms.map((a) => a.resolved ?? null); },
    };
  }
}

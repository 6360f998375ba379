// Live learning curves with uPlot: reward per episode with the paper's 20-episode window, policy
// entropy, decisions per episode, LTM fill and the share of contextual actions. Redrawn at most
// 10 times a second whatever the simulation speed; every parameter change is marked on the x axis.
import uPlot from './vendor/uPlot.esm.min.js';

/** The paper's sliding window (episodes). */
export const WINDOW = 20;
const REDRAW_MS = 100;
/** The width of a chart placed in a slot beside the camera and the action grid. */
const SLOT_WIDTH = 360;
const MARK = '#b3261e';

/** Axes in the page's text colour (readable in dark mode too), with faint grid lines. */
function axes(root) {
  const ink = (root instanceof Element ? getComputedStyle(root).color : '') || '#222';
  const grid = { stroke: 'rgba(128, 128, 128, 0.25)', width: 1 };
  return [{ label: 'episode', size: 36, stroke: ink, grid, ticks: grid }, { stroke: ink, grid, ticks: grid }];
}

/** The mean of the last `WINDOW` values pushed (fewer at the start). */
export class RollingMean {
  constructor() {
    this.clear();
  }

  /** Adds `v`; returns the mean of the window ending with it. */
  push(v) {
    this.window.push(v);
    this.sum += v;
    if (this.window.length > WINDOW) this.sum -= this.window.shift();
    return this.sum / this.window.length;
  }

  clear() {
    this.window = [];
    this.sum = 0;
  }
}

/** What each chart shows: a per-episode value, and whether to add its 20-episode mean. */
const CHARTS = [
  { id: 'reward', title: 'Reward per episode', value: (m) => m.reward, mean: true },
  // As the authors logged it: every decision's, whether memory acted or not (`entropyFresh` is
  // the mean over the decisions where it selected couplets).
  { id: 'entropy', title: "Entropy of memory's vote, bits (all decisions, as the authors logged)", value: (m) => m.entropy, mean: true },
  { id: 'decisions', title: 'Decisions per episode', value: (m) => m.decisions, mean: true },
  { id: 'ltm', title: 'LTM fill (sequences stored)', value: (m) => m.ltm, mean: false },
  { id: 'contextual', title: 'Share of contextual actions', value: (m) => m.contextualShare, mean: true, share: true },
];

/**
 * Axes from the start and fitted to the data: a share spans 0-1; other values start at 0 (or
 * their minimum) with headroom, and all zeros get 0-1, not uPlot's 0-100.
 */
const Y_RANGE = {
  share: () => [0, 1],
  value: (u, min, max) => [Math.min(0, min ?? 0), (max ?? 0) > 0 ? max * 1.1 : 1],
};
const X_RANGE = (u, min, max) => (min == null ? [0, 10] : [min, max > min ? max : min + 1]);

/** A uPlot plugin drawing the parameter changes as dashed lines with a label at the x axis. */
function markPlugin(marks) {
  return {
    hooks: {
      draw: [(u) => {
        const { ctx, bbox } = u;
        const px = devicePixelRatio || 1;
        ctx.save();
        ctx.strokeStyle = MARK;
        ctx.fillStyle = MARK;
        ctx.font = `${10 * px}px system-ui, sans-serif`;
        ctx.setLineDash([4 * px, 3 * px]);
        // Labels never overlap: each goes on the first of a few rows where it fits; when none
        // has room, the last label drawn on the top row counts it ("+1").
        const rows = [];
        const ROWS = 4;
        let merged = null;
        for (const m of marks) {
          const x = u.valToPos(m.episode, 'x', true);
          if (!(x >= bbox.left && x <= bbox.left + bbox.width)) continue;
          ctx.beginPath();
          ctx.moveTo(x, bbox.top);
          ctx.lineTo(x, bbox.top + bbox.height);
          ctx.stroke();
          // A triangle on the x axis and the change's label.
          ctx.beginPath();
          ctx.moveTo(x, bbox.top + bbox.height);
          ctx.lineTo(x - 4 * px, bbox.top + bbox.height + 6 * px);
          ctx.lineTo(x + 4 * px, bbox.top + bbox.height + 6 * px);
          ctx.fill();
          const w = ctx.measureText(m.label).width + 6 * px;
          let row = rows.findIndex((end) => end <= x);
          if (row < 0 && rows.length < ROWS) row = rows.length;
          if (row < 0) {
            merged = merged ?? { x: rows[0], n: 0 };
            merged.n += 1;
            continue;
          }
          rows[row] = x + w;
          // Right of its line, or left of it where the plot ends first.
          const right = x + w <= bbox.left + bbox.width;
          ctx.textAlign = right ? 'left' : 'right';
          ctx.fillText(m.label, right ? x + 3 * px : x - 3 * px, bbox.top + (11 + 12 * row) * px);
        }
        ctx.textAlign = 'left';
        if (merged) ctx.fillText(`+${merged.n} more`, merged.x, bbox.top + 11 * px);
        ctx.restore();
      }],
    },
  };
}

/**
 * The learning-curve panel in `root`; a chart whose id is a key of `slots` goes into that element
 * instead (the reward curve sits beside the camera, on the first screen).
 */
export class Charts {
  constructor(root, slots = {}) {
    this.root = root;
    this.marks = [];
    this.episodes = [];
    this.columns = CHARTS.map(() => ({ values: [], means: [], rolling: new RollingMean() }));
    this.dirty = false;
    const width = Math.max(300, Math.min(560, Math.floor((root.clientWidth || 900) / 2) - 16));
    // The scheme's curve colours (style.css), read once: a page does not switch scheme mid-run.
    const css = root instanceof Element ? getComputedStyle(root) : null;
    const colour = (name, fallback) => css?.getPropertyValue(name).trim() || fallback;
    const episodeColour = colour('--chart-episode', '#4a8fc9');
    const meanColour = colour('--chart-mean', '#1d4ed8');
    this.plots = CHARTS.map((c) => {
      const box = document.createElement('figure');
      box.className = 'chart';
      box.dataset.chart = c.id;
      (slots[c.id] ?? root).append(box);
      const series = [
        { label: 'episode' },
        { label: c.mean ? 'per episode' : c.title, stroke: c.mean ? episodeColour : meanColour, width: 1,
          points: { show: false } },
      ];
      if (c.mean) series.push({ label: `mean of ${WINDOW}`, stroke: meanColour, width: 2, points: { show: false } });
      return new uPlot({
        title: c.title,
        width: slots[c.id] ? Math.min(width, SLOT_WIDTH) : width,
        height: 170,
        scales: { x: { time: false, range: X_RANGE }, y: { range: c.share ? Y_RANGE.share : Y_RANGE.value } },
        axes: axes(this.root),
        legend: { live: false },
        series,
        plugins: [markPlugin(this.marks)],
      }, this.data(0), box);
    });
    this.timer = setInterval(() => this.redraw(), REDRAW_MS);
  }

  data(k) {
    const col = this.columns[k];
    return CHARTS[k].mean ? [this.episodes, col.values, col.means] : [this.episodes, col.values];
  }

  /** Adds finished episodes (`EpisodeMetrics[]`). */
  push(list) {
    for (const m of list) {
      this.episodes.push(m.episode);
      CHARTS.forEach((c, k) => {
        const col = this.columns[k];
        const v = c.value(m);
        col.values.push(v);
        col.means.push(col.rolling.push(v));
      });
    }
    this.dirty ||= list.length > 0;
  }

  /** Marks a parameter change at the current episode. */
  mark(label) {
    const episode = this.episodes.length ? this.episodes[this.episodes.length - 1] + 0.5 : 0;
    this.marks.push({ episode, label });
    this.dirty = true;
  }

  /** Forgets everything (a new run). */
  clear() {
    this.episodes.length = 0;
    this.marks.length = 0;
    for (const col of this.columns) {
      col.values.length = 0;
      col.means.length = 0;
      col.rolling.clear();
    }
    this.dirty = true;
  }

  /** Each chart's y axis as drawn, [min, max] by chart id. */
  ranges() {
    return Object.fromEntries(this.plots.map((u, k) => [CHARTS[k].id, [u.scales.y.min, u.scales.y.max]]));
  }

  redraw() {
    if (!this.dirty) return;
    this.dirty = false;
    this.plots.forEach((u, k) => u.setData(this.data(k)));
  }

  destroy() {
    clearInterval(this.timer);
    for (const u of this.plots) u.destroy();
  }
}

/** Colours of compared configurations (Okabe-Ito, readable by colour-blind viewers). */
export const ARM_COLOURS = ['#0072b2', '#d55e00', '#009e73', '#cc79a7', '#e69f00', '#56b4e9', '#000000', '#f0e442'];

/** `#rrggbb` at opacity `a`. */
function rgba(hex, a) {
  const n = parseInt(hex.slice(1), 16);
  return `rgba(${n >> 16}, ${(n >> 8) & 255}, ${n & 255}, ${a})`;
}

/** Values at every episode 0..n-1 from samples `v` at episodes `at` (ascending), linearly between. */
export function interpolate(at, v, n) {
  const out = new Array(n);
  let k = 0;
  for (let i = 0; i < n; i++) {
    while (k + 1 < at.length && at[k + 1] <= i) k++;
    if (k + 1 >= at.length || at[k] >= i) out[i] = v[k];
    else out[i] = v[k] + ((v[k + 1] - v[k]) * (i - at[k])) / (at[k + 1] - at[k]);
  }
  return out;
}

/**
 * Mean and standard error across seeds of the 20-episode sliding mean, per episode, over the
 * seeds that have played it (a comparison's pool plays its runs one after another); at the
 * episodes `at` only, if given (the chart's drawn points). `runs`: one array of per-episode values
 * per seed. `n` is how many seeds each point has.
 */
export function meanAndError(runs, at = null) {
  const smooth = runs.filter((v) => v.length).map((v) => {
    const rolling = new RollingMean();
    return v.map((x) => rolling.push(x));
  });
  const len = Math.max(0, ...smooth.map((s) => s.length));
  const points = at ?? Array.from({ length: len }, (_, i) => i);
  const mean = [];
  const se = [];
  const n = [];
  for (const i of points) {
    if (i >= len) break;
    const xs = smooth.filter((s) => i < s.length).map((s) => s[i]);
    const m = xs.reduce((a, b) => a + b, 0) / xs.length;
    const v = xs.length > 1 ? xs.reduce((a, b) => a + (b - m) ** 2, 0) / (xs.length - 1) : 0;
    mean.push(m);
    se.push(Math.sqrt(v / xs.length));
    n.push(xs.length);
  }
  return { mean, se, n, len };
}

/** Most points a comparison line draws: about one per pixel of the widest chart. */
export const MAX_POINTS = 1200;

/** The episodes drawn of `len`: all, or every k-th and the last, at most about `most`. */
export function drawnEpisodes(len, most = MAX_POINTS) {
  const stride = Math.max(1, Math.ceil(len / most));
  const at = [];
  for (let i = 0; i < len; i += stride) at.push(i);
  if (len && at[at.length - 1] !== len - 1) at.push(len - 1);
  return at;
}

/**
 * The comparison chart: per configuration its mean curve, and with two or more seeds a band of
 * ± one standard error. Redrawn at most 10 times a second.
 */
export class CompareChart {
  constructor(root) {
    this.root = root;
    this.plot = null;
    this.shape = '';
    this.dirty = false;
    this.drawn = { series: 0, bands: 0, episodes: 0, references: 0, liveAtFirstReference: null, x: null };
    this.source = () => ({ title: '', arms: [], references: [] });
    // The x axis follows the live runs unless `full` (the reference runs' whole length) or the
    // user zoomed (drag across the chart: the range, kept until `resetZoom`).
    this.full = false;
    this.zoomed = null;
    /** Most points per line (`MAX_POINTS`; the benchmark compares it with every episode). */
    this.maxPoints = MAX_POINTS;
    this.timer = setInterval(() => this.redraw(), REDRAW_MS);
  }

  /** Shows the reference runs' full length (true) or follows the live runs (false). */
  setFull(full) {
    this.full = full;
    this.zoomed = null;
    this.dirty = true;
  }

  resetZoom() {
    this.zoomed = null;
    this.dirty = true;
  }

  /**
   * `source()` gives {title, arms: [{label, colour, runs: number[][]}], references: [{label, colour,
   * at: number[], mean: number[], se: number[], episodes}]}: the live runs per seed, and the
   * reference runs' curve sampled at episodes `at` (drawn faint, interpolated in between).
   */
  watch(source) {
    this.source = source;
    this.dirty = true;
  }

  touch() {
    this.dirty = true;
  }

  /** A new comparison: what was drawn is forgotten. */
  reset() {
    this.drawn = { series: 0, bands: 0, episodes: 0, references: 0, liveAtFirstReference: null };
    this.dirty = true;
  }

  redraw() {
    if (!this.dirty) return;
    this.dirty = false;
    const { title, arms, references = [] } = this.source();
    if (!arms.length && !references.length) {
      this.plot?.destroy();
      this.plot = null;
      this.shape = '';
      this.drawn = { series: 0, bands: 0, episodes: 0, references: 0, liveAtFirstReference: null };
      return;
    }
    // Drawn at most MAX_POINTS episodes per line (the CSV keeps every one).
    const live = Math.max(0, ...arms.flatMap((a) => a.runs.map((r) => r.length)));
    const len = Math.max(live, ...references.map((r) => r.episodes));
    const x = drawnEpisodes(len, this.maxPoints);
    const stats = arms.map((a) => ({ ...a, banded: a.runs.filter((r) => r.length).length > 1, ...meanAndError(a.runs, x) }));
    // A line's values at the drawn episodes: `v` per drawn point (the live runs') or per episode.
    const pad = (v, perEpisode = false) => x.map((i, k) => (perEpisode ? v[i] : v[k]) ?? null);
    const data = [x];
    const series = [{ label: 'episode' }];
    const bands = [];
    // Where each line's LTM filled: ○ on a reference line, ● on a live one.
    const marks = [];
    const mark = (fill, index, colour, live) => { if (fill != null && fill < len) marks.push({ fill, index, colour, live }); };
    // The reference runs first, faint, so the live curves draw over them.
    for (const r of references) {
      const mean = interpolate(r.at, r.mean, r.episodes);
      const se = interpolate(r.at, r.se, r.episodes);
      const hi = series.length;
      data.push(pad(mean.map((m, i) => m + se[i]), true), pad(mean.map((m, i) => m - se[i]), true), pad(mean, true));
      mark(r.fill, hi + 2, r.colour, false);
      series.push({ label: `${r.label} reference +SE`, stroke: rgba(r.colour, 0.12), width: 1, points: { show: false } },
        { label: `${r.label} reference −SE`, stroke: rgba(r.colour, 0.12), width: 1, points: { show: false } },
        { label: `${r.label} reference`, stroke: rgba(r.colour, 0.55), width: 1, dash: [4, 3], points: { show: false } });
      bands.push({ series: [hi, hi + 1], fill: rgba(r.colour, 0.1) });
    }
    let banded = bands.length;
    for (const s of stats) {
      mark(s.fill, data.length, s.colour, true);
      data.push(pad(s.mean));
      series.push({ label: s.label, stroke: s.colour, width: 2, points: { show: false } });
      // Every arm has its band's lines, empty until a second run has episodes: the chart's
      // series stay the same as runs start, so it is not rebuilt under a user's drag.
      const hi = series.length;
      const none = x.map(() => null);
      data.push(s.banded ? pad(s.mean.map((m, i) => m + s.se[i])) : none, s.banded ? pad(s.mean.map((m, i) => m - s.se[i])) : none);
      series.push({ label: `${s.label} +SE`, stroke: rgba(s.colour, 0.25), width: 1, points: { show: false } },
        { label: `${s.label} −SE`, stroke: rgba(s.colour, 0.25), width: 1, points: { show: false } });
      bands.push({ series: [hi, hi + 1], fill: rgba(s.colour, 0.18) });
      if (s.banded) banded++;
    }
    this.marks = marks;
    const shape = `${title}|${series.map((s) => s.label).join('|')}`;
    if (shape !== this.shape || !this.plot) {
      this.plot?.destroy();
      this.shape = shape;
      const width = Math.max(320, Math.min(1100, (this.root.clientWidth || 900) - 8));
      this.plot = new uPlot({
        title,
        width,
        height: 260,
        scales: { x: { time: false, auto: false }, y: { range: (u, min, max) => [Math.min(0, min), max > 0 ? max * 1.1 : 1] } },
        axes: axes(this.root),
        legend: { show: false },
        series,
        bands,
        // A drag across the chart selects a range and zooms to it.
        hooks: {
          draw: [(u) => this.drawMarks(u)],
          setSelect: [(u) => {
            if (u.select.width > 0) {
              this.zoomed = [u.posToVal(u.select.left, 'x'), u.posToVal(u.select.left + u.select.width, 'x')];
            }
          }],
        },
      }, data, this.root);
    } else {
      this.plot.setData(data);
    }
    // The live runs' episodes with room to grow (a quarter more, at least 20), or everything.
    // setData re-ranges every axis: put x back where it belongs (a zoom stays until reset).
    if (this.zoomed) {
      this.plot.setScale('x', { min: this.zoomed[0], max: this.zoomed[1] });
    } else {
      const target = this.full || !live ? len : Math.min(len, Math.max(20, Math.ceil(live * 1.25)));
      this.plot.setScale('x', { min: 0, max: Math.max(1, target - 1) });
    }
    const liveAtFirstReference = this.drawn.liveAtFirstReference
      ?? (references.length ? stats.reduce((n, s) => n + s.len, 0) : null);
    this.drawn = {
      series: stats.length, bands: banded, episodes: len, references: references.length, liveAtFirstReference,
      live, x: [this.plot.scales.x.min, this.plot.scales.x.max], points: x.length,
      fills: marks.map((m) => ({ episode: m.fill, live: m.live })),
    };
  }

  /** The fill marks, on their lines at the drawn point nearest their episode. */
  drawMarks(u) {
    const ctx = u.ctx;
    const xs = u.data[0];
    for (const m of this.marks ?? []) {
      let k = 0;
      while (k + 1 < xs.length && xs[k + 1] <= m.fill) k++;
      const v = u.data[m.index]?.[k];
      if (v == null || m.fill < u.scales.x.min || m.fill > u.scales.x.max) continue;
      const px = u.valToPos(m.fill, 'x', true);
      const py = u.valToPos(v, 'y', true);
      ctx.save();
      ctx.beginPath();
      ctx.arc(px, py, 5 * devicePixelRatio, 0, 2 * Math.PI);
      ctx.lineWidth = 2 * devicePixelRatio;
      ctx.strokeStyle = m.colour;
      if (m.live) {
        ctx.fillStyle = m.colour;
        ctx.fill();
      } else {
        ctx.stroke();
      }
      ctx.restore();
    }
  }

  destroy() {
    clearInterval(this.timer);
    this.plot?.destroy();
  }
}

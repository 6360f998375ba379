// The playground page: starts the simulation worker, builds the controls from the core's
// parameter table, keeps the whole configuration in the URL hash, and draws what the worker
// posts (views at most 30 times a second, charts at most 10).
import { buildControls, runControls, SPEEDS } from './controls.js';
import { Charts } from './charts.js';
import { drawRgba, drawHeat, drawProbs, drawStatus } from './views.js';

const $ = (id) => document.getElementById(id);
let worker = null;
let fatal = false; // the simulation trapped: a reset starts a fresh worker

let params = [];
let settings = null;
let controls = null;
let playing = false;
let wantPlay = true; // the user's intent; visibility pauses without changing it
let speed = SPEEDS[Number($('speed').value)];
let episodes = 0;
let lastView = null;
const charts = new Charts($('charts'));
const rate = { t: performance.now(), decisions: 0, perSecond: 0 };

function showError(message) {
  const el = $('error');
  el.textContent = message ?? '';
  el.hidden = !message;
}

function notice(text) {
  $('notice').textContent = text;
}

/** The hash as settings: `#alpha=0.01&m=500` gives {alpha: '0.01', m: '500'}. */
function readHash() {
  return Object.fromEntries(new URLSearchParams(location.hash.slice(1)));
}

function writeHash() {
  const hash = `#${new URLSearchParams(settings)}`;
  if (location.hash !== hash) history.replaceState(null, '', hash);
}

const send = (msg) => worker.postMessage(msg);

/** A fresh simulation worker; with `settings` it carries on with them (after a fatal error). */
function startWorker() {
  worker?.terminate();
  fatal = false;
  worker = new Worker(new URL('./worker.js', import.meta.url), { type: 'module' });
  worker.onmessage = ({ data }) => handlers[data.type]?.(data);
  worker.onerror = (e) => showError(`The simulation worker failed: ${e.message}`);
}

function views() {
  const watching = speed !== 'max' && !document.hidden;
  send({ type: 'views', camera: watching, heat: watching ? $('heat-kind').value : null });
}

function setPlaying(p) {
  wantPlay = p;
  send({ type: p && !document.hidden ? 'play' : 'pause' });
}

const label = (key) => params.find((p) => p.key === key)?.symbol ?? key;

const handlers = {
  ready(msg) {
    params = msg.params;
    controls ??= buildControls($('controls'), params, (key, value) => {
      if (settings?.[key] !== value) send({ type: 'set', changes: { [key]: value } });
    });
    send({ type: 'speed', value: speed });
    send({ type: 'start', settings: settings ?? readHash() });
    views();
  },
  started(msg) {
    const first = settings === null;
    settings = msg.settings;
    controls.set(settings);
    writeHash();
    if (msg.errors.length) showError(`${msg.errors.join('; ')}. Using the default for ${msg.errors.length === 1 ? 'it' : 'them'}.`);
    else if (!first) showError(null);
    if (msg.mode === 'restart') {
      charts.clear();
      episodes = 0;
      if (!first) notice(msg.changes ? `New run: ${Object.keys(msg.changes).map(label).join(', ')} changed` : 'Run reset');
    } else if (msg.changes) {
      const what = Object.entries(msg.changes).map(([k, v]) => `${label(k)}=${v}`).join(' ');
      charts.mark(what);
      notice(`Applied live: ${what}`);
    }
    if (first || msg.fresh) setPlaying(wantPlay);
  },
  episodes({ list }) {
    charts.push(list);
    episodes += list.length;
    for (const m of list) rate.decisions += m.decisions;
  },
  view(msg) {
    lastView = msg.view;
    if (msg.camera) {
      drawRgba($('camera'), new Uint8Array(msg.camera), 84, 84);
      drawRgba($('reconstruction'), new Uint8Array(msg.reconstruction), 84, 84);
      drawRgba($('arena'), new Uint8Array(msg.top), 252, 252);
    }
    if (msg.heat) drawHeat($('heat'), new Float32Array(msg.heat), msg.n, new Uint32Array(msg.selected), $('heat-kind').value);
    const v = msg.view;
    drawProbs($('probs'), v.p, v.action);
    $('entropy').textContent = `${v.entropy.toFixed(3)} bits`;
    $('entropy-meter').value = v.entropy;
    $('layer').textContent = v.layer === 'C' ? 'contextual (memory)' : v.layer === 'R' ? 'reactive (random walk)' : '–';
    status();
  },
  state(msg) {
    playing = msg.playing;
    $('play').textContent = playing ? 'Pause' : 'Play';
    document.body.dataset.playing = playing;
  },
  error(msg) {
    showError(msg.message);
    fatal ||= msg.fatal;
    // A refused value: show the settings still in force.
    if (settings && controls) controls.set(settings);
  },
};

function status() {
  const v = lastView;
  if (!v) return;
  const now = performance.now();
  if (now - rate.t > 1000) {
    rate.perSecond = (rate.decisions * 1000) / (now - rate.t);
    rate.t = now;
    rate.decisions = 0;
  }
  drawStatus($('status'), [
    ['episode', String(v.episode)],
    ['env step', String(v.step)],
    ['reward', v.episodeReward.toFixed(3)],
    ['LTM', v.capacity ? `${v.ltm} / ${v.capacity}` : '–'],
    ['decisions/s', rate.perSecond ? rate.perSecond.toFixed(0) : '–'],
  ]);
}

startWorker();

runControls($, {
  toggle: () => setPlaying(!wantPlay),
  step: (what) => { wantPlay = false; send({ type: 'step', what }); },
  reset: () => (fatal ? startWorker() : send({ type: 'reset' })),
  preset: (name) => send({ type: 'preset', name }),
  speed: (v) => { speed = v; send({ type: 'speed', value: v }); views(); },
});
$('heat-kind').addEventListener('change', views);

// Someone edits the link: apply what changed (validated by the core like any control).
window.addEventListener('hashchange', () => {
  if (!settings) return;
  const next = readHash();
  const changes = Object.fromEntries(Object.entries(next).filter(([k, v]) => settings[k] !== v));
  if (Object.keys(changes).length) send({ type: 'set', changes });
});

// Pause while the tab is hidden; carry on when it is back.
document.addEventListener('visibilitychange', () => {
  send({ type: wantPlay && !document.hidden ? 'play' : 'pause' });
  views();
});

// For tests and the curious: the page's state.
window.secPlayground = {
  get settings() { return settings; },
  get episodes() { return episodes; },
  get playing() { return playing; },
  get marks() { return charts.marks; },
  get points() { return charts.episodes.length; },
  get view() { return lastView; },
  /** Test hook: makes the simulation panic. */
  crash() { send({ type: 'crash' }); },
};

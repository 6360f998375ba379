// The iframe's side of the host protocol (docs/EMBED.md): events to the page that frames
// embed.html, and commands from it. Every message is `{protocol: 'sec-playground', version, type,
// ...}`. Only the parent window is listened to, and only at one origin: the one `?origin=` names,
// or, without it, the origin of the parent's first `connect`. Events go to that origin alone,
// never to `*`, and a message from anywhere else changes nothing.
import { API_VERSION } from './playground.js';

export const PROTOCOL = 'sec-playground';

/** The commands, each `(playground, message) => value` (or a promise of it). */
const COMMANDS = {
  connect: (pg) => ({ version: API_VERSION, settings: pg.getState().settings }),
  play: (pg) => pg.play(),
  pause: (pg) => pg.pause(),
  reset: (pg) => pg.reset(),
  step: (pg, m) => pg.step(m.what ?? 'decision'),
  configure: (pg, m) => pg.configure(m.settings),
  getState: (pg) => pg.getState(),
  getMetrics: (pg, m) => pg.getMetrics(m.format ?? 'rows'),
  saveMemory: (pg) => pg.saveMemory(),
  loadMemory: (pg, m) => pg.loadMemory(m.bytes),
};

/** `value` if it is an origin (scheme, host and port, as `https://example.org`), else null. */
function asOrigin(value) {
  try {
    const o = new URL(value).origin;
    return o !== 'null' && o === value.replace(/\/$/, '') ? o : null;
  } catch {
    return null;
  }
}

/**
 * Serves the protocol for `pg` to `window.parent`. `origin`: the `?origin=` parameter, or null
 * (then the first `connect` from the parent names it). A bad `origin` is shown as the
 * playground's error and nothing is answered. Returns `{height(h)}`, which sends the page's
 * height to the host (again on connect), or null when there is no host to serve.
 */
export function serveHost(pg, origin) {
  if (window.parent === window) return null;
  let peer = null;
  if (origin != null) {
    peer = asOrigin(origin);
    if (!peer) {
      pg.showError(`origin: '${origin}' is not an origin like https://example.org (scheme, host and port only); this playground answers no host page`);
      return null;
    }
  }
  let ready = null; // the ready event's detail, once the run has started
  let height = null;
  const post = (msg, transfer = []) => {
    if (peer) window.parent.postMessage({ protocol: PROTOCOL, version: API_VERSION, ...msg }, peer, transfer);
  };
  pg.on('ready', (d) => {
    ready = d;
    post({ type: 'ready', ...d });
  });
  pg.on('episode', (row) => post({ type: 'episode', row }));
  pg.on('state', (s) => post({ type: 'state', playing: s.playing, running: s.running, decisions: s.decisions, episode: s.episode }));
  pg.on('error', ({ message }) => post({ type: 'error', message }));

  window.addEventListener('message', async (e) => {
    const m = e.data;
    if (e.source !== window.parent || m?.protocol !== PROTOCOL) return; // not for us
    if (peer === null) {
      // Not connected yet: only a connect names the host, and only one that can be answered.
      if (m.type !== 'connect' || e.origin === 'null') return;
      peer = e.origin;
    }
    if (e.origin !== peer) {
      console.warn(`sec-playground: a message from ${e.origin} was ignored: this playground answers ${peer} only`);
      return;
    }
    const reply = (msg, transfer) => post({ id: m.id ?? null, ...msg }, transfer);
    if (m.version !== API_VERSION) {
      reply({ type: 'error', message: `version: ${JSON.stringify(m.version)} is not supported; this playground speaks version ${API_VERSION}` });
      return;
    }
    const command = Object.hasOwn(COMMANDS, m.type) ? COMMANDS[m.type] : null;
    if (!command) {
      reply({ type: 'error', message: `type: unknown message type ${JSON.stringify(m.type)} (known: ${Object.keys(COMMANDS).join(', ')})` });
      return;
    }
    try {
      const value = await command(pg, m);
      reply({ type: 'result', command: m.type, value }, value instanceof ArrayBuffer ? [value] : []);
      if (m.type === 'connect') {
        if (ready) post({ type: 'ready', ...ready });
        if (height != null) post({ type: 'height', height });
      }
    } catch (err) {
      reply({ type: 'error', command: m.type, message: String(err?.message ?? err) });
    }
  });
  return {
    height(h) {
      height = h;
      post({ type: 'height', height });
    },
  };
}

// A host page's side of the iframe protocol (docs/EMBED.md), for pages that may run scripts:
//
//   import { connect } from 'https://example.org/sec-playground/www/embed-host.js';
//   const pg = connect(document.querySelector('iframe'));
//   pg.on('episode', (row) => console.log(row.episode, row.reward));
//   await pg.ready;
//   await pg.command('configure', { settings: { alpha: 0.05 } });
//   await pg.command('play');
//
// Any page can speak the protocol with postMessage alone; this is a convenience.

export const PROTOCOL = 'sec-playground';
export const VERSION = 1;

/**
 * Connects to the playground in `iframe` (embed.html). Its origin is the iframe's `src`'s unless
 * `origin` is given; a frame sandboxed without allow-same-origin answers from the opaque origin
 * 'null', which is accepted only from that iframe's own window. Returns `{ready, command, on,
 * close}`: `ready` resolves with the ready event's `{version, settings}`, `command(type,
 * payload)` with the command's value (it rejects with the playground's error message), `on(type,
 * f)` calls `f(payload)` for each event (ready, episode, state, error, height).
 */
export function connect(iframe, { origin = new URL(iframe.src, location.href).origin } = {}) {
  const listeners = new Map();
  const pending = new Map();
  let next = 1;
  let readyOk;
  const ready = new Promise((ok) => { readyOk = ok; });
  const sandboxed = iframe.sandbox.length > 0 && !iframe.sandbox.contains('allow-same-origin');
  const send = (msg) => iframe.contentWindow?.postMessage({ protocol: PROTOCOL, version: VERSION, ...msg }, sandboxed ? '*' : origin);
  const onMessage = (e) => {
    const m = e.data;
    if (e.source !== iframe.contentWindow || m?.protocol !== PROTOCOL) return;
    if (e.origin !== origin && !(sandboxed && e.origin === 'null')) return;
    if ((m.type === 'result' || m.type === 'error') && pending.has(m.id)) {
      const { ok, fail } = pending.get(m.id);
      pending.delete(m.id);
      if (m.type === 'result') ok(m.value);
      else fail(new Error(m.message));
      return;
    }
    if (m.type === 'ready') readyOk({ version: m.version, settings: m.settings });
    const { protocol, version, type, ...payload } = m;
    for (const f of listeners.get(type) ?? []) f(type === 'episode' ? m.row : payload);
  };
  window.addEventListener('message', onMessage);
  const command = (type, payload = {}) => new Promise((ok, fail) => {
    const id = next++;
    pending.set(id, { ok, fail });
    send({ type, id, ...payload });
  });
  // The frame listens once its module has run, which is before its load event: connect then
  // (and now, in case it has loaded already; a second connect is answered again).
  iframe.addEventListener('load', () => command('connect').catch(() => {}));
  command('connect').catch(() => {});
  return {
    ready,
    command,
    on(type, f) {
      if (!listeners.has(type)) listeners.set(type, []);
      listeners.get(type).push(f);
      return () => listeners.set(type, listeners.get(type).filter((g) => g !== f));
    },
    close() {
      window.removeEventListener('message', onMessage);
    },
  };
}

// Starting the simulation's module workers from any page. Each is started where its module is
// addressed as `new Worker(new URL('./x.js', import.meta.url), {type: 'module'})`, the form
// bundlers (Vite) recognise and bundle; this module decides when that cannot work.

/**
 * Whether this page may start a worker from `url` (the starting module's address) itself: only
 * from its own origin. A page on another origin than the modules (the element loaded from a CDN)
 * or an opaque one (an iframe sandboxed without allow-same-origin) may not. A module a notebook
 * loaded from a `blob:` address has the notebook's origin, and its bundler inlined the workers.
 */
export function sameOrigin(url) {
  return self.origin !== 'null' && new URL(url).origin === self.origin;
}

/**
 * A module worker started from a `data:` address whose one line imports `url`: the worker then
 * loads its modules, the wasm and the models across origins, which their server must allow
 * (`Access-Control-Allow-Origin`, as CDNs and GitHub Pages send; docs/EMBED.md). (Not a blob: a
 * blob made by an opaque page cannot be fetched as a worker's script.)
 */
export function importingWorker(url) {
  // Messages that come while the module loads wait for its handler.
  const source = `const early = []; self.onmessage = (e) => early.push(e);
    await import(${JSON.stringify(String(url))});
    for (const e of early) self.onmessage(e);`;
  return new Worker(`data:text/javascript,${encodeURIComponent(source)}`, { type: 'module' });
}

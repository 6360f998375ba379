// <sec-playground>: the playground as a custom element for course pages. Its attributes are the
// URL hash's keys (task, alpha, m, seed...) in any case or kebab form (HTML lowercases them; the
// core resolves `startheading` and `start-heading` to `startHeading` from its own table), plus
// `hide="key key ..."` (settings or sections a teacher hides: runbar, keepbar, controls, views,
// charts, compare) and `autoplay`. Each element
// has its own shadow root, worker and keyboard focus, so several on one page do not interfere;
// one that is scrolled off screen pauses.
//
//   <script type="module" src="sec-playground/www/element.js"></script>
//   <sec-playground task="double-t-maze" alpha="0.05" hide="compare keepbar" autoplay>
//     <p>Serve this page over HTTP (python3 -m http.server) to see the playground.</p>
//   </sec-playground>
//
// What is inside the tag shows only until the element starts (its shadow root has no slot): a
// page opened from disk, where browsers load no modules, shows it instead of nothing.
//
// Script drives it as a host page drives the iframe (docs/EMBED.md): the methods play, pause,
// reset, step, configure, getState, getMetrics, saveMemory and loadMemory, and the events
// `ready`, `episode`, `state` and `error` (CustomEvents whose `detail` is the protocol's payload).
import { Playground } from './playground.js';
import { fetchFile, filesProvided } from './files.js';

const EVENTS = ['ready', 'episode', 'state', 'error', 'settings', 'run', 'explanation'];
const OWN = new Set(['hide', 'autoplay', 'class', 'style', 'id', 'tabindex', 'title', 'lang', 'dir']);
/** The style sheets, each a literal `new URL(..., import.meta.url)` so that a bundler (Vite)
 * copies the file (a function: a module loaded from a string has no address to resolve them by). */
const CSS = () => [new URL('./vendor/uPlot.min.css', import.meta.url).href, new URL('./style.css', import.meta.url).href];
/** The same, as paths in the package, where the files are provided (files.js). */
const CSS_FILES = ['www/vendor/uPlot.min.css', 'www/style.css'];

class SecPlaygroundElement extends HTMLElement {
  connectedCallback() {
    if (this.playground) return;
    const root = this.shadowRoot ?? this.attachShadow({ mode: 'open' });
    if (filesProvided()) {
      for (const path of CSS_FILES) {
        const style = document.createElement('style');
        root.append(style);
        fetchFile(path).then((r) => (r.ok ? r.text() : '')).then((text) => { style.textContent = text; });
      }
    } else {
      for (const href of CSS()) {
        const link = document.createElement('link');
        link.rel = 'stylesheet';
        link.href = href;
        root.append(link);
      }
    }
    if (!this.hasAttribute('tabindex')) this.tabIndex = 0; // focus takes the keyboard shortcuts
    this.playground = new Playground(root, {
      settings: this.settingsFromAttributes(),
      autoplay: this.hasAttribute('autoplay'),
      hide: this.hideList(),
      keys: this,
    });
    for (const type of EVENTS) {
      this.playground.on(type, (detail) => this.dispatchEvent(new CustomEvent(type, { detail })));
    }
    this.observer = new IntersectionObserver((entries) => {
      for (const e of entries) this.playground.setOnScreen(e.isIntersecting);
    });
    this.observer.observe(this);
    // Only the attributes that changed: one refused earlier must not block the later ones.
    this.attributes$ = new MutationObserver((records) => {
      const changed = new Set(records.map((r) => r.attributeName));
      if (changed.has('hide')) this.playground.setHidden(this.hideList());
      const all = this.settingsFromAttributes();
      const keys = Object.keys(all).filter((name) => changed.has(name));
      if (keys.length) this.playground.set(Object.fromEntries(keys.map((k) => [k, all[k]])));
    });
    this.attributes$.observe(this, { attributes: true });
  }

  disconnectedCallback() {
    // Moved within the page: keep running; removed: stop the workers.
    queueMicrotask(() => {
      if (this.isConnected || !this.playground) return;
      this.observer.disconnect();
      this.attributes$.disconnect();
      this.playground.destroy();
      this.playground = null;
      this.shadowRoot.replaceChildren();
    });
  }

  /** The `hide` attribute's parts and keys. */
  hideList() {
    return (this.getAttribute('hide') ?? '').split(/[\s,]+/).filter(Boolean);
  }

  settingsFromAttributes() {
    return Object.fromEntries([...this.attributes].filter((a) => !OWN.has(a.name) && !a.name.startsWith('data-')
      && !a.name.startsWith('aria-')).map((a) => [a.name, a.value]));
  }

  /** The playground's state (settings, episodes, playing...), as `window.secPlayground` on the page. */
  get state() {
    return this.playground?.state;
  }

  /** The playground, or an error naming the call when the element is not on a page. */
  api(name) {
    if (!this.playground) throw new Error(`${name}: the <sec-playground> element is not on a page`);
    return this.playground;
  }

  play() { return this.api('play').play(); }

  pause() { return this.api('pause').pause(); }

  reset() { return this.api('reset').reset(); }

  step(what = 'decision') { return this.api('step').step(what); }

  configure(settings) { return this.api('configure').configure(settings); }

  getState() { return this.api('getState').getState(); }

  getMetrics(format = 'rows') { return this.api('getMetrics').getMetrics(format); }

  saveMemory() { return this.api('saveMemory').saveMemory(); }

  loadMemory(bytes) { return this.api('loadMemory').loadMemory(bytes); }
}

if (!customElements.get('sec-playground')) customElements.define('sec-playground', SecPlaygroundElement);

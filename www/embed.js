// The iframe page (embed.html): one playground, settings from the hash, parts hidden with
// ?hide=..., its height posted to the host page so that the iframe can fit it, and the host
// protocol (frame-protocol.js, docs/EMBED.md) for a page that drives it.
import { Playground } from './playground.js';
import { serveHost } from './frame-protocol.js';

const query = new URLSearchParams(location.search);
const app = document.getElementById('app');
const pg = new Playground(app, {
  hash: true,
  autoplay: query.get('autoplay') !== '0',
  hide: (query.get('hide') ?? '').split(/[\s,]+/).filter(Boolean),
});
window.secPlayground = pg.state;
const host = serveHost(pg, query.get('origin'));

let last = 0;
function postHeight() {
  const height = Math.ceil(document.documentElement.scrollHeight);
  if (height === last || window.parent === window) return;
  last = height;
  // The unversioned message older host pages resize by (it says nothing of the run), and the
  // protocol's event, which goes to the connected host only.
  window.parent.postMessage({ type: 'sec-playground:height', height }, '*');
  host?.height(height);
}
new ResizeObserver(postHeight).observe(document.body);
// Scrolled off the host page, the iframe pauses its runs (and carries on when it comes back).
new IntersectionObserver(([e]) => pg.setOnScreen(e.isIntersecting)).observe(document.body);
postHeight();

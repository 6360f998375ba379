// The iframe page (embed.html): one playground, settings from the hash, parts hidden with
// ?hide=..., and its height posted to the host page so that the iframe can fit it.
import { Playground } from './playground.js';

const query = new URLSearchParams(location.search);
const app = document.getElementById('app');
const pg = new Playground(app, {
  hash: true,
  autoplay: query.get('autoplay') !== '0',
  hide: (query.get('hide') ?? '').split(/[\s,]+/).filter(Boolean),
});
window.secPlayground = pg.state;

let last = 0;
function postHeight() {
  const height = Math.ceil(document.documentElement.scrollHeight);
  if (height === last || window.parent === window) return;
  last = height;
  window.parent.postMessage({ type: 'sec-playground:height', height }, '*');
}
new ResizeObserver(postHeight).observe(document.body);
// Scrolled off the host page, the iframe pauses its runs (and carries on when it comes back).
new IntersectionObserver(([e]) => pg.setOnScreen(e.isIntersecting)).observe(document.body);
postHeight();

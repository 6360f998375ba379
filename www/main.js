// The playground page (index.html): one playground in the document, its settings in the URL
// hash, starting to play on load.
import { Playground } from './playground.js';

// `?arena=05-25-01`: the playground plays that Olympics arena (the arena page links here).
const arena = new URLSearchParams(location.search).get('arena');
const pg = new Playground(document.getElementById('app'), { hash: true, autoplay: true, arena });

// For tests and the curious: the page's state.
window.secPlayground = pg.state;

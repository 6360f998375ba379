// The playground page (index.html): one playground in the document, its settings in the URL
// hash, starting to play on load.
import { Playground } from './playground.js';

const pg = new Playground(document.getElementById('app'), { hash: true, autoplay: true });

// For tests and the curious: the page's state.
window.secPlayground = pg.state;

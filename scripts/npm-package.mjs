// Makes the folder scripts/build.sh writes (dist/sec-playground/) an npm package: its package.json
// (exports with TypeScript declarations, the custom elements manifest) and a README. Every module
// addresses its wasm, models and workers relative to itself, so the same folder works from
// node_modules through a bundler (Vite), from a CDN line, or copied next to a course page.
//   node scripts/npm-package.mjs dist/sec-playground
import { readFileSync, writeFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';

const root = fileURLToPath(new URL('..', import.meta.url));
const dir = process.argv[2];
if (!dir) {
  console.error('usage: node scripts/npm-package.mjs <folder>');
  process.exit(2);
}
const cargo = readFileSync(`${root}Cargo.toml`, 'utf8');
const field = (name) => cargo.match(new RegExp(`^${name} = "([^"]*)"`, 'm'))[1];
const version = field('version');
const element = { types: './www/element.d.ts', default: './www/element.js' };

const pkg = {
  name: 'sec-playground',
  version,
  description: `${field('description')}: the <sec-playground> element, the iframe protocol and the wasm API`,
  license: field('license'),
  type: 'module',
  keywords: ['reinforcement-learning', 'episodic-control', 'webassembly', 'web-component', 'neuroscience', 'animal-ai'],
  exports: {
    '.': element,
    './element': element,
    './embed-host': { types: './www/embed-host.d.ts', default: './www/embed-host.js' },
    './wasm': { types: './pkg/sec_playground.d.ts', default: './pkg/sec_playground.js' },
    './custom-elements.json': './www/custom-elements.json',
    './widget': './widget.js',
    './package.json': './package.json',
    './*': './*',
  },
  types: './www/element.d.ts',
  customElements: 'www/custom-elements.json',
  sideEffects: ['./www/element.js', './www/sec-playground.js'],
  files: ['index.html', 'embed.html', 'arena.html', 'widget.js', 'www', 'pkg', 'assets', 'README.md'],
};
writeFileSync(`${dir}/package.json`, `${JSON.stringify(pkg, null, 2)}\n`);

writeFileSync(`${dir}/README.md`, `# sec-playground ${version}

Sequential Episodic Control (Freire, Amil & Verschure) learning Animal-AI arenas, in the browser:
the agent's camera, its memory and learning curves, and every setting, live. The simulation is Rust
compiled to WebAssembly and runs in a Web Worker; the models ship in the package (no network).

## On a page

From a CDN (no build step):

\`\`\`html
<script type="module" src="https://cdn.jsdelivr.net/npm/sec-playground@${version}/www/element.js"></script>
<sec-playground task="double-t-maze" alpha="0.05" autoplay hide="compare"></sec-playground>
\`\`\`

With a bundler (Vite, for one):

\`\`\`js
import 'sec-playground';
const el = document.querySelector('sec-playground');
el.addEventListener('episode', (e) => console.log(e.detail.reward));
await el.configure({ alpha: 0.05 }); // {applied: 'live', ...}
\`\`\`

Attributes are the settings (\`www/custom-elements.json\` lists each with its values and help);
the element's methods and events, and the iframe protocol for platforms that only allow iframes
(\`embed.html\`, driven with \`sec-playground/embed-host\`), are in docs/EMBED.md of the repository.
\`sec-playground/wasm\` is the WebAssembly API itself (\`SecRun\`, \`ArenaEnv\`; TypeScript
declarations included).

## In a notebook or a book

\`widget.js\` (\`sec-playground/widget\`) is the element as an anywidget module, one file with its
workers. The Python package's \`sec_playground.widget()\` uses it with the files from the kernel;
a MyST / Jupyter Book page renders it with no kernel, the files from this package:

\`\`\`markdown
:::{anywidget} https://cdn.jsdelivr.net/npm/sec-playground@${version}/widget.js
{"files": "https://cdn.jsdelivr.net/npm/sec-playground@${version}/", "task": "detour", "alpha": 0.05}
:::
\`\`\`
`);
console.log(`${dir}: package.json and README.md for sec-playground ${version}`);

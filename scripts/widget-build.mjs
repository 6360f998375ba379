// Bundles the notebook widget's front end (www/widget.js: the element, its modules and its two
// workers) into one ES module, `<out>/widget.js` (default dist/sec-playground/widget.js), with
// Vite's library mode. A notebook loads an anywidget's module from a string, so nothing may be
// fetched from beside it: the workers are inlined (Vite does so in library mode), and the files
// (wasm, models, reference runs, style sheets) are left out, to be provided at run time
// (www/files.js): by the kernel in a notebook, from a copy of the package on a static page.
//   node scripts/widget-build.mjs [out-dir]
import { build } from 'vite';
import { dirname, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { statSync } from 'node:fs';

const root = resolve(dirname(fileURLToPath(import.meta.url)), '..');
const out = resolve(process.argv[2] ?? `${root}/dist/sec-playground`);

/**
 * Three rewrites of the page's modules, for this build only:
 * - each `new URL('<file>', import.meta.url)` that names one of the provided files is marked as
 *   one Vite must leave alone (in library mode it would inline the file as base64: megabytes of
 *   models in the module); those addresses are used only where no one provides the files;
 * - each `new Worker(new URL('./x.js', import.meta.url), {type: 'module'})` becomes Vite's inline
 *   worker (`./x.js?worker&inline`: the worker's bundle in the module, started from a blob), as
 *   the page's form would emit the worker as a file beside the module, and the check of the
 *   module's origin that chooses between the two forms is dropped.
 */
const forOneModule = {
  name: 'sec-playground:one-module',
  enforce: 'pre',
  transform(code, id) {
    if (!/\/(www|pkg)\/.*\.js$/.test(id)) return null;
    const imports = [];
    // The inlined workers start from the page's own blob, wherever the module came from (a
    // blob: or a data: address, as notebooks load it): the origin check is for the page's build.
    let next = code.replaceAll('sameOrigin(import.meta.url)', 'true');
    next = next.replace(/new Worker\(new URL\('(\.\/[\w-]+\.js)', import\.meta\.url\), \{ type: 'module' \}\)/g, (_, file) => {
      imports.push(`import SecInlineWorker${imports.length} from '${file}?worker&inline';`);
      return `new SecInlineWorker${imports.length - 1}()`;
    });
    next = next.replace(/new URL\((?=['`](\.\.\/assets\/|\.\/vendor\/|\.\/style\.css|\.\/[\w-]*worker\.js|sec_playground_bg\.wasm))/g,
      'new URL(/* @vite-ignore */ ');
    if (next === code) return null;
    return { code: `${imports.join('\n')}\n${next}`, map: null };
  },
};

await build({
  root,
  configFile: false,
  logLevel: 'warn',
  publicDir: false,
  plugins: [forOneModule],
  worker: { format: 'es', plugins: () => [forOneModule], rolldownOptions: { output: { codeSplitting: false } } },
  build: {
    outDir: out,
    emptyOutDir: false,
    copyPublicDir: false,
    minify: true,
    lib: { entry: `${root}/www/widget.js`, formats: ['es'], fileName: () => 'widget.js' },
    rolldownOptions: { output: { codeSplitting: false } },
  },
});
console.log(`[widget] ${out}/widget.js: ${statSync(`${out}/widget.js`).size} bytes`);

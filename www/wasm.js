// Loads the simulation's wasm into a worker (`load`, told by the page which build): the SIMD build
// (simd128) where the browser runs wasm SIMD, the scalar build otherwise. Both give the same bits
// (the kernels sum in the same order), so a run is the same on either. `?wasm=scalar` in the
// page's address forces the fallback (for tests and for comparing speed). `?wasm=hooks` loads the
// test flavour (scripts/build-hooks.sh), the SIMD build with the test hooks; the published page
// has no such folder. A run of an Olympics arena file loads the arena build (scalar, with the
// YAML parser and the rigid bodies the other two leave out: `load({arena: true})`). Every file
// but those two is addressed by a literal `new URL(..., import.meta.url)` or `import(...)`, so a
// bundler (Vite) finds and copies the wasm and the models.

import { TASKS } from './tasks.js';
import { fetchFile, filesProvided, provideFiles } from './files.js';

/** A function returning a v128 (i8x16.splat, i8x16.popcnt): valid only where SIMD is. */
const SIMD_PROBE = new Uint8Array([0, 97, 115, 109, 1, 0, 0, 0, 1, 5, 1, 96, 0, 1, 123, 3, 2, 1, 0, 10, 10, 1, 8, 0,
  65, 0, 253, 15, 253, 98, 11]);
/** The test flavour, out of a bundler's sight (only the repository has it). */
const HOOKS = ['..', 'pkg', 'hooks', 'sec_playground.js'].join('/');
/** The arena build, out of a bundler's sight too: only the page's `?arena=` loads it (the element
 * never does), so a course page's bundle need not carry its 1 MB. */
const ARENA = ['..', 'pkg', 'arena', 'sec_playground.js'].join('/');

/** Models being registered, and model downloads under way, by task. */
const loading = new Map();
const fetched = new Map();

/** Which build runs: 'simd', 'scalar' or 'hooks' (set by `load`). */
export let build = null;
// The glue's exports, bound by `load` (live bindings: importers see them once it has run).
export let SecRun, agents, parameters, parseSettings, applySettings, presetSettings, panicForTest, registerModel, hasModel,
  taskNames, frameSize, withArena;

/**
 * Loads and instantiates the build `wanted` ('scalar', 'hooks', or anything else for the best
 * this engine runs; the arena build when `arena`), fetching the model of `task` meanwhile;
 * resolves with the wasm's exports. `files`: where the files come from (files.js; the page's
 * boot message says), beside the modules when null.
 */
export async function load({ wanted = null, task = null, files = null, arena = false } = {}) {
  build = arena ? 'arena' : wanted === 'hooks' ? 'hooks'
    : wanted === 'scalar' || !WebAssembly.validate(SIMD_PROBE) ? 'scalar' : 'simd';
  if (files) provideFiles(files);
  if (task && !arena) prefetchModel(task);
  const glue = build === 'hooks' ? await import(/* @vite-ignore */ new URL(HOOKS, import.meta.url).href)
    : build === 'arena' ? await import(/* @vite-ignore */ new URL(ARENA, import.meta.url).href)
      : build === 'scalar' ? await import('../pkg/scalar/sec_playground.js') : await import('../pkg/sec_playground.js');
  ({ SecRun, agents, parameters, parseSettings, applySettings, presetSettings, panicForTest, registerModel, hasModel,
    taskNames, frameSize, withArena } = glue);
  if (!filesProvided() || build === 'hooks') return glue.default();
  // The glue's own default is the wasm beside it, which a provided source replaces.
  const wasm = `${{ arena: 'pkg/arena', scalar: 'pkg/scalar' }[build] ?? 'pkg'}/sec_playground_bg.wasm`;
  const r = await fetchFile(wasm);
  if (!r.ok) throw new Error(`${wasm} could not be loaded (${r.statusText || `HTTP ${r.status}`})`);
  return glue.default({ module_or_path: r });
}

/** The trained model a run's reconstruction gate uses: its task's, trained on frames of its
 * surface (the core's `encoder::model_name`): `<task>` flat, `<task>-textured` textured; null
 * for an arena file's run, which has none. */
export function gateModel(config) {
  if (config.arena != null) return null;
  return config.surface === 'textured' ? `${config.task}-textured` : config.task;
}

/** The task a model name belongs to (a function declaration: the prefetch above runs before this
 * module's constants are initialised). */
function taskOf(model) {
  return model.replace(/-textured$/, '');
}

/** Starts downloading a model (a task's name, or `gateModel`'s) now, before the wasm is ready;
 * `ensureModel` uses it. An unknown task fetches nothing: the run refuses it by name. */
export function prefetchModel(task) {
  if (!TASKS.includes(taskOf(task)) || fetched.has(task)) return;
  const here = () => new URL(`../assets/encoders/${task}.secae`, import.meta.url);
  fetched.set(task, fetchFile(`assets/encoders/${task}.secae`, here).then((r) => {
    if (!r.ok) throw new Error(`weights: the model of '${task}' could not be loaded (${r.statusText || `HTTP ${r.status}`})`);
    return r.arrayBuffer();
  }));
  fetched.get(task).catch(() => {}); // reported when ensureModel awaits it
}

/**
 * Fetches and registers a trained model, `task` a task's name or `gateModel`'s
 * (assets/encoders/<task>.secae, next to www/), unless it is there already. An unknown task is
 * left to the run to refuse by name.
 */
export function ensureModel(task) {
  if (task == null || !taskNames().includes(taskOf(task)) || hasModel(task)) return Promise.resolve();
  if (!loading.has(task)) {
    prefetchModel(task);
    loading.set(task, fetched.get(task)
      .then((b) => { registerModel(new Uint8Array(b)); })
      .finally(() => {
        loading.delete(task);
        fetched.delete(task);
      }));
  }
  return loading.get(task);
}

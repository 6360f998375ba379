// The built-in tasks' names, for what runs before the wasm is loaded (the worker's first model
// download). The wasm's `taskNames()` is the source; tests/browser/types.test.mjs checks that
// this list equals it.
export const TASKS = ['double-t-maze', 'detour', 'detour-transparent', 'cylinder', 'object-permanence', 'object-permanence-pits'];

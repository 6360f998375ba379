// Writes www/custom-elements.json, the Custom Elements Manifest of <sec-playground>, from the core's
// settings table (every attribute with its values, range, default and help), or with --check
// fails when the committed file differs from what the table gives. Needs pkg/ (scripts/build.sh).
//   node scripts/custom-elements.mjs [--check]
import { readFileSync, writeFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';

const root = fileURLToPath(new URL('..', import.meta.url));
const OUT = `${root}www/custom-elements.json`;

/** `thetaAbs` as an HTML attribute: `theta-abs` (HTML lowercases names; the element reads both). */
export const attributeName = (key) => key.replace(/[A-Z]/g, (c) => `-${c.toLowerCase()}`);

/** A setting's values in words, as the page's controls show them. */
function range(kind) {
  switch (kind.type) {
    case 'number': return `${kind.minOpen ? '(' : '['}${kind.min}, ${kind.max}]${kind.auto ? ' or auto' : ''}`;
    case 'integer': return `${kind.min} to ${kind.max}`;
    case 'choice': return kind.options.join(', ');
    default: return '0 or 1';
  }
}

function type(kind) {
  switch (kind.type) {
    case 'number': return kind.auto ? "number | 'auto'" : 'number';
    case 'integer': return 'number';
    case 'choice': return kind.options.map((o) => `'${o}'`).join(' | ');
    default: return "'0' | '1'";
  }
}

/** The manifest for the table `params` with its `defaults` (key to string). */
export function manifest(params, defaults, version) {
  const settings = params.map((p) => ({
    name: attributeName(p.key),
    type: { text: type(p.kind) },
    default: JSON.stringify(defaults[p.key]),
    description: `${p.help} Values: ${range(p.kind)}.${p.live ? ' Changes apply live.' : ''} Setting key: ${p.key} (symbol ${p.symbol}).`,
    fieldName: p.key,
  }));
  const method = (name, description, params = [], returns = 'void') => ({
    kind: 'method', name, description, parameters: params, return: { type: { text: returns } },
  });
  const event = (name, detail, description) => ({ name, type: { text: `CustomEvent<${detail}>` }, description });
  return {
    schemaVersion: '2.1.0',
    readme: 'README.md',
    modules: [{
      kind: 'javascript-module',
      path: 'www/element.js',
      declarations: [{
        kind: 'class',
        name: 'SecPlaygroundElement',
        tagName: 'sec-playground',
        customElement: true,
        description: `Sequential Episodic Control (SEC) learning an Animal-AI arena, live: the agent's camera, its memory, learning curves and every setting (sec-playground ${version}). Attributes are settings; changing one applies it like a control.`,
        attributes: [
          ...settings,
          { name: 'hide', type: { text: 'string' }, description: 'Space- or comma-separated parts to hide (runbar, keepbar, controls, views, charts, compare, or one view: camera, arena, reconstruction, heat, policy) or setting keys. May change at any time.' },
          { name: 'autoplay', type: { text: 'boolean' }, description: 'Start playing when loaded.' },
        ],
        members: [
          method('play', 'Plays; returns the state.', [], 'SecPlaygroundState'),
          method('pause', 'Pauses; returns the state.', [], 'SecPlaygroundState'),
          method('reset', 'A new run with the same settings and seed.', [], 'Promise<SecPlaygroundState>'),
          method('step', 'One decision or one episode, paused after it.', [{ name: 'what', type: { text: "'decision' | 'episode'" } }], 'Promise<SecPlaygroundState>'),
          method('configure', 'Applies settings as one batch, all or none; resolves with what applied (live, restart, unchanged), rejects naming each bad key and its range.', [{ name: 'settings', type: { text: 'Partial<SecPlaygroundSettings>' } }], 'Promise<SecPlaygroundApplied>'),
          method('getState', 'Playing, running, decisions, episode, LTM, capacity and settings.', [], 'SecPlaygroundState'),
          method('getMetrics', "Every finished episode: metrics rows, or the CSV export ('csv').", [{ name: 'format', type: { text: "'rows' | 'csv'" } }], 'SecPlaygroundEpisode[] | string'),
          method('saveMemory', 'The memory file (.secmem).', [], 'Promise<ArrayBuffer>'),
          method('loadMemory', 'Loads a memory file; resolves with the sequences in the LTM.', [{ name: 'bytes', type: { text: 'ArrayBuffer | ArrayBufferView' } }], 'Promise<{sequences: number}>'),
        ],
        events: [
          event('ready', '{version: number, settings: Record<string, string>}', 'The first run has started.'),
          event('episode', 'SecPlaygroundEpisode', 'An episode finished: its metrics row.'),
          event('state', 'SecPlaygroundState', 'Play or pause.'),
          event('error', '{message: string}', 'An error the playground shows (a refused value names its key and range).'),
          event('settings', "{applied: 'live' | 'restart' | 'unchanged', changes: Record<string, string> | null, settings: Record<string, string>}", 'Settings changed after the first run started, by a control, a shortcut or the API.'),
          event('run', '{settings: Record<string, string>}', 'A new run began (the first, a reset, or a change that restarts): its episodes count from 1.'),
          event('explanation', 'object', "The last decision explained (posted while paused or stepping): the contextual layer's sum term by term."),
        ],
      }],
      exports: [
        { kind: 'js', name: 'SecPlaygroundElement', declaration: { name: 'SecPlaygroundElement', module: 'www/element.js' } },
        { kind: 'custom-element-definition', name: 'sec-playground', declaration: { name: 'SecPlaygroundElement', module: 'www/element.js' } },
      ],
    }],
  };
}

if (process.argv[1] && fileURLToPath(import.meta.url) === process.argv[1]) {
  const wasm = await import(`${root}pkg/sec_playground.js`);
  wasm.initSync({ module: readFileSync(`${root}pkg/sec_playground_bg.wasm`) });
  const version = JSON.parse(readFileSync(`${root}package.json`, 'utf8')).version;
  const text = `${JSON.stringify(manifest(wasm.parameters(), wasm.parseSettings({}).settings, version), null, 2)}\n`;
  if (process.argv.includes('--check')) {
    if (readFileSync(OUT, 'utf8') !== text) {
      console.error('www/custom-elements.json differs from the settings table: run node scripts/custom-elements.mjs');
      process.exit(1);
    }
  } else {
    writeFileSync(OUT, text);
    console.log(`wrote ${OUT.slice(root.length)}`);
  }
}

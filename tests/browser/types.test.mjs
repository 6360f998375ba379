// The TypeScript declarations of pkg/ (written by hand in src/web/run.rs) name every field the
// wasm API really returns: a field added in Rust but not declared fails here.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';

const root = fileURLToPath(new URL('../../', import.meta.url));
const dts = readFileSync(`${root}pkg/sec_playground.d.ts`, 'utf8');
const wasm = await import(`${root}pkg/sec_playground.js`);
wasm.initSync({ module: readFileSync(`${root}pkg/sec_playground_bg.wasm`) });
wasm.registerModel(readFileSync(`${root}assets/encoders/object-permanence.secae`));

/** The text of every `export interface name { ... }` (balanced braces), joined: TypeScript merges
 * them (each agent's configuration section is declared by its agent's module). */
function block(name) {
  const texts = [];
  for (let start = dts.indexOf(`export interface ${name} {`); start >= 0;
    start = dts.indexOf(`export interface ${name} {`, start + 1)) {
    let depth = 0;
    for (let i = dts.indexOf('{', start); i < dts.length; i++) {
      if (dts[i] === '{') depth++;
      if (dts[i] === '}' && --depth === 0) {
        texts.push(dts.slice(start, i + 1));
        break;
      }
    }
  }
  assert.ok(texts.length > 0, `${name} is declared`);
  return texts.join('\n');
}

/** Every key of `value`, nested objects included ("agent.memory.alpha" checks "alpha"). */
function keys(value) {
  return Object.entries(value).flatMap(([k, v]) => (v && typeof v === 'object' && !Array.isArray(v) ? [k, ...keys(v)] : [k]));
}

function declares(name, value, deep = true) {
  const text = block(name);
  for (const k of deep ? keys(value) : Object.keys(value)) assert.match(text, new RegExp(`\\b${k}\\??:`), `${name} declares ${k}`);
}

test('RunConfig, EpisodeMetrics, DecisionView, ConfigChange, Param and ParsedSettings match what the API returns', () => {
  const run = new wasm.SecRun({ task: 'object-permanence' }, 3);
  declares('RunConfig', run.config());
  declares('EpisodeMetrics', run.stepEpisode());
  declares('DecisionView', run.view());
  const change = run.configure({ agent: { memory: { tau: 0.5 } } });
  declares('ConfigChange', change, false);
  declares('ConfigChange', change.changed[0]);
  declares('ConfigChange', run.replaceConfig({ task: 'object-permanence' }), false);
  for (const p of wasm.parameters()) declares('Param', p);
  // Its config is a RunConfig and its settings a Record: the top level only.
  declares('ParsedSettings', wasm.parseSettings({}), false);
  run.free();
});

test('the published build has no test or benchmark hooks', () => {
  for (const name of ['panicForTest', 'benchEnvSteps', 'benchRenders', 'benchAutoencoder', 'scriptedRun']) {
    assert.ok(!dts.includes(name), `${name} is not declared`);
    assert.equal(wasm[name], undefined, `${name} is not exported`);
  }
  assert.ok(!dts.includes('benchFillMemory'));
  assert.equal(wasm.SecRun.prototype.benchFillMemory, undefined);
});

test("the playground's build leaves the YAML parser out; the arena page's build has it", async () => {
  assert.equal(wasm.ArenaEnv.fromYaml, undefined);
  assert.ok(!dts.includes('fromYaml'));
  const arena = await import(`${root}pkg/arena/sec_playground.js`);
  arena.initSync({ module: readFileSync(`${root}pkg/arena/sec_playground_bg.wasm`) });
  const env = arena.ArenaEnv.fromYaml('mine', 'arenas:\n  0:\n    t: 250\n    items:\n    - name: GoodGoal\n', 1);
  assert.equal(env.observation().length, 84 * 84 * 4); // RGBA
  assert.throws(() => arena.ArenaEnv.fromYaml('mine', 'arenas: [', 1), /yaml|YAML/);
});

test("the page's list of tasks (www/tasks.js, used before the wasm loads) is the wasm's", async () => {
  const { TASKS } = await import(`${root}www/tasks.js`);
  assert.deepEqual(TASKS, wasm.taskNames());
});

test("every compare preset's summary is two or three sentences of at most 60 words, with details behind 'more'", async () => {
  const { COMPARE_PRESETS, SUMMARY_WORDS, exp1In, referenceMap } = await import(`${root}www/presets.js`);
  const presets = [...Object.values(COMPARE_PRESETS), ...['detour', 'cylinder', 'object-permanence'].map(exp1In)];
  assert.equal(presets.length, 7);
  const refs = referenceMap(JSON.parse(readFileSync(`${root}assets/reference/index.json`, 'utf8')));
  for (const preset of presets) {
    const p = { title: preset.title, summary: preset.summary(refs),
      caption: typeof preset.caption === 'function' ? preset.caption(refs) : preset.caption };
    assert.doesNotMatch(`${p.summary} ${p.caption}`, /null|undefined|NaN|not in this build/, `${p.title}: every number is in the index`);
    const words = p.summary.trim().split(/\s+/).length;
    const sentences = p.summary.split(/(?<=[.!?])\s+(?=[A-Z])/).length;
    assert.ok(words <= SUMMARY_WORDS, `${p.title}: ${words} words`);
    assert.ok(sentences >= 2 && sentences <= 3, `${p.title}: ${sentences} sentences`);
    assert.match(p.summary, /Live/, `${p.title} says what the live runs show`);
    assert.ok(p.caption.length > p.summary.length, `${p.title} has details`);
  }

});

test('no measured number is typed in the presets: their captions are templates over the reference index', async () => {
  // Every string literal of www/presets.js (template expressions left out): a decimal or a
  // percentage there would be a number copied from a report, which new runs would leave stale.
  const source = readFileSync(`${root}www/presets.js`, 'utf8').replace(/^\s*(\/\/|\*|\/\*\*).*$/gm, '');
  const literals = source.match(/'(?:[^'\\\n]|\\.)*'|`(?:[^`\\]|\\.)*`/g) ?? [];
  const typed = literals.map((l) => l.replace(/\$\{[^}]*\}/g, '')).filter((l) => /\d\.\d|\d ?%/.test(l));
  assert.deepEqual(typed, [], 'measured numbers typed in www/presets.js');
  // And the captions do change with the index: scale every run's reward and the text follows.
  const { COMPARE_PRESETS, referenceMap } = await import(`${root}www/presets.js`);
  const index = JSON.parse(readFileSync(`${root}assets/reference/index.json`, 'utf8'));
  const refs = referenceMap(index);
  // Neighbouring entries (the arms of one preset) get different factors.
  const factor = (i) => 1 + (i % 3) * 0.25;
  const scaled = referenceMap({ ...index, references: index.references.map((r, i) => ({
    ...r, meanReward: r.meanReward * factor(i), runs: r.runs.map((x) => x * factor(i)),
  })) });
  // A build without some experiment's runs yet still has captions (saying so), never an error.
  for (const gone of ['exp1:', 'exp2:', 'exp3:', 'exp4:']) {
    const some = referenceMap({ ...index, references: index.references.filter((r) => !r.reference.startsWith(gone)) });
    for (const p of Object.values(COMPARE_PRESETS)) assert.doesNotThrow(() => `${p.summary(some)} ${p.caption(some)}`);
  }
  for (const [name, p] of Object.entries(COMPARE_PRESETS)) {
    assert.notEqual(p.caption(scaled), p.caption(refs), `${name}'s caption reads the index`);
  }
});

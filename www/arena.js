// The arena page: builds an environment, steps it in real time with the keyboard's action and
// draws the camera and the top-down view. Errors show on the page and keep the last good run.
// Its own build (scripts/build.sh): the scalar flavour with the YAML parser the playground's
// builds leave out.
import init, { ArenaEnv, taskNames, taskDescription, frameSize, maxTextFileBytes } from '../pkg/arena/sec_playground.js';
import { drawRgba, drawStatus } from './views.js';
import { keyboard } from './keys.js';

const $ = (id) => document.getElementById(id);
const STEP_MS = 60; // one env step is 3 physics frames of 20 ms
const TOP = 336;

let env = null;
let episodeReward = 0;
let lastEpisode = null;
let message = '';
/** Where the arena comes from: a built-in task, or a loaded YAML file (kept across seed changes). */
let source = { kind: 'task' };

function showError(e) {
  const el = $('error');
  el.textContent = e ? String(e.message ?? e) : '';
  el.hidden = !e;
}

/** Seed and t as written: a number where the text is one, else the text itself. The core checks
 * both (`ArenaEnv`) and a bad value throws naming the parameter and its range, so no range is
 * written here to go stale. */
function settings() {
  const read = (id) => {
    const text = $(id).value;
    return text.trim() !== '' && Number.isFinite(Number(text)) ? Number(text) : text;
  };
  return { seed: read('seed'), t: read('limit') };
}

/**
 * Replaces the environment only when the new one builds (then the description changes too);
 * otherwise the old one keeps running, described as it was.
 */
function rebuild(make, description) {
  try {
    const next = make(settings());
    env?.free();
    env = next;
    episodeReward = 0;
    showError(null);
    // What the loader changed to read a file as v1 does (a size clamped) follows its description.
    const warnings = env.warnings();
    $('description').textContent = warnings.length ? `${description}. As v1 does: ${warnings.join('; ')}` : description;
    return true;
  } catch (e) {
    showError(e);
    return false;
  }
}

/** The menu's entry for a loaded file: shown (and selected) only while that file runs. */
const CUSTOM = '(custom)';

function fromTask() {
  const task = $('task').value;
  // Leaving a file's arena: its own t goes with it, back to the tasks' limit.
  const fileT = source.kind === 'yaml' && source.ownT;
  const limit = $('limit').value;
  if (fileT) $('limit').value = $('limit').defaultValue;
  if (rebuild(({ seed, t }) => new ArenaEnv(task, seed, t), taskDescription(task))) {
    source = { kind: 'task' };
    learnLink(null);
    $('task').querySelector(`option[value="${CUSTOM}"]`)?.remove();
    $('olympics').value = '';
  } else if (source.kind === 'yaml') {
    // The file's arena goes on: the menu and the limit say so.
    $('limit').value = limit;
    $('task').value = CUSTOM;
  }
}

/** The current source again, with the seed and limit now in the fields. */
function again() {
  if (source.kind === 'task') return fromTask();
  const { name, text } = source;
  // The file's own t until the limit field is edited.
  rebuild(({ seed, t }) => ArenaEnv.fromYaml(name, text, seed, source.ownT ? undefined : t), `${source.label} ${name}`);
}

function draw() {
  const n = frameSize();
  drawRgba($('camera'), env.observation(), n, n);
  drawRgba($('arena'), env.topDown(TOP), TOP, TOP);
  const a = env.agent();
  drawStatus($('status'), [
    ['task', env.taskName()], ['layout', a.layout], ['episode', a.episode], ['env step', `${a.steps} / ${a.t || '∞'}`],
    ['x, z', `${a.x.toFixed(2)}, ${a.z.toFixed(2)}`], ['heading', `${a.heading.toFixed(0)}°`], ['speed', `${a.speed.toFixed(2)} m/s`],
    ['episode reward', episodeReward.toFixed(3)], ['last episode', lastEpisode ?? '–'], ['', message],
  ]);
}

function tick(action) {
  const r = env.step(action);
  episodeReward += r.reward;
  if (r.terminated || r.truncated) {
    lastEpisode = `${episodeReward.toFixed(3)} (${r.goodGoal ? 'goal' : r.terminated ? 'ended' : 'time out'})`;
    message = r.goodGoal ? 'Goal! Next layout.' : r.terminated ? 'Episode ended.' : 'Out of time.';
    env.reset();
    episodeReward = 0;
  }
}

await init();
for (const name of taskNames()) $('task').add(new Option(name, name));
fromTask();
const action = keyboard(() => again());
$('task').addEventListener('change', fromTask);
$('reset').addEventListener('click', again);
$('seed').addEventListener('change', again);
$('limit').addEventListener('change', () => {
  if (source.kind === 'yaml') source.ownT = false;
  again();
});
/**
 * Loads an arena file's text as the arena (kept across seed changes); `label` describes it
 * ("Custom arena") and `menu` names it in the task menu ("custom"). Returns whether it built.
 */
function fromText(name, text, label, menu) {
  if (!rebuild(({ seed }) => ArenaEnv.fromYaml(name, text, seed, undefined), `${label} ${name}`)) return false;
  source = { kind: 'yaml', name, text, ownT: true, label };
  $('limit').value = String(env.agent().t); // the file's t
  let custom = $('task').querySelector(`option[value="${CUSTOM}"]`);
  if (!custom) {
    custom = new Option('', CUSTOM);
    custom.disabled = true;
    $('task').prepend(custom);
  }
  custom.textContent = `${menu}: ${name}`;
  $('task').value = CUSTOM;
  if (menu !== 'olympics') $('olympics').value = '';
  learnLink(menu === 'olympics' ? name.replace(/\.ya?ml$/, '') : null);
  return true;
}

/** The link to the playground playing the Olympics arena `name` (none for a task or a user's file). */
function learnLink(name) {
  $('learn').hidden = !name;
  if (name) $('learn-link').href = `index.html?arena=${encodeURIComponent(name)}`;
}

/** The Olympics corpus's menu (assets/arenas/olympics.json, made by `sec-experiment arenas`): by
 * category, each file that cannot run here yet disabled with what it needs. */
async function olympicsMenu() {
  const menu = $('olympics');
  let index;
  try {
    const r = await fetch(new URL('../assets/arenas/olympics.json', import.meta.url));
    if (!r.ok) throw new Error(`HTTP ${r.status}`);
    index = await r.json();
  } catch (e) {
    menu.disabled = true;
    menu.title = `The Olympics arenas could not be listed (assets/arenas/olympics.json: ${e.message ?? e})`;
    return;
  }
  const runs = index.files.filter((f) => f.loads).length;
  menu.options[0].textContent = `(choose one: ${runs} of ${index.files.length} run here)`;
  index.categories.forEach((name, i) => {
    const group = document.createElement('optgroup');
    group.label = `${String(i + 1).padStart(2, '0')} ${name}`;
    for (const f of index.files.filter((x) => x.category === i + 1)) {
      const o = new Option(f.file.replace(/\.ya?ml$/, ''), f.file);
      if (!f.loads) {
        o.disabled = true;
        o.textContent += f.needs.length ? ` (needs ${f.needs.join(', ')})` : ` (refused: ${f.refused})`;
      } else if (!f.asV1) {
        o.textContent += ' (its random run failed: results/arenas.csv)';
      }
      group.append(o);
    }
    menu.append(group);
  });
}

$('olympics').addEventListener('change', async (e) => {
  const file = e.target.value;
  if (!file) return;
  try {
    const r = await fetch(new URL(`../assets/arenas/competition/${file}`, import.meta.url));
    if (!r.ok) throw new Error(`HTTP ${r.status}`);
    fromText(file, await r.text(), 'Olympics arena', 'olympics');
  } catch (err) {
    showError(`${file} could not be loaded: ${err.message ?? err}`);
  }
});

$('yaml').addEventListener('change', async (e) => {
  const file = e.target.files?.[0];
  if (!file) return;
  e.target.value = '';
  // The core's one limit for text files, checked before the file is read (a huge file is not loaded).
  if (file.size > maxTextFileBytes()) {
    showError(`yaml: ${file.name} is ${file.size} bytes, larger than ${maxTextFileBytes()}, the most an arena file may be`);
    return;
  }
  const bytes = new Uint8Array(await file.arrayBuffer());
  let text;
  try {
    text = new TextDecoder('utf-8', { fatal: true }).decode(bytes);
  } catch {
    showError(`yaml: ${file.name} is not UTF-8 text: not an Animal-AI YAML file`);
    return;
  }
  fromText(file.name, text, 'Custom arena', 'custom');
});
olympicsMenu();

let last = performance.now();
let pending = 0;
function frame(now) {
  pending += now - last;
  last = now;
  // Catch up in real time, but never more than 10 steps per animation frame (background tabs).
  let n = 0;
  while (pending >= STEP_MS && n < 10) {
    if (env) tick(action());
    pending -= STEP_MS;
    n++;
  }
  if (n === 10) pending = 0;
  if (env) draw();
  requestAnimationFrame(frame);
}
requestAnimationFrame(frame);
window.secPlayground = { get env() { return env; } };

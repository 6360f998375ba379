// The controls: one per setting of the core's `parameters()` (symbol, one-line explanation,
// range), the run bar (play, step, reset, speed, presets) and the keyboard shortcuts. Values go
// out as strings, exactly as the URL hash holds them; the core validates them.
import { keepsKey } from './typing.js';

/** The speed slider's stops, in decisions per second; the last is "max". */
export const SPEEDS = [1, 2, 5, 10, 25, 50, 100, 250, 1000, 'max'];

function rangeText(kind) {
  switch (kind.type) {
    case 'number': return `${kind.minOpen ? '(' : '['}${kind.min}, ${kind.max}]${kind.auto ? ' or auto' : ''}`;
    case 'integer': return `${kind.min} – ${kind.max.toLocaleString('en')}`;
    case 'choice': return `${kind.options.length} choices`;
    default: return 'on / off';
  }
}

function input(p) {
  const { kind } = p;
  if (kind.type === 'choice') {
    const sel = document.createElement('select');
    for (const o of kind.options) sel.add(new Option(o, o));
    return sel;
  }
  const el = document.createElement('input');
  if (kind.type === 'switch') {
    el.type = 'checkbox';
  } else {
    // A text box with a number keyboard, not an <input type=number>: that one hands over ''
    // for text it cannot read, so the core could only say "empty"; this one hands over what was
    // typed, and the core names it ("tau: 'abc' is not a number in [0.01, 100]").
    el.type = 'text';
    el.inputMode = kind.type === 'integer' ? 'numeric' : 'decimal';
    el.autocomplete = 'off';
    el.spellcheck = false;
    // A number or the word "auto" (empty shows auto).
    if (kind.auto) el.placeholder = 'auto';
  }
  return el;
}

/**
 * Builds a control per parameter into `root`. `onChange(key, value)` gets the new value as a
 * string. Returns `set(settings)`, which shows settings without firing `onChange`, and
 * `hide(keys)`.
 */
export function buildControls(root, params, onChange) {
  const fields = new Map();
  const sliders = new Map();
  const groups = new Map();
  const groupOf = (name) => {
    if (!groups.has(name)) {
      const d = document.createElement('details');
      d.className = 'group';
      d.dataset.group = name;
      d.open = true;
      const s = document.createElement('summary');
      s.textContent = GROUPS[name] ?? name;
      d.append(s);
      root.append(d);
      groups.set(name, d);
    }
    return groups.get(name);
  };
  for (const p of params) {
    const row = document.createElement('div');
    row.className = 'param';
    row.dataset.key = p.key;
    const label = document.createElement('label');
    label.htmlFor = `p-${p.key}`;
    label.className = 'symbol';
    label.textContent = p.symbol;
    const el = input(p);
    el.id = `p-${p.key}`;
    el.dataset.key = p.key;
    el.setAttribute('aria-describedby', `h-${p.key}`);
    const value = () => {
      if (el.type === 'checkbox') return el.checked ? '1' : '0';
      const v = el.value.trim();
      return v === '' && p.kind.auto ? 'auto' : v;
    };
    el.addEventListener('change', () => onChange(p.key, value()));
    row.append(label, el);
    if (p.kind.type === 'number' && !p.kind.auto) {
      // A slider next to the number box for the real-valued knobs.
      const slider = document.createElement('input');
      slider.type = 'range';
      slider.min = String(p.kind.min);
      slider.max = String(p.kind.max);
      slider.step = String(p.kind.step);
      slider.setAttribute('aria-label', `${p.symbol} slider`);
      slider.addEventListener('input', () => { el.value = slider.value; });
      slider.addEventListener('change', () => onChange(p.key, slider.value));
      sliders.set(p.key, slider);
      row.append(slider);
    }
    const range = document.createElement('span');
    range.className = 'range';
    range.textContent = rangeText(p.kind) + (p.live ? '' : ' · new run');
    const help = document.createElement('p');
    help.id = `h-${p.key}`;
    help.className = 'help';
    help.textContent = p.help;
    const unused = document.createElement('p');
    unused.className = 'unused';
    unused.hidden = true;
    // Where a refused value of this control is reported, next to it.
    const refused = document.createElement('p');
    refused.id = `e-${p.key}`;
    refused.className = 'refused';
    refused.setAttribute('role', 'alert');
    refused.hidden = true;
    row.append(range, help, unused, refused);
    groupOf(p.group ?? 'run').append(row);
    fields.set(p.key, el);
  }
  return {
    set(settings) {
      for (const [k, v] of Object.entries(settings)) {
        const el = fields.get(k);
        if (!el) continue;
        if (el.type === 'checkbox') el.checked = v === '1';
        else el.value = v === 'auto' && el.placeholder === 'auto' ? '' : v;
        const s = sliders.get(k);
        if (s) s.value = v;
      }
    },
    /**
     * Shows each refused value's message (`key: ...`) next to its control, and clears the
     * others; `messages` empty clears all.
     */
    refused(messages) {
      for (const [key, el] of fields) {
        const message = messages.find((m) => m.startsWith(`${key}:`));
        const alert = root.querySelector(`#e-${key}`);
        alert.textContent = message ?? '';
        alert.hidden = !message;
        if (message) el.setAttribute('aria-invalid', 'true');
        else el.removeAttribute('aria-invalid');
      }
    },
    /** Hides the rows of `keys` and shows every other (a later call replaces an earlier one). */
    hide(keys) {
      for (const row of root.querySelectorAll('.param[data-key]')) row.hidden = keys.includes(row.dataset.key);
    },
    /** Disables, with a note, the knobs that `agent` (the agent table's row) does not read. */
    agent(agent) {
      for (const p of params) {
        const ignored = p.agents?.length > 0 && !p.agents.includes(agent.key);
        const row = root.querySelector(`.param[data-key="${p.key}"]`);
        row.classList.toggle('ignored', ignored);
        for (const el of row.querySelectorAll('input, select')) el.disabled = ignored;
        const note = row.querySelector('.unused');
        note.hidden = !ignored;
        note.textContent = ignored ? `Not used by ${agent.label}.` : '';
      }
    },
  };
}

/** The control groups' headings. */
const GROUPS = { run: 'Run: task, agent, episode', perception: 'Perception', memory: 'Memory', retrieval: 'Retrieval and the bias T' };

/**
 * Wires the run bar and the keyboard shortcuts to `actions`; the shortcuts listen on `target`
 * (the window for the page, the element itself for an embedded playground).
 */
export function runControls($, actions, { target = window } = {}) {
  $('play').addEventListener('click', actions.toggle);
  $('step-decision').addEventListener('click', () => actions.step('decision'));
  $('step-episode').addEventListener('click', () => actions.step('episode'));
  $('reset').addEventListener('click', actions.reset);
  $('preset-code').addEventListener('click', () => actions.preset('code'));
  $('preset-paper').addEventListener('click', () => actions.preset('paper'));
  const speed = $('speed');
  const showSpeed = () => {
    const v = SPEEDS[Number(speed.value)];
    $('speed-out').textContent = v === 'max' ? 'max' : `${v}/s`;
    return v;
  };
  speed.addEventListener('input', () => actions.speed(showSpeed()));
  showSpeed();
  target.addEventListener('keydown', (e) => {
    if (keepsKey(e) || e.ctrlKey || e.metaKey || e.altKey) return;
    const key = {
      ' ': actions.toggle, '.': () => actions.step('decision'), e: () => actions.step('episode'), r: actions.reset,
      d: actions.drive,
    }[e.key];
    if (key) {
      e.preventDefault();
      key();
    }
  });
}

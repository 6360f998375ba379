// Keyboard driving: arrow keys map to the two action branches, action = 3*a0 + a1
// (a0: none, forward, back; a1: none, right, left).
import { typing } from './typing.js';

const ARROWS = ['ArrowUp', 'ArrowDown', 'ArrowLeft', 'ArrowRight'];

/** The action the held arrow keys make. */
export function actionOf(held) {
  const a0 = held.has('ArrowUp') ? 1 : held.has('ArrowDown') ? 2 : 0;
  const a1 = held.has('ArrowRight') ? 1 : held.has('ArrowLeft') ? 2 : 0;
  return 3 * a0 + a1;
}


/**
 * Starts listening on `target` (the window, or an element that takes focus); `onReset` runs on
 * R, `onChange(action)` whenever the held arrows change (`active()` decides whether arrows are
 * taken from the page at all). Returns a function giving the current action.
 */
export function keyboard(onReset, { target = window, onChange = () => {}, active = () => true } = {}) {
  const held = new Set();
  const changed = () => onChange(actionOf(held));
  target.addEventListener('keydown', (e) => {
    if (typing(e) || !active()) return;
    if (ARROWS.includes(e.key)) {
      e.preventDefault();
      if (!held.has(e.key)) {
        held.add(e.key);
        changed();
      }
    }
    if (onReset && (e.key === 'r' || e.key === 'R')) onReset();
  });
  target.addEventListener('keyup', (e) => {
    if (held.delete(e.key)) changed();
  });
  const clear = () => {
    if (held.size) {
      held.clear();
      changed();
    }
  };
  target.addEventListener('blur', clear);
  window.addEventListener('blur', clear);
  return () => actionOf(held);
}

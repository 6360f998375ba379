// Keyboard driving: arrow keys map to the two action branches, action = 3*a0 + a1.

const held = new Set();

/** Starts listening; `onReset` runs on R. Returns a function giving the current action. */
export function keyboard(onReset) {
  const keys = ['ArrowUp', 'ArrowDown', 'ArrowLeft', 'ArrowRight'];
  window.addEventListener('keydown', (e) => {
    if (e.target instanceof HTMLInputElement || e.target instanceof HTMLSelectElement) return;
    if (keys.includes(e.key)) { held.add(e.key); e.preventDefault(); }
    if (e.key === 'r' || e.key === 'R') onReset();
  });
  window.addEventListener('keyup', (e) => held.delete(e.key));
  window.addEventListener('blur', () => held.clear());
  return () => {
    const a0 = held.has('ArrowUp') ? 1 : held.has('ArrowDown') ? 2 : 0;
    const a1 = held.has('ArrowRight') ? 1 : held.has('ArrowLeft') ? 2 : 0;
    return 3 * a0 + a1;
  };
}

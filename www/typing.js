// Whether a key event is someone typing into a field (then it is not a shortcut). Buttons,
// checkboxes and sliders keep the shortcuts working after a click on them.
const KEYS_OF_THEIR_OWN = new Set(['text', 'number', 'search', 'email', 'url', 'password', 'tel']);

export function typing(e) {
  return e.composedPath().some((t) => (t instanceof HTMLInputElement && KEYS_OF_THEIR_OWN.has(t.type))
    || t instanceof HTMLSelectElement || t instanceof HTMLTextAreaElement);
}

/** The keys a focused control uses itself, by kind. */
const ACTIVATE = [' ', 'Enter'];
const SLIDE = ['ArrowLeft', 'ArrowRight', 'ArrowUp', 'ArrowDown', 'Home', 'End', 'PageUp', 'PageDown'];

function ownKeys(t) {
  if (t instanceof HTMLButtonElement || t.localName === 'summary') return ACTIVATE;
  if (t instanceof HTMLInputElement) {
    if (t.type === 'range') return SLIDE;
    if (['checkbox', 'radio', 'button', 'submit', 'reset', 'file', 'color'].includes(t.type)) return ACTIVATE;
  }
  if (t instanceof HTMLAnchorElement && t.href) return ['Enter'];
  const role = t.getAttribute?.('role');
  if (role === 'slider') return SLIDE;
  if (['button', 'checkbox', 'tab', 'link', 'menuitem'].includes(role)) return ACTIVATE;
  return null;
}

/**
 * The controls that took focus from the keyboard (Tab): as they took it, they showed it
 * (`:focus-visible`), which a click does not. (Chromium shows any focus once a key is pressed,
 * so the moment of focus is the only time to tell.)
 */
const byKeyboard = new WeakSet();
if (typeof document !== 'undefined') {
  document.addEventListener('focusin', (e) => {
    const t = e.composedPath()[0];
    if (!(t instanceof Element)) return;
    if (t.matches(':focus-visible')) byKeyboard.add(t);
    else byKeyboard.delete(t);
  }, true);
}

/**
 * Whether a key event belongs to the control that has focus, so the page's shortcuts leave it
 * alone: every key of a field one types into or a menu; a button's, a box's or a slider's own
 * keys (Space, Enter; the arrows) when it was reached by the keyboard. After a click, a control
 * keeps focus but not those keys, and the shortcuts work as before the click.
 */
export function keepsKey(e) {
  for (const t of e.composedPath()) {
    if (!(t instanceof HTMLElement)) continue;
    if (t.isContentEditable || t instanceof HTMLSelectElement || t instanceof HTMLTextAreaElement
      || (t instanceof HTMLInputElement && KEYS_OF_THEIR_OWN.has(t.type))) return true;
    const keys = ownKeys(t);
    if (keys) return keys.includes(e.key) && byKeyboard.has(t);
  }
  return false;
}

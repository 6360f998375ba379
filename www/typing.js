// Whether a key event is someone typing into a field (then it is not a shortcut). Buttons,
// checkboxes and sliders keep the shortcuts working after a click on them.
const KEYS_OF_THEIR_OWN = new Set(['text', 'number', 'search', 'email', 'url', 'password', 'tel']);

export function typing(e) {
  return e.composedPath().some((t) => (t instanceof HTMLInputElement && KEYS_OF_THEIR_OWN.has(t.type))
    || t instanceof HTMLSelectElement || t instanceof HTMLTextAreaElement);
}

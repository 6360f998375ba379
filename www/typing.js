// Whether a key event is someone typing into a field (then it is not a shortcut). Buttons,
// checkboxes and sliders keep the shortcuts working after a click on them.
const KEYS_OF_THEIR_OWN = new Set(['text', 'number', 'search', 'email', 'url', 'password', 'tel']);

export function typing(e) {
  return e.composedPath().some((t) => (t instanceof HTMLInputElement && KEYS_OF_THEIR_OWN.has(t.type))
    || t instanceof HTMLSelectElement || t instanceof HTMLTextAreaElement);
}

/**
 * Whether a key event goes to a control that has focus (a button, a box, a slider, a menu, a
 * link, a summary): then the page's shortcuts leave it alone, and Space or Enter do what the
 * control does.
 */
export function onControl(e) {
  return e.composedPath().some((t) => t instanceof HTMLButtonElement || t instanceof HTMLInputElement
    || t instanceof HTMLSelectElement || t instanceof HTMLTextAreaElement || (t instanceof HTMLAnchorElement && t.href)
    || (t instanceof HTMLElement && (t.localName === 'summary' || t.isContentEditable
      || ['button', 'checkbox', 'slider', 'tab', 'link', 'menuitem'].includes(t.getAttribute('role')))));
}

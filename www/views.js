// Draws the wasm frame buffers (RGBA bytes) on the page's canvases.

/** Puts an RGBA byte buffer of size w x h on a canvas (scaled by CSS, pixelated). */
export function drawRgba(canvas, rgba, w, h) {
  const ctx = canvas.getContext('2d');
  ctx.putImageData(new ImageData(new Uint8ClampedArray(rgba.buffer, rgba.byteOffset, rgba.byteLength), w, h), 0, 0);
}

/** Fills the status list with label/value pairs. */
export function drawStatus(dl, entries) {
  dl.replaceChildren(...entries.flatMap(([k, v]) => {
    const dt = document.createElement('dt');
    dt.textContent = k;
    const dd = document.createElement('dd');
    dd.textContent = v;
    return [dt, dd];
  }));
}

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

/** Viridis-like colour map, t in [0, 1]. */
const STOPS = [[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]];
function colour(t) {
  const x = Math.min(Math.max(t, 0), 1) * (STOPS.length - 1);
  const i = Math.min(Math.floor(x), STOPS.length - 2);
  const f = x - i;
  return STOPS[i].map((c, k) => Math.round(c + f * (STOPS[i + 1][k] - c)));
}

/** Display ranges: G near the 0.98 threshold, T from 1 up to its fixed point 1.2. */
export const HEAT_RANGE = { g: [0.9, 1.05], t: [1, 1.2] };

/** The heat map's colour scale: a gradient canvas and its two end values. */
export function drawHeatScale(canvas, lo, hi, kind) {
  const ctx = canvas.getContext('2d');
  for (let x = 0; x < canvas.width; x++) {
    const [R, G, B] = colour(x / (canvas.width - 1));
    ctx.fillStyle = `rgb(${R}, ${G}, ${B})`;
    ctx.fillRect(x, 0, 1, canvas.height);
  }
  const [a, b] = HEAT_RANGE[kind];
  const name = kind === 'g' ? 'G' : 'T';
  lo.textContent = `${name} ≤ ${a}`;
  hi.textContent = `≥ ${b}`;
}
/** Most LTM rows drawn (the newest); the rest are summarised in the caption. */
const MAX_ROWS = 1000;

/**
 * The LTM as a heat map: `values` (Float32Array, rows x n, row-major) of G or T, with the
 * selected couplets (flat indices) boxed in white. Returns the number of rows drawn.
 */
export function drawHeat(canvas, values, n, selected, kind) {
  const ctx = canvas.getContext('2d');
  ctx.fillStyle = '#222';
  ctx.fillRect(0, 0, canvas.width, canvas.height);
  const rows = n ? Math.floor(values.length / n) : 0;
  canvas.dataset.empty = rows ? '' : '1';
  canvas.setAttribute('aria-label', rows ? `Long-term memory heat map: ${rows} sequences`
    : 'Long-term memory heat map: empty');
  if (!rows) {
    // Why it is empty, rather than a black square.
    ctx.fillStyle = '#bbb';
    ctx.font = '13px system-ui, sans-serif';
    ctx.textAlign = 'center';
    const lines = ['The LTM is empty.', 'A sequence is stored', 'when an episode ends at a goal.'];
    lines.forEach((line, i) => ctx.fillText(line, canvas.width / 2, canvas.height / 2 + (i - 1) * 18));
    return 0;
  }
  const first = Math.max(0, rows - MAX_ROWS);
  const shown = rows - first;
  const [lo, hi] = HEAT_RANGE[kind];
  const img = new ImageData(n, shown);
  for (let r = 0; r < shown; r++) {
    for (let j = 0; j < n; j++) {
      const [R, G, B] = colour((values[(first + r) * n + j] - lo) / (hi - lo));
      const o = (r * n + j) * 4;
      img.data[o] = R; img.data[o + 1] = G; img.data[o + 2] = B; img.data[o + 3] = 255;
    }
  }
  const off = new OffscreenCanvas(n, shown);
  off.getContext('2d').putImageData(img, 0, 0);
  ctx.imageSmoothingEnabled = false;
  ctx.drawImage(off, 0, 0, canvas.width, canvas.height);
  const cw = canvas.width / n;
  const ch = canvas.height / shown;
  ctx.strokeStyle = '#fff';
  ctx.lineWidth = 1.5;
  for (const idx of selected) {
    const r = Math.floor(idx / n) - first;
    if (r < 0) continue;
    ctx.strokeRect((idx % n) * cw, r * ch, Math.max(cw, 3), Math.max(ch, 3));
  }
  return shown;
}

/** The embedding's 20 numbers as bars from a zero line (scaled to the largest magnitude). */
export function drawEmbedding(canvas, e) {
  const ctx = canvas.getContext('2d');
  const { width: w, height: h } = canvas;
  ctx.clearRect(0, 0, w, h);
  if (!e) return;
  const max = Math.max(1e-9, ...e.map(Math.abs));
  const bw = w / e.length;
  const zero = e.some((v) => v < 0) ? h / 2 : h - 1;
  const scale = (zero === h - 1 ? h - 2 : h / 2 - 1) / max;
  ctx.fillStyle = '#1d9ad6';
  e.forEach((v, i) => {
    const y = v * scale;
    ctx.fillRect(i * bw + 1, y >= 0 ? zero - y : zero, bw - 2, Math.abs(y));
  });
  ctx.fillStyle = 'rgba(128, 128, 128, 0.6)';
  ctx.fillRect(0, zero, w, 1);
}

/** The 3x3 action grid (rows a0: none, forward, backward; columns a1: none, right, left). */
export function drawProbs(table, p, action) {
  const body = table.tBodies[0];
  if (!body.rows.length) {
    for (const name of ['none', 'forward', 'back']) {
      const tr = body.insertRow();
      const th = document.createElement('th');
      th.textContent = name;
      tr.append(th);
      for (let k = 0; k < 3; k++) tr.insertCell();
    }
  }
  for (let a0 = 0; a0 < 3; a0++) {
    for (let a1 = 0; a1 < 3; a1++) {
      const cell = body.rows[a0].cells[a1 + 1];
      const v = p ? p[3 * a0 + a1] : null;
      cell.textContent = v == null ? '–' : v.toFixed(2);
      cell.style.background = v == null ? '' : `rgba(29, 154, 214, ${v.toFixed(3)})`;
      cell.classList.toggle('taken', action === 3 * a0 + a1);
    }
  }
}

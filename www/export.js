// Keeping results: per-episode metrics as CSV, and files handed to the browser's downloads.

/** The CSV columns after `run` and `seed`: every field of EpisodeMetrics. */
const FIELDS = ['episode', 'layout', 'reward', 'rawReward', 'goal', 'envSteps', 'decisions', 'entropy',
  'entropyFresh', 'ltm', 'contextualShare', 'human'];

/**
 * Significant digits a CSV number keeps: an episode's sums (the raw reward adds 1/t per env
 * step) carry float error from about the 15th digit (-1.0000000000000007 for -1), and nothing
 * it measures is finer than this.
 */
export const CSV_DIGITS = 9;

function cell(v) {
  if (v == null) return '';
  const s = typeof v === 'boolean' ? (v ? '1' : '0')
    : typeof v === 'number' ? String(Number(v.toPrecision(CSV_DIGITS))) : String(v);
  return /[",\n]/.test(s) ? `"${s.replace(/"/g, '""')}"` : s;
}

/**
 * `runs`: [{name, seed, episodes: EpisodeMetrics[]}]. A header, then one row per episode and
 * run; numbers rounded to CSV_DIGITS significant digits (the run's own log, the JSON export and
 * the native runs keep every bit).
 */
export function episodesCsv(runs) {
  const lines = [['run', 'seed', ...FIELDS].join(',')];
  for (const r of runs) {
    for (const m of r.episodes) lines.push([r.name, r.seed, ...FIELDS.map((f) => (f === 'human' ? !!m.human : m[f]))].map(cell).join(','));
  }
  return `${lines.join('\n')}\n`;
}

/** Hands `data` (a string or bytes) to the browser as a download called `name`. */
export function download(root, name, type, data) {
  const url = URL.createObjectURL(new Blob([data], { type }));
  const a = document.createElement('a');
  a.href = url;
  a.download = name;
  a.hidden = true;
  (root.host ?? root).append?.(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10_000);
}

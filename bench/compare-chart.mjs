// The comparison chart's redraw with the paper's horizon in it, in Debian's Chromium:
//   node bench/compare-chart.mjs
// 4 configurations x 5 seeds x 5000 episodes of synthetic rewards (20 runs, as Experiment 2 at
// its end) and 4 reference curves, drawn by the page's CompareChart as the comparison redraws it
// (a new point in every run, then a redraw): the median and the longest of 50 redraws, with at
// most MAX_POINTS points per line (what the page draws) and with every episode (before).
import { openChromium } from './browser.mjs';

const { server, browser, base } = await openChromium(['--no-first-run', '--disable-background-networking']);

try {
  const page = await browser.newPage({ viewport: { width: 1300, height: 1000 } });
  await page.goto(`${base}index.html`);
  const results = await page.evaluate(async () => {
    const { CompareChart, MAX_POINTS } = await import('./www/charts.js');
    // A fixed pseudo-random walk per run (mulberry32), so every measurement draws the same rows.
    let state = 7;
    const random = () => {
      state = (state + 0x6d2b79f5) | 0;
      let t = Math.imul(state ^ (state >>> 15), 1 | state);
      t = (t + Math.imul(t ^ (t >>> 7), 61 | t)) ^ t;
      return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
    };
    const EPISODES = 5000;
    const arms = Array.from({ length: 4 }, (_, a) => ({
      label: `arm ${a}`, colour: ['#0072b2', '#d55e00', '#009e73', '#cc79a7'][a],
      runs: Array.from({ length: 5 }, () => Array.from({ length: EPISODES - 1 }, (_, i) => (random() < i / EPISODES ? 1 : 0))),
    }));
    const at = Array.from({ length: 251 }, (_, i) => i * 20);
    const references = arms.map((a) => ({
      label: a.label, colour: a.colour, at, episodes: EPISODES, mean: at.map((i) => i / EPISODES), se: at.map(() => 0.05),
    }));
    const out = {};
    for (const [name, most] of [['drawn (MAX_POINTS)', MAX_POINTS], ['every episode', Infinity]]) {
      const root = document.createElement('div');
      root.style.width = '1100px';
      document.body.append(root);
      const chart = new CompareChart(root);
      clearInterval(chart.timer); // redrawn here, on demand
      chart.maxPoints = most;
      chart.full = true;
      chart.watch(() => ({ title: 'bench', arms, references }));
      chart.redraw(); // the plot built once
      const times = [];
      for (let i = 0; i < 50; i++) {
        for (const a of arms) for (const r of a.runs) r.push(random() < 0.9 ? 1 : 0);
        chart.touch();
        // Away from a frame's start; uPlot paints in a microtask after setData, which the
        // `await` lets run first, so the time is the whole redraw, painting included.
        await new Promise((r) => requestAnimationFrame(() => setTimeout(r, 0)));
        const t0 = performance.now();
        chart.redraw();
        await null;
        times.push(performance.now() - t0);
        for (const a of arms) for (const r of a.runs) r.pop();
      }
      times.sort((a, b) => a - b);
      out[name] = { median: times[25], longest: times[49], points: chart.drawn.points };
      chart.destroy();
      root.remove();
    }
    return out;
  });
  for (const [name, r] of Object.entries(results)) {
    console.log(`${name}: ${r.points} points per line, redraw median ${r.median.toFixed(1)} ms, longest ${r.longest.toFixed(1)} ms`);
  }
} finally {
  await browser.close();
  server.close();
}

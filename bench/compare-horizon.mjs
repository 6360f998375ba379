// Experiment 1 to the paper's horizon in the page, in Debian's Chromium:
//   node bench/compare-horizon.mjs [workers]      (after scripts/build.sh; an hour or more)
// Clicks the preset (SEC, NSEC, MFEC-ae x 5 seeds x 5000 episodes) with a pool of `workers`
// (default: the page's own, the machine's threads less one) and samples the comparison every
// 10 s until every run is at its horizon. Reports the wall time, each run's time, episodes/s
// and decisions/s (its decisions over the time it played), and what the same runs would take on
// an 8-thread machine's pool of 7 at this machine's speed per thread: the runs' measured times
// scheduled in the pool's order (each run to the first free worker).
import { openChromium, UNTHROTTLED } from './browser.mjs';

const workers = process.argv[2];
const { server, browser, base } = await openChromium(UNTHROTTLED);

/** The makespan of `times` (in the pool's order) on `k` workers, each run to the first free one. */
function makespan(times, k) {
  const free = Array(k).fill(0);
  for (const t of times) {
    const i = free.indexOf(Math.min(...free));
    free[i] += t;
  }
  return Math.max(...free);
}

try {
  const page = await browser.newPage({ viewport: { width: 1300, height: 1000 } });
  await page.goto(`${base}#task=double-t-maze`);
  await page.waitForFunction(() => window.secPlayground?.settings && window.secPlayground.view);
  if (workers) await page.selectOption('#compare-workers', workers);
  const pool = Number(await page.inputValue('#compare-workers'));
  const t0 = Date.now();
  await page.click('#compare-exp1');
  const started = new Map();
  const ended = new Map();
  let jobs = [];
  for (;;) {
    await new Promise((r) => setTimeout(r, 10_000));
    jobs = await page.evaluate(() => window.secPlayground.compare.jobs);
    const now = (Date.now() - t0) / 1000;
    for (const j of jobs) {
      const id = `${j.label} seed ${j.seed}`;
      if (j.state !== 'queued' && !started.has(id)) started.set(id, now);
      if (j.state === 'done' && !ended.has(id)) ended.set(id, { at: now, ...j });
    }
    const done = jobs.filter((j) => j.state === 'done').length;
    process.stdout.write(`\r${now.toFixed(0)} s: ${done} of ${jobs.length} runs done`);
    if (done === jobs.length) break;
  }
  const wall = (Date.now() - t0) / 1000;
  console.log(`\nExperiment 1, ${ended.size} runs x 5000 episodes, a pool of ${pool}: ${(wall / 60).toFixed(1)} min`);
  const times = [];
  // In the pool's order (the jobs' order), for the projection.
  for (const id of jobs.map((j) => `${j.label} seed ${j.seed}`)) {
    const j = ended.get(id);
    // A run's time: from the sample that first saw it play to the one that saw it done (10 s each).
    const t = j.at - started.get(id);
    times.push(t);
    console.log(`  ${id}: ${(t / 60).toFixed(1)} min, ${(j.episodes / t).toFixed(1)} episodes/s, ${(j.decisions / t).toFixed(0)} decisions/s`);
  }
  console.log(`the same runs on a pool of 7 (an 8-thread machine at this speed per thread): ${(makespan(times, 7) / 60).toFixed(1)} min`);
} finally {
  await browser.close();
  server.close();
}

// Experiment 1 to the paper's horizon in the page, in Debian's Chromium:
//   node bench/compare-horizon.mjs [workers]      (after scripts/build.sh; an hour or more)
// Clicks the preset (SEC, NSEC, MFEC-ae x 5 seeds x 5000 episodes) with a pool of `workers`
// (default: the page's own, the machine's threads less one) and samples the comparison every
// 10 s until every run is at its horizon. Reports the wall time, each run's time on a worker
// (`held`: its turns together), episodes/s and decisions/s over that time, and what the same
// runs would take on an 8-thread machine's pool of 7 at this machine's speed per thread: each
// episode's time taken as its decisions at its run's rate, scheduled as the page schedules them
// (turns of `TURN_MS`, the run with the fewest episodes next, MFEC's runs whole), and, for
// comparison, with every run played whole in the plan's order.
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

/**
 * The makespan of `runs` ({episodes: seconds per episode, turns: whether it can checkpoint}, in
 * the plan's order) on `k` workers as the page's pool plays them: a free worker takes the waiting
 * run with the fewest episodes, which plays a turn of `turn` seconds and on to its episode's end
 * while more runs are unfinished than workers, else to its horizon.
 */
function turnsMakespan(runs, k, turn) {
  const state = runs.map(() => ({ next: 0, busy: false }));
  const workers = Array(k).fill(0); // when each is free
  let end = 0;
  for (;;) {
    const w = workers.indexOf(Math.min(...workers));
    const now = workers[w];
    // Runs whose turn ended by now are waiting again.
    for (const s of state) if (s.busy && s.until <= now) s.busy = false;
    const unfinished = runs.filter((_, i) => state[i].next < runs[i].episodes.length).length;
    let pick = -1;
    runs.forEach((r, i) => {
      const s = state[i];
      if (!s.busy && s.next < r.episodes.length && (pick < 0 || s.next < state[pick].next)) pick = i;
    });
    if (pick < 0) {
      if (unfinished === 0) return end;
      // Every unfinished run is on a worker: this one waits for the first turn to end.
      workers[w] = Math.min(...state.filter((s) => s.busy).map((s) => s.until));
      continue;
    }
    const r = runs[pick];
    const s = state[pick];
    const limit = r.turns && unfinished > k ? turn : Infinity;
    let t = 0;
    while (s.next < r.episodes.length && t < limit) t += r.episodes[s.next++];
    Object.assign(s, { busy: true, until: now + t });
    workers[w] = now + t;
    end = Math.max(end, now + t);
  }
}

try {
  const page = await browser.newPage({ viewport: { width: 1300, height: 1000 } });
  await page.goto(`${base}#task=double-t-maze`);
  await page.waitForFunction(() => window.secPlayground?.settings && window.secPlayground.view);
  if (workers) await page.selectOption('#compare-workers', workers);
  const pool = Number(await page.inputValue('#compare-workers'));
  const t0 = Date.now();
  await page.click('#compare-exp1');
  const ended = new Map();
  let jobs = [];
  for (;;) {
    await new Promise((r) => setTimeout(r, 10_000));
    jobs = await page.evaluate(() => window.secPlayground.compare.jobs);
    const now = (Date.now() - t0) / 1000;
    for (const j of jobs) {
      const id = `${j.label} seed ${j.seed}`;
      if (j.state === 'done' && !ended.has(id)) ended.set(id, { at: now, ...j });
    }
    const done = jobs.filter((j) => j.state === 'done').length;
    process.stdout.write(`\r${now.toFixed(0)} s: ${done} of ${jobs.length} runs done`);
    if (done === jobs.length) break;
  }
  const wall = (Date.now() - t0) / 1000;
  console.log(`\nExperiment 1, ${ended.size} runs x 5000 episodes, a pool of ${pool}: ${(wall / 60).toFixed(1)} min`);
  const times = [];
  const runs = [];
  // In the plan's order (the jobs' order), for the projection.
  for (const [i, j] of jobs.entries()) {
    const id = `${j.label} seed ${j.seed}`;
    const t = j.held;
    times.push(t);
    console.log(`  ${id}: ${(t / 60).toFixed(1)} min in ${j.turns} turn(s), ${(j.episodes / t).toFixed(1)} episodes/s, ${(j.decisions / t).toFixed(0)} decisions/s`);
    const log = await page.evaluate((k) => window.secPlayground.compare.log(k).map((e) => e.decisions), i);
    runs.push({ episodes: log.map((d) => (d / j.decisions) * t), turns: j.checkpoints });
  }
  const TURN_MS = await page.evaluate(async () => (await import('./www/compare.js')).TURN_MS);
  const total = times.reduce((a, b) => a + b, 0);
  console.log(`worker-minutes: ${(total / 60).toFixed(1)} (a pool of 7 needs at least ${(total / 7 / 60).toFixed(1)} min)`);
  console.log('the same runs on a pool of 7 (an 8-thread machine at this speed per thread):');
  console.log(`  as the page plays them (turns of ${TURN_MS / 1000} s): ${(turnsMakespan(runs, 7, TURN_MS / 1000) / 60).toFixed(1)} min`);
  console.log(`  each run whole, in the plan's order: ${(makespan(times, 7) / 60).toFixed(1)} min`);
} finally {
  await browser.close();
  server.close();
}

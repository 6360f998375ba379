// One-click comparisons: the paper's experiments 1-4 in the double T-maze, as settings (the URL
// hash's keys) per configuration. Each arm names its reference runs (`experiment:condition` of
// results/experiments, reduced to assets/reference/ by `sec-experiment reference`), which the
// chart draws faint behind the live runs. Each has a summary in view (the paper's finding, the
// reference runs', and what the first minutes can show: at most 60 words) and the details
// behind "more" (REPRODUCTION.md has the tables). Summaries and details are templates over the
// reference index (assets/reference/index.json, written by `sec-experiment reference` from the
// committed runs): no measured number is typed here, so new runs rewrite the captions.

/** Most words of a preset's summary, the part of its caption in view before "more". */
export const SUMMARY_WORDS = 60;

/**
 * The numbers a summary quotes, from the reference index (assets/reference/index.json, written by
 * `sec-experiment reference` from the committed runs and the core's presets): `refs` maps a
 * reference name to its entry, `meanReward` per episode and `paperTotal` over the paper's 5000.
 */
const PAPER_EPISODES = 5000;
const ours = (refs, name) => refs.get(name)?.meanReward;
const paper = (refs, name) => {
  const t = refs.get(name)?.paperTotal;
  return t == null ? undefined : t / PAPER_EPISODES;
};
/** `a / b` to two decimals, or null when either is missing. */
const times = (a, b) => (a > 0 && b > 0 ? (a / b).toFixed(2) : null);
/** `x` to `d` decimals, or null. */
const fixed = (x, d = 2) => (Number.isFinite(x) ? x.toFixed(d) : null);
/**
 * The reference index as the presets read it: its entries by reference name, with the tests of
 * the paper's claims on our runs (results/orderings.md) as `orderings`.
 */
export function referenceMap(json) {
  const refs = new Map((json?.references ?? []).map((r) => [r.reference, r]));
  return Object.assign(refs, { orderings: json?.orderings ?? [] });
}
/** The test of one claim (`family` and `ordering` as results/orderings.md names them). */
const claim = (refs, family, ordering) => refs.orderings?.find((o) => o.family === family && o.ordering === ordering);
/** A claim's corrected p as the reports print it, with its verdict at 0.05. */
const tested = (refs, family, ordering) => sig(claim(refs, family, ordering)?.p);
/** The details in place of a caption whose reference runs are not all in this build (yet). */
const lacking = (refs, names) => (names.every((n) => refs.has(n)) ? null
  : 'Our reference runs of this preset are not in this build yet; REPRODUCTION.md has what there is.');
/** The median of `xs`. */
const median = (xs) => {
  const v = [...xs].sort((a, b) => a - b);
  const h = v.length >> 1;
  return v.length % 2 ? v[h] : (v[h - 1] + v[h]) / 2;
};
/** In how many seeds `a`'s run beat `b`'s (runs in seed order, as the index lists them). */
const wins = (a, b) => a.filter((x, i) => x > b[i]).length;
/** A corrected p as the reports print it, with its verdict at 0.05. */
const sig = (p) => {
  if (p == null) return 'not tested';
  const shown = p < 0.001 ? p.toExponential(1) : p.toFixed(3);
  return `${p < 0.05 ? 'significant' : 'not significant'}, p ${shown}`;
};
/** The episodes at which the runs' LTMs filled: how many filled, and the first and last. */
const fills = (entry) => {
  const f = (entry?.ltmFull ?? []).filter((e) => e != null);
  return { filled: f.length, of: entry?.ltmFull?.length, first: Math.min(...f), last: Math.max(...f) };
};
/**
 * The first episode at which an entry's runs' LTMs filled: where arms that differ only in what a
 * full memory does (its size, forgetting, the value of old sequences) part, run for run.
 */
const parting = (refs, name) => {
  const f = fills(refs.get(name));
  return f.filled ? f.first : '(not in this build)';
};
/** Each run's reward per episode, to two decimals, joined. */
const listed = (xs) => xs.map((x) => fixed(x)).join(', ');

/** How many MFEC-ae runs learned (above the reactive walk's bar), as the exp1 caption counts them. */
const mfecLearned = (refs) => {
  const ae = refs.get('exp1:double-t-maze/MFEC-ae');
  return ae?.learned == null ? 'MFEC far less' : `MFEC-ae learned in ${ae.learned} of ${ae.seeds} runs`;
};
/**
 * Which of an entry's runs learned only near their end: above the learned bar over their last 10 %
 * of episodes and not over their first 90 %.
 */
const lateLearners = (entry) => {
  const late = entry.lateRuns ?? [];
  const k = late.filter((x, i) => x > entry.learnedBar && !(entry.earlyRuns?.[i] > entry.learnedBar)).length;
  if (k === 0) return 'none of them learned over its last tenth';
  return `${k === late.length ? 'all' : `${k} of ${late.length}`} began to learn only near their end, over their `
    + 'last tenth (REPRODUCTION.md relates it to their graphs filling)';
};

/** The sentence on our runs, or a note that this build has none of them. */
const oursSaid = (parts) => (parts.every((p) => p != null) ? null : 'Our reference runs are not in this build.');

const SEC = { bias: '1' };
const NSEC = { bias: '0' };

export const COMPARE_PRESETS = {
  exp1: {
    title: 'Experiment 1: SEC vs NSEC vs MFEC',
    summary: (refs) => {
      const p = times(paper(refs, 'exp1:double-t-maze/SEC'), paper(refs, 'exp1:double-t-maze/NSEC'));
      const o = times(ours(refs, 'exp1:double-t-maze/SEC'), ours(refs, 'exp1:double-t-maze/NSEC'));
      return `The paper: in the double T-maze SEC collects ${p} times NSEC's reward and MFEC far less. `
        + (oursSaid([o]) ?? `Our reference runs: SEC ${o} times NSEC over ${refs.get('exp1:double-t-maze/SEC').episodes} `
          + `episodes; ${mfecLearned(refs)}. `)
        + 'Live, all curves lie together at first: SEC acts from memory only once it holds 5 sequences.';
    },
    caption: (refs) => {
      const get = (m) => refs.get(`exp1:double-t-maze/${m}`);
      const models = ['SEC', 'NSEC', 'MFEC-ae', 'MFEC-rp', 'reactive', 'DQN', 'ERLAM', 'ERLAM-noPastTerminals'];
      const missing = lacking(refs, models.map((m) => `exp1:double-t-maze/${m}`));
      if (missing) return missing;
      const [s, n, ae, rp, walk, dqn, erlam, stopped] = models.map(get);
      const P = (m) => paper(refs, `exp1:double-t-maze/${m}`);
      const at = (k) => `${fixed(s.curveAt[k])} against ${fixed(n.curveAt[k])}${k === 'end' ? ' at the end' : ` at ${k}`}`;
      return `The paper (figure 4, table 1): in the double T-maze SEC collects the most reward, ${times(P('SEC'), P('NSEC'))} `
        + 'times NSEC\'s, with a low policy entropy; NSEC, the same model without the sequential bias, collects less '
        + `with a higher entropy; MFEC far less. The reference runs at these settings (the authors' untrained encoder; `
        + `SEC and NSEC ${s.seeds} seeds x ${s.episodes} episodes, MFEC ${ae.seeds} x ${ae.episodes}): SEC and NSEC are `
        + 'together while the reactive walk explores, and SEC pulls ahead once its memory acts: '
        + `${fixed(s.curveAt['100'])} against ${fixed(n.curveAt['100'])} per episode at episode 100 (20-episode means), `
        + `${at('200')}, ${at('end')}; SEC beats NSEC on `
        + `${wins(s.runs, n.runs)} of ${s.seeds} seeds, by ${times(s.meanReward, n.meanReward)} times over the run, less `
        + `than the paper's ${times(P('SEC'), P('NSEC'))}. Against the authors' own runs, our SEC's median run got `
        + `${fixed(median(s.runs))} per episode to their ${fixed(median(s.authorsRuns))}, our NSEC's ${fixed(median(n.runs))} `
        + `to their ${fixed(median(n.authorsRuns))}. Both have settled by episode 2000 (SEC ${fixed(s.curveAt['2000'])} there, `
        + `NSEC ${fixed(n.curveAt['2000'])}). MFEC does not reproduce: ${ae.learned} of ${ae.seeds} MFEC-ae runs and `
        + `${rp.learned} of ${rp.seeds} MFEC-rp runs learned (above the reactive walk's 95th percentile, `
        + `${fixed(ae.learnedBar, 3)} per episode); they got ${fixed(ae.meanReward)} and ${fixed(rp.meanReward)} per episode `
        + `against the walk's ${fixed(walk.meanReward)}, where the paper's MFEC-ae got ${times(P('MFEC-ae'), P('SEC'))} times `
        + 'SEC\'s (REPRODUCTION.md). Live, the first minutes cover the first few dozen episodes, where all three curves '
        + 'still lie together: SEC acts from memory only once 5 sequences are stored. DQN and ERLAM, the paper\'s deep '
        + 'baselines, train with burn and run only natively, so the chart has their reference runs alone: the paper has '
        + `DQN at ${times(P('DQN'), P('SEC'))} times SEC's reward, but our ${dqn.seeds} DQN runs (${dqn.episodes} episodes `
        + `each) got ${listed(dqn.runs)} per episode (${fixed(dqn.meanReward)} on average, the paper's ${fixed(P('DQN'))}) `
        + `against SEC's ${fixed(s.over[dqn.episodes])} over the same episodes (${tested(refs, 'exp1 double-t-maze', 'SEC > DQN (over DQN\'s episodes)')}); DQN learns fast and `
        + `unstably. ERLAM's ${erlam.seeds} runs got ${listed(erlam.runs)} per episode, far below both; `
        + `${lateLearners(erlam)}. With propagation stopped at the goals (a `
        + `one-seed test of why), ERLAM got ${fixed(stopped.meanReward)} per episode and ${fixed(stopped.late)} over its `
        + `last ${stopped.episodes / 10} episodes (REPRODUCTION.md).`;
    },
    arms: [
      { label: 'SEC', settings: { ...SEC }, reference: 'exp1:double-t-maze/SEC' },
      { label: 'NSEC', settings: { ...NSEC }, reference: 'exp1:double-t-maze/NSEC' },
      { label: 'MFEC', settings: { agent: 'mfec-ae' }, reference: 'exp1:double-t-maze/MFEC-ae' },
    ],
    // Reference runs only: agents the page cannot run (native, burn).
    natives: [
      { label: 'DQN', reference: 'exp1:double-t-maze/DQN' },
      { label: 'ERLAM', reference: 'exp1:double-t-maze/ERLAM' },
      { label: 'ERLAM-5k', reference: 'exp1:double-t-maze/ERLAM-5k' },
    ],
  },
  exp2: {
    title: 'Experiment 2: LTM capacity 125 and 1000',
    summary: (refs) => {
      const r = (m, f) => times(f(refs, `exp2:m${m}/SEC`), f(refs, `exp2:m${m}/NSEC`));
      return `The paper: SEC beats NSEC at every memory size, by most with the smallest (${r(125, paper)} times at 125 `
        + `sequences, ${r(1000, paper)} at 1000). `
        + (oursSaid([r(125, ours), r(1000, ours)]) ?? `Our reference runs: ${r(125, ours)} times at 125, ${r(1000, ours)} at 1000. `)
        + `Live, each model's two arms are one line until its 125-sequence memory fills (○): the reference `
        + `runs part from episode ${parting(refs, 'exp2:m125/SEC')} (SEC) and ${parting(refs, 'exp2:m125/NSEC')} (NSEC).`;
    },
    caption: (refs) => {
      const sizes = [125, 250, 500, 1000];
      const get = (model, m) => refs.get(`exp2:m${m}/${model}`);
      const missing = lacking(refs, sizes.flatMap((m) => [`exp2:m${m}/SEC`, `exp2:m${m}/NSEC`]));
      if (missing) return missing;
      const r = (m, f) => times(f(refs, `exp2:m${m}/SEC`), f(refs, `exp2:m${m}/NSEC`));
      const ratios = sizes.map((m) => get('SEC', m).meanReward / get('NSEC', m).meanReward);
      const falls = /^holds/.test(claim(refs, 'exp2', 'SEC/NSEC at equal memory falls as m grows (125 / 250 / 500 / 1000)')?.verdict);
      const ps = sizes.map((m) => claim(refs, 'exp2', `SEC > NSEC at m=${m}`)?.p);
      const [small, large] = [get('SEC', 125), get('SEC', 1000)];
      const span = (f) => `${f.first} to ${f.last}`;
      const fillSmall = fills(small);
      const fillLarge = fills(large);
      return 'The paper (figures 5 and 6): SEC beats NSEC at every memory size, and the gap grows as memory shrinks '
        + `(${r(1000, paper)} times with 1000 sequences, ${r(125, paper)} times with 125); SEC with 125 sequences gets `
        + `${times(paper(refs, 'exp2:m125/SEC'), paper(refs, 'exp2:m1000/NSEC'))} times the reward of NSEC with 1000. `
        + `The reference runs (${small.seeds} seeds x ${small.episodes} episodes per arm, the authors' untrained encoder) `
        + `show SEC above NSEC at every size, ${fixed(small.meanReward)} against ${fixed(get('NSEC', 125).meanReward)} `
        + `per episode with 125 sequences and ${fixed(large.meanReward)} against ${fixed(get('NSEC', 1000).meanReward)} `
        + `with 1000: ${ratios.map((x) => x.toFixed(2)).join(', ')} times from 125 to 1000 sequences, `
        + (falls ? 'falling with memory as the paper\'s (the claim holds), but far less'
          : 'not falling with memory as the paper\'s')
        + `; with ${small.seeds} runs per arm ${ps.some((p) => p < 0.05) ? 'some' : 'none'} of these gaps `
        + `${ps.some((p) => p < 0.05) ? 'are' : 'is'} significant after correction (p ${fixed(Math.min(...ps), 3)} to `
        + `${fixed(Math.max(...ps), 3)}); SEC with 125 gets ${times(small.meanReward, get('NSEC', 1000).meanReward)} `
        + `times NSEC with 1000 (${tested(refs, 'exp2', 'SEC m=125 > NSEC m=1000')}; REPRODUCTION.md). `
        + 'The capacity matters only once the memory is full: SEC\'s filled '
        + `after ${span(fillSmall)} episodes with 125 sequences and ${span(fillLarge)} with 1000 (in ${fillLarge.filled} `
        + `of ${fillLarge.of} runs); live, the first minutes show the arms together.`;
    },
    arms: [
      { label: 'SEC m=125', settings: { ...SEC, m: '125' }, reference: 'exp2:m125/SEC' },
      { label: 'NSEC m=125', settings: { ...NSEC, m: '125' }, reference: 'exp2:m125/NSEC' },
      { label: 'SEC m=1000', settings: { ...SEC, m: '1000' }, reference: 'exp2:m1000/SEC' },
      { label: 'NSEC m=1000', settings: { ...NSEC, m: '1000' }, reference: 'exp2:m1000/NSEC' },
    ],
  },
  exp3: {
    title: 'Experiment 3: the value function and its ablations',
    summary: (refs) => {
      const variants = ['noGi', 'noDist', 'noRR', 'soloGi', 'soloDist', 'soloRR'].map((v) => ours(refs, `exp3:value-function/SEC-${v}`));
      const base = ours(refs, 'exp3:value-function/SEC-default');
      const said = oursSaid([base, ...variants]) ?? `Our reference runs: ${fixed(Math.min(...variants))} to `
        + `${fixed(Math.max(...variants))} per episode against the default's ${fixed(base)}. `;
      return 'The paper: removing one term of the value costs no significant reward. ' + said
        + 'Live, the arms stay together: they can differ only once memory holds many sequences, its 500 from '
        + `episode ${parting(refs, 'exp3:value-function/SEC-default')} in the reference runs (○ on the line).`;
    },
    caption: (refs) => {
      const get = (v) => refs.get(`exp3:value-function/SEC-${v}`);
      const names = ['default', 'noGi', 'noDist', 'noRR', 'soloGi', 'soloDist', 'soloRR'];
      const missing = lacking(refs, names.map((v) => `exp3:value-function/SEC-${v}`));
      if (missing) return missing;
      const variants = ['noGi', 'noDist', 'noRR', 'soloGi', 'soloDist', 'soloRR'].map(get);
      const base = get('default');
      const rewards = variants.map((v) => v.meanReward);
      const ps = ['noGi', 'noDist', 'noRR', 'soloGi', 'soloDist', 'soloRR']
        .map((v) => claim(refs, 'exp3', `SEC-${v} = SEC-default`)?.p);
      const some = ps.some((p) => p < 0.05);
      return 'The paper (figure 7): removing one term of the value (noGi, noRR, noDist) costs no significant reward. '
        + `The reference runs at the code preset (the protocol's ${base.seeds} seeds x ${base.episodes} episodes per arm, `
        + `the authors' untrained encoder) ${some ? 'disagree in part' : 'agree'}: the six variants got `
        + `${fixed(Math.min(...rewards))} to ${fixed(Math.max(...rewards))} per episode against the default's `
        + `${fixed(base.meanReward)}, ${some ? 'some' : 'none'} significantly different (corrected p from `
        + `${fixed(Math.min(...ps), 3)}), though ${base.seeds} runs per arm detect only a large difference `
        + '(REPRODUCTION.md). Live, they stay together: they differ only once the memory holds many sequences, '
        + 'hundreds of episodes in.';
    },
    arms: ['default', 'noGi', 'noDist', 'noRR', 'soloGi', 'soloDist', 'soloRR']
      .map((v) => ({ label: `SEC ${v}`, settings: { ...SEC, value: v }, reference: `exp3:value-function/SEC-${v}` })),
  },
  exp4: {
    title: 'Experiment 4: forgetting',
    summary: (refs) => 'The paper: once the LTM is full, forgetting helps both models a little. Our reference runs '
      + 'point the same way once the memory fills, not significantly. Live, each arm is one run with its seed\'s '
      + `no-forgetting arm until the memory fills (○ on the line), from episode ${parting(refs, 'exp4:forgetting/SEC-none')} `
      + 'in the reference runs.',
    caption: (refs) => {
      const get = (m) => refs.get(`exp4:forgetting/${m}`);
      const arms = ['SEC-none', 'NSEC-none', 'SEC-fifo', 'SEC-rwd', 'NSEC-rwd'];
      const missing = lacking(refs, arms.map((m) => `exp4:forgetting/${m}`));
      if (missing) return missing;
      const [sec, nsec] = [fills(get('SEC-none')), fills(get('NSEC-none'))];
      const gain = (m, f) => times(get(`${m}-${f}`).meanReward, get(`${m}-none`).meanReward);
      return 'The paper (figure 8): once the LTM is full, forgetting (FIFO, or the lowest reward first) helps '
        + 'both models a little; the sequential bias matters more than forgetting. The reference runs at the code '
        + `preset (m = 500, as the paper) are ${get('SEC-none').seeds} x ${get('SEC-none').episodes} per arm, the arms `
        + 'without forgetting exp1\'s runs (REPRODUCTION.md). Forgetting acts only on a full memory: in the reference '
        + `runs SEC's filled in ${sec.filled} of ${sec.of} runs, after ${sec.first} to ${sec.last} episodes, NSEC's in `
        + `${nsec.filled} of ${nsec.of}, and until then a run with forgetting is the same run as its seed's without. Over `
        + `whole runs, SEC with FIFO got ${gain('SEC', 'fifo')} times SEC without forgetting, with the lowest reward `
        + `first ${gain('SEC', 'rwd')}; NSEC with the lowest reward first ${gain('NSEC', 'rwd')} times NSEC without; `
        + 'REPRODUCTION.md tests them, and compares them from the episode the memory filled. Live, the arms are one '
        + 'for a long while.';
    },
    arms: [
      { label: 'SEC none', settings: { ...SEC, forgetting: 'none' }, reference: 'exp4:forgetting/SEC-none' },
      { label: 'SEC fifo', settings: { ...SEC, forgetting: 'fifo' }, reference: 'exp4:forgetting/SEC-fifo' },
      { label: 'SEC rwd', settings: { ...SEC, forgetting: 'rwd' }, reference: 'exp4:forgetting/SEC-rwd' },
      { label: 'NSEC none', settings: { ...NSEC, forgetting: 'none' }, reference: 'exp4:forgetting/NSEC-none' },
      { label: 'NSEC rwd', settings: { ...NSEC, forgetting: 'rwd' }, reference: 'exp4:forgetting/NSEC-rwd' },
    ],
  },
};

/** The task and episode limit every preset runs in. */
export const PRESET_BASE = { task: 'double-t-maze' };

/**
 * Exp1's other tasks: how the paper's table 1 reads there, in words; every number comes from the
 * reference index (results/experiments/exp1/report.md has the tables).
 */
const TABLE1 = {
  detour: {
    name: 'the detour',
    note: 'only SEC learned it',
    remark: 'but NSEC and MFEC-ae collect reward here too, where the paper\'s got almost none',
  },
  cylinder: { name: 'the cylinder', note: 'SEC ahead by a little' },
  'object-permanence': { name: 'object permanence', note: 'SEC ahead of both' },
};

/** What the reference runs found in a task of table 1: SEC over NSEC and MFEC-ae, tested. */
function found(refs, task) {
  const get = (m) => refs.get(`exp1:${task}/${m}`);
  const [s, n, ae] = ['SEC', 'NSEC', 'MFEC-ae'].map(get);
  const family = `exp1 ${task}`;
  return `SEC collected ${times(s.meanReward, n.meanReward)} times NSEC's reward (${tested(refs, family, 'SEC > NSEC')}) and `
    + `${times(s.meanReward, ae.meanReward)} times MFEC-ae's (${tested(refs, family, 'SEC > MFEC-ae')})`
    + (TABLE1[task].remark ? `; ${TABLE1[task].remark}`
      : `, where the paper's SEC collected ${times(paper(refs, `exp1:${task}/SEC`), paper(refs, `exp1:${task}/NSEC`))} `
        + `and ${times(paper(refs, `exp1:${task}/SEC`), paper(refs, `exp1:${task}/MFEC-ae`))} times theirs`);
}

/**
 * Experiment 1 in `task`: the double T-maze's preset, or the same three arms in another task of the
 * paper's table 1 (their reference runs are 10 seeds x 5000 episodes, the paper's horizon).
 */
export function exp1In(task) {
  if (task === 'double-t-maze' || !TABLE1[task]) return { ...COMPARE_PRESETS.exp1, base: PRESET_BASE };
  const t = TABLE1[task];
  const models = ['SEC', 'NSEC', 'MFEC-ae'].map((m) => `exp1:${task}/${m}`);
  const numbers = (refs) => ({
    paper: models.map((m) => fixed(paper(refs, m), 3)),
    ours: models.map((m) => fixed(ours(refs, m))),
  });
  return {
    title: `Experiment 1 in ${t.name}: SEC vs NSEC vs MFEC`,
    summary: (refs) => {
      const { paper: [sec, nsec, mfec], ours: o } = numbers(refs);
      return `The paper: in ${t.name} SEC collected ${sec} per episode, NSEC ${nsec} and MFEC-ae ${mfec} (${t.note}). `
        + (oursSaid(o) ?? `Our reference runs: ${o[0]}, ${o[1]} and ${o[2]}. `)
        + 'Live, the first minutes show the reactive walk: SEC acts from memory once it holds 5 sequences.';
    },
    caption: (refs) => {
      const missing = lacking(refs, models);
      if (missing) return missing;
      const { paper: [sec, nsec, mfec], ours: o } = numbers(refs);
      const first = refs.get(models[0]);
      return `The paper (table 1): in ${t.name} SEC collected ${sec} per episode over 5000 episodes, NSEC ${nsec} and `
        + `MFEC-ae ${mfec} (${t.note}). The reference runs here (${first.seeds} seeds x ${first.episodes} episodes, `
        + 'the authors\' untrained '
        + `encoder) got ${o.join(', ')} per episode: ${found(refs, task)}. SEC's policy entropy ends below NSEC's, as in the `
        + 'paper (REPRODUCTION.md). Live, the first minutes show the reactive walk: SEC acts from memory only once 5 '
        + 'sequences are stored.';
    },
    arms: COMPARE_PRESETS.exp1.arms.map((a) => ({ ...a, reference: a.reference.replace('double-t-maze', task) })),
    natives: [], // the protocol runs DQN and ERLAM in the double T-maze only
    base: { task },
  };
}

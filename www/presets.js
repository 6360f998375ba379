// One-click comparisons: the paper's experiments 1-4 in the double T-maze, as settings (the URL
// hash's keys) per configuration. Each arm names its reference runs (`experiment:condition` of
// results/experiments, reduced to assets/reference/ by `sec-experiment reference`), which the
// chart draws faint behind the live runs. Each has a summary in view (the paper's finding, the
// reference runs', and what the first minutes can show: at most 60 words) and the details
// behind "more" (REPRODUCTION.md has the tables).

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
          + 'episodes; MFEC does not learn here. ')
        + 'Live, all curves lie together at first: SEC acts from memory only once it holds 5 sequences.';
    },
    caption: 'The paper (figure 4, table 1): in the double T-maze SEC collects the most reward, 2.3 times NSEC\'s, '
      + 'with a low policy entropy; NSEC, the same model without the sequential bias, collects less with a higher '
      + 'entropy; MFEC far less. The reference runs at these settings (the authors\' untrained encoder; SEC and NSEC '
      + '20 seeds x 5000 episodes, MFEC 10 x 5000): SEC and NSEC are together while the reactive walk explores, and SEC pulls '
      + 'ahead once its memory acts (from episode 96 in the median run): 0.51 against 0.36 per episode at episode '
      + '100, 1.08 against 0.64 at 200, 1.94 against 1.33 at the end; SEC beats NSEC on all 20 seeds, by 1.54 times '
      + 'over the run, less than the paper\'s 2.3: our SEC is a fifth below the authors\' runs (1.96 median per episode '
      + 'against 2.40) and our NSEC above theirs (1.36 against 1.00). Both settle by episode 2000. MFEC does not '
      + 'reproduce: six of its ten runs per variant loop with no goal after '
      + 'episode 2000, a few escape late, and over 5000 episodes it gets 0.04-0.07 per episode, below the reactive '
      + 'walk (0.11), where the paper\'s got a third of SEC\'s (REPRODUCTION.md). Live, the first minutes cover the first few dozen '
      + 'episodes, where all three curves still lie together: SEC acts from memory only once 5 sequences are stored. '
      + 'DQN and ERLAM, the paper\'s deep baselines, train with burn and run only natively, so the chart has their '
      + 'reference runs alone: the paper has DQN at about half SEC\'s reward, but our three DQN runs (1000 episodes '
      + 'each) got 1.94, 1.24 and 0.47 per episode (1.22 on average, the paper\'s 1.24) against SEC\'s 1.54 over the '
      + 'same episodes, not significantly below it; DQN learns fast and unstably (two of the three runs collapsed '
      + 'after episode 500). ERLAM\'s three runs got 0.11, 0.16 and 0.15 per episode, far below both; two of them began '
      + 'to learn only in their last 100-200 episodes, about when their graphs filled. With propagation stopped at '
      + 'the goals (a one-seed test of why), ERLAM got 0.49 per episode and 0.91 over its last 200 (REPRODUCTION.md).',
    arms: [
      { label: 'SEC', settings: { ...SEC }, reference: 'exp1:double-t-maze/SEC' },
      { label: 'NSEC', settings: { ...NSEC }, reference: 'exp1:double-t-maze/NSEC' },
      { label: 'MFEC', settings: { agent: 'mfec-ae' }, reference: 'exp1:double-t-maze/MFEC-ae' },
    ],
    // Reference runs only: agents the page cannot run (native, burn).
    natives: [
      { label: 'DQN', reference: 'exp1:double-t-maze/DQN' },
      { label: 'ERLAM', reference: 'exp1:double-t-maze/ERLAM' },
    ],
  },
  exp2: {
    title: 'Experiment 2: LTM capacity 125 and 1000',
    summary: (refs) => {
      const r = (m, f) => times(f(refs, `exp2:m${m}/SEC`), f(refs, `exp2:m${m}/NSEC`));
      return `The paper: SEC beats NSEC at every memory size, by most with the smallest (${r(125, paper)} times at 125 `
        + `sequences, ${r(1000, paper)} at 1000). `
        + (oursSaid([r(125, ours), r(1000, ours)]) ?? `Our reference runs: ${r(125, ours)} times at 125, ${r(1000, ours)} at 1000. `)
        + 'Live, the arms stay together: capacity matters only once a memory is full, hundreds of episodes in.';
    },
    caption: 'The paper (figures 5 and 6): SEC beats NSEC at every memory size, and the gap grows as memory '
      + 'shrinks (1.6 times with 1000 sequences, 2.4 times with 125); SEC with 125 sequences gets 1.2 times the '
      + 'reward of NSEC with 1000. The reference runs (10 seeds x 2000 episodes per arm, the authors\' untrained '
      + 'encoder) show SEC above NSEC at every size, 1.36 against 0.84 per episode with 125 sequences and 1.71 against '
      + '1.05 with 1000, but by the same 1.63 times at every size, not falling with memory as the paper\'s, and with '
      + '10 runs per arm none of these gaps is significant after correction; SEC with 125 gets 1.30 times NSEC with '
      + '1000 (REPRODUCTION.md). The capacity matters only once the memory is full, which takes SEC about 380 '
      + 'episodes for 125 sequences; live, the first minutes show the arms together.',
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
        + 'Live, the arms stay together: they can differ only once memory holds many sequences.';
    },
    caption: 'The paper (figure 7): removing one term of the value (noGi, noRR, noDist) costs no significant reward. '
      + 'The reference runs at the code preset (the protocol\'s 10 seeds x 2000 episodes per arm, the authors\' '
      + 'untrained encoder) agree: the six variants got 1.58 to 1.73 per episode against the default\'s 1.65, none '
      + 'significantly different, though 10 runs per arm could not detect a difference under about a quarter '
      + '(REPRODUCTION.md). Live, they stay together: they differ only once the memory holds many sequences, '
      + 'hundreds of episodes in.',
    arms: ['default', 'noGi', 'noDist', 'noRR', 'soloGi', 'soloDist', 'soloRR']
      .map((v) => ({ label: `SEC ${v}`, settings: { ...SEC, value: v }, reference: `exp3:value-function/SEC-${v}` })),
  },
  exp4: {
    title: 'Experiment 4: forgetting',
    summary: () => 'The paper: once the LTM is full, forgetting helps both models a little. Our reference runs point '
      + 'the same way once the memory fills, not significantly. Live, each arm is one run with its seed\'s '
      + 'no-forgetting arm until the memory fills, hundreds of episodes in.',
    caption: 'The paper (figure 8): once the LTM is full, forgetting (FIFO, or the lowest reward first) helps '
      + 'both models a little; the sequential bias matters more than forgetting. The reference runs at the code preset '
      + '(m = 500, as the paper) are 10 x 2000 per arm, the arms without forgetting exp1\'s runs (REPRODUCTION.md). '
      + 'Forgetting acts only on a full memory: in the reference runs SEC\'s filled after 711 to 1886 episodes, '
      + 'NSEC\'s in 5 of 10 runs, and until then a run '
      + 'with forgetting is the same run as its seed\'s without. From the episode the memory filled, forgetting got '
      + '4 to 5 % more reward for SEC and 5 to 9 % for NSEC on the same seeds, the paper\'s direction; over whole '
      + 'runs no difference is significant. Live, the arms are one for a long while.',
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
 * Exp1's other tasks: how the paper's table 1 reads there, and the significance tests of our
 * reference runs (results/experiments/exp1/report.md, results/orderings.md); the numbers
 * themselves come from the reference index.
 */
const TABLE1 = {
  detour: {
    name: 'the detour',
    note: 'only SEC learned it',
    found: 'SEC collected 1.90 times NSEC\'s reward (significant, p 0.002) and 2.26 times MFEC-ae\'s (not '
      + 'significant, p 0.37); but NSEC and MFEC-ae collect reward here too, where the paper\'s got almost none',
  },
  cylinder: {
    name: 'the cylinder',
    note: 'SEC ahead by a little',
    found: 'SEC collected 2.24 times NSEC\'s reward (p 0.005) and 2.15 times MFEC-ae\'s (p 0.034), both '
      + 'significant and wider gaps than the paper\'s 1.14 and 1.43',
  },
  'object-permanence': {
    name: 'object permanence',
    note: 'SEC ahead of both',
    found: 'SEC is ahead of both, but by 1.24 times NSEC and 1.27 times MFEC-ae, neither significant with 10 runs '
      + '(the paper: 1.90 and 1.38)',
  },
};

/**
 * Experiment 1 in `task`: the double T-maze's preset, or the same three arms in another task of the
 * paper's table 1 (their reference runs are 10 seeds x 1000 episodes in the protocol).
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
      const { paper: [sec, nsec, mfec], ours: o } = numbers(refs);
      return `The paper (table 1): in ${t.name} SEC collected ${sec} per episode over 5000 episodes, NSEC ${nsec} and `
        + `MFEC-ae ${mfec} (${t.note}). The reference runs here (10 seeds x 1000 episodes, the authors' untrained `
        + `encoder) got ${o.join(', ')} per episode: ${t.found}. SEC's policy entropy ends below NSEC's, as in the `
        + 'paper (REPRODUCTION.md). Live, the first minutes show the reactive walk: SEC acts from memory only once 5 '
        + 'sequences are stored.';
    },
    arms: COMPARE_PRESETS.exp1.arms.map((a) => ({ ...a, reference: a.reference.replace('double-t-maze', task) })),
    natives: [], // the protocol runs DQN and ERLAM in the double T-maze only
    base: { task },
  };
}

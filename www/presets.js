// One-click comparisons: the paper's experiments 1-4 in the double T-maze, as settings (the URL
// hash's keys) per configuration, each with what the paper found, what the long runs at the same
// settings show (REPRODUCTION.md) and what the first minutes of live runs can show.

const SEC = { bias: '1' };
const NSEC = { bias: '0' };

export const COMPARE_PRESETS = {
  exp1: {
    title: 'Experiment 1: SEC vs NSEC vs MFEC',
    caption: 'The paper (figure 4, table 1): in the double T-maze SEC collects the most reward, 2.3 times NSEC\'s, '
      + 'with a low policy entropy; NSEC, the same model without the sequential bias, collects less with a higher '
      + 'entropy; MFEC far less. Our runs at these settings (the authors\' untrained encoder, 20 runs x 2000 '
      + 'episodes each, REPRODUCTION.md): SEC 1.75 per episode against NSEC\'s 1.08 (1.62 times, p = 0.0001), '
      + 'entropy 0.65 against 1.19 bits late in the runs. MFEC does not reproduce here: 0.02 per episode (5 runs), '
      + 'below the reactive walk\'s 0.11, trapped by its greedy rule (REPRODUCTION.md). '
      + 'Live, give it time: SEC acts from memory only once 5 sequences are stored (episode 96 in the median run) '
      + 'and its curve separates from NSEC\'s after about 200 episodes, so the first minutes show the reactive walk in all three.',
    arms: [
      { label: 'SEC', settings: { ...SEC } },
      { label: 'NSEC', settings: { ...NSEC } },
      { label: 'MFEC', settings: { agent: 'mfec-ae' } },
    ],
  },
  exp2: {
    title: 'Experiment 2: LTM capacity 125 and 1000',
    caption: 'The paper (figures 5 and 6): SEC beats NSEC at every memory size, and the gap grows as memory '
      + 'shrinks (1.6 times with 1000 sequences, 2.4 times with 125); SEC with 125 sequences gets 1.2 times the '
      + 'reward of NSEC with 1000. The long runs of this experiment at the code preset are still to come '
      + '(REPRODUCTION.md); with the trained encoder (3 runs x 600 episodes) SEC\'s entropy was lower at every size '
      + 'and the reward gap did not show. Live, the 125-sequence memories fill first, after a few hundred episodes.',
    arms: [
      { label: 'SEC m=125', settings: { ...SEC, m: '125' } },
      { label: 'NSEC m=125', settings: { ...NSEC, m: '125' } },
      { label: 'SEC m=1000', settings: { ...SEC, m: '1000' } },
      { label: 'NSEC m=1000', settings: { ...NSEC, m: '1000' } },
    ],
  },
  exp3: {
    title: 'Experiment 3: the value function and its ablations',
    caption: 'The paper (figure 7): removing one term of the value (noGi, noRR, noDist) costs no significant reward. '
      + 'The long runs at the code preset are still to come (REPRODUCTION.md); with the trained encoder (3 runs x 600 '
      + 'episodes) the seven variants learned at the same pace. Live, they stay together: they differ only once the '
      + 'memory holds many sequences.',
    arms: ['default', 'noGi', 'noDist', 'noRR', 'soloGi', 'soloDist', 'soloRR']
      .map((v) => ({ label: `SEC ${v}`, settings: { ...SEC, value: v } })),
  },
  exp4: {
    title: 'Experiment 4: forgetting',
    caption: 'The paper (figure 8): once the LTM is full, forgetting (FIFO, or the lowest reward first) helps '
      + 'both models a little; the sequential bias matters more than forgetting. The long runs at the code preset are '
      + 'still to come (REPRODUCTION.md); with the trained encoder (2 runs x 1000 episodes) every mode was a little above '
      + 'none, not significantly. m = 125 here so that the memory fills within minutes; until it does, the arms are one.',
    arms: [
      { label: 'SEC none', settings: { ...SEC, m: '125', forgetting: 'none' } },
      { label: 'SEC fifo', settings: { ...SEC, m: '125', forgetting: 'fifo' } },
      { label: 'SEC rwd', settings: { ...SEC, m: '125', forgetting: 'rwd' } },
      { label: 'NSEC none', settings: { ...NSEC, m: '125', forgetting: 'none' } },
      { label: 'NSEC rwd', settings: { ...NSEC, m: '125', forgetting: 'rwd' } },
    ],
  },
};

/** The task and episode limit every preset runs in. */
export const PRESET_BASE = { task: 'double-t-maze' };

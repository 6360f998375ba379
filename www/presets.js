// One-click comparisons: the paper's experiments 1-4 in the double T-maze, as settings (the URL
// hash's keys) per configuration, each with what the paper found. At the paper's scale (20 runs
// of 5000 episodes) they take hours; here they show the curves' early shape within minutes, and
// REPRODUCTION.md has the full runs.

const SEC = { bias: '1' };
const NSEC = { bias: '0' };

export const COMPARE_PRESETS = {
  exp1: {
    title: 'Experiment 1: SEC vs NSEC vs MFEC',
    caption: 'The paper (figure 4, table 1): in the double T-maze SEC collects the most reward and its policy '
      + 'entropy falls as it learns; NSEC, the same model without the sequential bias, collects less and its '
      + 'entropy stays high; MFEC, with the same autoencoder, learns far less in the same number of episodes.',
    arms: [
      { label: 'SEC', settings: { ...SEC } },
      { label: 'NSEC', settings: { ...NSEC } },
      { label: 'MFEC', settings: { agent: 'mfec-ae' } },
    ],
  },
  exp2: {
    title: 'Experiment 2: LTM capacity 125 and 1000',
    caption: 'The paper (figures 5 and 6): SEC beats NSEC at every memory size, and the gap grows as memory '
      + 'shrinks (1.5 times with 1000 sequences, 2.5 times with 125); SEC with 125 sequences gets 1.2 times the '
      + 'reward of NSEC with 1000: the sequential bias makes memory an order of magnitude more efficient.',
    arms: [
      { label: 'SEC m=125', settings: { ...SEC, m: '125' } },
      { label: 'NSEC m=125', settings: { ...NSEC, m: '125' } },
      { label: 'SEC m=1000', settings: { ...SEC, m: '1000' } },
      { label: 'NSEC m=1000', settings: { ...NSEC, m: '1000' } },
    ],
  },
  exp3: {
    title: 'Experiment 3: the value function and its ablations',
    caption: 'The paper (figure 7): removing one term of the value (noGi, noRR, noDist) or keeping only one '
      + '(soloGi, soloDist, soloRR) costs a little reward, the distance to the goal the most; every variant still '
      + 'beats the other models of experiment 1.',
    arms: ['default', 'noGi', 'noDist', 'noRR', 'soloGi', 'soloDist', 'soloRR']
      .map((v) => ({ label: `SEC ${v}`, settings: { ...SEC, value: v } })),
  },
  exp4: {
    title: 'Experiment 4: forgetting',
    caption: 'The paper (figure 8): once the LTM is full, forgetting (FIFO, or the lowest reward first) helps '
      + 'both models a little and lowers their entropy, reward-based forgetting the most; the sequential bias '
      + 'matters more than forgetting. m = 125 here so that the memory fills within minutes.',
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

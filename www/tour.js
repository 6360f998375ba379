// The guided tour: one decision, stage by stage, each stage pointing at the view it talks about.
// Started from the Tour button or with `tour` in the page's address (#tour), so a teacher can
// link it. It pauses the run and steps one decision, so the views show a real one.

export const STAGES = [
  {
    target: '#camera', title: 'What the agent sees',
    text: 'This is the agent\'s camera: 84 × 84 pixels, the only thing it senses. Every 4 steps of the '
      + 'simulation it decides what to do, and holds that action until the next decision.',
  },
  {
    target: '#embedding', title: 'Twenty numbers',
    text: 'An encoder turns the image into 20 numbers, the embedding. As in the authors\' code, this encoder '
      + 'is untrained: its weights are random (but fixed for the run), so similar views give similar numbers '
      + 'without the encoder having learnt anything.',
  },
  {
    target: '#reconstruction', title: 'The familiarity check',
    text: 'A second, trained autoencoder rebuilds the image from its own code. Its error is the gate: while '
      + 'it is high the view is unfamiliar and the agent does not trust its memory.',
  },
  {
    target: '#status', title: 'Short- and long-term memory',
    text: 'Each decision adds a couplet (the embedding and the action taken) to the short-term memory, the last '
      + '50 couplets. When the agent reaches a goal, that sequence is stored in the long-term memory (LTM here), '
      + 'with the episode\'s reward.',
  },
  {
    memory: true, target: '#heat', title: 'Recalling: the similarity G',
    text: 'At every decision the current embedding is compared with every stored couplet. Each row here is a '
      + 'stored sequence, each column a position in it (the goal is at the right); brighter is more similar. '
      + 'G is 1 minus the mean absolute difference, times the bias T.',
  },
  {
    memory: true, target: '[data-key="thetaAbs"]', title: 'The thresholds',
    text: 'A couplet is selected (white boxes on the map) only if G exceeds θ_abs and is within a hair of the best '
      + 'G (G / Gmax above θ_prop). Everything else is ignored for this decision.',
  },
  {
    memory: true, target: '[data-key="bias"]', title: 'The sequential bias T',
    text: 'This is what makes SEC sequential. When a couplet is selected, the one after it in its sequence gets '
      + 'a boost (α) at the next decision, decaying back (β) otherwise. So the agent tends to follow a stored '
      + 'path step by step. Switch it off and you have NSEC. The heat map can show T instead of G.',
  },
  {
    memory: true, target: '#explain', title: 'Votes: value and Q',
    text: 'Each selected couplet votes for the action it took, with a value: its G, times how good its '
      + 'sequence\'s reward was (rr), times how close it was to the goal (exp(−d/τ)). Q adds the votes per '
      + 'action. "Explain this decision" lists them.',
  },
  {
    memory: true, target: '#probs', title: 'The draw',
    text: 'Q becomes probabilities p = Q / ΣQ (this grid: move × turn) and the action is drawn from them. The '
      + 'entropy says how undecided the memory is.',
  },
  {
    target: '#why', title: 'Who acts',
    text: 'Memory acts only if it selected something, holds at least 5 sequences, and the view is familiar. '
      + 'Otherwise a reactive random walk acts: that is all you see in the first minutes, until goals fill '
      + 'the memory. This line says which rule decided.',
  },
  {
    target: '#charts', title: 'Learning',
    text: 'Reward, entropy and memory per episode. Press Play and watch SEC find the goal more often; below, '
      + 'Compare runs the paper\'s experiments side by side over reference runs.',
  },
];

/** The tour over the playground in `root` (an element or a shadow root). */
export class Tour {
  constructor(root, { onStart, view }) {
    this.root = root;
    this.view = view;
    this.$ = (id) => root.querySelector(`#${id}`);
    this.onStart = onStart;
    this.stage = -1;
    this.$('tour').addEventListener('click', () => this.start());
    this.$('tour-next').addEventListener('click', () => this.go(this.stage + 1));
    this.$('tour-back').addEventListener('click', () => this.go(this.stage - 1));
    this.$('tour-close').addEventListener('click', () => this.close());
    root.addEventListener('keydown', (e) => { if (e.key === 'Escape' && this.stage >= 0) this.close(); });
  }

  start() {
    this.onStart();
    this.go(0);
  }

  go(i) {
    if (i >= STAGES.length) return this.close();
    this.stage = Math.max(0, i);
    const s = STAGES[this.stage];
    this.highlight(s.target);
    if (s.target === '#explain') this.$('explain').open = true;
    const box = this.$('tour-box');
    box.hidden = false;
    box.querySelector('.tour-count').textContent = `${this.stage + 1} of ${STAGES.length}`;
    this.$('tour-title').textContent = s.title;
    const v = this.view();
    const empty = s.memory && v && v.capacity && v.ltm < v.minSequences;
    // A memory stage over a decision memory did not take: say so, so its votes are not read as the action's cause.
    const notActed = s.memory && v && !empty && v.layer != null && v.layer !== 'C';
    box.querySelector('.tour-text').textContent = s.text + (empty
      ? ` Right now the LTM holds ${v.ltm} of the ${v.minSequences} sequences memory needs, so there is little to see: `
        + 'close the tour and press "Skip the warm-up" (or play at max speed for a minute or two), and take it again.'
      : notActed
        ? ' In this decision memory did not act: the reactive layer chose (stage 10 says why), so what you see here is '
          + 'the vote memory would have cast. Step a few decisions (.) to catch one where memory acts.'
        : '');
    this.$('tour-back').disabled = this.stage === 0;
    this.$('tour-next').textContent = this.stage === STAGES.length - 1 ? 'Done' : 'Next';
    this.$('tour-next').focus();
  }

  highlight(selector) {
    for (const el of this.root.querySelectorAll('.tour-focus')) el.classList.remove('tour-focus');
    const el = this.root.querySelector(selector);
    const box = el?.closest('figure, .param, details, section, dl') ?? el;
    box?.classList.add('tour-focus');
    box?.scrollIntoView?.({ block: 'center', behavior: 'smooth' });
  }

  close() {
    this.stage = -1;
    this.$('tour-box').hidden = true;
    for (const el of this.root.querySelectorAll('.tour-focus')) el.classList.remove('tour-focus');
  }

  get state() {
    const me = this;
    return {
      get stage() { return me.stage; },
      get stages() { return STAGES.length; },
      get focused() { return [...me.root.querySelectorAll('.tour-focus')].map((e) => e.id || e.className); },
    };
  }
}

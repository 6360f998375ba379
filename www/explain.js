// What the page says about a decision: why the reactive layer acted (the warm-up made visible),
// and the contextual layer's sum term by term.

const ACTION_NAMES = ['none', 'right', 'left', 'forward', 'forward right', 'forward left', 'back', 'back right', 'back left'];

/**
 * One line on who acted and why: for an agent with a sequential memory (the agent table's
 * `hasMemory`: SEC) the first rule of the arbitration that kept its memory from acting (too few
 * sequences, nothing passed the thresholds, the reconstruction gate); for the others the table's
 * `explores` line. `agent` is the table's row of the running agent.
 */
export function whyLayer(view, agent) {
  if (!view || view.layer == null) return 'No decision yet.';
  if (view.layer === 'H') return 'You are driving: your action is taken.';
  if (view.layer === 'C') {
    return `Memory acts: ${view.selected} stored couplet${view.selected === 1 ? '' : 's'} passed the thresholds and voted.`;
  }
  if (!agent?.hasMemory) return agent?.explores ?? 'Reactive walk.';
  if (view.ltm < view.minSequences) {
    const more = view.minSequences - view.ltm;
    return `Reactive walk: memory holds ${view.ltm} of the ${view.minSequences} sequences ${agent.label} needs before it acts `
      + `from memory (${more} more; a sequence is stored at every goal).`;
  }
  if (!view.selected) return 'Reactive walk: no stored couplet passed the thresholds θ_abs and θ_prop for this view.';
  if (view.gate != null && view.gateMse == null) {
    return 'Reactive walk: the reconstruction gate has not measured a view yet (it does every 16 steps), '
      + 'so memory is not trusted.';
  }
  if (view.gate != null && view.gateMse >= view.gate) {
    return `Reactive walk: reconstruction error ${view.gateMse.toFixed(4)} is above the gate's ${+view.gate.toPrecision(4)}, `
      + 'so this view is unfamiliar and memory is not trusted.';
  }
  return 'Reactive walk.';
}

const fmt = (x, d = 4) => (Math.abs(x) >= 1e4 || (x !== 0 && Math.abs(x) < 1e-3) ? x.toExponential(2) : x.toFixed(d));

/** Who took the decision, said first. */
const ACTED = {
  C: 'Memory acted (the contextual layer): the action was drawn from its vote p below.',
  R: 'The reactive layer acted: its walk chose the action. Memory\'s vote below was not acted on.',
  H: 'You acted (driving): your action was taken. Memory\'s vote below was not acted on.',
};

/**
 * The explain panel: first which layer acted (`layer`: C, R or H), then the selected couplets'
 * terms and their sum into Q and p per action.
 */
export function drawExplanation(root, e, layer) {
  const body = root.querySelector('tbody');
  const foot = root.querySelector('tfoot');
  const formula = root.querySelector('.formula');
  const acted = ACTED[layer] ?? '';
  if (!e || !e.couplets.length) {
    body.replaceChildren();
    foot.replaceChildren();
    const who = layer === 'H' ? 'You acted (driving): your action was taken.' : 'The reactive layer acted.';
    formula.textContent = `${who} No stored couplet passed the thresholds at this decision, so memory had no `
      + 'vote. Step on until memory selects something.';
    return;
  }
  const g = e.sequentialBias ? 'G = (1 − MAE) × T' : 'G = 1 − MAE (no bias: NSEC)';
  const v = {
    default: 'G × rr × exp(−d/τ)', noGi: 'rr × exp(−d/τ)', noDist: 'G × rr', noRR: 'G × exp(−d/τ)',
    soloGi: 'G', soloDist: 'exp(−d/τ)', soloRR: 'rr',
  }[e.valueFunction];
  formula.textContent = `${acted} Selected: ${g} > θ_abs ${e.thetaAbs} and G / Gmax > θ_prop ${e.thetaProp}. `
    + `Each votes value = ${v} (τ = ${e.tau}; rr: its sequence's reward over the best selected; `
    + 'd: its distance to the goal, (n − position) / n) for its action; Q sums the votes per action and '
    + 'p = Q / ΣQ is what the 3×3 grid shows'
    + ({ C: '; the action was drawn from p.', H: ', the vote your driving overrode.' }[layer]
      ?? ', the vote the reactive layer overrode.');
  formula.textContent = formula.textContent.trim();
  const rows = e.couplets.slice(0, 200).map((c) => {
    const tr = document.createElement('tr');
    for (const x of [c.sequence, c.position, fmt(c.g), fmt(c.t), fmt(c.rr, 3), fmt(c.d, 3), ACTION_NAMES[c.action], fmt(c.value)]) {
      const td = document.createElement('td');
      td.textContent = String(x);
      tr.append(td);
    }
    return tr;
  });
  if (e.couplets.length > 200) {
    const tr = document.createElement('tr');
    tr.innerHTML = `<td colspan="8">… and ${e.couplets.length - 200} more</td>`;
    rows.push(tr);
  }
  body.replaceChildren(...rows);
  const sums = e.q.map((q, a) => ({ a, q, p: e.p[a] })).filter((s) => s.q > 0);
  foot.replaceChildren(...sums.map((s) => {
    const tr = document.createElement('tr');
    tr.className = 'sum';
    tr.dataset.action = String(s.a);
    tr.innerHTML = `<th colspan="6">Q(${ACTION_NAMES[s.a]}) = sum of its values</th><td>${ACTION_NAMES[s.a]}</td>`;
    const q = document.createElement('td');
    q.textContent = `${fmt(s.q)} → p ${s.p.toFixed(2)}`;
    q.dataset.q = String(s.q);
    tr.append(q);
    return tr;
  }));
}

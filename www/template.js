// The playground's markup, shared by the page (index.html, embed.html) and the
// <sec-playground> element (in its shadow root, where the ids are its own).

export const TEMPLATE = `
<div class="playground">
  <section class="runbar" aria-label="Run control">
    <button id="play" type="button" title="Play or pause (space)">Play</button>
    <button id="step-decision" type="button" title="Step one decision (.)">Step decision</button>
    <button id="step-episode" type="button" title="Step one episode (e)">Step episode</button>
    <button id="reset" type="button" title="Restart the run with the same seed (r)">Reset</button>
    <label class="speed" title="Decisions per second; at max only the charts are drawn">Speed
      <input id="speed" type="range" min="0" max="9" step="1" value="8">
      <output id="speed-out">1000/s</output>
    </label>
    <button id="tour" type="button" title="A guided tour through one decision (or add #tour to the address)">Tour</button>
    <button id="to-controls" class="to-controls" type="button" title="Jump to the settings, below the views">Settings ↓</button>
    <span class="presets">Preset
      <button id="preset-code" type="button" title="The authors' code: θ_abs 0.98, θ_prop 0.995, α 0.01">code</button>
      <button id="preset-paper" type="button" title="The paper's text: θ_abs 0.995, θ_prop 0.98, α 0.1 (D2, D3)">paper</button>
    </span>
    <dl id="status" class="status" aria-live="off"></dl>
    <button id="reward-help" class="help-button" type="button" aria-expanded="false" aria-controls="reward-note"
      title="What reward and raw mean">reward?</button>
  </section>
  <p id="reward-note" class="note reward-note" hidden><strong>reward</strong>: the episode's return as the paper's
    tables count it, the goal's reward less 1/t for every env step (t: the episode limit), and 0 when that is below
    0 (no goal reached). <strong>raw</strong>: that sum before the floor, shown when it is below 0. The charts show
    the reward; the CSV has both.</p>
  <section class="keepbar" aria-label="Drive, export and memory files">
    <button id="drive" type="button" aria-pressed="false"
      title="Drive the agent yourself with the arrow keys or the on-screen pad (d); the run slows to a watchable speed">Drive</button>
    <label title="Store a rewarded episode you drive in SEC's long-term memory, like any other sequence">
      <input id="record" type="checkbox"> record</label>
    <span class="sep"></span>
    <button id="export-csv" type="button" title="Per-episode metrics of this run and the compared runs">Export CSV</button>
    <button id="export-json" type="button" title="The configuration: settings, RunConfig and seed">Export JSON</button>
    <button id="save-memory" type="button" title="SEC's memory (STM and LTM) as a file">Save memory</button>
    <button id="warm-up" type="button"
      title="Start again from the memory a reference run of this task had after its first 200 episodes, with that run's seed: a learned SEC at once">Skip the warm-up</button>
    <label class="file" title="Load a saved memory into this run (same task, encoder and n)">Load memory…
      <input id="load-memory" type="file" accept=".secmem,application/octet-stream"></label>
  </section>
  <p id="main-paused" class="note paused-note" hidden>This run is paused while the comparison below plays, so
    that the comparison has the machine. <button id="main-resume" type="button">Resume it</button></p>
  <p id="error" class="error" role="alert" hidden></p>
  <p id="notice" class="notice" aria-live="polite"></p>
  <p id="arena-note" class="note arena-note" hidden>Olympics arena <strong class="arena-name"></strong>: SEC learns it with
    the untrained encoder (random weights drawn from the seed: nothing to train) and without the reconstruction gate,
    since no model was trained on this arena. <a href="arena.html">Other arenas</a> ·
    <a href="index.html">the paper's tasks</a></p>
  <div class="layout">
    <section id="controls" class="controls" aria-label="Parameters"></section>
    <section class="views" aria-label="What the agent sees and remembers">
      <figure class="camera">
        <canvas id="camera" width="84" height="84" aria-label="The agent's first-person camera, 84 by 84"></canvas>
        <figcaption>Camera (84×84)</figcaption>
        <div id="drive-pad" class="drive-pad" role="group" aria-label="Drive: touch and hold" hidden>
          <button type="button" data-action="5" aria-label="forward left">↖</button>
          <button type="button" data-action="3" aria-label="forward">↑</button>
          <button type="button" data-action="4" aria-label="forward right">↗</button>
          <button type="button" data-action="2" aria-label="turn left">↶</button>
          <button type="button" data-action="0" aria-label="stand still">■</button>
          <button type="button" data-action="1" aria-label="turn right">↷</button>
          <button type="button" data-action="8" aria-label="back left">↙</button>
          <button type="button" data-action="6" aria-label="back">↓</button>
          <button type="button" data-action="7" aria-label="back right">↘</button>
        </div>
      </figure>
      <figure class="policy">
        <table id="probs" aria-label="Action probabilities">
          <thead><tr><th></th><th>none</th><th>right</th><th>left</th></tr></thead>
          <tbody></tbody>
        </table>
        <div class="entropy"><span title="Shannon entropy of memory's vote p, in bits (0: one action; 3.17: all nine equal)">entropy of p</span><meter id="entropy-meter" min="0" max="3.17"></meter><output id="entropy"></output></div>
        <div class="layer">acting layer: <output id="layer">–</output></div>
        <p id="why" class="why"></p>
        <figcaption id="policy-caption">Action probabilities p (3×3 grid)</figcaption>
      </figure>
      <div id="chart-slot" class="chart-slot" aria-label="Reward per episode"></div>
      <figure class="arena">
        <canvas id="arena" width="252" height="252" aria-label="Top-down view of the arena with the agent's trail"></canvas>
        <figcaption>Top-down: agent, heading, trail</figcaption>
      </figure>
      <figure class="embedding">
        <canvas id="embedding" width="252" height="70" aria-label="The encoder's 20 numbers for the last decision's frame"></canvas>
        <figcaption>Embedding: the encoder's 20 numbers for this frame</figcaption>
      </figure>
      <figure class="reconstruction">
        <canvas id="reconstruction" width="84" height="84" aria-label="The autoencoder's reconstruction of the camera image"></canvas>
        <figcaption>Autoencoder reconstruction (the trained model); error
          <output id="gate-mse" title="Mean squared reconstruction error of the last measured frame; memory may act only while it is below the gate">–</output></figcaption>
      </figure>
      <figure class="heat">
        <canvas id="heat" width="252" height="252" aria-label="Long-term memory heat map"></canvas>
        <div class="heat-legend" aria-hidden="true">
          <span id="heat-lo"></span><canvas id="heat-scale" width="120" height="10"></canvas><span id="heat-hi"></span>
        </div>
        <figcaption>LTM: one row per stored sequence (oldest at the top), one column per STM position
          (newest, nearest the goal, at the right);
          <select id="heat-kind" aria-label="Heat map quantity">
            <option value="g">G (biased similarity)</option>
            <option value="t">T (sequential bias)</option>
          </select>; white boxes: selected</figcaption>
      </figure>
    </section>
  </div>
  <aside id="tour-box" class="tour-box" role="dialog" aria-labelledby="tour-title" hidden>
    <p class="tour-count"></p>
    <h3 id="tour-title"></h3>
    <p class="tour-text"></p>
    <div class="tour-buttons">
      <button id="tour-back" type="button">Back</button>
      <button id="tour-next" type="button">Next</button>
      <button id="tour-close" type="button">Close</button>
    </div>
  </aside>
  <details id="explain" class="explain">
    <summary>Explain this decision</summary>
    <p class="formula">Pause or step to see the last decision explained.</p>
    <table>
      <thead><tr><th>sequence</th><th>position</th><th>G</th><th>T</th><th>rr</th><th>d</th><th>action</th><th>value</th></tr></thead>
      <tbody></tbody>
      <tfoot></tfoot>
    </table>
  </details>
  <section id="charts" class="charts" aria-label="Learning curves"></section>
  <section id="compare" class="compare" aria-label="Compare configurations">
    <h2>Compare</h2>
    <p class="help">Run several configurations with the same seeds, to the paper's horizon: a pool of workers
      plays one run (a configuration and a seed) each at a time. The chart overlays their 20-episode mean
      reward, with a band of ± one standard error across the seeds played so far.</p>
    <div class="compare-bar">
      <span>Paper's experiments:
        <button id="compare-exp1" type="button">1: SEC vs NSEC vs MFEC</button>
        <select id="compare-task" aria-label="Experiment 1's task">
          <option value="double-t-maze">in the double T-maze</option><option value="detour">in the detour</option>
          <option value="cylinder">in the cylinder</option><option value="object-permanence">in object permanence</option>
        </select>
        <button id="compare-exp2" type="button">2: LTM 125–1000</button>
        <button id="compare-exp3" type="button">3: value function</button>
        <button id="compare-exp4" type="button">4: forgetting</button>
      </span>
      <button id="compare-add" type="button" title="Add the settings in force above as a configuration">Add current settings</button>
      <label>seeds <select id="compare-seeds">
        <option>1</option><option>2</option><option selected>3</option><option>4</option><option>5</option>
      </select></label>
      <label title="Episodes each run plays (the paper's horizon is 5000)">episodes
        <input id="compare-episodes" type="number" min="10" max="20000" step="10" value="5000" inputmode="numeric"></label>
      <label title="Runs played at once, one per worker: the machine's threads less one, or fewer">workers
        <select id="compare-workers"></select></label>
      <label>chart <select id="compare-metric">
        <option value="reward">reward</option><option value="entropy">entropy</option>
        <option value="decisions">decisions</option>
      </select></label>
      <button id="compare-run" type="button">Start</button>
      <button id="compare-clear" type="button">Clear</button>
      <label title="The x axis follows the live runs; tick to see the reference runs' whole length">
        <input id="compare-full" type="checkbox"> reference runs' full length</label>
      <button id="compare-zoom-reset" type="button" title="Drag across the chart to zoom; this goes back">Reset zoom</button>
    </div>
    <p id="compare-caption" class="caption"></p>
    <details id="compare-more" class="caption" hidden><summary>more</summary><p id="compare-more-text"></p></details>
    <p id="compare-progress" class="note" aria-live="off"></p>
    <p id="compare-reference" class="note" aria-live="polite"></p>
    <ol id="compare-arms" class="arms"></ol>
    <div id="compare-chart" class="compare-chart"></div>
  </section>
</div>`;

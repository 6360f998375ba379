// The <sec-playground> element and its settings (docs/EMBED.md). `SecPlaygroundSettings` lists every
// key of the core's settings table with its values; tests/browser/package.test.mjs checks it against
// the table, so a setting added to the core without its declaration fails there.

/** The settings: the URL hash's keys (attributes may be written in kebab case: `theta-abs`). Values
 * go in as strings or numbers and come back as the strings the hash holds. */
export interface SecPlaygroundSettings {
  task: 'double-t-maze' | 'detour' | 'detour-transparent' | 'cylinder' | 'object-permanence' | 'object-permanence-pits';
  agent: 'sec' | 'mfec-ae' | 'mfec-rp' | 'reactive';
  perception: 'untrained' | 'trained';
  surface: 'flat' | 'textured';
  /** (0, 1000000] or 'auto'. */
  embeddingScale: number | 'auto';
  /** The sequential bias T: 1 is SEC, 0 is NSEC. */
  bias: 0 | 1 | '0' | '1';
  /** [0, 1] */
  alpha: number;
  /** [0, 1] */
  beta: number;
  /** [0.01, 100] */
  tau: number;
  /** [0, 2] */
  thetaAbs: number;
  /** [0, 1] */
  thetaProp: number;
  /** 1 - 1000 */
  n: number;
  /** 1 - 100000 */
  m: number;
  /** 0 - 100000 */
  minSequences: number;
  forgetting: 'none' | 'fifo' | 'rwd' | 'rwd-prop' | 'prior';
  value: 'default' | 'noGi' | 'noDist' | 'noRR' | 'soloGi' | 'soloDist' | 'soloRR';
  /** 0 - 100000 */
  t: number;
  startHeading: 'random' | 'fixed';
  /** 0 - 2^53 - 1 */
  seed: number;
}

/** Settings as they come back: every key, as the string the URL hash holds. */
export type SecPlaygroundSettingStrings = { [K in keyof SecPlaygroundSettings]: string };

/** Where the run is (`getState`, and the `state` event without `ltm`, `capacity` and `settings`). */
export interface SecPlaygroundState {
  /** Asked to play. */
  playing: boolean;
  /** Stepping now: not while off screen, in a hidden tab or paused for a comparison. */
  running: boolean;
  decisions: number;
  episode: number;
  ltm: number;
  capacity: number | null;
  settings: SecPlaygroundSettingStrings | null;
}

/** One finished episode: a row of the CSV export. */
export interface SecPlaygroundEpisode {
  episode: number;
  layout: string;
  reward: number;
  rawReward: number;
  goal: boolean;
  envSteps: number;
  decisions: number;
  entropy: number;
  entropyFresh: number | null;
  ltm: number;
  contextualShare: number;
  human?: boolean;
  census?: unknown;
}

/** What `configure` applied: live (from the next decision), a new run, or nothing new. */
export interface SecPlaygroundApplied {
  applied: 'live' | 'restart' | 'unchanged';
  changes: Partial<SecPlaygroundSettingStrings>;
  settings: SecPlaygroundSettingStrings;
}

export interface SecPlaygroundEventMap {
  ready: CustomEvent<{ version: number; settings: SecPlaygroundSettingStrings }>;
  episode: CustomEvent<SecPlaygroundEpisode>;
  state: CustomEvent<SecPlaygroundState>;
  error: CustomEvent<{ message: string }>;
  /** Settings changed after the first run started (a control, a shortcut, the API). */
  settings: CustomEvent<{ applied: 'live' | 'restart' | 'unchanged'; changes: Partial<SecPlaygroundSettingStrings> | null; settings: SecPlaygroundSettingStrings }>;
  /** A new run began: its episodes count from 1. */
  run: CustomEvent<{ settings: SecPlaygroundSettingStrings }>;
  /** The last decision explained (while paused or stepping). */
  explanation: CustomEvent<Record<string, unknown>>;
}

export declare class SecPlaygroundElement extends HTMLElement {
  play(): SecPlaygroundState;
  pause(): SecPlaygroundState;
  reset(): Promise<SecPlaygroundState>;
  step(what?: 'decision' | 'episode'): Promise<SecPlaygroundState>;
  configure(settings: Partial<SecPlaygroundSettings>): Promise<SecPlaygroundApplied>;
  getState(): SecPlaygroundState;
  getMetrics(format?: 'rows'): SecPlaygroundEpisode[];
  getMetrics(format: 'csv'): string;
  saveMemory(): Promise<ArrayBuffer>;
  loadMemory(bytes: ArrayBuffer | ArrayBufferView): Promise<{ sequences: number }>;
  addEventListener<K extends keyof SecPlaygroundEventMap>(type: K, listener: (this: SecPlaygroundElement, ev: SecPlaygroundEventMap[K]) => unknown, options?: boolean | AddEventListenerOptions): void;
  addEventListener(type: string, listener: EventListenerOrEventListenerObject, options?: boolean | AddEventListenerOptions): void;
}

declare global {
  interface HTMLElementTagNameMap {
    'sec-playground': SecPlaygroundElement;
  }
}

// The TypeScript declarations of the values the wasm adapter (`SecRun`, `parameters()`,
// `agents()`, `tasks()`) hands to JS; wasm-bindgen appends them to the package's .d.ts.
// tests/typescript.rs checks them against the core's tables and configuration and lists what
// is missing.
/** What `SecRun.configure` did: "live" or "restart", and each field it changed (its path,
 *  old and new values, and whether a change of it alone acts live). */
export interface ConfigChange {
  applied: "live" | "restart";
  changed: { field: string; from: unknown; to: unknown; live: boolean }[];
}

/** A run's configuration (every field optional; defaults are the authors' code). Each agent's
 *  section (`agent` for SEC's, `mfec`) is declared by its agent's module and
 *  merged into this interface; the native agents' (`dqn`, `erlam`) are kept as given, unchecked. */
export interface RunConfig {
  task?: string;
  /** Episode limit in env steps (null: the task's, 1000). */
  t?: number | null;
  decisionPeriod?: number;
  /** The agent's kind: the `kind` the agent table lists ("dqn" and "erlam" run only natively,
   *  through sec-experiment: the page refuses them by name). */
  kind?: string;
  /** Which encoder embeds the frames: untrained (the authors' code, the default) or trained. */
  perception?: "untrained" | "trained";
  /** Replaces the embedding scale, in (0, 1e6] (null: 1 untrained, the calibrated scale trained). */
  embeddingScale?: number | null;
  rawEmbeddings?: boolean;
  startHeading?: "random" | "fixed";
  /** How the camera draws the floor and fences: flat colours (the default) or v1's textures. */
  surface?: "flat" | "textured";
  /** An Animal-AI arena file's YAML text, played instead of a preset task (`task` names it): see
   *  `withArena`, which also sets what an arena without a trained model needs. */
  arena?: string;
}
/** One finished episode, as the paper's tables count it. */
export interface EpisodeMetrics {
  episode: number; layout: string; reward: number; rawReward: number; goal: boolean;
  envSteps: number; decisions: number; entropy: number; entropyFresh: number | null;
  ltm: number; contextualShare: number;
  /** Present and true when a person drove part of the episode. */
  human?: boolean;
  /** The agent's census of its memory, where it logs one (ERLAM natively; never on the page). */
  census?: { nodes: number; valuedShare: number; medianValue: number };
}
/** One of the page's settings, with its range. */
export interface Param {
  key: string; symbol: string; help: string; live: boolean;
  /** The page's group of controls, and the agents that read it (empty: all). */
  group: "run" | "perception" | "memory" | "retrieval"; agents: string[];
  kind: { type: "number"; min: number; max: number; minOpen: boolean; step: number; auto: boolean }
    | { type: "integer"; min: number; max: number }
    | { type: "choice"; options: string[] }
    | { type: "switch" };
}
/** One agent of the core's table (`agents()`): the page reads agents through it alone. */
export interface AgentInfo {
  /** Its name everywhere: the `agent` setting, the CLI, Python. */
  key: string; label: string;
  /** Its label with the sequential bias off (SEC: NSEC), for an agent that has one. */
  unbiasedLabel: string | null;
  about: string;
  /** Why its decision was not its memory's, unless its views explain that (SEC). */
  explores: string | null;
  /** The RunConfig section of its parameters. */
  section: string | null;
  reads: "embedding" | "image" | "nothing";
  hasMemory: boolean; hasGate: boolean; nativeOnly: boolean; canBeDriven: boolean;
  /** The RunConfig `kind` and `mfec.embedding` that run it. */
  kind: string; mfecEmbedding: "autoencoder" | "random-projection" | null;
}
/** One built-in task of the core's table (`tasks()`). */
export interface TaskInfo {
  /** Its name everywhere (RunConfig.task, the URL hash). */
  name: string;
  /** As a sentence writes it ("the double T-maze"). */
  title: string; description: string;
  /** Its Gymnasium id (sec_playground registers it). */
  gymId: string;
  /** Its trained autoencoder, under assets/encoders/. */
  modelFile: string;
}
/** Settings (URL hash keys to values) with the run they describe. */
export interface ParsedSettings {
  config: RunConfig; seed: number; settings: Record<string, string>; errors: string[];
}
/** The last decision and the state the page's views show. */
export interface DecisionView {
  action: number | null; layer: "R" | "C" | "H" | null; selected: number; entropy: number;
  p: number[] | null;
  /** The reconstruction error the gate measured last (null before its first measurement). */
  gateMse: number | null; ltm: number; capacity: number;
  episode: number; step: number; episodeReward: number; x: number; z: number; heading: number;
  /** Decisions since the run started (a rate is its change over time). */
  decisions: number;
  /** SEC acts from memory only once the LTM holds this many sequences. */
  minSequences: number;
  /** The reconstruction gate's threshold (null: no gate). */
  gate: number | null;
  /** The 20 numbers the perception made of the last decision's frame (null without SEC). */
  embedding: number[] | null;
}
/** The last decision's contextual layer, term by term (empty when it selected nothing). */
export interface Explanation {
  /** Each selected couplet: LTM sequence and STM position, G = similarity x T, T, relative reward, distance, the action it votes for and its value. */
  couplets: { sequence: number; position: number; g: number; t: number; rr: number; d: number; action: number; value: number }[];
  /** Q per action (the sum of its couplets' values) and p = Q / sum Q. */
  q: number[]; p: number[];
  tau: number; valueFunction: string; thetaAbs: number; thetaProp: number; sequentialBias: boolean;
}

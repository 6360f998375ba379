// A host page's side of the iframe protocol (docs/EMBED.md).
import type { SecPlaygroundApplied, SecPlaygroundEpisode, SecPlaygroundSettings, SecPlaygroundSettingStrings, SecPlaygroundState } from './element.js';

export declare const PROTOCOL: 'sec-playground';
export declare const VERSION: 1;

export interface HostEvents {
  ready: { version: number; settings: SecPlaygroundSettingStrings };
  episode: SecPlaygroundEpisode;
  state: Pick<SecPlaygroundState, 'playing' | 'running' | 'decisions' | 'episode'>;
  error: { message: string };
  height: { height: number };
}

export interface HostCommands {
  connect: [{}, { version: number; settings: SecPlaygroundSettingStrings | null }];
  play: [{}, SecPlaygroundState];
  pause: [{}, SecPlaygroundState];
  reset: [{}, SecPlaygroundState];
  step: [{ what?: 'decision' | 'episode' }, SecPlaygroundState];
  configure: [{ settings: Partial<SecPlaygroundSettings> }, SecPlaygroundApplied];
  getState: [{}, SecPlaygroundState];
  getMetrics: [{ format?: 'rows' | 'csv' }, SecPlaygroundEpisode[] | string];
  saveMemory: [{}, ArrayBuffer];
  loadMemory: [{ bytes: ArrayBuffer | ArrayBufferView }, { sequences: number }];
}

export interface Connection {
  ready: Promise<HostEvents['ready']>;
  command<K extends keyof HostCommands>(type: K, payload?: HostCommands[K][0]): Promise<HostCommands[K][1]>;
  on<K extends keyof HostEvents>(type: K, f: (payload: HostEvents[K]) => void): () => void;
  close(): void;
}

export declare function connect(iframe: HTMLIFrameElement, options?: { origin?: string }): Connection;

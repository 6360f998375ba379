// What both simulation workers share: stepping in time slices with a batch size that adapts to
// the machine, and handling messages one at a time, in order.
import { takeFileAnswer } from './files.js';

/** Longest time slice of simulation before yielding to messages (ms). */
export const SLICE_MS = 12;

/**
 * Decisions per wasm call, adapted so that one call takes `share` of a slice: big batches cost
 * little per call, small ones keep the slice (and so the page's response) short.
 */
export class AdaptiveBatch {
  constructor(size, max, share) {
    this.size = size;
    this.max = max;
    this.share = share;
  }

  /** Calls `work(size)` until the slice is used up, adapting `size` after each call. */
  fillSlice(work) {
    const t0 = performance.now();
    while (performance.now() - t0 < SLICE_MS) {
      const s0 = performance.now();
      work(this.size);
      const took = Math.max(performance.now() - s0, 0.05);
      this.size = Math.max(1, Math.min(this.max, Math.round(this.size * ((SLICE_MS * this.share) / took))));
    }
  }
}

/**
 * Runs `fn` as a new task, after the messages already queued (so a pause still gets in between
 * two slices). Not `setTimeout(fn, 0)`: once nested, a timer waits at least 4 ms (the HTML
 * timer clamp), which took a quarter of every 12 ms slice at full speed.
 */
export function soon(fn) {
  waiting.push(fn);
  channel.port2.postMessage(null);
}
const waiting = [];
const channel = new MessageChannel();
channel.port1.onmessage = () => waiting.shift()?.();

/**
 * Runs `handlers[data.type](data)` for each message, one at a time and in order (a handler that
 * fetches a model finishes before the next starts); a thrown error, or an unknown type, goes to
 * `onError(error, id)`. A message with an `id` (a request of the page's API) is answered with
 * `{type: 'done', id, result}`, the handler's value, after everything the handler posted, or its
 * error carries the `id`.
 */
export function serveMessages(handlers, onError) {
  let queue = Promise.resolve();
  self.onmessage = ({ data }) => {
    if (takeFileAnswer(data)) return; // a file the running handler may be waiting for
    const h = handlers[data?.type];
    const id = data?.id;
    if (!h) return onError(new Error(`unknown message '${data?.type}'`), id);
    queue = queue.then(() => h(data)).then((result) => {
      if (id != null) self.postMessage({ type: 'done', id, result });
    }).catch((e) => onError(e, id));
  };
}

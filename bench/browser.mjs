// What the browser benchmarks share: the repository served on a free port and Debian's Chromium
// (a test tool's own browser download does not work here).
import { chromium } from 'playwright-core';
import { serve } from '../scripts/serve.mjs';

/** Flags that keep a benchmark's timers and renderer at full speed when its page is not in front. */
export const UNTHROTTLED = ['--disable-background-timer-throttling', '--disable-renderer-backgrounding'];

/** Starts the server and the browser with `args` beside the usual flags: `{server, browser, base}`. */
export async function openChromium(args = []) {
  const server = await serve(0);
  const base = `http://127.0.0.1:${server.address().port}/`;
  const browser = await chromium.launch({
    executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
    args: ['--no-sandbox', '--disable-gpu', ...args],
  });
  return { server, browser, base };
}

/** Sets the page's speed slider to its last stop, max speed. */
export function maxSpeed(page) {
  return page.evaluate(() => {
    const s = document.getElementById('speed');
    s.value = s.max;
    s.dispatchEvent(new Event('input'));
  });
}

// Shared by the browser tests: a static server for the repository and Debian's Chromium driven
// by playwright-core (a test tool's own browser download does not work here).
import { mkdirSync } from 'node:fs';
import { chromium } from 'playwright-core';
import { serve } from '../../scripts/serve.mjs';

/** Where screenshots go. */
export const ARTIFACTS = new URL('../../test-artifacts/', import.meta.url);

/** Starts the server and the browser: `{server, browser, base}`; close both in `after`. */
export async function launch() {
  mkdirSync(ARTIFACTS, { recursive: true });
  const server = await serve(0);
  const base = `http://127.0.0.1:${server.address().port}/`;
  const browser = await chromium.launch({
    executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
    args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking',
      '--disable-component-update', '--disable-sync'],
  });
  return { server, browser, base };
}

/** Distinct colours on a canvas (`selector`): a blank canvas has one. */
export function colours(page, selector) {
  return page.evaluate((selector) => {
    const c = document.querySelector(selector);
    const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    const seen = new Set();
    for (let i = 0; i < d.length; i += 4) seen.add((d[i] << 16) | (d[i + 1] << 8) | d[i + 2]);
    return seen.size;
  }, selector);
}

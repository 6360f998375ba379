// A static file server for the playground (no dependencies). Usage: node scripts/serve.mjs [port]
// Serves the repository root, so index.html, www/ and pkg/ resolve as on any static host.
import { createServer } from 'node:http';
import { readFile, stat } from 'node:fs/promises';
import { extname, join, normalize, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = resolve(fileURLToPath(new URL('..', import.meta.url)));
const TYPES = {
  '.html': 'text/html; charset=utf-8', '.js': 'text/javascript; charset=utf-8', '.mjs': 'text/javascript; charset=utf-8',
  '.css': 'text/css; charset=utf-8', '.wasm': 'application/wasm', '.json': 'application/json', '.png': 'image/png',
  '.svg': 'image/svg+xml', '.secae': 'application/octet-stream', '.yml': 'text/yaml', '.yaml': 'text/yaml', '.ts': 'text/plain; charset=utf-8',
};

/**
 * Serves `dir` (default: the repository) on `port` (0: any free one); resolves to the server.
 * Every answer allows loading from any origin (`Access-Control-Allow-Origin: *`), as static hosts
 * such as GitHub Pages do, so that embed.html runs in a frame sandboxed without
 * allow-same-origin; `cors: false` leaves the header out (a host that does not send it).
 */
export function serve(port = 8080, host = '127.0.0.1', dir = root, { cors = true } = {}) {
  const allow = cors ? { 'access-control-allow-origin': '*' } : {};
  const server = createServer(async (req, res) => {
    try {
      const path = decodeURIComponent(new URL(req.url, 'http://x').pathname);
      let file = normalize(join(dir, path));
      if (!file.startsWith(dir)) { res.writeHead(403).end(); return; }
      if ((await stat(file)).isDirectory()) file = join(file, 'index.html');
      const body = await readFile(file);
      res.writeHead(200, { 'content-type': TYPES[extname(file)] ?? 'application/octet-stream', 'cache-control': 'no-cache', ...allow });
      res.end(body);
    } catch {
      res.writeHead(404, { 'content-type': 'text/plain', ...allow }).end('not found');
    }
  });
  return new Promise((ok) => server.listen(port, host, () => ok(server)));
}

if (process.argv[1] && resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  const port = Number(process.argv[2] ?? process.env.PORT ?? 8080);
  await serve(port);
  console.log(`SEC Playground at http://127.0.0.1:${port}/`);
}

// Serves the repository over HTTP for the three.js example (no dependencies):
//   node examples/three/serve.mjs [port]    then open http://localhost:8080/examples/three/
// three.js comes from tests/node/node_modules (`npm ci --prefix tests/node`), the
// package from generated/three/airlight-three (`cargo run --release -- regenerate`).
import { createServer } from 'node:http';
import { readFile } from 'node:fs/promises';
import { extname, join, normalize, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = resolve(fileURLToPath(new URL('../..', import.meta.url)));
const port = Number(process.argv[2] ?? 8080);
const types = { '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript', '.json': 'application/json', '.css': 'text/css' };

createServer(async (req, res) => {
  const path = normalize(decodeURIComponent(new URL(req.url, 'http://x').pathname));
  const file = join(root, path.endsWith('/') ? join(path, 'index.html') : path);
  if (!file.startsWith(root)) {
    res.writeHead(403).end();
    return;
  }
  try {
    const body = await readFile(file);
    res.writeHead(200, { 'content-type': types[extname(file)] ?? 'application/octet-stream' }).end(body);
  } catch {
    res.writeHead(404).end(`not found: ${path}`);
  }
}).listen(port, '127.0.0.1', () => console.log(`http://localhost:${port}/examples/three/`));

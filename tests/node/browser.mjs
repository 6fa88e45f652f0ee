// The browser of the three.js tests (shaders/tests/browser/driver.rs): one headless
// Chromium, launched once by playwright-core (pinned in package.json) from the
// machine's own executable, serves every page a test binary draws.
//
//   node tests/node/browser.mjs CHROMIUM
//
// Reads one request per line on stdin, `{"dir", "page", "timeout_s", "what"}`: the page
// `page` (a path and query) is loaded as http://127.0.0.1/<page> in a fresh
// browser context whose every request is answered from the files under `dir`
// (nothing reaches the network); the page POSTs its result to /result. Answers
// each request with `ok <bytes>\n<result>` or `error <bytes>\n<why>` on stdout
// (bytes: the UTF-8 length of what follows), and prints the page's time and
// `what` (the test drawing it) on stderr. Ends when stdin closes.
// AIRLIGHT_CHROMIUM_ARGS adds flags to Chromium's.
import { chromium } from 'playwright-core';
import { readFile } from 'node:fs/promises';
import { createInterface } from 'node:readline';
import path from 'node:path';

const executablePath = process.argv[2];
if (!executablePath) {
  console.error('usage: node browser.mjs CHROMIUM');
  process.exit(2);
}
const ORIGIN = 'http://127.0.0.1:8123';
const ARGS = [
  '--no-sandbox',
  '--disable-gpu-sandbox',
  '--use-angle=swiftshader',
  '--enable-unsafe-swiftshader',
  '--enable-unsafe-webgpu',
  '--use-webgpu-adapter=swiftshader',
  '--ignore-gpu-blocklist',
  ...(process.env.AIRLIGHT_CHROMIUM_ARGS ?? '').split(' ').filter((a) => a),
];
const TYPES = { '.js': 'text/javascript', '.mjs': 'text/javascript', '.html': 'text/html; charset=utf-8', '.json': 'application/json' };

let browser = null;
async function theBrowser() {
  if (!browser || !browser.isConnected()) {
    browser = await chromium.launch({ executablePath, headless: true, args: ARGS });
  }
  return browser;
}

function reply(kind, text) {
  const body = Buffer.from(text, 'utf8');
  process.stdout.write(`${kind} ${body.length}\n`);
  process.stdout.write(body);
}

let pages = 0;
async function draw({ dir, page, timeout_s, what }) {
  const started = Date.now();
  pages += 1;
  const context = await (await theBrowser()).newContext();
  const log = [];
  let report;
  const reported = new Promise((resolve) => { report = resolve; });
  try {
    await context.route(`${ORIGIN}/**`, async (route) => {
      const req = route.request();
      const url = new URL(req.url());
      if (req.method() === 'POST' && url.pathname === '/result') {
        report(req.postData() ?? '');
        return route.fulfill({ status: 204 });
      }
      const rel = decodeURIComponent(url.pathname === '/' ? '/index.html' : url.pathname).slice(1);
      const file = path.resolve(dir, rel);
      if (!file.startsWith(path.resolve(dir) + path.sep)) return route.fulfill({ status: 404 });
      try {
        const body = await readFile(file);
        return route.fulfill({ status: 200, body, contentType: TYPES[path.extname(file)] ?? 'application/octet-stream' });
      } catch {
        return route.fulfill({ status: 404 });
      }
    });
    const tab = await context.newPage();
    tab.on('console', (m) => {
      const line = `console.${m.type()}: ${m.text()}`;
      log.push(line);
      if (process.env.AIRLIGHT_BROWSER_CONSOLE) console.error(line);
    });
    tab.on('pageerror', (e) => log.push(`uncaught: ${e.message}`));
    tab.on('crash', () => report(null));
    let timer;
    const late = new Promise((resolve) => { timer = setTimeout(() => resolve(undefined), timeout_s * 1000); });
    await tab.goto(`${ORIGIN}/${page}`, { timeout: timeout_s * 1000 });
    const posted = await Promise.race([reported, late]);
    clearTimeout(timer);
    const tail = log.slice(-12).join('\n');
    if (posted === undefined) reply('error', `the page did not report within ${timeout_s} s; its console ends:\n${tail}`);
    else if (posted === null) reply('error', `the page crashed; its console ends:\n${tail}`);
    else reply('ok', posted);
  } catch (e) {
    reply('error', `${e.message}; the page's console ends:\n${log.slice(-12).join('\n')}`);
  } finally {
    await context.close().catch(() => {});
    // Where CI's time goes: one line per page, on the test's own stderr.
    console.error(`browser page ${pages} (${what ?? page}): ${((Date.now() - started) / 1000).toFixed(1)} s`);
  }
}

const lines = createInterface({ input: process.stdin });
for await (const line of lines) {
  if (line.trim()) await draw(JSON.parse(line));
}
if (browser) await browser.close();

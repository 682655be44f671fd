// A static server for the example page: the page's own files from this folder, and a data folder
// (the LEAN map, its plateau layer and the exported shaders) under /data/.
//
//   node serve.mjs --data DIR [--port N]
//
// With --capture OUT --browser CHROMIUM it opens the page (--page, index.html by default; --scene
// for gltf.html) in that browser, headless (SwiftShader's WebGL2), with ?capture=CELLS, writes
// each cell's posted floats to OUT/NAME.f32 and the page's report to OUT/done.json, and exits:
// 0 when the page reported no error, 1 otherwise, 2 on a timeout. The browser is started with an argument list (no shell). Only GET of regular files
// inside the two folders and POST of the capture names are served.
import { spawn } from 'node:child_process';
import { createServer } from 'node:http';
import { mkdtempSync, readFileSync, realpathSync, rmSync, statSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, extname, join, sep } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
// The three.js package of this repository (examples/three), which the pages import.
const threePackage = realpathSync(join(here, '..', 'three'));

function fail(message) {
  process.stderr.write(`serve.mjs: ${message}\n`);
  process.exit(1);
}

const options = { port: '0', timeout: '120', size: '128', cells: '', page: 'index.html' };
const args = process.argv.slice(2);
for (let i = 0; i < args.length; i += 2) {
  const name = args[i].replace(/^--/, '');
  if (!['data', 'port', 'capture', 'browser', 'timeout', 'size', 'cells', 'map', 'page', 'scene'].includes(name) || args[i + 1] === undefined)
    fail(`unknown option or missing value: ${args[i]}`);
  options[name] = args[i + 1];
}
if (!options.data) fail('--data DIR is required (the folder of the LEAN map and the shaders)');
const dataRoot = realpathSync(options.data);
const port = Number(options.port);
if (!Number.isInteger(port) || port < 0 || port > 65535) fail(`--port ${options.port} is not a port`);
if (options.capture && !options.browser) fail('--capture needs --browser');
if (!/^[a-z_]+\.html$/.test(options.page)) fail(`--page ${options.page} is not a page of this folder`);

const types = {
  '.html': 'text/html', '.css': 'text/css', '.js': 'text/javascript', '.mjs': 'text/javascript', '.json': 'application/json',
  '.essl': 'text/plain', '.wgsl': 'text/wgsl', '.ktx2': 'image/ktx2',
};

// The regular file `relative` names inside `root`, or null (no escape through .. or links).
function fileInside(root, relative) {
  let path;
  try {
    path = realpathSync(join(root, relative));
  } catch {
    return null;
  }
  if (path !== root && !path.startsWith(root + sep)) return null;
  return statSync(path).isFile() ? path : null;
}

let browser = null;
let timer = null;
let profile = null;
// The browser's profile folder, removed once the browser has exited (its helper processes may
// still write for a moment: retried, and left behind rather than failing the run).
function removeProfile() {
  if (profile === null) return;
  try {
    rmSync(profile, { recursive: true, force: true, maxRetries: 10, retryDelay: 100 });
  } catch {
    // a temporary folder; the system's cleaning takes it
  }
  profile = null;
}

function finish(code, message) {
  if (message) process.stderr.write(`serve.mjs: ${message}\n`);
  if (timer) clearTimeout(timer);
  server.close();
  process.exitCode = code;
  const exit = () => {
    removeProfile();
    process.exit(code);
  };
  if (browser === null || browser.exitCode !== null) return exit();
  browser.once('exit', exit);
  browser.kill('SIGTERM');
  setTimeout(() => browser.kill('SIGKILL'), 5000).unref();
}

// The decoded path of a request, or null when it is malformed: a bad % escape (decodeURIComponent
// throws URIError), a target that is no path of this server ("//", which URL reads as a host, or
// an absolute URL), a NUL.
function requestPath(target) {
  if (typeof target !== 'string' || !target.startsWith('/') || target.startsWith('//')) return null;
  try {
    const path = decodeURIComponent(new URL(target, 'http://localhost').pathname);
    return path.includes('\0') ? null : path;
  } catch {
    return null;
  }
}

// One request. Whatever a request holds, it is answered and the server keeps serving: a
// malformed one gets 400, an unexpected failure 500 (a page open in the same browser must not be
// able to end the session).
function serve(request, response) {
  const path = requestPath(request.url);
  if (path === null) {
    response.writeHead(400).end();
    return;
  }
  if (request.method === 'POST' && options.capture && path.startsWith('/capture/')) {
    const name = path.slice('/capture/'.length);
    const chunks = [];
    request.on('data', (chunk) => chunks.push(chunk));
    request.on('end', () => {
      response.end('ok');
      const body = Buffer.concat(chunks);
      if (name === 'done') {
        writeFileSync(join(options.capture, 'done.json'), body);
        let report = {};
        try { report = JSON.parse(body.toString()); } catch { report = { errors: ['unreadable report'] }; }
        const errors = report.errors ?? [];
        finish(errors.length === 0 ? 0 : 1, errors.length ? `the page reported: ${errors.join('; ')}` : '');
      } else if (/^[a-z0-9.-]+_d[0-9.]+\.f32$/.test(name)) {
        writeFileSync(join(options.capture, name), body);
      }
    });
    return;
  }
  if (request.method !== 'GET') {
    response.writeHead(405).end();
    return;
  }
  const file = path.startsWith('/data/') ? fileInside(dataRoot, path.slice('/data/'.length))
    : path.startsWith('/three/') ? fileInside(threePackage, path.slice('/three/'.length))
    : fileInside(here, path === '/' ? 'index.html' : path.slice(1));
  if (file === null) {
    response.writeHead(404).end();
    return;
  }
  const body = readFileSync(file);
  response.writeHead(200, { 'Content-Type': types[extname(file)] ?? 'application/octet-stream' });
  response.end(body);
}

const server = createServer((request, response) => {
  try {
    serve(request, response);
  } catch (error) {
    process.stderr.write(`serve.mjs: ${request.method} ${JSON.stringify(request.url)}: ${error.message}\n`);
    if (!response.headersSent) response.writeHead(500);
    response.end();
  }
});
server.on('clientError', (error, socket) => {
  // A request line or header Node's parser refuses: 400, and the connection closed.
  if (socket.writable) socket.end('HTTP/1.1 400 Bad Request\r\nConnection: close\r\n\r\n');
  else socket.destroy();
});

server.listen(port, '127.0.0.1', () => {
  const address = `http://127.0.0.1:${server.address().port}/`;
  if (!options.capture) {
    process.stdout.write(`serving ${address} (data: ${dataRoot})\n`);
    return;
  }
  const query = new URLSearchParams({ data: 'data', capture: options.cells || '1', size: options.size });
  if (options.map) query.set('map', options.map);
  if (options.scene) query.set('scene', options.scene);
  profile = mkdtempSync(join(tmpdir(), 'leanfade-chromium-'));
  browser = spawn(options.browser, [
    '--headless=new', '--no-sandbox', '--no-first-run', '--disable-extensions',
    '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist',
    // WebGPU (webgpu.html) on SwiftShader's Vulkan, which headless Chromium has without a GPU.
    '--enable-unsafe-webgpu', '--use-webgpu-adapter=swiftshader',
    `--user-data-dir=${profile}`, `${address}${options.page}?${query}`,
  ], { stdio: ['ignore', 'ignore', 'pipe'] });
  let log = '';
  browser.stderr.on('data', (chunk) => { log = (log + chunk).slice(-4000); });
  browser.on('error', (error) => finish(1, `cannot start ${options.browser}: ${error.message}`));
  timer = setTimeout(() => finish(2, `no report from the page after ${options.timeout} s; the browser said:\n${log}`),
                     Number(options.timeout) * 1000);
});

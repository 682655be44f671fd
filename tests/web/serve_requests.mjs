// Sends raw GET requests to examples/web/serve.mjs and prints each reply's status line, and
// whether the server was still running after them, as one JSON object.
//
//   TARGETS='["/%", "/"]' node serve_requests.mjs SERVE.mjs DATA_DIR
import { spawn } from 'node:child_process';
import { connect } from 'node:net';
const [serveScript, site] = process.argv.slice(2);
const server = spawn(process.execPath, [serveScript, '--data', site], { stdio: ['ignore', 'pipe', 'pipe'] });
let out = '';
const port = await new Promise((resolve, reject) => {
  server.stdout.on('data', (c) => { out += c; const m = /127\.0\.0\.1:(\d+)\//.exec(out); if (m) resolve(Number(m[1])); });
  server.on('exit', (code) => reject(new Error(`serve.mjs exited ${code}`)));
});
function ask(target) {
  return new Promise((resolve) => {
    const socket = connect(port, '127.0.0.1', () => socket.write(`GET ${target} HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n`));
    let reply = '';
    socket.on('data', (c) => { reply += c; });
    socket.on('close', () => resolve(reply.split('\r\n')[0]));
    socket.on('error', () => resolve('error'));
  });
}
const results = {};
for (const target of JSON.parse(process.env.TARGETS)) results[target] = await ask(target);
results.alive = server.exitCode === null;
server.kill('SIGTERM');
process.stdout.write(JSON.stringify(results) + '\n');

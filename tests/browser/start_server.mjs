// The real surfdeform-server on a free loopback port, for the browser tests
// and bench/viewer_feel.mjs: {server, port} once it says it is listening.
import { spawn } from 'node:child_process';

export async function startServer(binary) {
  const server = spawn(binary, ['--host', '127.0.0.1', '--port', '0', '--log-level', 'warn'], {
    stdio: ['ignore', 'pipe', 'inherit'],
  });
  const port = await new Promise((resolve, reject) => {
    let out = '';
    server.stdout.on('data', (d) => {
      out += d;
      const m = out.match(/"listening".*"port":(\d+)/);
      if (m) resolve(Number(m[1]));
    });
    server.on('exit', (code) => reject(new Error(`the server exited (${code})`)));
    setTimeout(() => reject(new Error('the server did not start')), 20000);
  });
  return { server, port };
}

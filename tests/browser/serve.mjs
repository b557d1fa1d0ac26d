// Starts `surfaced serve` on a free loopback port (--port 0) and resolves once it prints where it listens.
import { spawn } from 'node:child_process';

// `extraArgs`: more `serve` options (e.g. ['--access-log', 'off']).
export function startServer(binary, webRoot, extraArgs = []) {
  const args = ['serve', '--host', '127.0.0.1', '--port', '0', '--threads', process.env.SURFACED_TEST_THREADS ?? '2'];
  if (webRoot) args.push('--web-root', webRoot);
  args.push(...extraArgs);
  const child = spawn(binary, args, { stdio: ['ignore', 'pipe', 'inherit'] });
  return new Promise((resolve, reject) => {
    let out = '';
    const timer = setTimeout(() => { child.kill('SIGTERM'); reject(new Error(`${binary} did not start: ${out}`)); }, 15000);
    child.on('error', (e) => { clearTimeout(timer); reject(e); });
    child.on('exit', (code) => { clearTimeout(timer); reject(new Error(`${binary} exited with ${code}: ${out}`)); });
    let started = false;
    child.stdout.on('data', (chunk) => {   // keeps reading: the server's stdout must never fill up
      if (started) return;
      out += chunk;
      const m = /listening on (http:\/\/[^/\s]+)\//.exec(out);
      if (m) {
        started = true;
        clearTimeout(timer);
        child.removeAllListeners('exit');
        resolve({
          url: m[1],
          stop: () => new Promise((done) => {
            if (child.exitCode !== null) return done();
            child.on('exit', done);
            child.kill('SIGTERM');
          }),
        });
      }
    });
  });
}

// Shared by the viewer's tests: the tools they need, and an artemis process serving the viewer.
import { spawn } from 'node:child_process';
import { existsSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import path from 'node:path';

export const VIEWER_DIR = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
export const CHROMIUM = process.env.ARTEMIS_CHROMIUM || '/usr/bin/chromium';

// Exits with 77 (ctest: skipped) when a tool is missing, saying which and how to install it;
// under CI=true a missing tool is a failure (exit 1).
export function requireTools({ browser = false, validator = false } = {}) {
  const missing = [];
  if (!existsSync(path.join(VIEWER_DIR, 'node_modules', 'three'))) missing.push('three (npm)');
  if (browser && !existsSync(path.join(VIEWER_DIR, 'node_modules', 'playwright-core'))) missing.push('playwright-core (npm)');
  if (validator && !existsSync(path.join(VIEWER_DIR, 'node_modules', 'gltf-validator'))) missing.push('gltf-validator (npm)');
  if (browser && !existsSync(CHROMIUM)) missing.push(`Chromium (${CHROMIUM})`);
  if (missing.length === 0) return;
  const ci = process.env.CI === 'true';
  console.error(`${ci ? 'FAIL' : 'SKIP'}: missing ${missing.join(', ')}; run scripts/install-deps.sh`);
  process.exit(ci ? 1 : 77);
}

export function check(condition, message) {
  if (!condition) throw new Error(`check failed: ${message}`);
  console.log(`ok: ${message}`);
}

// Starts `artemis <args>` and waits for its "viewer: http://..." line; returns { proc, url, output }.
export function startArtemis(binary, args, { timeoutMs = 120000 } = {}) {
  return new Promise((resolve, reject) => {
    const proc = spawn(binary, args, { stdio: ['ignore', 'pipe', 'pipe'] });
    const output = { stdout: '', stderr: '' };
    const timer = setTimeout(() => reject(new Error(`no viewer URL within ${timeoutMs} ms:\n${output.stderr}`)), timeoutMs);
    proc.stdout.on('data', (d) => {
      output.stdout += d;
      const m = output.stdout.match(/viewer: (http:\/\/[0-9.]+:[0-9]+\/)/);
      if (m) {
        clearTimeout(timer);
        resolve({ proc, url: m[1], output });
      }
    });
    proc.stderr.on('data', (d) => { output.stderr += d; });
    proc.on('exit', (code) => {
      clearTimeout(timer);
      reject(new Error(`artemis ${args[0]} exited with ${code} before serving:\n${output.stderr}`));
    });
  });
}

export function stop(proc) {
  return new Promise((resolve) => {
    if (proc.exitCode !== null) return resolve(proc.exitCode);
    proc.removeAllListeners('exit');
    proc.on('exit', (code, signal) => resolve(code ?? signal));
    proc.kill('SIGTERM');
  });
}

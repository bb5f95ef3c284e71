// artemis run --viewer: the map updates while it is built. Polls the server as the page does and
// checks that the version advances at least twice a second while mapping, that an update carries
// only the blocks changed since the page's version (fewer bytes than the whole map), and that
// the frame counter reaches the last frame. Usage: node live.test.mjs ARTEMIS SIM_DIR OUT_DIR
import { mkdirSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import { check, requireTools, startArtemis, stop } from './harness.mjs';

requireTools();
const [artemis, simDir, outDir] = process.argv.slice(2);
mkdirSync(outDir, { recursive: true });
const { proc, url } = await startArtemis(artemis, [
  '--log-level', 'warn', 'run', simDir, '--query', 'car', '--segmenter', 'sim', '--out', path.join(outDir, 'live'),
  '--viewer', '--viewer-port', '0', '--viewer-linger', '3']);
const exited = new Promise((resolve) => proc.on('exit', (code) => resolve(code)));
const samples = [];
let version = 0;
const t0 = Date.now();
try {
  for (;;) {
    const info = await (await fetch(`${url}api/info`)).json();
    const sample = {
      t_ms: Date.now() - t0, version: info.version, done: info.status.done, total: info.status.total,
      running: info.status.running,
    };
    if (info.version !== version) {
      const bytes = new Uint8Array(await (await fetch(`${url}api/blocks?since=${version}`)).arrayBuffer());
      const view = new DataView(bytes.buffer);
      sample.bytes = bytes.length;
      sample.blocks = view.getUint32(12, true);
      sample.since = version;
      version = view.getUint32(8, true);
    }
    samples.push(sample);
    if (!info.status.running) break;
    await new Promise((r) => setTimeout(r, 50));
  }
  const full = (await fetch(`${url}api/blocks?since=0`)).arrayBuffer();
  const fullBytes = (await full).byteLength;
  writeFileSync(path.join(outDir, 'live_samples.json'), JSON.stringify({ samples, fullBytes }, null, 2));
  // While frames are mapped (the final meshing after the last frame is one step of its own).
  const mapping = samples.filter((s) => s.running && s.done > 0 && s.done < s.total);
  const span_s = (mapping[mapping.length - 1].t_ms - mapping[0].t_ms) / 1000;
  // Each publish is one new version: count them by the version numbers, not by the versions this
  // loop happened to see (on a loaded machine a large update takes long to fetch, and the
  // publishes in between are never sampled).
  const versions = mapping[mapping.length - 1].version - mapping[0].version;
  const seen = new Set(mapping.map((s) => s.version)).size;
  console.log(`${versions} new versions (${seen} sampled) over ${span_s.toFixed(2)} s of mapping; ` +
    `the whole map is ${fullBytes} bytes`);
  check(span_s > 1, `mapping was watched for ${span_s.toFixed(2)} s`);
  check(versions / span_s >= 2, `${(versions / span_s).toFixed(1)} updates per second while mapping`);
  const updates = samples.filter((s) => s.bytes !== undefined && s.since > 0);
  check(updates.length >= 3, `${updates.length} incremental updates fetched`);
  const bytes = updates.map((s) => s.bytes).sort((a, b) => a - b);
  const median = bytes[Math.floor(bytes.length / 2)];
  check(median < 0.5 * fullBytes, `an update carries the changed blocks only: median ${median} bytes of ${fullBytes}`);
  const last = samples[samples.length - 1];
  check(last.total === 30 && last.done === 30, `the frame counter reached ${last.done} / ${last.total}`);
} finally {
  const code = await Promise.race([exited, new Promise((r) => setTimeout(() => r('timeout'), 15000))]);
  if (code === 'timeout') await stop(proc);
  check(code === 0, `artemis run --viewer exited with ${code}`);
}
console.log('live test passed');

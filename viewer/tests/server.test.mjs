// The viewer's HTTP server: what it serves, what it refuses (paths outside its roots, in every
// spelling), its size caps, and the query API. Usage: node server.test.mjs ARTEMIS RUN_DIR
import http from 'node:http';
import { check, requireTools, startArtemis, stop } from './harness.mjs';

requireTools();
const [artemis, runDir] = process.argv.slice(2);

// A raw GET (node sends the path as given: no normalisation of "..").
function get(url, rawPath, method = 'GET') {
  const u = new URL(url);
  return new Promise((resolve, reject) => {
    const req = http.request({ host: u.hostname, port: u.port, path: rawPath, method }, (res) => {
      const chunks = [];
      res.on('data', (c) => chunks.push(c));
      res.on('end', () => resolve({ status: res.statusCode, headers: res.headers, body: Buffer.concat(chunks) }));
    });
    req.on('error', reject);
    req.end();
  });
}

const { proc, url } = await startArtemis(artemis, ['view', runDir, '--port', '0']);
try {
  check(new URL(url).hostname === '127.0.0.1', `binds to loopback by default (${url})`);

  const page = await get(url, '/');
  check(page.status === 200 && page.body.toString().includes('importmap'), 'serves the page');
  const app = await get(url, '/app.js');
  check(app.status === 200 && app.headers['content-type'].startsWith('text/javascript'), 'serves app.js as JavaScript');
  const three = await get(url, '/vendor/three/build/three.module.js');
  check(three.status === 200 && three.body.length > 100000, 'serves three.js from the local npm packages');
  const controls = await get(url, '/vendor/three/examples/jsm/controls/OrbitControls.js');
  check(controls.status === 200, 'serves the three.js add-ons');
  check((await get(url, '/vendor/three/package.json')).status === 404, 'serves nothing else of three');
  check((await get(url, '/run/mesh.ply')).status === 200, "serves the run's outputs");
  check((await get(url, '/run/semantics.json')).status === 200, 'serves semantics.json');

  const escapes = [
    '/../../../../etc/passwd', '/%2e%2e/%2e%2e/%2e%2e/etc/passwd', '/run/../../../../etc/passwd',
    '/run/..%2f..%2f..%2f..%2fetc%2fpasswd', '/run/%2e%2e/%2e%2e/%2e%2e/%2e%2e/etc/passwd', '/run/..%5c..%5cetc%5cpasswd',
    '/run/%2fetc%2fpasswd', '/run//etc/passwd', '/vendor/three/build/../../../../../../etc/passwd',
    '/vendor/three/build/%2e%2e/%2e%2e/package.json', '/vendor/three/build/..%2f..%2fpackage.json',
    '/app.js/../../../etc/passwd', '/run/../sim/scene.json', '/run/%2e%2e/run.log', '/run/.%2e/run.log',
    '/run/mesh.ply%00.txt', '/node_modules/three/package.json', '/tests/harness.mjs', '/package.json',
  ];
  for (const p of escapes) {
    const r = await get(url, p);
    check(r.status >= 400 && r.status < 500 && !r.body.toString().includes('root:'), `refuses ${p} (HTTP ${r.status})`);
  }

  const info = JSON.parse((await get(url, '/api/info')).body);
  check(info.version >= 1 && info.vertices > 1000 && info.faces > 1000, `info: ${info.vertices} vertices, version ${info.version}`);
  check(info.classes.some((c) => c.name === 'car') && info.trajectory.length === 30, 'info lists the classes and the trajectory');
  const all = await get(url, '/api/blocks?since=0');
  check(all.body.readUInt32LE(0) === 0x42545241 && all.body.readUInt32LE(12) === info.blocks, `blocks: ${info.blocks}`);
  const none = await get(url, `/api/blocks?since=${info.version}`);
  check(none.body.length === 16 && none.body.readUInt32LE(12) === 0, 'nothing is sent for a current version');
  check((await get(url, '/api/blocks?since=abc')).status === 400, 'a malformed version is refused');

  const cars = JSON.parse((await get(url, '/api/query?q=cars')).body);
  check(cars.matched.length === 1 && cars.matched[0].name === 'car' && cars.matched[0].in_map, 'query "cars" matches car');
  const unicorn = JSON.parse((await get(url, '/api/query?q=unicorn')).body);
  check(unicorn.matched.length === 0 && unicorn.message.includes('unicorn'), `query "unicorn": ${unicorn.message}`);
  const long = await get(url, `/api/query?q=${'a'.repeat(1500)}`);
  check(long.status === 413, 'a query over 1000 bytes is refused (413)');
  const huge = await get(url, `/api/query?q=${'b'.repeat(5000)}`);
  check(huge.status === 414, 'a URI over 2 KB is refused (414)');
  check((await get(url, '/api/query?q=cars', 'POST')).status !== 200, 'POST is not served');
} finally {
  await stop(proc);
}
console.log('server test passed');

// ARTEMIS viewer: the Living Map served by `artemis view` / `artemis run --viewer`.
// The mesh arrives as blocks (GET /api/blocks?since=V, format in apps/artemis/viewer/scene.hpp);
// the page keeps one three.js mesh per block and asks only for the blocks changed since the
// version it has. Colours are computed here from each vertex's texture and class, so switching
// modes or highlighting a query costs one pass over the vertices and no request.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { FlyControls } from 'three/addons/controls/FlyControls.js';

const MAGIC = 0x42545241;
const FORMAT = 1;
const POLL_MS = 250;
const NONE_RGB = [150, 150, 150];
const LIGHT = new THREE.Vector3(0.3, 0.5, 0.8).normalize();

const state = {
  version: 0,
  blocks: new Map(),     // "x,y,z" -> { mesh, rgb, cls, shade }
  mode: 'texture',
  highlight: new Map(),  // class id -> [r, g, b]
  classRgb: new Map(),   // class id -> [r, g, b] (vocabulary display colours)
  info: null,
  fitted: false,
  trajectoryLength: 0,
  lastQuery: null,  // {answer_ms, recolour_ms, draw_ms, total_ms, vertices} of the last query
  lastUpdateMs: null,
  updates: 0,
};

// Frames are drawn when something changed (camera, mesh, colours), not 60 times a second: a
// large map then costs nothing while it is only looked at.
let needsRender = true;
function requestRender() { needsRender = true; }

// --- three.js set-up -------------------------------------------------------------------------
const container = document.getElementById('view');
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.outputColorSpace = THREE.LinearSRGBColorSpace;  // vertex colours are sRGB already: pass them through
renderer.setPixelRatio(1);
container.appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color().setRGB(0.14, 0.15, 0.18, THREE.LinearSRGBColorSpace);
const camera = new THREE.PerspectiveCamera(60, 1, 0.1, 5000);
camera.up.set(0, 0, 1);  // the map's world frame is z up
camera.position.set(-20, -20, 20);
const material = new THREE.MeshBasicMaterial({ vertexColors: true, side: THREE.DoubleSide });
const orbit = new OrbitControls(camera, renderer.domElement);
orbit.enableDamping = false;
const fly = new FlyControls(camera, renderer.domElement);
fly.dragToLook = true;
fly.rollSpeed = 0.6;
fly.enabled = false;
const trajectory = new THREE.Line(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color: 0xff3030 }));
trajectory.frustumCulled = false;
scene.add(trajectory);
const clock = new THREE.Clock();

function resize() {
  const w = container.clientWidth;
  const h = container.clientHeight;
  renderer.setSize(w, h);
  camera.aspect = w / Math.max(1, h);
  camera.updateProjectionMatrix();
  needsRender = true;
}
window.addEventListener('resize', resize);
resize();

orbit.addEventListener('change', requestRender);
function animate() {
  const dt = clock.getDelta();
  if (fly.enabled) {
    fly.update(dt);
    needsRender = true;
  } else {
    orbit.update();
  }
  if (needsRender) {
    needsRender = false;
    renderer.render(scene, camera);
  }
  requestAnimationFrame(animate);
}
requestAnimationFrame(animate);

// --- colours ---------------------------------------------------------------------------------
function colourBlock(b) {
  const n = b.cls.length;
  const out = b.mesh.geometry.getAttribute('color').array;
  const textured = state.info ? state.info.textured !== false : true;
  for (let i = 0; i < n; ++i) {
    const c = b.cls[i];
    const k = 3 * i;
    let r, g, bl;
    if (state.mode === 'classes') {
      const rgb = c === 0 ? NONE_RGB : (state.classRgb.get(c) || NONE_RGB);
      const s = b.shade[i];
      r = rgb[0] * s; g = rgb[1] * s; bl = rgb[2] * s;
    } else {
      const h = state.mode === 'highlight' ? state.highlight.get(c) : undefined;
      if (h !== undefined) {
        r = h[0]; g = h[1]; bl = h[2];
      } else {
        const s = textured ? 1 : b.shade[i];
        const dim = state.mode === 'highlight' && state.highlight.size > 0 ? 0.55 : 1;
        r = b.rgb[k] * s * dim; g = b.rgb[k + 1] * s * dim; bl = b.rgb[k + 2] * s * dim;
      }
    }
    out[k] = r; out[k + 1] = g; out[k + 2] = bl;
  }
  b.mesh.geometry.getAttribute('color').needsUpdate = true;
  requestRender();
}

function recolourAll() {
  for (const b of state.blocks.values()) colourBlock(b);
}

// --- blocks ----------------------------------------------------------------------------------
function applyBlocks(buffer) {
  const view = new DataView(buffer);
  if (buffer.byteLength < 16 || view.getUint32(0, true) !== MAGIC || view.getUint32(4, true) !== FORMAT) {
    throw new Error('unexpected block data from the server');
  }
  const version = view.getUint32(8, true);
  const count = view.getUint32(12, true);
  let at = 16;
  for (let k = 0; k < count; ++k) {
    const bx = view.getInt32(at, true), by = view.getInt32(at + 4, true), bz = view.getInt32(at + 8, true);
    const n = view.getUint32(at + 12, true), m = view.getUint32(at + 16, true);
    at += 20;
    const key = `${bx},${by},${bz}`;
    const old = state.blocks.get(key);
    if (old) {
      scene.remove(old.mesh);
      old.mesh.geometry.dispose();
      state.blocks.delete(key);
    }
    if (n === 0) continue;
    const xyz = new Float32Array(buffer, at, 3 * n); at += 12 * n;
    const rgb = new Uint8Array(buffer, at, 3 * n); at += 3 * n;
    const cls = new Uint8Array(buffer, at, n); at += n;
    const index = new Uint32Array(buffer, at, m); at += 4 * m;
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(xyz, 3));
    geometry.setAttribute('color', new THREE.BufferAttribute(new Uint8Array(3 * n), 3, true));
    geometry.setIndex(new THREE.BufferAttribute(index, 1));
    geometry.computeVertexNormals();
    geometry.computeBoundingSphere();
    const normals = geometry.getAttribute('normal').array;
    const shade = new Float32Array(n);
    for (let i = 0; i < n; ++i) {
      const d = normals[3 * i] * LIGHT.x + normals[3 * i + 1] * LIGHT.y + normals[3 * i + 2] * LIGHT.z;
      shade[i] = 0.5 + 0.5 * Math.abs(d);
    }
    geometry.deleteAttribute('normal');  // unlit material: the shade above is all it needs
    const mesh = new THREE.Mesh(geometry, material);
    const b = { mesh, rgb, cls, shade };
    colourBlock(b);
    scene.add(mesh);
    state.blocks.set(key, b);
  }
  state.version = version;
  state.updates += 1;
  requestRender();
  if (!state.fitted && state.blocks.size > 0) fit();
}

function sceneBounds() {
  const box = new THREE.Box3();
  for (const b of state.blocks.values()) {
    b.mesh.geometry.computeBoundingBox();
    box.union(b.mesh.geometry.boundingBox);
  }
  return box;
}

// Frames the trajectory (with 25 m around it) when there is one, else the whole mesh.
function fit() {
  const box = new THREE.Box3();
  const traj = (state.info && state.info.trajectory) || [];
  if (traj.length > 0) {
    for (const p of traj) box.expandByPoint(new THREE.Vector3(p[0], p[1], p[2]));
    box.expandByScalar(25);
  } else {
    box.copy(sceneBounds());
  }
  if (box.isEmpty()) return;
  const centre = box.getCenter(new THREE.Vector3());
  const size = Math.max(10, box.getSize(new THREE.Vector3()).length());
  orbit.target.copy(centre);
  camera.position.set(centre.x - 0.18 * size, centre.y - 0.3 * size, centre.z + 0.22 * size);
  camera.near = Math.max(0.05, size / 5000);
  camera.far = 20 * size;
  camera.updateProjectionMatrix();
  camera.lookAt(centre);
  fly.movementSpeed = Math.max(2, size / 20);
  state.fitted = true;
  requestRender();
}

// --- panel -----------------------------------------------------------------------------------
const el = (id) => document.getElementById(id);

function swatch(rgb) {
  const s = document.createElement('span');
  s.className = 'swatch';
  s.style.background = `rgb(${rgb[0]},${rgb[1]},${rgb[2]})`;
  return s;
}

function showLegend() {
  const legend = el('legend');
  legend.replaceChildren();
  const entries = [];
  if (state.mode === 'classes') {
    for (const c of (state.info && state.info.classes) || []) entries.push([c.rgb, c.name]);
    entries.push([NONE_RGB, 'none / unobserved']);
  } else if (state.mode === 'highlight') {
    for (const [id, rgb] of state.highlight) entries.push([rgb, nameOf(id)]);
  }
  for (const [rgb, name] of entries) {
    const row = document.createElement('div');
    row.append(swatch(rgb), document.createTextNode(name));
    legend.append(row);
  }
}

function nameOf(id) {
  const all = (state.info && state.info.vocabulary) || [];
  const c = all.find((x) => x.id === id);
  return c ? c.name : `class ${id}`;
}

function showInfo(info) {
  state.info = info;
  el('title').textContent = `ARTEMIS · ${info.title || 'Living Map'}`;
  for (const c of info.vocabulary || []) state.classRgb.set(c.id, c.rgb);
  const st = info.status || {};
  const frames = st.total ? `frame ${st.done} / ${st.total}` : '';
  const live = st.running ? ' · mapping' : ' · finished';
  el('status').textContent =
      `${frames}${live} · ${info.vertices.toLocaleString()} vertices, ${info.faces.toLocaleString()} faces, ` +
      `${info.blocks} blocks`;
  const rows = [];
  for (const [name, s] of Object.entries(st.stages || {})) {
    const last = s.last_ms !== undefined ? s.last_ms.toFixed(1) : '';
    rows.push(`<tr><td>${name}</td><td class="ms">${last}</td><td class="ms">${s.median_ms.toFixed(1)}</td></tr>`);
  }
  el('timings').innerHTML = rows.length ? `<tr><td>ms per frame</td><td class="ms">last</td><td class="ms">median</td></tr>${rows.join('')}` : '';
  const traj = info.trajectory || [];
  if (traj.length !== state.trajectoryLength) {
    trajectory.geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(traj.flat()), 3));
    trajectory.geometry.computeBoundingSphere();
    state.trajectoryLength = traj.length;
    requestRender();
  }
  // The class names may arrive after a query was answered (a query in the link).
  if (state.mode !== 'texture') showLegend();
}

async function poll() {
  try {
    const info = await (await fetch('/api/info', { cache: 'no-store' })).json();
    showInfo(info);
    if (info.version !== state.version) {
      const t0 = performance.now();
      const res = await fetch(`/api/blocks?since=${state.version}`, { cache: 'no-store' });
      if (!res.ok) throw new Error(`blocks: HTTP ${res.status}`);
      applyBlocks(await res.arrayBuffer());
      state.lastUpdateMs = performance.now() - t0;
    }
  } catch (e) {
    el('status').textContent = `server unreachable (${e.message}); retrying`;
  }
  const running = state.info && state.info.status && state.info.status.running;
  setTimeout(poll, running ? POLL_MS : 4 * POLL_MS);
}

function setMode(mode) {
  state.mode = mode;
  for (const r of document.querySelectorAll('input[name=mode]')) r.checked = r.value === mode;
  recolourAll();
  showLegend();
}

async function runQuery(text) {
  const box = el('matched');
  box.className = '';
  box.textContent = 'asking…';
  const t0 = performance.now();
  let answer;
  try {
    const res = await fetch(`/api/query?q=${encodeURIComponent(text)}`, { cache: 'no-store' });
    answer = await res.json();
    if (!res.ok) throw new Error(answer.error || `HTTP ${res.status}`);
  } catch (e) {
    box.className = 'none';
    box.textContent = e.message;
    return;
  }
  const t1 = performance.now();
  state.highlight.clear();
  for (const m of answer.matched) state.highlight.set(m.id, m.rgb);
  box.replaceChildren();
  if (answer.matched.length === 0) {
    box.className = 'none';
    box.textContent = answer.message;
  } else {
    box.append(document.createTextNode('matched: '));
    for (const m of answer.matched) {
      const chip = document.createElement('span');
      chip.className = 'chip';
      chip.dataset.classId = m.id;
      chip.style.background = `rgb(${m.rgb[0]},${m.rgb[1]},${m.rgb[2]})`;
      chip.textContent = m.name;
      if (!m.in_map) chip.title = 'not in this map';
      box.append(chip);
    }
    const note = answer.message.indexOf('(');
    if (note >= 0) box.append(document.createTextNode(' ' + answer.message.slice(note)));
  }
  setMode('highlight');
  const t2 = performance.now();
  // One frame drawn with the highlight; reading a pixel back waits until the GPU has finished it.
  renderer.render(scene, camera);
  const gl = renderer.getContext();
  gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
  const t3 = performance.now();
  state.lastQuery = {
    answer_ms: t1 - t0, recolour_ms: t2 - t1, draw_ms: t3 - t2, total_ms: t3 - t0,
    vertices: [...state.blocks.values()].reduce((n, b) => n + b.cls.length, 0),
  };
  window.artemis.highlightDone += 1;
}

el('query-form').addEventListener('submit', (e) => {
  e.preventDefault();
  runQuery(el('query').value.trim());
});
for (const r of document.querySelectorAll('input[name=mode]')) r.addEventListener('change', () => setMode(r.value));
for (const r of document.querySelectorAll('input[name=nav]')) {
  r.addEventListener('change', () => {
    fly.enabled = r.value === 'fly' && r.checked;
    orbit.enabled = !fly.enabled;
    if (!fly.enabled) {
      // Orbit around the point ahead of the camera.
      const ahead = new THREE.Vector3(0, 0, -1).applyQuaternion(camera.quaternion);
      orbit.target.copy(camera.position).addScaledVector(ahead, camera.position.distanceTo(orbit.target) || 10);
    }
  });
}
el('fit').addEventListener('click', fit);
el('show-trajectory').addEventListener('change', (e) => {
  trajectory.visible = e.target.checked;
  requestRender();
});

// For tests and scripts: the state, and world points projected to page pixels.
window.artemis = {
  state,
  highlightDone: 0,
  project(points) {
    const rect = renderer.domElement.getBoundingClientRect();
    return points.map(([x, y, z]) => {
      const p = new THREE.Vector3(x, y, z).project(camera);
      return [rect.left + (p.x + 1) / 2 * rect.width, rect.top + (1 - p.y) / 2 * rect.height, p.z];
    });
  },
  recolourAll,
};

// A link can carry a query: /?q=parked%20cars highlights it once the map has loaded.
const linkedQuery = new URLSearchParams(window.location.search).get('q');
if (linkedQuery) {
  el('query').value = linkedQuery;
  runQuery(linkedQuery.trim());
}

poll();

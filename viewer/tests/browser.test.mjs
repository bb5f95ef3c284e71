// The viewer in Debian's Chromium (playwright-core): the page loads, the mesh renders, typing
// "cars" shows "car" as matched and lights up pixels inside the projected boxes of the simulated
// cars, typing "unicorn" says that nothing matches. Screenshots go to OUT_DIR.
// Usage: node browser.test.mjs ARTEMIS SIM_DIR RUN_DIR OUT_DIR
import { mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import { CHROMIUM, VIEWER_DIR, check, requireTools, startArtemis, stop } from './harness.mjs';

requireTools({ browser: true });
const { chromium } = await import(path.join(VIEWER_DIR, 'node_modules', 'playwright-core', 'index.mjs'));
const [artemis, simDir, runDir, outDir] = process.argv.slice(2);
mkdirSync(outDir, { recursive: true });

// The simulated cars' boxes in the world frame (scene.json: street frame S, p_W = inv(T_S_W) p_S).
function carBoxes() {
  const sceneJson = JSON.parse(readFileSync(path.join(simDir, 'scene.json'), 'utf8'));
  const T = sceneJson.T_S_W;  // 3x4 row-major, p_S = R p_W + t
  const R = [[T[0], T[1], T[2]], [T[4], T[5], T[6]], [T[8], T[9], T[10]]];
  const t = [T[3], T[7], T[11]];
  const toWorld = (p) => {
    const d = [p[0] - t[0], p[1] - t[1], p[2] - t[2]];
    return [0, 1, 2].map((i) => R[0][i] * d[0] + R[1][i] * d[1] + R[2][i] * d[2]);  // R^T d
  };
  return sceneJson.objects.filter((o) => o.kind === 'car').map((o) => {
    const [sx, sy, sz] = o.size_m;
    const c = Math.cos(o.yaw_rad), s = Math.sin(o.yaw_rad);
    const corners = [];
    for (const dx of [-sx / 2, sx / 2]) {
      for (const dy of [-sy / 2, sy / 2]) {
        for (const z of [o.position_S[2], o.position_S[2] + sz]) {
          corners.push(toWorld([o.position_S[0] + c * dx - s * dy, o.position_S[1] + s * dx + c * dy, z]));
        }
      }
    }
    return corners;
  });
}

// Counts, in a PNG screenshot, the pixels within `tol` of `rgb` inside and outside `boxes`
// ([x0, y0, x1, y1] in page pixels), and those unlike the background.
async function countPixels(page, png, rgb, tol, boxes, background) {
  return page.evaluate(async ({ b64, rgb, tol, boxes, background }) => {
    const img = new Image();
    img.src = `data:image/png;base64,${b64}`;
    await img.decode();
    const canvas = document.createElement('canvas');
    canvas.width = img.width;
    canvas.height = img.height;
    const ctx = canvas.getContext('2d');
    ctx.drawImage(img, 0, 0);
    const data = ctx.getImageData(0, 0, img.width, img.height).data;
    const view = document.getElementById('view').getBoundingClientRect();
    let inside = 0, outside = 0, drawn = 0, total = 0;
    for (let y = Math.floor(view.top); y < Math.floor(view.bottom); ++y) {
      for (let x = Math.floor(view.left); x < Math.floor(view.right); ++x) {
        const k = 4 * (y * img.width + x);
        const r = data[k], g = data[k + 1], b = data[k + 2];
        ++total;
        if (Math.abs(r - background[0]) + Math.abs(g - background[1]) + Math.abs(b - background[2]) > 6) ++drawn;
        if (Math.abs(r - rgb[0]) > tol || Math.abs(g - rgb[1]) > tol || Math.abs(b - rgb[2]) > tol) continue;
        if (boxes.some(([x0, y0, x1, y1]) => x >= x0 && x <= x1 && y >= y0 && y <= y1)) ++inside; else ++outside;
      }
    }
    return { inside, outside, drawn, total };
  }, { b64: png.toString('base64'), rgb, tol, boxes, background });
}

const { proc, url } = await startArtemis(artemis, ['view', runDir, '--port', '0']);
const browser = await chromium.launch({
  executablePath: CHROMIUM,
  headless: true,
  args: ['--no-sandbox', '--disable-gpu', '--no-first-run', '--disable-background-networking',
         '--disable-component-update', '--disable-sync', '--use-gl=angle', '--use-angle=swiftshader',
         '--enable-unsafe-swiftshader'],
});
const results = {};
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  await page.goto(url);
  await page.waitForFunction(() => window.artemis && window.artemis.state.updates > 0, null, { timeout: 60000 });
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
  const first = await page.screenshot({ path: path.join(outDir, 'viewer_loaded.png') });
  // The background: the colour of the view's top-left pixel (the sky: nothing is drawn there).
  const bg = await page.evaluate(async (b64) => {
    const img = new Image();
    img.src = `data:image/png;base64,${b64}`;
    await img.decode();
    const c = document.createElement('canvas');
    c.width = img.width; c.height = img.height;
    const ctx = c.getContext('2d');
    ctx.drawImage(img, 0, 0);
    return Array.from(ctx.getImageData(2, 2, 1, 1).data.slice(0, 3));
  }, first.toString('base64'));
  const loaded = await countPixels(page, first, [0, 0, 0], -1, [], bg);
  results.loaded_drawn_share = loaded.drawn / loaded.total;
  check(loaded.drawn > 0.05 * loaded.total, `the mesh renders: ${(100 * loaded.drawn / loaded.total).toFixed(1)} % of the view drawn`);
  check((await page.textContent('#status')).includes('30 / 30'), 'the frame counter shows the run');

  await page.fill('#query', 'cars');
  await page.click('#query-form button');
  await page.waitForFunction(() => window.artemis.highlightDone >= 1, null, { timeout: 10000 });
  const chips = await page.$$eval('#matched .chip', (els) => els.map((e) => e.textContent));
  check(chips.length === 1 && chips[0] === 'car', `"cars" shows "car" as matched (${JSON.stringify(chips)})`);
  const highlight = await page.evaluate(() => [...window.artemis.state.highlight.values()][0]);
  const boxes = [];
  for (const corners of carBoxes()) {
    const p = await page.evaluate((pts) => window.artemis.project(pts), corners);
    if (p.some(([, , z]) => z < -1 || z > 1)) continue;  // behind the camera or clipped
    const xs = p.map((q) => q[0]), ys = p.map((q) => q[1]);
    boxes.push([Math.min(...xs) - 2, Math.min(...ys) - 2, Math.max(...xs) + 2, Math.max(...ys) + 2]);
  }
  check(boxes.length > 0, `${boxes.length} cars in view`);
  const shot = await page.screenshot({ path: path.join(outDir, 'viewer_cars.png') });
  const lit = await countPixels(page, shot, highlight, 8, boxes, bg);
  results.cars = { ...lit, boxes: boxes.length, query: await page.evaluate(() => window.artemis.state.lastQuery) };
  check(lit.inside > 200, `${lit.inside} highlight-coloured pixels inside the cars' boxes`);
  check(lit.inside >= 0.8 * (lit.inside + lit.outside),
        `${(100 * lit.inside / (lit.inside + lit.outside)).toFixed(1)} % of the highlight lies inside the cars' boxes`);

  await page.fill('#query', 'unicorn');
  await page.click('#query-form button');
  await page.waitForFunction(() => window.artemis.highlightDone >= 2, null, { timeout: 10000 });
  const message = await page.textContent('#matched');
  check(message.includes("no class matches 'unicorn'") && (await page.getAttribute('#matched', 'class')) === 'none',
        `"unicorn": ${message}`);
  const none = await page.screenshot({ path: path.join(outDir, 'viewer_unicorn.png') });
  const unlit = await countPixels(page, none, highlight, 8, boxes, bg);
  check(unlit.inside + unlit.outside < 0.1 * (lit.inside + lit.outside), 'no highlight after a query matching nothing');
  results.unicorn_query = await page.evaluate(() => window.artemis.state.lastQuery);

  // Class colours and fly mode do not break the page.
  await page.check('input[name=mode][value=classes]');
  await page.check('input[name=nav][value=fly]');
  await page.screenshot({ path: path.join(outDir, 'viewer_classes.png') });
  check(errors.length === 0, `no page errors${errors.length ? ': ' + errors.join('; ') : ''}`);
} finally {
  await browser.close();
  await stop(proc);
}
writeFileSync(path.join(outDir, 'browser_results.json'), JSON.stringify(results, null, 2));
console.log(JSON.stringify(results));
console.log(`browser test passed; screenshots in ${outDir}`);

// Drawing on the page of `curvenet serve` in headless Chromium, on the tower: a geodesic drawn
// with the mouse (press on the surface, drag a direction: a preview while dragging) gives a new
// curve and a changed λ; the curve dragged along the surface; both undone (λ back to the
// tower's); the Slide button (cancelled after a moment), its result adopted and undone; a curve through three points (clicks, a double-click to end); the design saved
// (its curves and its surface) and served again from the saved files, with the same curves and
// λ. A screenshot of each step is kept in target/browser-demo/draw-*.png.
//
// Run from this folder:  npm ci && node draw.test.mjs
// Environment: see common.mjs (CURVENET_BIN, CHROMIUM, BROWSER_DEMO).

import { test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync, spawn } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import readline from 'node:readline';
import { binary, openBrowser, outDir, root } from './common.mjs';

function serve(args) {
  const proc = spawn(binary(), ['serve', ...args, '--port', '0'], { cwd: root, stdio: ['ignore', 'pipe', 'inherit'] });
  return new Promise((resolve, reject) => {
    const lines = readline.createInterface({ input: proc.stdout });
    lines.once('line', (url) => resolve({ proc, url: url.trim() }));
    proc.once('exit', (code) => reject(new Error(`curvenet serve exited with ${code}`)));
  });
}

// Waits for the page (loaded again after a drawing edit) to be ready; its state.
async function ready(page) {
  for (let i = 0; i < 600; i++) {
    try {
      const s = await page.evaluate(async () => {
        const cv = window.curvenet;
        if (!cv || cv.error) return cv ? { error: cv.error } : null;
        const a = cv.app;
        if (!a || !a.ready || !a.drawReady || a.busy || cv.frames < 2) return null;
        const state = await (await fetch('api/state')).json();
        return {
          error: a.error, curves: a.drawing.curves.length, undo: a.drawing.undo,
          lambda: state.lambda, shown: document.getElementById('stat-lambda').textContent,
          message: document.getElementById('app-msg').textContent,
        };
      });
      if (s) return s;
    } catch (e) { /* the page is loading again */ }
    await page.waitForTimeout(100);
  }
  throw new Error('the page did not get ready');
}

// Does `action` (a drawing edit) and waits for the page loaded again after it.
async function reloadedAfter(page, action) {
  await page.evaluate(() => { window.beforeEdit = true; });
  await action();
  for (let i = 0; i < 1200; i++) {
    const gone = await page.evaluate(() => !window.beforeEdit).catch(() => false);
    if (gone) break;
    const err = await page.evaluate(() => window.curvenet.app && window.curvenet.app.error).catch(() => null);
    if (err) throw new Error(err);
    await page.waitForTimeout(100);
  }
  const s = await ready(page);
  assert.equal(s.error, null);
  return s;
}

// A pixel of the canvas right of the panel where the surface is drawn, at fractions (fx, fy)
// of the free area, searched outward from there.
async function surfacePixel(page, fx, fy) {
  return page.evaluate(([fx, fy]) => {
    const cv = window.curvenet;
    const left = document.getElementById('panel').getBoundingClientRect().right + 20;
    const w = window.innerWidth - 20, h = window.innerHeight - 20;
    const x0 = left + fx * (w - left), y0 = 20 + fy * (h - 20);
    for (let r = 0; r < 300; r += 10) {
      for (const [dx, dy] of [[0, 0], [r, 0], [-r, 0], [0, r], [0, -r]]) {
        const x = x0 + dx, y = y0 + dy;
        if (cv.surfaceAt(x, y)) return [x, y];
      }
    }
    return null;
  }, [fx, fy]);
}

// Waits for the page to show a preview (or says what the page said instead).
async function previewed(page) {
  await page.waitForFunction(() => (window.curvenet.app.previews || 0) > 0 && window.curvenet.previewLine, null, { timeout: 60_000 })
    .catch(async (e) => {
      const said = await page.evaluate(() => [window.curvenet.app.tool, document.getElementById('draw-note').textContent]);
      throw new Error(`${e.message}: ${said.join(': ')}`);
    });
}

const shot = (page, name) => page.screenshot({ path: path.join(outDir, `draw-${name}.png`) });

// The page as a 640x400 picture for docs/serve.md (docs/tools/serve_pictures.sh copies it
// there): the screenshot scaled down in the page's own canvas.
async function picture(page, name) {
  const png = (await page.screenshot()).toString('base64');
  const small = await page.evaluate(async (png) => {
    const img = new Image();
    img.src = `data:image/png;base64,${png}`;
    await img.decode();
    const c = document.createElement('canvas');
    c.width = 640; c.height = 400;
    const g = c.getContext('2d');
    g.imageSmoothingQuality = 'high';
    g.drawImage(img, 0, 0, 640, 400);
    return c.toDataURL('image/png').split(',')[1];
  }, png);
  fs.writeFileSync(path.join(outDir, `serve-${name}.png`), Buffer.from(small, 'base64'));
}

test('drawing on the page of curvenet serve', { timeout: 900_000 }, async () => {
  fs.mkdirSync(outDir, { recursive: true });
  const { proc, url } = await serve(['--example', 'tower']);
  const { page, problems, close } = await openBrowser();
  let second = null;
  try {
    await page.goto(url + '/');
    const s0 = await ready(page);
    assert.equal(s0.error, null);
    const n0 = s0.curves;
    assert.ok(n0 > 0, 'the tower is editable');
    await page.click('#animate');
    await page.check('input[name=deform][value=none]');
    await shot(page, '0-tower');

    // A geodesic: press on the surface, drag a direction (previewed), let go.
    await page.check('input[name=tool][value=geodesic]');
    const a = await surfacePixel(page, 0.45, 0.55);
    assert.ok(a, 'the surface is on screen');
    await page.mouse.move(a[0], a[1]);
    await page.mouse.down();
    // Down the tower: a geodesic heading round it would not reach the boundary.
    await page.mouse.move(a[0] + 10, a[1] + 60, { steps: 8 });
    await previewed(page);
    await shot(page, '1-geodesic-preview');
    const s1 = await reloadedAfter(page, () => page.mouse.up());
    assert.equal(s1.curves, n0 + 1, s1.message);
    assert.notEqual(s1.lambda, s0.lambda, 'λ follows the new curve');
    assert.match(s1.message, /drew geodesic curve \d+/);
    await shot(page, '2-geodesic');

    // Drag the new curve along the surface.
    await page.check('input[name=deform][value=none]');
    await page.check('input[name=tool][value=drag]');
    // A point of the new curve, on the surface, where a press picks it.
    const c = await page.evaluate((n) => {
      const cv = window.curvenet;
      for (const t of [0.5, 0.4, 0.6, 0.3, 0.7, 0.2, 0.8, 0.15, 0.85, 0.1, 0.9]) {
        const q = cv.screenPointOf(n, t);
        if (q && cv.surfaceAt(q[0], q[1]) && cv.pick(q[0], q[1]) === n) return q;
      }
      return null;
    }, n0);
    assert.ok(c, 'the new curve is on screen');
    await page.mouse.move(c[0], c[1]);
    await page.mouse.down();
    await page.mouse.move(c[0] + 15, c[1], { steps: 6 });
    await previewed(page);
    await shot(page, '3-drag-preview');
    const s2 = await reloadedAfter(page, () => page.mouse.up());
    assert.match(s2.message, /moved curve/);
    assert.equal(s2.curves, n0 + 1);
    await shot(page, '4-dragged');

    // Undo both: the tower again.
    await reloadedAfter(page, () => page.click('#undo'));
    const s3 = await reloadedAfter(page, () => page.click('#undo'));
    assert.equal(s3.curves, n0);
    assert.equal(s3.lambda, s0.lambda, 'λ is the tower\'s again');
    await shot(page, '5-undone');

    // Slide the tower's curves (cancelled after a moment, keeping the best so far), adopt the
    // slid curves as one edit, and undo it: the tower's λ again.
    await page.click('#run-slide');
    await page.waitForFunction(() => window.curvenet.app.slide && window.curvenet.app.slide.status === 'running', null, { timeout: 60_000 })
      .catch(() => { /* it may have ended already */ });
    await page.waitForTimeout(1000);
    await page.evaluate(() => fetch('api/slide/cancel', { method: 'POST' }));
    await page.waitForFunction(() => !document.getElementById('adopt-slide').disabled, null, { timeout: 300_000 });
    assert.match(await page.textContent('#slide-progress'), /slide (done|cancelled): /);
    await shot(page, '5b-slid');
    await picture(page, 'slide');
    const sSlid = await reloadedAfter(page, () => page.click('#adopt-slide'));
    assert.match(sSlid.message, /^slid: /);
    assert.equal(sSlid.curves, n0);
    const sBack = await reloadedAfter(page, () => page.click('#undo'));
    assert.equal(sBack.lambda, s0.lambda, 'undo of the slide gives the tower\'s λ');

    // A curve through three points, a double-click ending it.
    await page.check('input[name=deform][value=none]');
    await page.check('input[name=tool][value=through]');
    const pts = [];
    for (const [fx, fy] of [[0.35, 0.4], [0.5, 0.5], [0.65, 0.45]]) pts.push(await surfacePixel(page, fx, fy));
    assert.ok(pts.every(Boolean));
    await page.mouse.click(pts[0][0], pts[0][1]);
    await page.mouse.click(pts[1][0], pts[1][1]);
    await previewed(page);
    const s4 = await reloadedAfter(page, () => page.mouse.dblclick(pts[2][0], pts[2][1]));
    assert.equal(s4.curves, n0 + 1, s4.message);
    await shot(page, '6-through-points');

    // Save the design (its curves and its surface) and serve it again from the files.
    const saved = await page.evaluate(async () => {
      const get = async (f) => (await fetch(`api/export?format=${f}`)).text();
      const d = await (await fetch('api/curves')).json();
      return { json: await get('json'), surface: await get('surface'), h: d.edge_length };
    });
    const dir = path.join(outDir, 'draw-saved');
    fs.mkdirSync(dir, { recursive: true });
    fs.writeFileSync(path.join(dir, 'saved.json'), saved.json);
    fs.writeFileSync(path.join(dir, 'surface.obj'), saved.surface);
    // The file carries the edge length (and the units, the curves' own specs and supports).
    assert.match(saved.json, new RegExp(`"edge_length": ${saved.h}`));
    second = await serve(['--curves', path.join(dir, 'saved.json'), '--mesh', path.join(dir, 'surface.obj')]);
    await page.goto(second.url + '/');
    const s5 = await ready(page);
    assert.equal(s5.curves, n0 + 1);
    assert.equal(s5.lambda, s4.lambda, 'the saved design reloads with its λ');
    await shot(page, '7-reloaded');
    assert.deepEqual(problems, []);
  } finally {
    await close();
    proc.kill();
    if (second) second.proc.kill();
  }
});

// A run made with --slide served: its slid network, the curves before shown by the toggle.
test('a slid run on the page of curvenet serve', { timeout: 900_000 }, async () => {
  const dir = path.join(outDir, 'slid-run');
  fs.rmSync(dir, { recursive: true, force: true });
  fs.mkdirSync(dir, { recursive: true });
  const run = (args) => execFileSync(binary(), args, { cwd: root, stdio: ['ignore', 'ignore', 'inherit'] });
  run(['trace', '--mesh', 'dome', '--geodesics', '8', '--seed', '3', '--out', path.join(dir, 'curves.json'), '--mesh-out', path.join(dir, 'dome.obj')]);
  run(['simplify', '--curves', path.join(dir, 'curves.json'), '--mesh', path.join(dir, 'dome.obj'), '--budget', '0.85',
    '--slide', '--out', path.join(dir, 'run')]);
  const { proc, url } = await serve(['--run', path.join(dir, 'run')]);
  const { page, problems, close } = await openBrowser();
  try {
    await page.goto(url + '/');
    await page.waitForFunction(() => window.curvenet && window.curvenet.app && window.curvenet.app.ready && window.curvenet.frames >= 2, null, { timeout: 120_000 });
    const net = await page.evaluate(async () => (await fetch('api/network')).json());
    const state = await page.evaluate(async () => (await fetch('api/state')).json());
    assert.ok(net.slid, 'the API says the network slid');
    assert.equal(net.slid.before.length, net.curves.length);
    assert.ok(Math.abs(state.lambda - net.slid.record.lambda_after) <= 1e-6 * Math.abs(state.lambda), 'the slid network is served');
    assert.equal(await page.isVisible('#row-before'), true, 'the before/after toggle is shown');
    await page.check('#show-before');
    await page.waitForTimeout(300);
    await shot(page, '8-slid-run');
    await picture(page, 'slid-run');
    assert.deepEqual(problems, []);
  } finally {
    await close();
    proc.kill();
  }
});

// Opens the app `curvenet serve` answers at / in a real browser (Debian's headless Chromium
// through playwright-core) and uses it: a click on a curve removes it (λ changes, the curve is
// drawn as removed), a short greedy from the budget slider runs to its end, a step through its
// iterations, undo; a structure short of equilibrium named as such. On a small random network
// in the physical mode: the physical numbers and the gravity deflection shown, a design
// constraint set from the form, the local search run from its button and its best network
// adopted, a run folder loaded from the page. No console errors, and no request but to the
// server.
//
// Run from this folder:  npm ci && npm test
// Environment: see common.mjs (CURVENET_BIN, CHROMIUM, BROWSER_DEMO).

import { test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync, spawn } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import readline from 'node:readline';
import { binary, openBrowser, outDir, outsideTheView, root } from './common.mjs';

// Starts `curvenet serve` on a free port; resolves with the process and the URL it prints first.
function serve(args) {
  const proc = spawn(binary(), ['serve', ...args, '--port', '0'], { cwd: root, stdio: ['ignore', 'pipe', 'inherit'] });
  return new Promise((resolve, reject) => {
    const lines = readline.createInterface({ input: proc.stdout });
    lines.once('line', (url) => resolve({ proc, url: url.trim() }));
    proc.once('exit', (code) => reject(new Error(`curvenet serve exited with ${code}`)));
  });
}

// Waits until the app has made `n` edits (or failed: its message is the assertion's).
async function edited(page, n) {
  await page.waitForFunction((n) => {
    const a = window.curvenet.app;
    return (a.edits >= n && !a.busy) || a.error;
  }, n, { timeout: 60_000 });
  const a = await page.evaluate(() => ({ edits: window.curvenet.app.edits, error: window.curvenet.app.error }));
  assert.equal(a.error, null);
  assert.equal(a.edits, n);
}

test('the app of curvenet serve works in headless Chromium', { timeout: 600_000 }, async () => {
  fs.mkdirSync(outDir, { recursive: true });
  const { proc, url } = await serve(['--example', 'tower']);
  assert.match(url, /^http:\/\/127\.0\.0\.1:\d+$/);
  const { page, problems, close } = await openBrowser();
  const foreign = [];
  try {
    page.on('request', (r) => { if (!r.url().startsWith(url + '/')) foreign.push(r.url()); });
    await page.goto(url + '/');
    await page.waitForFunction(() => window.curvenet && (window.curvenet.error || (window.curvenet.app && window.curvenet.app.ready)), null, { timeout: 60_000 });
    assert.equal(await page.evaluate(() => window.curvenet.error), null);
    const html = await page.content();
    assert.ok(!/https?:\/\/(?!127\.0\.0\.1)/.test(html), 'the page references no outside URL');
    await page.waitForFunction(() => window.curvenet.frames > 2, null, { timeout: 30_000 });
    assert.deepEqual(await outsideTheView(page), [], 'the first view shows the whole tower');
    const all = await page.evaluate(() => window.curvenet.keptCurves());
    const lambda0 = await page.textContent('#stat-lambda');
    assert.equal(await page.textContent('#stat-status'), 'stable');

    // Click a kept curve: it is removed, λ changes, and it is drawn as removed.
    await page.click('#animate');
    await page.waitForTimeout(100);
    // A kept curve drawn well inside the canvas, right of the panel.
    const p = await page.evaluate(() => {
      const cv = window.curvenet;
      const left = document.getElementById('panel').getBoundingClientRect().right + 20;
      const w = window.innerWidth, h = window.innerHeight;
      for (const t of [0.4, 0.3, 0.6, 0.2, 0.7]) {
        for (const c of cv.keptCurves()) {
          const q = cv.screenPointOf(c, t);
          if (q && q[0] > left && q[0] < w - 380 && q[1] > 40 && q[1] < h - 40) return q;
        }
      }
      return null;
    });
    assert.ok(p, 'a kept curve is on screen');
    await page.mouse.click(p[0], p[1]);
    await edited(page, 1);
    const picked = await page.evaluate(() => window.curvenet.selected);
    assert.equal(typeof picked, 'number');
    const afterClick = await page.evaluate(() => window.curvenet.keptCurves());
    assert.deepEqual(afterClick, all.filter((c) => c !== picked));
    assert.equal(await page.evaluate((c) => window.curvenet.drawnAs(c), picked), 'removed');
    assert.notEqual(await page.textContent('#stat-lambda'), lambda0, 'λ changes');
    assert.match(await page.textContent('#info'), /removed/);
    const server = await (await page.request.get(url + '/api/state')).json();
    assert.deepEqual(server.curves, afterClick, 'the server holds the edit');

    // A short greedy from the budget slider, then its last iteration.
    await page.fill('#budget', '0.9');
    await page.click('#run-greedy');
    await page.waitForFunction(() => {
      const a = window.curvenet.app;
      return a.greedy && a.greedy.status !== 'running' && a.steps.length > 0 && !document.getElementById('greedy-steps').hidden;
    }, null, { timeout: 120_000 });
    const greedy = await page.evaluate(() => window.curvenet.app.greedy);
    assert.equal(greedy.status, 'done', JSON.stringify(greedy));
    assert.match(await page.textContent('#greedy-progress'), /done/);
    const steps = await page.evaluate(() => window.curvenet.app.steps);
    const last = steps[steps.length - 1];
    assert.ok(last.length <= 0.9 * steps[0].length, 'the last iteration meets the budget');
    await page.fill('#greedy-iter', String(steps.length - 1));
    await edited(page, 2);
    assert.deepEqual(await page.evaluate(() => window.curvenet.keptCurves()), last.curves);

    // Undo: back to the structure of the click; redo: the greedy's again.
    await page.click('#undo');
    await edited(page, 3);
    assert.deepEqual(await page.evaluate(() => window.curvenet.keptCurves()), afterClick);
    assert.equal(await page.evaluate((c) => window.curvenet.drawnAs(c), picked), 'removed');
    await page.click('#undo');
    await edited(page, 4);
    assert.deepEqual(await page.evaluate(() => window.curvenet.keptCurves()), all);
    assert.equal(await page.textContent('#stat-lambda'), lambda0, 'undo gives the first λ back');
    assert.equal(await page.evaluate((c) => window.curvenet.drawnAs(c), picked), 'kept');
    assert.ok(await page.isDisabled('#undo'));
    await page.keyboard.press('Control+y');
    await edited(page, 5);
    assert.deepEqual(await page.evaluate(() => window.curvenet.keptCurves()), afterClick);

    // A structure whose relaxation stopped short of equilibrium (the server's answer to one
    // undo rewritten to say so): the page names its λ as the unrelaxed state's, beside the
    // number and in the message, and a relaxed structure again drops the note.
    await page.route('**/api/set', async (route) => {
      const answer = await route.fetch();
      const body = await answer.json();
      await route.fulfill({ response: answer, json: Object.assign(body, { converged: false }) });
    }, { times: 1 });
    await page.keyboard.press('Control+z');
    await edited(page, 6);
    assert.deepEqual(await page.evaluate(() => window.curvenet.keptCurves()), all);
    assert.match(await page.textContent('#stat-lambda'), /no equilibrium reached: λ_eq of the state where the relaxation stopped/);
    assert.match(await page.textContent('#stat-status'), /not at equilibrium/);
    assert.match(await page.textContent('#app-msg'), /no equilibrium reached/);
    await page.keyboard.press('Control+y');
    await edited(page, 7);
    assert.deepEqual(await page.evaluate(() => window.curvenet.keptCurves()), afterClick);
    assert.doesNotMatch(await page.textContent('#stat-lambda'), /equilibrium/);
    assert.doesNotMatch(await page.textContent('#app-msg'), /equilibrium/);

    // The save links answer files.
    const obj = await page.request.get(url + (await page.getAttribute('#save-obj', 'href')).replace(/^/, '/'));
    assert.equal(obj.status(), 200);
    assert.match(await obj.text(), /^# curvenet export/);

    await page.screenshot({ path: path.join(outDir, 'serve.png') });
    assert.deepEqual(foreign, [], 'the page made no request but to the server');
    assert.deepEqual(problems, [], 'no console errors');
  } finally {
    await close();
    proc.kill('SIGTERM');
  }
});

test('the local search, a constraint, the physical numbers and loading a run in the app', { timeout: 300_000 }, async () => {
  const dir = path.join(outDir, 'serve-small');
  fs.rmSync(dir, { recursive: true, force: true });
  fs.mkdirSync(dir, { recursive: true });
  const geo = path.join(dir, 'geo.json');
  execFileSync(binary(), ['trace', '--mesh', 'dome', '--geodesics', '8', '--seed', '3', '--out', geo], { stdio: 'ignore' });
  const run = path.join(dir, 'run');
  execFileSync(binary(), ['simplify', '--curves', geo, '--mesh', 'dome', '--budget', '0.6', '--out', run], { stdio: 'ignore' });
  const { proc, url } = await serve(['--curves', geo, '--mesh', 'dome', '--units', 'mm', '--material', 'steel', '--radius', '10']);
  const { page, problems, close } = await openBrowser();
  const foreign = [];
  try {
    page.on('request', (r) => { if (!r.url().startsWith(url + '/')) foreign.push(r.url()); });
    await page.goto(url + '/');
    const ready = () => page.waitForFunction(() => window.curvenet && (window.curvenet.error || (window.curvenet.app && window.curvenet.app.ready && window.curvenet.app.constraints)), null, { timeout: 60_000 });
    await ready();
    assert.equal(await page.evaluate(() => window.curvenet.error), null);

    // The physical numbers of the current structure, and its gravity deflection.
    assert.ok(await page.isVisible('#stat-physical'));
    assert.match(await page.textContent('#stat-physical'), /first frequency [0-9.e+-]+ Hz/);
    assert.match(await page.textContent('#stat-physical'), /utilisation .* \(curve \d+/);
    await page.check('input[name=deform][value=gravity]');
    assert.match(await page.textContent('#deform-info'), /largest deflection/);

    // A constraint from the form: the kept curves connected.
    await page.click('#constraints-box summary');
    await page.check('#c-connected');
    await page.click('#set-constraints');
    await page.waitForFunction(() => window.curvenet.app.margins !== null, null, { timeout: 30_000 });
    assert.match(await page.textContent('#constraint-margins'), /constraints met: ✓ separate structures: 1 \(limit 1\)/);

    // The local search from the current structure, then its best network adopted.
    await page.fill('#budget', '0.5');
    await page.click('#run-local');
    await page.waitForFunction(() => {
      const l = window.curvenet.app.local;
      return l && l.status !== 'running' && l.status !== 'idle';
    }, null, { timeout: 120_000 });
    const local = await page.evaluate(() => window.curvenet.app.local);
    assert.equal(local.status, 'done', JSON.stringify(local));
    assert.match(await page.textContent('#local-progress'), /done; best: /);
    const best = local.result.best.curves;
    await page.click('#adopt-local');
    await edited(page, 1);
    assert.deepEqual(await page.evaluate(() => window.curvenet.keptCurves()), best);
    assert.match(await page.textContent('#constraint-margins'), /constraints met: ✓ length \(budget of the last search\): .*separate structures: 1/);
    assert.match(await page.textContent('#stat-physical'), /Hz/);

    // A run folder loaded from the page: the page comes back on its answer.
    const result = JSON.parse(fs.readFileSync(path.join(run, 'result.json'), 'utf8'));
    await page.fill('#run-path', run);
    await Promise.all([page.waitForNavigation({ timeout: 60_000 }), page.click('#load-run')]);
    await ready();
    assert.match(await page.title(), /serve-small\/run/);
    assert.deepEqual(await page.evaluate(() => window.curvenet.keptCurves()), result.answer.curves);
    await page.waitForFunction(() => window.curvenet.app.steps.length > 0, null, { timeout: 30_000 });
    assert.equal(await page.evaluate(() => window.curvenet.app.steps.length), result.iterations.length);

    await page.screenshot({ path: path.join(outDir, 'serve-small.png') });
    assert.deepEqual(foreign, [], 'the page made no request but to the server');
    assert.deepEqual(problems, [], 'no console errors');
  } finally {
    await close();
    proc.kill('SIGTERM');
  }
});

// Opens the page written by `curvenet view` in a real browser (Debian's headless Chromium through
// playwright-core) and checks it works: no console errors, a WebGL canvas that is not blank, the
// iteration slider changing the displayed curve count and λ, the answer's and the
// alternatives' buttons showing their networks, a click on a curve showing its details, the
// deformation and shape toggles, an iteration short of equilibrium named as such. Saves
// target/browser-demo/screenshot.png.
//
// Run from the repository root or this folder:  npm ci && npm test   (in tests/browser)
// Environment: see common.mjs (CURVENET_BIN, CHROMIUM, BROWSER_DEMO).

import { test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { pathToFileURL } from 'node:url';
import { binary, openBrowser, outDir, outsideTheView, root } from './common.mjs';

function curvenet(args) {
  return execFileSync(binary(), args, { cwd: root, encoding: 'utf8', stdio: ['ignore', 'pipe', 'inherit'] });
}

test('the viewer of a demo run works in headless Chromium', { timeout: 600_000 }, async () => {
  fs.rmSync(outDir, { recursive: true, force: true });
  curvenet(['demo', '--alternatives', '2', '--out', outDir]);
  const printed = curvenet(['view', outDir]).trim().split('\n').pop();
  const page_path = path.resolve(root, printed);
  assert.equal(page_path, path.join(outDir, 'viewer.html'), 'view prints the page path');
  const html = fs.readFileSync(page_path, 'utf8');
  assert.ok(!/https?:\/\//.test(html), 'the page references no URL');
  const result = JSON.parse(fs.readFileSync(path.join(outDir, 'result.json'), 'utf8'));
  const n = result.iterations.length;
  assert.ok(n >= 3, `the demo has several iterations (${n})`);

  const { page, problems, close } = await openBrowser();
  const requests = [];
  try {
    page.on('request', (r) => { if (!r.url().startsWith('file:') && !r.url().startsWith('data:')) requests.push(r.url()); });
    await page.goto(pathToFileURL(page_path).href);
    await page.waitForFunction(() => window.curvenet && (window.curvenet.ready || window.curvenet.error), null, { timeout: 60_000 });
    const err = await page.evaluate(() => window.curvenet.error);
    assert.equal(err, null, `viewer error: ${err}`);
    await page.waitForFunction(() => window.curvenet.frames > 2, null, { timeout: 30_000 });

    // The canvas is not blank: many pixels differ from the background, in several colours.
    const pixels = await page.evaluate(() => {
      const src = document.getElementById('view');
      const c = document.createElement('canvas');
      c.width = src.width; c.height = src.height;
      const ctx = c.getContext('2d');
      ctx.drawImage(src, 0, 0);
      const d = ctx.getImageData(0, 0, c.width, c.height).data;
      let drawn = 0;
      const colours = new Set();
      for (let i = 0; i < d.length; i += 4) {
        const diff = Math.abs(d[i] - 244) + Math.abs(d[i + 1] - 245) + Math.abs(d[i + 2] - 247);
        if (diff > 24) { drawn++; colours.add((d[i] >> 4) * 256 + (d[i + 1] >> 4) * 16 + (d[i + 2] >> 4)); }
      }
      return { drawn, total: d.length / 4, colours: colours.size };
    });
    assert.ok(pixels.drawn > 0.02 * pixels.total, `canvas mostly blank: ${JSON.stringify(pixels)}`);
    assert.ok(pixels.colours > 8, `too few colours: ${JSON.stringify(pixels)}`);
    assert.deepEqual(await outsideTheView(page), [], 'the first view shows the whole network');

    // The page opens on the answer; the answer and each alternative have a button that shows
    // that network (its curves, λ).
    const read = async () => ({
      iter: await page.textContent('#stat-iter'),
      curves: await page.textContent('#stat-curves'),
      lambda: await page.textContent('#stat-lambda'),
    });
    const answer = result.answer;
    const alts = result.alternatives || [];
    assert.ok(answer, 'the demo has an answer');
    assert.ok(alts.length >= 1, `the demo has alternatives (${alts.length})`);
    const opened = await read();
    assert.ok(opened.curves.startsWith(`${answer.curves.length} of `), opened.curves);
    assert.equal(await page.evaluate(() => window.curvenet.chosen), 0);
    const buttons = await page.$$('#chosen button');
    assert.equal(buttons.length, 1 + alts.length, 'one button per chosen network');
    assert.match(await buttons[1].textContent(), /^alternative 1: λ_eq /);
    await buttons[1].click();
    const alt = await read();
    assert.equal(await page.evaluate(() => window.curvenet.chosen), 1);
    assert.deepEqual(await page.evaluate(() => window.curvenet.keptCurves()), alts[0].curves);
    assert.ok(alt.curves.startsWith(`${alts[0].curves.length} of `), alt.curves);
    assert.ok(alt.iter.includes('alternative 1'), alt.iter);
    await buttons[0].click();
    assert.deepEqual(await page.evaluate(() => window.curvenet.keptCurves()), answer.curves);

    // The slider: Home goes to the first iteration, the arrow keys step, End to the last.
    await page.focus('#iter');
    await page.keyboard.press('End');
    const last = await read();
    assert.ok(last.curves.startsWith(`${result.iterations[n - 1].curves.length} of `), last.curves);
    assert.equal(await page.evaluate(() => window.curvenet.chosen), null);
    await page.keyboard.press('Home');
    const first = await read();
    assert.ok(first.curves.startsWith(`${result.iterations[0].curves.length} of `), first.curves);
    assert.notEqual(first.lambda, last.lambda, 'λ changes with the iteration');
    assert.notEqual(first.curves, last.curves, 'the curve count changes with the iteration');
    await page.keyboard.press('ArrowRight');
    const second = await read();
    assert.ok(second.curves.startsWith(`${result.iterations[1].curves.length} of `), second.curves);
    assert.notEqual(second.lambda, first.lambda);
    assert.equal(await page.evaluate(() => window.curvenet.iteration), 1);
    await page.keyboard.press('End');
    assert.equal(await page.evaluate(() => window.curvenet.iteration), n - 1);

    // Click a kept curve: its details appear.
    await page.click('#animate');
    await page.waitForTimeout(100);
    const target = await page.evaluate(() => {
      const c = window.curvenet.keptCurves()[0];
      return { c, p: window.curvenet.screenPointOf(c) };
    });
    assert.ok(target.p, 'the kept curve is on screen');
    await page.mouse.click(target.p[0], target.p[1]);
    await page.waitForSelector('#info:not([hidden])', { timeout: 5_000 });
    const info = await page.textContent('#info');
    assert.match(info, /curve \d+/);
    assert.match(info, /rest length/);
    assert.match(info, /joint/);
    const picked = await page.evaluate(() => window.curvenet.selected);
    assert.equal(typeof picked, 'number');

    // Gravity and the designed shape.
    await page.check('input[name=deform][value=gravity]');
    assert.match(await page.textContent('#deform-info'), /gravity/);
    await page.check('input[name=shape][value=rest]');
    await page.check('input[name=deform][value=mode]');
    await page.check('input[name=shape][value=equilibrium]');
    await page.check('#overlay');
    await page.click('#animate');
    await page.waitForTimeout(300);

    await page.screenshot({ path: path.join(outDir, 'screenshot.png') });

    // An iteration whose relaxation stopped short of equilibrium is named as such: the page
    // again, with the record of iteration 1 saying so (the demo's all reached it).
    const flags = html.match(/"unrelaxed":(true|false)/g) || [];
    assert.equal(flags.length, n, 'each iteration says whether it reached equilibrium');
    assert.ok(flags.every((f) => f.endsWith('false')), 'the demo relaxed every iteration');
    let seen = 0;
    const marked = html.replace(/"unrelaxed":false/g, (f) => (seen++ === 1 ? '"unrelaxed":true' : f));
    const markedPath = path.join(outDir, 'viewer-unrelaxed.html');
    fs.writeFileSync(markedPath, marked);
    await page.goto(pathToFileURL(markedPath).href);
    await page.waitForFunction(() => window.curvenet && (window.curvenet.ready || window.curvenet.error), null, { timeout: 60_000 });
    await page.focus('#iter');
    await page.keyboard.press('Home');
    assert.doesNotMatch(await page.textContent('#stat-lambda'), /equilibrium/);
    await page.keyboard.press('ArrowRight');
    assert.match(await page.textContent('#stat-lambda'), /no equilibrium reached: λ_eq of the state where the relaxation stopped/);
    assert.match(await page.textContent('#stat-status'), /not at equilibrium/);
    fs.rmSync(markedPath);

    assert.deepEqual(requests, [], 'the page made no network request');
    assert.deepEqual(problems, [], 'no console errors');
  } finally {
    await close();
  }
});

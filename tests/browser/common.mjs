// What the browser tests share: the repository's folders, the `curvenet` binary, and headless
// Chromium on a fresh profile with a page that records its console errors and page errors.
//
// Environment: CURVENET_BIN = a built `curvenet` binary (default: target/release/curvenet,
// built with `cargo build --release -p curvenet-cli`), CHROMIUM = the browser (default
// /usr/bin/chromium), BROWSER_DEMO = the folder of the screenshots (default target/browser-demo).

import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

const here = path.dirname(fileURLToPath(import.meta.url));
export const root = path.resolve(here, '..', '..');
export const outDir = path.resolve(root, process.env.BROWSER_DEMO || 'target/browser-demo');
const browserPath = process.env.CHROMIUM || '/usr/bin/chromium';

let built = null;

// The binary under test (built once when CURVENET_BIN does not name one).
export function binary() {
  if (process.env.CURVENET_BIN) return process.env.CURVENET_BIN;
  if (!built) {
    execFileSync('cargo', ['build', '--quiet', '--release', '--locked', '-p', 'curvenet-cli'], { cwd: root, stdio: 'inherit' });
    built = path.join(root, 'target', 'release', 'curvenet');
  }
  return built;
}

// Headless Chromium on a fresh profile: its page, the problems the page reported (console
// errors, page errors) and close(), which also removes the profile.
export async function openBrowser() {
  const userDir = fs.mkdtempSync(path.join(os.tmpdir(), 'curvenet-chromium-'));
  const context = await chromium.launchPersistentContext(userDir, {
    executablePath: browserPath,
    headless: true,
    viewport: { width: 1280, height: 800 },
    args: [
      '--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync',
      '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
    ],
  });
  const close = async () => {
    await context.close();
    fs.rmSync(userDir, { recursive: true, force: true });
  };
  const problems = [];
  try {
    const page = context.pages()[0] || await context.newPage();
    page.on('console', (m) => { if (m.type() === 'error') problems.push(`console: ${m.text()}`); });
    page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
    return { page, problems, close };
  } catch (e) {
    await close();
    throw e;
  }
}

// The points of the kept curves (ends, quarters, middle) that the page draws outside the part
// of the canvas its panel leaves free, undeformed: the first view must show the whole network.
export async function outsideTheView(page) {
  const deform = await page.evaluate(() => document.querySelector('input[name=deform]:checked').value);
  await page.check('input[name=deform][value=none]');
  await page.waitForTimeout(100);
  const outside = await page.evaluate(() => {
    const cv = window.curvenet;
    const canvas = document.getElementById('view');
    const left = document.getElementById('panel').getBoundingClientRect().right;
    const bad = [];
    for (const c of cv.keptCurves()) {
      for (const t of [0, 0.25, 0.5, 0.75, 1]) {
        const q = cv.screenPointOf(c, t);
        if (!q || q[0] < left || q[0] > canvas.clientWidth || q[1] < 0 || q[1] > canvas.clientHeight) bad.push({ c, t, q });
      }
    }
    return bad;
  });
  await page.check(`input[name=deform][value=${deform}]`);
  return outside;
}

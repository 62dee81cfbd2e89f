// curvenet serve: the viewer grown into a design tool. Loaded after viewer.js only on the page
// `curvenet serve` answers at /, it talks to that server alone (its JSON API, docs/serve.md):
// a click on a curve removes or restores it, undo and redo, the greedy from a budget slider
// (progress, cancel, then a slider over its iterations), and saving the current structure.
(function () {
  'use strict';
  const cv = window.curvenet;
  if (!cv || !cv.ready || !cv.showLive) return;
  const $ = (id) => document.getElementById(id);
  const app = { busy: false, edits: 0, past: 0, future: 0, greedy: null, steps: [], error: null };
  cv.app = app;

  const box = document.createElement('fieldset');
  box.id = 'app';
  box.innerHTML = `<legend>design</legend>
    <div class="row"><button id="undo" type="button" disabled title="undo (Ctrl+Z)">undo</button>
      <button id="redo" type="button" disabled title="redo (Ctrl+Y)">redo</button>
      <span id="app-busy" class="note"></span></div>
    <div class="note">click a curve to remove it, a removed one to restore it</div>
    <div id="app-msg" class="note"></div>
    <div class="row"><label for="budget">budget</label>
      <input type="range" id="budget" min="0.05" max="1" step="0.05" value="0.5" aria-label="greedy budget">
      <span id="budget-text">50%</span></div>
    <div class="row"><button id="run-greedy" type="button">Run greedy</button>
      <button id="cancel-greedy" type="button" disabled>Cancel</button></div>
    <div id="greedy-progress" class="note"></div>
    <div class="row" id="greedy-steps" hidden><label for="greedy-iter">step</label>
      <input type="range" id="greedy-iter" min="0" max="0" step="1" value="0" aria-label="greedy iteration">
      <span id="greedy-iter-text"></span></div>
    <div class="row">save
      <a id="save-obj" href="api/export?format=obj" download>OBJ</a>
      <a id="save-csv" href="api/export?format=csv" download>CSV</a>
      <a id="save-json" href="api/export?format=json" download>JSON</a></div>`;
  const panel = $('panel');
  panel.insertBefore(box, $('setup').nextSibling);

  const sci = (x, d) => (x === null || x === undefined) ? '–'
    : (x === 0 ? '0' : (Math.abs(x) >= 1e-3 && Math.abs(x) < 1e5 ? Number(x.toPrecision(d)).toString() : x.toExponential(d - 1)));
  function msg(text, bad) {
    const m = $('app-msg');
    m.textContent = text;
    m.className = bad ? 'note bad' : 'note';
    app.error = bad ? text : null;
  }

  async function api(method, path, body) {
    const init = { method, headers: {} };
    if (body !== undefined) {
      init.headers['Content-Type'] = 'application/json';
      init.body = JSON.stringify(body);
    }
    const r = await fetch(path, init);
    const j = await r.json().catch(() => ({ error: `the server answered ${r.status}` }));
    if (!r.ok) throw new Error(j.error || `the server answered ${r.status}`);
    return j;
  }

  // The drawing of the current structure: its mode and equilibrium from /api/mode, checked to
  // belong to the same structure as the summary (another client may have edited between).
  let current = cv.keptCurves();
  async function show(summary) {
    for (let tries = 0; tries < 4; tries++) {
      const m = await api('GET', 'api/mode');
      if (m.curves.join() === summary.curves.join()) {
        cv.showLive(Object.assign({}, summary, { u: { full: m.displacement }, mode: { full: m.mode } }));
        current = summary.curves.slice();
        return;
      }
      summary = await api('GET', 'api/state');
    }
    throw new Error('the structure keeps changing (another client is editing)');
  }

  // History of structures for undo and redo (curve lists).
  const past = [], future = [];
  function buttons() {
    $('undo').disabled = app.busy || !past.length;
    $('redo').disabled = app.busy || !future.length;
    app.past = past.length; app.future = future.length;
  }
  async function edit(request, done) {
    if (app.busy) return;
    app.busy = true;
    $('app-busy').textContent = 'computing…';
    buttons();
    const before = current.slice();
    try {
      const s = await request();
      await show(s);
      (done || (() => { past.push(before); future.length = 0; }))(before);
      msg(`${s.curves.length} curves, λ ${sci(s.lambda, 5)} (${s.status}), computed in ${sci(s.elapsed_ms, 3)} ms`);
      app.edits++;
    } catch (e) {
      msg(e.message, true);
    }
    app.busy = false;
    $('app-busy').textContent = '';
    buttons();
  }
  cv.onPick = (c) => edit(() => api('POST', 'api/toggle', { curve: c }));
  function undo() {
    if (!past.length) return;
    const to = past[past.length - 1];
    edit(() => api('POST', 'api/set', { curves: to }), (before) => { past.pop(); future.push(before); });
  }
  function redo() {
    if (!future.length) return;
    const to = future[future.length - 1];
    edit(() => api('POST', 'api/set', { curves: to }), (before) => { future.pop(); past.push(before); });
  }
  $('undo').addEventListener('click', undo);
  $('redo').addEventListener('click', redo);
  window.addEventListener('keydown', (ev) => {
    if (!(ev.ctrlKey || ev.metaKey)) return;
    const k = ev.key.toLowerCase();
    if (k === 'z' && !ev.shiftKey) { ev.preventDefault(); undo(); }
    if (k === 'y' || (k === 'z' && ev.shiftKey)) { ev.preventDefault(); redo(); }
  });

  // The greedy: start, progress, cancel, then its iterations.
  const budget = $('budget');
  const budgetText = () => { $('budget-text').textContent = `${Math.round(100 * budget.value)}%`; };
  budget.addEventListener('input', budgetText);
  budgetText();
  function progressText(p) {
    const last = p.last ? `iteration ${p.last.iteration}: ${p.last.curves} curves, λ ${sci(p.last.lambda, 4)}, length ${sci(p.last.length, 5)}` : '';
    const pct = p.budget ? ` to ${Math.round(100 * p.budget)}%` : '';
    switch (p.status) {
      case 'idle': return '';
      case 'running': return `greedy${pct} running… ${last}`;
      case 'done': return `greedy${pct} done (${p.stop}): ${p.iterations} iterations; step through them below`;
      case 'cancelled': return `greedy cancelled after ${p.iterations} iterations`;
      default: return `greedy failed: ${p.error}`;
    }
  }
  let polling = false;
  async function poll() {
    if (polling) return;
    polling = true;
    try {
      for (;;) {
        const p = await api('GET', 'api/greedy');
        app.greedy = p;
        $('greedy-progress').textContent = progressText(p);
        const running = p.status === 'running';
        $('run-greedy').disabled = running;
        $('cancel-greedy').disabled = !running;
        if (!running) break;
        await new Promise((r) => setTimeout(r, 200));
      }
      const list = await api('GET', 'api/greedy/iterations');
      app.steps = list.iterations;
      const it = $('greedy-iter');
      $('greedy-steps').hidden = !app.steps.length;
      it.max = String(Math.max(0, app.steps.length - 1));
      it.value = '0';
      stepText();
    } catch (e) {
      msg(e.message, true);
    }
    polling = false;
  }
  function stepText() {
    const s = app.steps[+$('greedy-iter').value];
    $('greedy-iter-text').textContent = s ? `${s.iteration}: ${s.curves.length} curves` : '';
  }
  $('run-greedy').addEventListener('click', async () => {
    try {
      await api('POST', 'api/greedy', { budget: Number(budget.value) });
      poll();
    } catch (e) {
      msg(e.message, true);
    }
  });
  $('cancel-greedy').addEventListener('click', () => api('POST', 'api/greedy/cancel').catch((e) => msg(e.message, true)));
  $('greedy-iter').addEventListener('input', stepText);
  $('greedy-iter').addEventListener('change', (ev) => {
    const k = Number(ev.target.value);
    edit(() => api('POST', 'api/greedy/step', { iteration: k }));
  });

  buttons();
  poll();
  app.ready = true;
})();

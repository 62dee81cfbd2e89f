// curvenet serve: the viewer grown into a design tool. Loaded after viewer.js only on the page
// `curvenet serve` answers at /, it talks to that server alone (its JSON API, docs/serve.md):
// a click on a curve removes or restores it, undo and redo, the greedy from a budget slider
// (progress, cancel, then a slider over its iterations), the local search from the current
// structure (progress, cancel, adopt its best network), the design constraints (set for the
// session, the current structure's margins shown), loading a run folder, and saving the
// current structure; and drawing: a geodesic (press on the surface, drag a direction), a curve
// through points (click them, double-click to end), deleting a curve, dragging one along the
// surface; the slide of the current structure's curves on the surface (progress, cancel, adopt
// as one drawing edit); each drawing edit rebuilds the network on the server and the page
// loads it again.
(function () {
  'use strict';
  const cv = window.curvenet;
  if (!cv || !cv.ready || !cv.showLive) return;
  const $ = (id) => document.getElementById(id);
  const app = {
    busy: false, edits: 0, past: 0, future: 0, greedy: null, steps: [], local: null,
    constraints: null, margins: null, error: null,
  };
  cv.app = app;
  // The objective's symbol and the physical mode's scene unit, for the messages.
  const goalValue = (cv.objective && cv.objective.value) || 'λ';
  // A structure's value and status in a message, named unrelaxed when its relaxation stopped
  // short of equilibrium.
  const valueText = (s) => `${goalValue} ${sci(s.lambda, 5)} (${s.status}${cv.unrelaxed(s) ? `; ${cv.unrelaxedText}` : ''})`;
  const lenUnit = cv.units ? ` ${cv.units}` : '';

  const box = document.createElement('fieldset');
  box.id = 'app';
  box.innerHTML = `<legend>design</legend>
    <div class="row"><button id="undo" type="button" disabled title="undo (Ctrl+Z)">undo</button>
      <button id="redo" type="button" disabled title="redo (Ctrl+Y)">redo</button>
      <span id="app-busy" class="note"></span></div>
    <div class="note">click a curve to remove it, a removed one to restore it</div>
    <div id="app-msg" class="note"></div>
    <div class="row" id="draw-tools" role="radiogroup" aria-label="drawing tool">draw
      <label><input type="radio" name="tool" value="none" checked> view</label>
      <label><input type="radio" name="tool" value="geodesic"> geodesic</label>
      <label><input type="radio" name="tool" value="through"> through points</label>
      <label><input type="radio" name="tool" value="drag"> drag</label>
      <label><input type="radio" name="tool" value="delete"> delete</label></div>
    <div id="draw-note" class="note"></div>
    <div class="row"><label for="budget">budget</label>
      <input type="range" id="budget" min="0.05" max="1" step="0.05" value="0.5" aria-label="greedy budget">
      <span id="budget-text">50%</span></div>
    <div class="row"><button id="run-greedy" type="button">Run greedy</button>
      <button id="cancel-greedy" type="button" disabled>Cancel</button></div>
    <div id="greedy-progress" class="note"></div>
    <div class="row" id="greedy-steps" hidden><label for="greedy-iter">step</label>
      <input type="range" id="greedy-iter" min="0" max="0" step="1" value="0" aria-label="greedy iteration">
      <span id="greedy-iter-text"></span></div>
    <div class="row"><button id="run-local" type="button" title="local search from the current structure within the budget">Run local search</button>
      <button id="cancel-local" type="button" disabled>Cancel</button>
      <button id="adopt-local" type="button" disabled title="make the local search's best network current">Adopt</button></div>
    <div id="local-progress" class="note"></div>
    <div class="row" id="slide-row" hidden><button id="run-slide" type="button" title="slide the current structure's curves on the surface within its length and the constraints">Slide</button>
      <button id="cancel-slide" type="button" disabled>Cancel</button>
      <button id="adopt-slide" type="button" disabled title="put the slid curves in place of the drawn ones (one edit: undo takes it back)">Adopt</button></div>
    <div id="slide-progress" class="note"></div>
    <details id="constraints-box"><summary>constraints</summary>
      <div class="row"><label><input type="checkbox" id="c-connected"> connected</label>
        <label for="c-min-curves">min curves</label> <input type="number" id="c-min-curves" min="1" step="1" style="width:4em"></div>
      <div class="row"><label for="c-symmetry">symmetry</label>
        <input type="text" id="c-symmetry" placeholder="none, mirror, auto, rotate:N" style="width:11em"></div>
      <div class="row"><label for="c-max-gap">max gap</label> <input type="number" id="c-max-gap" min="0" step="any" style="width:6em">
        <label for="c-max-deviation">max deviation</label> <input type="number" id="c-max-deviation" min="0" step="any" style="width:6em"></div>
      <div><label for="c-groups">groups (one per line: <code>NAME: 0 1 4-7</code>)</label>
        <textarea id="c-groups" rows="2" style="width:100%"></textarea></div>
      <div class="row"><button id="set-constraints" type="button">Apply</button>
        <button id="clear-constraints" type="button">Clear</button></div>
      <div id="constraint-notes" class="note"></div>
    </details>
    <div id="constraint-margins" class="note"></div>
    <div class="row">save
      <a id="save-obj" href="api/export?format=obj" download>OBJ</a>
      <a id="save-csv" href="api/export?format=csv" download>CSV</a>
      <a id="save-json" href="api/export?format=json" download>JSON</a>
      <a id="save-surface" href="api/export?format=surface" download>surface</a></div>
    <div class="row"><input type="text" id="run-path" placeholder="run folder on the server" aria-label="run folder" style="flex:1">
      <button id="load-run" type="button">Load run</button></div>`;
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
        const g = m.gravity && { full: m.gravity.displacement, max_displacement: m.gravity.max_displacement, vertex: m.gravity.vertex };
        cv.showLive(Object.assign({}, summary, { u: { full: m.displacement }, mode: { full: m.mode }, gravity: g || null }));
        current = summary.curves.slice();
        showMargins(summary.constraints);
        return;
      }
      summary = await api('GET', 'api/state');
    }
    throw new Error('the structure keeps changing (another client is editing)');
  }

  // The current structure's margin for each constraint in force.
  const marginNames = {
    budget: 'length (budget of the last search)', keep: 'keep-list curves missing', groups: 'groups split',
    symmetry: 'symmetry orbits split', connected: 'separate structures', min_curves: 'curves',
    max_gap: 'largest gap',
    max_deviation: cv.units ? 'largest deviation under self-weight (the physical model)' : 'largest deviation',
  };
  function showMargins(c) {
    app.margins = c || null;
    const box = $('constraint-margins');
    if (!c) { box.textContent = ''; return; }
    // Lengths carry the physical mode's scene unit.
    const lengths = { budget: 1, max_gap: 1, max_deviation: 1 };
    const u = (k) => (cv.units && lengths[k] ? ` ${cv.units}` : '');
    const rows = Object.entries(c.margins).map(([k, m]) =>
      `${m.met ? '✓' : '✗'} ${marginNames[k] || k}: ${sci(m.value, 4)}${u(k)} (limit ${sci(m.limit, 4)}${u(k)})`);
    box.textContent = `constraints ${c.met ? 'met' : 'NOT met'}: ` + rows.join('; ');
    box.className = c.met ? 'note' : 'note bad';
  }

  // History of structures for undo and redo (curve lists).
  const past = [], future = [];
  function buttons() {
    $('undo').disabled = app.busy || !(past.length || drawing.undo);
    $('redo').disabled = app.busy || !(future.length || drawing.redo);
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
      msg(`${s.curves.length} curves, ${valueText(s)}, computed in ${sci(s.elapsed_ms, 3)} ms`);
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
    if (!past.length) { if (drawing.undo) redrawn(api('POST', 'api/curves/undo'), 'undone'); return; }
    const to = past[past.length - 1];
    edit(() => api('POST', 'api/set', { curves: to }), (before) => { past.pop(); future.push(before); });
  }
  function redo() {
    if (!future.length) { if (drawing.redo) redrawn(api('POST', 'api/curves/redo'), 'redone'); return; }
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
    // The last iteration's value, named unstable or unrelaxed as the panel would name it, the
    // two in one parenthesis as in the messages.
    const named = (l) => {
      const caveats = [l.unstable, cv.unrelaxed(l) && cv.unrelaxedText].filter(Boolean);
      return caveats.length ? ` (${caveats.join('; ')})` : '';
    };
    const last = p.last ? `iteration ${p.last.iteration}: ${p.last.curves} curves, ${goalValue} ${sci(p.last.lambda, 4)}${named(p.last)}, length ${sci(p.last.length, 5)}${lenUnit}` : '';
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

  // The local search from the current structure, with the budget of the slider.
  function localText(p) {
    const pct = p.budget ? ` to ${Math.round(100 * p.budget)}%` : '';
    const r = p.result;
    const best = r ? `best: ${r.best.curves.length} curves, ${goalValue} ${sci(r.best.lambda, 4)}, length ${sci(r.best.length, 5)}${lenUnit}`
      + ` (${r.moves} moves from ${r.given && r.start.curves.join() === r.given.curves.join() ? 'the current structure' : 'a single-curve start'}, ${r.evaluations} networks evaluated)` : '';
    switch (p.status) {
      case 'idle': return '';
      case 'running': return `local search${pct} running… ${sci(p.elapsed_ms / 1000, 3)} s`;
      case 'done': return `local search${pct} done; ${best}`;
      case 'cancelled': return `local search cancelled; ${best || 'nothing found'}`;
      default: return `local search failed: ${p.error}`;
    }
  }

  let localPolling = false;
  async function pollLocal() {
    if (localPolling) return;
    localPolling = true;
    try {
      for (;;) {
        const p = await api('GET', 'api/local');
        app.local = p;
        $('local-progress').textContent = localText(p);
        const running = p.status === 'running';
        $('run-local').disabled = running;
        $('cancel-local').disabled = !running;
        $('adopt-local').disabled = running || !p.result;
        if (!running) break;
        await new Promise((r) => setTimeout(r, 200));
      }
    } catch (e) {
      msg(e.message, true);
    }
    localPolling = false;
  }
  $('run-local').addEventListener('click', async () => {
    try {
      await api('POST', 'api/local', { budget: Number(budget.value) });
      pollLocal();
    } catch (e) {
      msg(e.message, true);
    }
  });
  $('cancel-local').addEventListener('click', () => api('POST', 'api/local/cancel').catch((e) => msg(e.message, true)));
  $('adopt-local').addEventListener('click', () => edit(() => api('POST', 'api/local/adopt')));

  // The slide of the current structure's curves on the surface (within its length).
  function slideText(p) {
    const best = p.best !== undefined ? `, best ${goalValue} ${sci(p.best, 5)}` : '';
    const r = p.result;
    const found = r ? `${goalValue} ${sci(r.lambda_before, 5)} → ${sci(r.lambda_after, 5)}, `
      + `largest move ${sci(r.largest_move, 3)}${lenUnit}, ${r.evaluations} network${r.evaluations === 1 ? '' : 's'} evaluated`
      + (r.limited ? ' (stopped at the most evaluations asked for: the best so far is kept)' : '') : '';
    switch (p.status) {
      case 'idle': return '';
      case 'running': return `slide running… ${p.evaluations} networks evaluated at the last gain${best}, ${sci(p.elapsed_ms / 1000, 3)} s`;
      case 'done': return `slide done: ${found}`;
      case 'cancelled': return `slide cancelled: ${found || 'nothing found'}`;
      default: return `slide failed: ${p.error}`;
    }
  }
  let slidePolling = false;
  async function pollSlide() {
    if (slidePolling) return;
    slidePolling = true;
    try {
      for (;;) {
        const p = await api('GET', 'api/slide');
        app.slide = p;
        $('slide-progress').textContent = slideText(p);
        const running = p.status === 'running';
        $('run-slide').disabled = running;
        $('cancel-slide').disabled = !running;
        $('adopt-slide').disabled = running || !p.result;
        if (!running) break;
        await new Promise((r) => setTimeout(r, 200));
      }
    } catch (e) {
      msg(e.message, true);
    }
    slidePolling = false;
  }
  $('run-slide').addEventListener('click', async () => {
    try {
      await api('POST', 'api/slide', {});
      pollSlide();
    } catch (e) {
      msg(e.message, true);
    }
  });
  $('cancel-slide').addEventListener('click', () => api('POST', 'api/slide/cancel').catch((e) => msg(e.message, true)));
  $('adopt-slide').addEventListener('click', () => redrawn(api('POST', 'api/slide/adopt'), 'slid'));

  // The design constraints of the session.
  function constraintsBody() {
    const num = (id) => ($(id).value.trim() === '' ? undefined : Number($(id).value));
    const body = { connected: $('c-connected').checked };
    const sym = $('c-symmetry').value.trim();
    if (sym) body.symmetry = sym;
    if (num('c-min-curves') !== undefined) body.min_curves = num('c-min-curves');
    if (num('c-max-gap') !== undefined) body.max_gap = num('c-max-gap');
    if (num('c-max-deviation') !== undefined) body.max_deviation = num('c-max-deviation');
    if ($('c-groups').value.trim()) body.groups = $('c-groups').value;
    return body;
  }
  function showConstraints(a) {
    app.constraints = a;
    const c = a.constraints;
    $('c-connected').checked = !!c.connected;
    $('c-min-curves').value = c.min_curves ?? '';
    $('c-symmetry').value = c.symmetry === 'none' ? '' : c.symmetry;
    $('c-max-gap').value = c.max_gap ?? '';
    $('c-max-deviation').value = c.max_deviation ?? '';
    $('c-groups').value = (c.groups || []).map((g) => `${g.name.replace(/:/g, ' ')}: ${g.curves.join(' ')}`).join('\n');
    $('constraint-notes').textContent = a.notes.join(' ');
    showMargins(a.current);
  }
  async function setConstraints(body) {
    try {
      showConstraints(await api('POST', 'api/constraints', body));
      msg(app.margins ? 'constraints set: the greedy and the local search honour them' : 'no constraint in force');
    } catch (e) {
      msg(e.message, true);
    }
  }
  $('set-constraints').addEventListener('click', () => setConstraints(constraintsBody()));
  $('clear-constraints').addEventListener('click', () => setConstraints({}));

  // Loading a run folder replaces the served network: the page is loaded again.
  $('load-run').addEventListener('click', async () => {
    const path = $('run-path').value.trim();
    if (!path) { msg('give the folder of a run (holding result.json)', true); return; }
    $('load-run').disabled = true;
    $('app-busy').textContent = 'loading…';
    try {
      await api('POST', 'api/run', { path });
      location.reload();
    } catch (e) {
      msg(e.message, true);
      $('app-busy').textContent = '';
      $('load-run').disabled = false;
    }
  });

  // ---------- drawing ----------
  // The design's curves and the drawing's undo history on the server (GET /api/curves).
  const drawing = { editable: false, undo: 0, redo: 0, curves: [] };
  app.drawing = drawing;
  const note = (t) => { $('draw-note').textContent = t; };
  const tools = {
    none: '',
    geodesic: 'press on the surface and drag a direction: the geodesic runs from there to the boundary',
    through: 'click points on the surface; double-click to end the curve',
    drag: 'press on a curve and drag it along the surface; it is rebuilt when you let go',
    delete: 'click a curve to delete it from the design',
  };
  let tool = 'none';
  for (const el of document.querySelectorAll('input[name=tool]')) {
    el.addEventListener('change', () => setTool(el.value));
  }
  function setTool(t) {
    tool = t;
    app.tool = t;
    points.length = 0;
    cv.setPreview(null);
    note(tools[t] || '');
    const el = document.querySelector(`input[name=tool][value=${t}]`);
    if (el) el.checked = true;
  }
  app.setTool = setTool;
  // A drawing edit: the server rebuilds the network, and the page is loaded again to draw it
  // (the message and the tool kept for the new page).
  async function redrawn(request, what) {
    if (app.busy) return;
    app.busy = true;
    $('app-busy').textContent = 'rebuilding…';
    buttons();
    try {
      const s = await request;
      const joints = s.joints ? `, ${s.joints.length} joints` : '';
      const text = `${what}${s.curve !== undefined ? ` curve ${s.curve}` : ''}: ${s.curve_count} curves${joints}, `
        + `${valueText(s)}, computed in ${sci(s.elapsed_ms, 3)} ms`;
      sessionStorage.setItem('curvenet-drawn', JSON.stringify({ text, tool }));
      location.reload();
    } catch (e) {
      msg(e.message, true);
      app.busy = false;
      $('app-busy').textContent = '';
      cv.setPreview(null);
      buttons();
    }
  }
  // One preview request at a time; the latest asked is sent when the last one answers.
  let previewing = false, nextPreview = null;
  async function preview(body, then) {
    nextPreview = [body, then];
    if (previewing) return;
    previewing = true;
    while (nextPreview) {
      const [b, t] = nextPreview;
      nextPreview = null;
      try {
        const r = await api('POST', 'api/curves/preview', b);
        if (tool !== 'none') cv.setPreview(r.points);
        if (t) t(r);
        app.previews = (app.previews || 0) + 1;
      } catch (e) {
        note(e.message);
      }
    }
    previewing = false;
  }
  const points = [];
  let press = null;
  cv.tool = {
    down(x, y) {
      if (tool === 'none' || app.busy || !drawing.editable) return false;
      const p = cv.surfaceAt(x, y);
      if (tool === 'geodesic') {
        if (!p) return false;
        press = { p, x, y };
        return true;
      }
      if (tool === 'drag') {
        const c = cv.pick(x, y);
        if (c === null || !p) return false;
        press = { p, c, x, y, params: null };
        return true;
      }
      if (tool === 'through' ? !p : cv.pick(x, y) === null) return false;
      press = { p, x, y };
      return true;
    },
    move(x, y) {
      if (!press) return;
      const q = cv.surfaceAt(x, y);
      if (!q) return;
      if (tool === 'geodesic') {
        const d = [0, 1, 2].map((k) => q[k] - press.p[k]);
        if (Math.hypot(...d) > 0) { press.d = d; preview({ geodesic: { point: press.p, direction: d } }); }
      } else if (tool === 'drag') {
        const pr = press;
        preview({ drag: { curve: pr.c, from: pr.p, to: q } }, (r) => { pr.params = r.params; });
      }
    },
    up(x, y) {
      const pr = press;
      press = null;
      if (!pr) return;
      const clicked = Math.hypot(x - pr.x, y - pr.y) < 5;
      if (tool === 'geodesic') {
        if (pr.d && !clicked) redrawn(api('POST', 'api/curves', { geodesic: { point: pr.p, direction: pr.d } }), 'drew geodesic');
        else cv.setPreview(null);
      } else if (tool === 'drag') {
        const wait = async () => {
          while (previewing) await new Promise((r) => setTimeout(r, 20));
          if (pr.params && pr.params.some((a) => a !== 0)) redrawn(api('POST', `api/curves/${pr.c}/move`, { params: pr.params }), 'moved');
          else cv.setPreview(null);
        };
        wait();
      } else if (tool === 'through' && clicked && pr.p) {
        points.push(pr.p);
        if (points.length > 1) preview({ through: points.slice() });
        else cv.setPreview([pr.p, pr.p]);
        note(`${points.length} point${points.length > 1 ? 's' : ''}; double-click to end the curve`);
      } else if (tool === 'delete' && clicked) {
        const c = cv.pick(x, y);
        if (c !== null) redrawn(api('DELETE', `api/curves/${c}`), 'deleted');
      }
    },
    dblclick() {
      if (tool !== 'through' || points.length < 2) return;
      const pts = points.slice();
      points.length = 0;
      redrawn(api('POST', 'api/curves', { through: pts }), 'drew');
    },
  };
  // While a tool is chosen, a click on a curve does not remove it.
  const pickCurve = cv.onPick;
  cv.onPick = (c) => { if (tool === 'none') pickCurve(c); };
  async function loadDrawing() {
    try {
      Object.assign(drawing, await api('GET', 'api/curves'));
    } catch (e) {
      msg(e.message, true);
    }
    $('draw-tools').hidden = !drawing.editable;
    $('slide-row').hidden = !drawing.editable;
    buttons();
  }
  const kept = sessionStorage.getItem('curvenet-drawn');
  if (kept) {
    sessionStorage.removeItem('curvenet-drawn');
    try {
      const k = JSON.parse(kept);
      msg(k.text);
      setTool(k.tool || 'none');
    } catch (e) { /* a stale entry: ignored */ }
  }

  buttons();
  loadDrawing().then(() => { app.drawReady = true; });
  poll();
  pollLocal();
  pollSlide();
  api('GET', 'api/constraints').then(showConstraints).catch((e) => msg(e.message, true));
  app.ready = true;
})();

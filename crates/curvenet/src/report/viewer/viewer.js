// curvenet viewer: a small hand-written WebGL viewer for one run's output folder.
// The data (format "curvenet-viewer", version 1) is embedded in the page by `curvenet view`;
// nothing is loaded from the network. In app mode (`D.app`, the page `curvenet serve` answers)
// it shows one live structure that app.js replaces after each edit (`showLive`), and a click on
// a curve is handed to app.js (`onPick`).
(function () {
  'use strict';

  const state = {
    ready: false, error: null, frames: 0, iteration: 0, selected: null, chosen: null,
    setIteration: null, setChosen: null, pick: null, onPick: null, showLive: null,
  };
  window.curvenet = state;

  const $ = (id) => document.getElementById(id);

  function fail(msg) {
    state.error = msg;
    const box = $('error');
    box.hidden = false;
    box.textContent = msg;
  }

  // ---------- data ----------
  function bytesOf(b64) {
    const s = atob(b64);
    const u = new Uint8Array(s.length);
    for (let i = 0; i < s.length; i++) u[i] = s.charCodeAt(i);
    return u.buffer;
  }
  const f32 = (o) => new Float32Array(bytesOf(o.f32));
  const u32 = (o) => new Uint32Array(bytesOf(o.u32));
  function i16(o) {
    const q = new Int16Array(bytesOf(o.i16));
    const out = new Float32Array(q.length);
    for (let i = 0; i < q.length; i++) out[i] = q[i] * o.scale;
    return out;
  }

  const D = JSON.parse($('curvenet-data').textContent);
  // What the iterations' numbers are: λ_eq (the paper's) or μ_min (the frequency objective).
  const goal = D.objective || { value: 'λ_eq', score: 'λ_fix' };
  state.objective = goal;
  // A network whose relaxation stopped short of equilibrium (a run's recorded `unrelaxed`, the
  // server's `converged: false`): its numbers belong to the state where the relaxation stopped,
  // and every place that shows them says so.
  state.unrelaxed = (it) => !!(it && (it.unrelaxed || it.converged === false));
  state.unrelaxedText = `no equilibrium reached: ${goal.value} of the state where the relaxation stopped`;
  if (D.objective && D.objective.name !== 'lambda') {
    $('label-lambda').textContent = goal.value;
    $('chart').title = `${goal.value} along the greedy; click to jump`;
  }
  // The physical mode's scene unit (`mm`, `cm`, `m`): every length shown carries it, and the
  // paper's figures (its λ_eq, equilibrium and gravity deflection) say they are the paper's.
  const units = (D.setup && D.setup.units) || null;
  const lenUnit = units ? ` ${units}` : '';
  const paperModel = units && (!D.objective || D.objective.name === 'lambda');
  state.units = units;
  if (paperModel) $('label-lambda').textContent = `${goal.value} (the paper's model)`;
  const rest = f32(D.positions);
  const V = rest.length / 3;
  const rods = D.rods;
  const its = D.iterations;
  // The answer and the alternatives; those that are greedy iterations show that iteration.
  const chosen = D.chosen || [];

  // Scene centre and size (the rest network and the surface).
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  function grow(a) {
    for (let i = 0; i < a.length; i += 3) {
      for (let k = 0; k < 3; k++) {
        if (a[i + k] < lo[k]) lo[k] = a[i + k];
        if (a[i + k] > hi[k]) hi[k] = a[i + k];
      }
    }
  }
  grow(rest);
  let meshPos = null, meshFaces = null;
  if (D.mesh) {
    meshPos = f32(D.mesh.vertices);
    meshFaces = u32(D.mesh.faces);
    grow(meshPos);
  }
  const center = [0, 1, 2].map((k) => 0.5 * (lo[k] + hi[k]));
  const size = Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) || 1;
  const restC = new Float32Array(rest.length);
  for (let i = 0; i < rest.length; i++) restC[i] = rest[i] - center[i % 3];

  // Per-network fields (an iteration k, or 'c' + i for chosen network i that is not an
  // iteration), decoded on first use, expanded to 3V.
  const cache = new Map();
  function fields(k) {
    if (cache.has(k)) return cache.get(k);
    const it = netOf(k);
    const on = new Uint8Array(V);
    for (const c of it.curves) for (const v of rods[c].v) on[v] = 1;
    const expand = (o) => {
      if (!o) return null;
      if (o.full) return Float32Array.from(o.full);
      const q = i16(o);
      const out = new Float32Array(3 * V);
      let j = 0;
      for (let v = 0; v < V; v++) {
        if (!on[v]) continue;
        out[3 * v] = q[j]; out[3 * v + 1] = q[j + 1]; out[3 * v + 2] = q[j + 2];
        j += 3;
      }
      return out;
    };
    const f = {
      kept: new Set(it.curves), u: expand(it.u), mode: expand(it.mode),
      gravity: expand(it.gravity), modeMax: maxNorm(it.mode), gravityMax: maxNorm(it.gravity),
    };
    cache.set(k, f);
    return f;
  }
  function maxNorm(o) {
    if (!o) return 0;
    if (!o.full) return o.max || 0;
    let m = 0;
    for (let i = 0; i + 2 < o.full.length; i += 3) m = Math.max(m, Math.hypot(o.full[i], o.full[i + 1], o.full[i + 2]));
    return m;
  }
  function netOf(key) { return typeof key === 'string' ? chosen[+key.slice(1)] : its[key]; }

  // ---------- formatting ----------
  const sci = (x, d) => (x === null || x === undefined) ? '–'
    : (x === 0 ? '0' : (Math.abs(x) >= 1e-3 && Math.abs(x) < 1e5 ? Number(x.toPrecision(d)).toString() : x.toExponential(d - 1)));
  const esc = (s) => String(s).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' }[c]));

  // ---------- WebGL ----------
  const canvas = $('view');
  const gl = canvas.getContext('webgl', { antialias: true, preserveDrawingBuffer: true, alpha: false });
  if (!gl) {
    fail('WebGL is not available in this browser, so the 3D view cannot be shown. ' +
      'The pictures final.png, mode.png and lambda.png next to result.json show the result.');
    return;
  }

  function shader(type, src) {
    const s = gl.createShader(type);
    gl.shaderSource(s, src);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
    return s;
  }
  function program(vs, fs, attrs) {
    const p = gl.createProgram();
    gl.attachShader(p, shader(gl.VERTEX_SHADER, vs));
    gl.attachShader(p, shader(gl.FRAGMENT_SHADER, fs));
    gl.linkProgram(p);
    if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(p));
    const a = {}, u = {};
    for (const [name, n] of attrs) a[name] = { loc: gl.getAttribLocation(p, name), n };
    const nu = gl.getProgramParameter(p, gl.ACTIVE_UNIFORMS);
    for (let i = 0; i < nu; i++) {
      const info = gl.getActiveUniform(p, i);
      u[info.name] = gl.getUniformLocation(p, info.name);
    }
    return { p, a, u, stride: attrs.reduce((s, x) => s + x[1], 0) };
  }

  // Thick lines: every segment is a quad expanded in screen space; endpoints carry a
  // displacement scaled by u_amp (mode or gravity animation without rebuilding buffers).
  const lineProg = program(`
    attribute vec3 a_p0; attribute vec3 a_d0; attribute vec3 a_p1; attribute vec3 a_d1;
    attribute vec2 a_se; attribute float a_w; attribute vec4 a_c;
    uniform mat4 u_mvp; uniform vec2 u_half; uniform float u_amp;
    varying vec4 v_c;
    void main() {
      vec4 c0 = u_mvp * vec4(a_p0 + u_amp * a_d0, 1.0);
      vec4 c1 = u_mvp * vec4(a_p1 + u_amp * a_d1, 1.0);
      vec2 s0 = c0.xy / c0.w * u_half;
      vec2 s1 = c1.xy / c1.w * u_half;
      vec2 d = s1 - s0;
      float l = length(d);
      vec2 dir = l > 1e-6 ? d / l : vec2(1.0, 0.0);
      vec2 n = vec2(-dir.y, dir.x);
      vec4 c = a_se.y < 0.5 ? c0 : c1;
      vec2 off = (n * a_se.x + dir * (a_se.y < 0.5 ? -0.5 : 0.5)) * a_w * 0.5;
      c.xy += off / u_half * c.w;
      gl_Position = c;
      v_c = a_c;
    }`, `
    precision mediump float;
    varying vec4 v_c;
    void main() { gl_FragColor = v_c; }`,
  [['a_p0', 3], ['a_d0', 3], ['a_p1', 3], ['a_d1', 3], ['a_se', 2], ['a_w', 1], ['a_c', 4]]);

  const meshProg = program(`
    attribute vec3 a_p; attribute vec3 a_n;
    uniform mat4 u_mvp; uniform vec3 u_eye;
    varying float v_s;
    void main() {
      gl_Position = u_mvp * vec4(a_p, 1.0);
      v_s = 0.55 + 0.45 * abs(dot(normalize(a_n), normalize(u_eye - a_p)));
    }`, `
    precision mediump float;
    uniform vec4 u_color;
    varying float v_s;
    void main() { gl_FragColor = vec4(u_color.rgb * v_s, u_color.a); }`,
  [['a_p', 3], ['a_n', 3]]);

  const pointProg = program(`
    attribute vec3 a_p; attribute vec3 a_d; attribute vec4 a_c; attribute float a_s;
    uniform mat4 u_mvp; uniform float u_amp;
    varying vec4 v_c;
    void main() {
      gl_Position = u_mvp * vec4(a_p + u_amp * a_d, 1.0);
      gl_PointSize = a_s;
      v_c = a_c;
    }`, `
    precision mediump float;
    varying vec4 v_c;
    void main() { gl_FragColor = v_c; }`,
  [['a_p', 3], ['a_d', 3], ['a_c', 4], ['a_s', 1]]);

  function makeBuffer(data) {
    const b = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, b);
    gl.bufferData(gl.ARRAY_BUFFER, data, gl.STATIC_DRAW);
    return { b, count: 0 };
  }
  function bindAttribs(prog, buf) {
    gl.bindBuffer(gl.ARRAY_BUFFER, buf);
    let off = 0;
    for (const name in prog.a) {
      const a = prog.a[name];
      if (a.loc >= 0) {
        gl.enableVertexAttribArray(a.loc);
        gl.vertexAttribPointer(a.loc, a.n, gl.FLOAT, false, prog.stride * 4, off * 4);
      }
      off += a.n;
    }
  }
  function unbindAttribs(prog) {
    for (const name in prog.a) if (prog.a[name].loc >= 0) gl.disableVertexAttribArray(prog.a[name].loc);
  }

  // Surface: flat-shaded triangles, centred.
  let meshBuf = null;
  if (meshPos && meshFaces) {
    const nf = meshFaces.length / 3;
    const data = new Float32Array(nf * 18);
    let o = 0;
    for (let f = 0; f < nf; f++) {
      const ids = [meshFaces[3 * f], meshFaces[3 * f + 1], meshFaces[3 * f + 2]];
      const p = ids.map((i) => [0, 1, 2].map((k) => meshPos[3 * i + k] - center[k]));
      const e1 = [0, 1, 2].map((k) => p[1][k] - p[0][k]);
      const e2 = [0, 1, 2].map((k) => p[2][k] - p[0][k]);
      const n = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]];
      for (let j = 0; j < 3; j++) {
        data.set(p[j], o); data.set(n, o + 3); o += 6;
      }
    }
    meshBuf = makeBuffer(data);
    meshBuf.count = nf * 3;
  }

  // ---------- colours ----------
  const hex = (h) => [parseInt(h.slice(1, 3), 16) / 255, parseInt(h.slice(3, 5), 16) / 255, parseInt(h.slice(5, 7), 16) / 255, 1];
  const C = {
    bg: hex('#f4f5f7'), kept: hex('#1c56aa'), removed: hex('#e39a8a'), overlay: hex('#9aa0a8'),
    selected: hex('#f09a00'), support: hex('#202028'), partial: hex('#2a6fdb'), joint: hex('#f09a00'), mesh: [0.80, 0.77, 0.70, 0.38],
  };
  const STOPS = [[48, 18, 110], [33, 120, 180], [60, 180, 120], [235, 200, 40], [200, 30, 30]];
  function colormap(t) {
    t = Math.min(1, Math.max(0, t || 0)) * (STOPS.length - 1);
    const i = Math.min(STOPS.length - 2, Math.floor(t)), f = t - i;
    return [0, 1, 2].map((k) => (STOPS[i][k] + f * (STOPS[i + 1][k] - STOPS[i][k])) / 255).concat([1]);
  }

  // ---------- UI state ----------
  const ui = {
    k: Number.isInteger(D.start) && D.start < its.length ? D.start : its.length - 1, shape: 'equilibrium', overlay: false, deform: 'mode', amp: 0.25, animate: true,
    mesh: !!meshBuf, removed: true, supports: true,
    // The chosen network shown (index into `chosen`), or null: the iteration ui.k.
    c: null,
  };
  // The viewer opens on the answer (on its own state when it is not an iteration).
  if (chosen.length && chosen[0].label === 'the answer') ui.c = 0;
  if (ui.c !== null && chosen[ui.c].iteration !== null) ui.k = chosen[ui.c].iteration;
  // What is shown: the key of fields() and the record.
  function key() { return ui.c !== null && chosen[ui.c].iteration === null ? 'c' + ui.c : ui.k; }
  function shown() { return netOf(key()); }
  const FOV = 35 * Math.PI / 180;
  const cam = { target: [0, 0, 0], dist: 1.6 * size, yaw: -60 * Math.PI / 180, pitch: 25 * Math.PI / 180 };
  cam.dist = fitDistance();
  const camHome = JSON.parse(JSON.stringify(cam));

  // ---------- geometry of the current state ----------
  let lineBuf = null, pointBuf = null, pickable = [], dispScale = 0;
  const drawn = new Map();
  function build() {
    const f = fields(key());
    const eq = ui.shape === 'equilibrium';
    const disp = ui.deform === 'mode' ? f.mode : (ui.deform === 'gravity' ? f.gravity : null);
    const dmax = ui.deform === 'mode' ? f.modeMax : (ui.deform === 'gravity' ? f.gravityMax : 0);
    dispScale = disp && dmax > 0 ? 0.25 * size / dmax : 0;
    const segs = [];
    pickable = [];
    drawn.clear();
    const pos = (v, useU) => {
      const b = [restC[3 * v], restC[3 * v + 1], restC[3 * v + 2]];
      if (useU && f.u) { b[0] += f.u[3 * v]; b[1] += f.u[3 * v + 1]; b[2] += f.u[3 * v + 2]; }
      return b;
    };
    const zero = [0, 0, 0];
    const dispOf = (v) => disp ? [disp[3 * v], disp[3 * v + 1], disp[3 * v + 2]] : zero;
    function addCurve(c, useU, withDisp, width, colorOf, pick) {
      const vs = rods[c].v;
      const n = vs.length, m = rods[c].closed ? n : n - 1;
      const P = vs.map((v) => pos(v, useU));
      const Dd = vs.map((v) => withDisp ? dispOf(v) : zero);
      for (let j = 0; j < m; j++) {
        const a = j, b = (j + 1) % n;
        segs.push([P[a], Dd[a], P[b], Dd[b], width, colorOf(vs[a], vs[b])]);
      }
      if (pick) pickable.push({ c, P, D: Dd, closed: rods[c].closed });
    }
    const magColor = (a, b) => {
      if (!disp || dmax <= 0) return C.kept;
      const m = (v) => Math.hypot(disp[3 * v], disp[3 * v + 1], disp[3 * v + 2]);
      return colormap(0.5 * (m(a) + m(b)) / dmax);
    };
    for (let c = 0; c < rods.length; c++) {
      const kept = f.kept.has(c);
      const sel = state.selected === c;
      if (kept) {
        drawn.set(c, 'kept');
        addCurve(c, eq, true, sel ? 5 : 3, sel ? () => C.selected : magColor, true);
        if (ui.overlay) addCurve(c, !eq, false, 1.5, () => C.overlay, false);
      } else if (ui.removed || sel) {
        drawn.set(c, 'removed');
        addCurve(c, false, false, sel ? 4 : 1.5, () => sel ? C.selected : C.removed, true);
      }
    }
    // A slid run's network before it slid, drawn thin in the other shape's colour.
    if (ui.before && D.before) {
      for (const b of D.before) {
        const p = f32(b.points);
        const n = p.length / 3, m = b.closed ? n : n - 1;
        const at = (i) => [p[3 * i] - center[0], p[3 * i + 1] - center[1], p[3 * i + 2] - center[2]];
        for (let j = 0; j < m; j++) segs.push([at(j), zero, at((j + 1) % n), zero, 1.5, C.overlay]);
      }
    }
    // App mode: a curve being drawn or dragged (world coordinates), drawn over the rest.
    if (state.previewLine && state.previewLine.length > 1) {
      const q = state.previewLine.map((p) => [p[0] - center[0], p[1] - center[1], p[2] - center[2]]);
      for (let j = 0; j + 1 < q.length; j++) segs.push([q[j], zero, q[j + 1], zero, 4, C.selected]);
    }
    const data = new Float32Array(segs.length * 6 * 19);
    const corners = [[-1, 0], [1, 0], [1, 1], [-1, 0], [1, 1], [-1, 1]];
    let o = 0;
    for (const s of segs) {
      for (const [side, end] of corners) {
        data.set(s[0], o); data.set(s[1], o + 3); data.set(s[2], o + 6); data.set(s[3], o + 9);
        data[o + 12] = side; data[o + 13] = end; data[o + 14] = s[4]; data.set(s[5], o + 15);
        o += 19;
      }
    }
    if (lineBuf) gl.deleteBuffer(lineBuf.b);
    lineBuf = makeBuffer(data);
    lineBuf.count = segs.length * 6;
    // Points: supports of kept curves, joints of the selected curve.
    const pts = [];
    if (ui.supports) {
      // Each end as held: a clamp large, a pin small, a partial support (some translations
      // or the rotation only) in its own colour; a free end not at all.
      const look = { clamped: [C.support, 10], pinned: [C.support, 6], partial: [C.partial, 8] };
      for (const c of f.kept) {
        const r = rods[c];
        (r.ends || []).forEach((kind, i) => {
          const v = i === 0 ? r.v[0] : r.v[r.v.length - 1];
          if (look[kind]) pts.push([pos(v, eq), dispOf(v), look[kind][0], look[kind][1]]);
        });
      }
    }
    if (state.selected !== null) {
      const sk = f.kept.has(state.selected);
      for (const j of rods[state.selected].joints) {
        pts.push([pos(j[2], sk && eq), sk ? dispOf(j[2]) : zero, C.joint, 9]);
      }
    }
    const pd = new Float32Array(pts.length * 11);
    pts.forEach((p, i) => { pd.set(p[0], 11 * i); pd.set(p[1], 11 * i + 3); pd.set(p[2], 11 * i + 6); pd[11 * i + 10] = p[3]; });
    if (pointBuf) gl.deleteBuffer(pointBuf.b);
    pointBuf = makeBuffer(pd);
    pointBuf.count = pts.length;
    updateText();
    requestDraw();
  }

  // ---------- camera ----------
  function eye() {
    const cp = Math.cos(cam.pitch);
    return [0, 1, 2].map((k) => cam.target[k] + cam.dist * [cp * Math.cos(cam.yaw), cp * Math.sin(cam.yaw), Math.sin(cam.pitch)][k]);
  }
  function basis() {
    const e = eye();
    const f = [0, 1, 2].map((k) => cam.target[k] - e[k]);
    const fl = Math.hypot(...f);
    const fw = f.map((x) => x / fl);
    let r = [fw[1], -fw[0], 0];
    const rl = Math.hypot(...r) || 1;
    r = r.map((x) => x / rl);
    const up = [r[1] * fw[2] - r[2] * fw[1], r[2] * fw[0] - r[0] * fw[2], r[0] * fw[1] - r[1] * fw[0]];
    return { e, fw, r, up };
  }
  // The part of the canvas the panels leave free: [left, right) in CSS pixels.
  function freeArea() {
    const W = canvas.clientWidth;
    const panel = $('panel'), info = $('info');
    const left = W > 2 * panel.offsetWidth ? panel.offsetLeft + panel.offsetWidth : 0;
    const right = !info.hidden && W > 2 * info.offsetWidth ? info.offsetLeft : W;
    return right > left ? { left, right, W } : { left: 0, right: W, W };
  }
  // The camera distance at which the drawn network's bounding box, seen from the current
  // direction, fits the free part of the canvas with a margin: each corner c (from the
  // target) must satisfy |c·r| ≤ tan(half width)·(d + c·fw) and |c·up| ≤ tan(half fov)·(d + c·fw).
  function fitDistance() {
    const { fw, r, up } = basis();
    const { left, right, W } = freeArea();
    const H = Math.max(1, canvas.clientHeight);
    const tv = Math.tan(0.5 * FOV);
    const th = tv * ((right - left) / H);
    const half = [0, 1, 2].map((k) => 0.5 * (hi[k] - lo[k]));
    let d = 0;
    for (let i = 0; i < 8; i++) {
      const c = half.map((h, k) => ((i >> k) & 1 ? h : -h));
      const dot = (a) => a[0] * c[0] + a[1] * c[1] + a[2] * c[2];
      d = Math.max(d, Math.abs(dot(r)) / th - dot(fw), Math.abs(dot(up)) / tv - dot(fw));
    }
    return W > 0 && d > 0 ? 1.08 * d : 1.6 * size;
  }
  function mvp() {
    const { e, fw, r, up } = basis();
    const aspect = canvas.width / Math.max(1, canvas.height);
    const near = Math.max(cam.dist - size, cam.dist * 0.02), far = cam.dist + 2 * size;
    const t = 1 / Math.tan(0.5 * FOV);
    // view matrix rows: r, up, -fw; column-major projection * view.
    const view = [
      r[0], up[0], -fw[0], 0, r[1], up[1], -fw[1], 0, r[2], up[2], -fw[2], 0,
      -(r[0] * e[0] + r[1] * e[1] + r[2] * e[2]), -(up[0] * e[0] + up[1] * e[1] + up[2] * e[2]),
      (fw[0] * e[0] + fw[1] * e[1] + fw[2] * e[2]), 1,
    ];
    const proj = [t / aspect, 0, 0, 0, 0, t, 0, 0, 0, 0, (far + near) / (near - far), -1, 0, 0, 2 * far * near / (near - far), 0];
    const m = new Float32Array(16);
    for (let i = 0; i < 4; i++) for (let j = 0; j < 4; j++) {
      let s = 0;
      for (let k = 0; k < 4; k++) s += proj[k * 4 + i] * view[j * 4 + k];
      m[j * 4 + i] = s;
    }
    // Centre the scene in the part of the canvas the panels leave free.
    const { left, right, W } = freeArea();
    const tx = W > 0 ? (left + right - W) / W : 0;
    for (let j = 0; j < 4; j++) m[j * 4] += tx * m[j * 4 + 3];
    return { m, e };
  }

  // ---------- drawing ----------
  let pending = false;
  const t0 = performance.now();
  function currentAmp(now) {
    if (!dispScale) return 0;
    const a = ui.amp * dispScale;
    if (!ui.animate) return a;
    const t = (now - t0) / 1000;
    return ui.deform === 'mode' ? a * Math.sin(2 * Math.PI * t / 1.6) : a * 0.5 * (1 - Math.cos(2 * Math.PI * t / 2.4));
  }
  let lastAmp = 0;
  function draw(now) {
    pending = false;
    const dpr = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(canvas.clientWidth * dpr)), h = Math.max(1, Math.round(canvas.clientHeight * dpr));
    if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }
    gl.viewport(0, 0, w, h);
    gl.clearColor(C.bg[0], C.bg[1], C.bg[2], 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    const { m, e } = mvp();
    const amp = currentAmp(now || performance.now());
    lastAmp = amp;
    // Curves (opaque).
    gl.disable(gl.BLEND);
    gl.depthMask(true);
    gl.useProgram(lineProg.p);
    gl.uniformMatrix4fv(lineProg.u.u_mvp, false, m);
    gl.uniform2f(lineProg.u.u_half, 0.5 * w, 0.5 * h);
    gl.uniform1f(lineProg.u.u_amp, amp);
    bindAttribs(lineProg, lineBuf.b);
    gl.drawArrays(gl.TRIANGLES, 0, lineBuf.count);
    unbindAttribs(lineProg);
    // Points.
    if (pointBuf.count) {
      gl.useProgram(pointProg.p);
      gl.uniformMatrix4fv(pointProg.u.u_mvp, false, m);
      gl.uniform1f(pointProg.u.u_amp, amp);
      bindAttribs(pointProg, pointBuf.b);
      gl.drawArrays(gl.POINTS, 0, pointBuf.count);
      unbindAttribs(pointProg);
    }
    // Surface (translucent, over the curves, no depth writes).
    if (meshBuf && ui.mesh) {
      gl.enable(gl.BLEND);
      gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
      gl.depthMask(false);
      gl.useProgram(meshProg.p);
      gl.uniformMatrix4fv(meshProg.u.u_mvp, false, m);
      gl.uniform3f(meshProg.u.u_eye, e[0], e[1], e[2]);
      gl.uniform4f(meshProg.u.u_color, C.mesh[0], C.mesh[1], C.mesh[2], C.mesh[3]);
      bindAttribs(meshProg, meshBuf.b);
      gl.drawArrays(gl.TRIANGLES, 0, meshBuf.count);
      unbindAttribs(meshProg);
      gl.depthMask(true);
    }
    state.frames++;
    if (ui.animate && dispScale) requestDraw();
  }
  function requestDraw() {
    if (!pending) { pending = true; requestAnimationFrame(draw); }
  }

  // ---------- text ----------
  function updateText() {
    const it = shown();
    const s = D.setup;
    const own = typeof key() === 'string';
    const named = chosen.filter((c) => c.iteration === ui.k).map((c) => c.label);
    $('stat-iter').textContent = D.app ? 'the current structure'
      : own ? `– (${chosen[ui.c].label}: the ${chosen[ui.c].source.replace('_', ' ')}'s network)`
      : `${ui.k} of ${its.length - 1}` + (ui.k === its.length - 1 ? ' (final)' : '')
        + (named.length ? ` (${named.join(', ')})` : '');
    $('stat-curves').textContent = `${it.curves.length} of ${rods.length}: ${it.curves.join(' ')}`;
    for (const b of document.querySelectorAll('#chosen button')) {
      b.classList.toggle('on', ui.c !== null && +b.dataset.i === ui.c);
    }
    $('stat-length').textContent = `${sci(it.length, 6)}${lenUnit} (${(100 * it.length / s.total_length).toFixed(1)}%`
      + (s.budget ? `; budget ${sci(s.budget, 6)}${lenUnit})` : ' of the whole network)');
    // An unstable network (zero or negative modes) is named as such beside its numbers, and so
    // is one whose relaxation stopped short of equilibrium.
    const unrelaxed = state.unrelaxed(it);
    $('stat-lambda').textContent = sci(it.lambda, 5) + (it.unstable ? ` — ${it.unstable}` : '')
      + (unrelaxed ? ` — ${state.unrelaxedText}` : '');
    $('stat-lambda').classList.toggle('unstable', !!it.unstable || unrelaxed);
    $('stat-status').textContent = (it.status
      || (it.negative_modes ? 'unstable' : (it.zero_modes ? 'mechanism' : 'stable')))
      + (unrelaxed ? ' (not at equilibrium)' : '');
    $('stat-eigen').textContent = it.eigenvalues ? it.eigenvalues.map((x) => sci(x, 3)).join(', ') : '–';
    $('row-physical').hidden = !it.physical;
    $('stat-physical').textContent = it.physical ? physicalText(it.physical) : '–';
    $('stat-removed').textContent = own ? '–' : (it.removed === null ? 'none (last iteration)' : `curve ${it.removed} (${goal.score} ${sci(it.score, 4)})`);
    state.iteration = ui.k;
    state.chosen = ui.c;
    const f = fields(key());
    let info = '';
    if (ui.deform === 'mode') {
      info = `worst-case mode (unit vector) shown ×${sci(ui.amp * dispScale, 3)}`;
    } else if (ui.deform === 'gravity') {
      // Beside physical units this is the paper's gravity load (a weight per unit length
      // of its own units), not a physical deflection: the physical row gives that.
      const paper = units ? " of the paper's model (not a physical deflection)" : '';
      info = it.gravity
        ? `gravity${paper} (${sci(s.gravity.weight_per_length, 3)} per unit length): largest deflection ${sci(it.gravity.max_displacement, 4)} at vertex ${it.gravity.vertex}, shown ×${sci(ui.amp * dispScale, 3)}`
        : 'no gravity deflection: the structure is not positive definite (or it was not computed)';
    } else {
      info = 'no deformation shown';
    }
    if (ui.shape === 'equilibrium' && f.u) {
      let m = 0;
      for (let v = 0; v < V; v++) m = Math.max(m, Math.hypot(f.u[3 * v], f.u[3 * v + 1], f.u[3 * v + 2]));
      info += paperModel
        ? `; the paper's model's equilibrium moves up to ${sci(m, 3)}${lenUnit} from the designed shape`
        : `; equilibrium moves up to ${sci(m, 3)}${lenUnit} from the designed shape`;
    }
    $('deform-info').textContent = info;
    drawChart();
    showInfo();
  }

  // The physical mode's numbers of a structure, one per line: an iteration's record (numbers)
  // or the server's full analysis (deflection and utilisation with where they occur).
  function physicalText(p) {
    const unit = p.units ? ` ${p.units}` : (lenUnit || ' (scene units)');
    const len = (x) => (x === null || x === undefined) ? 'none (unstable)' : sci(x, 4) + unit;
    const load = p.load_max_deflection;
    const lines = [
      p.first_frequency_hz === null || p.first_frequency_hz === undefined
        ? 'first frequency: none (unstable)' : `first frequency ${sci(p.first_frequency_hz, 4)} Hz`,
      `self-weight deflection ${len(p.self_weight_max_deflection)}`,
      `worst-load deflection ${len(load && typeof load === 'object' ? load.max : load)}`
        + (load && typeof load === 'object' ? ` at vertex ${load.vertex}` : ''),
    ];
    const dev = p.max_deviation;
    if (dev !== null && dev !== undefined) {
      lines.push(`deviation from the design under self-weight ${len(typeof dev === 'object' ? dev.max : dev)}`);
    }
    lines.push(
      `assembly stress: bending ${sci(p.assembly_max_bending_stress_mpa, 4)} MPa, axial ${sci(p.assembly_max_axial_stress_mpa, 4)} MPa`,
    );
    const u = p.max_utilisation;
    if (u !== null && u !== undefined) {
      lines.push(typeof u === 'object'
        ? `utilisation ${sci(u.value, 3)} (curve ${u.curve}${u.near ? ', ' + u.near : ''}: ${sci(u.stress_mpa, 4)} of ${sci(u.strength_mpa, 4)} MPa)`
        : `utilisation ${sci(u, 3)}`);
    }
    if (p.mass_kg !== undefined) lines.push(`mass ${sci(p.mass_kg, 4)} kg`);
    if (p.overstressed_curves && p.overstressed_curves.length) {
      lines.push(`would break when bent: curves ${p.overstressed_curves.join(' ')}`);
    }
    // Each load case as the summary words it: deflection, utilisation, buckling, verdict.
    for (const c of (p.load_cases || [])) {
      const parts = [];
      if (c.max_deflection !== null && c.max_deflection !== undefined) {
        parts.push(`max deflection ${sci(c.max_deflection, 4)}${unit} at vertex ${c.max_deflection_vertex}`);
      }
      if (c.max_utilisation !== null && c.max_utilisation !== undefined) {
        parts.push(`utilisation ${sci(c.max_utilisation, 3)}`);
      }
      parts.push(c.buckling_factor !== null && c.buckling_factor !== undefined
        ? `buckles at ${sci(c.buckling_factor, 3)} × the load (${c.buckling})`
        : 'stands 100 × the load without buckling');
      const verdict = c.passes ? 'passes' : `FAILS: ${(c.failures || []).join('; ')}`;
      lines.push(`load case ${c.name}: ${parts.join(', ')}; ${verdict}`);
    }
    for (const w of (p.warnings || [])) lines.push(`warning: ${w}`);
    return lines.join('\n');
  }

  function drawChart() {
    const cv = $('chart');
    const ctx = cv.getContext('2d');
    const W = cv.width, H = cv.height;
    ctx.clearRect(0, 0, W, H);
    const lam = its.map((i) => i.lambda);
    let a = Math.min(...lam), b = Math.max(...lam);
    if (!(b > a)) { a -= Math.abs(a) * 0.1 + 1e-30; b += Math.abs(b) * 0.1 + 1e-30; }
    const X = (k) => 8 + (W - 16) * (its.length > 1 ? k / (its.length - 1) : 0.5);
    const Y = (y) => H - 14 - (H - 24) * (y - a) / (b - a);
    ctx.strokeStyle = '#d0d2d8'; ctx.strokeRect(0.5, 0.5, W - 1, H - 1);
    ctx.strokeStyle = '#1c56aa'; ctx.lineWidth = 1.5; ctx.beginPath();
    lam.forEach((y, k) => (k ? ctx.lineTo(X(k), Y(y)) : ctx.moveTo(X(k), Y(y))));
    ctx.stroke();
    ctx.fillStyle = '#f09a00'; ctx.beginPath(); ctx.arc(X(ui.k), Y(lam[ui.k]), 4, 0, 2 * Math.PI); ctx.fill();
    ctx.fillStyle = '#60606a'; ctx.font = '10px sans-serif';
    ctx.fillText(`${goal.value} ${sci(b, 3)}`, 4, 10);
    ctx.fillText(`${sci(a, 3)}   (x: iteration)`, 4, H - 3);
  }

  function showInfo() {
    const box = $('info');
    const c = state.selected;
    if (c === null) { box.hidden = true; return; }
    const r = rods[c];
    const f = fields(key());
    const kept = f.kept.has(c);
    const ra = D.removed_at[c];
    const own = typeof key() === 'string';
    const status = D.app
      ? (kept ? '<span class="kept">kept</span> (click to remove)' : '<span class="gone">removed</span> (click to restore)')
      : kept ? `<span class="kept">kept</span> ${own ? 'in ' + esc(chosen[ui.c].label) : 'at this iteration'}`
      : (own ? `<span class="gone">not in</span> ${esc(chosen[ui.c].label)}` : `<span class="gone">removed</span> after iteration ${ra}`);
    let rows = '';
    for (const j of r.joints) {
      const v = j[2];
      const p = [0, 1, 2].map((k) => sci(rest[3 * v + k], 6)).join(', ');
      const meets = j[3].map((m) => (f.kept.has(m) ? `<span class="kept">${m}</span>` : `<span class="gone">${m}</span>`)).join(' ');
      rows += `<tr><td>${sci(j[1], 6)}</td><td>${v}</td><td>${p}</td><td>${meets}</td></tr>`;
    }
    box.innerHTML = `<h2>curve ${c}</h2>
      <div>${status}</div>
      <div>rest length ${sci(r.length, 6)}${lenUnit} · ${r.closed ? 'closed' : 'open'} · supports ${esc(r.supports)} · ${r.v.length} vertices</div>
      <div>${r.joints.length} joint(s); meeting curves in blue are kept at this iteration</div>
      <table><tr><th>s${units ? ` (${esc(units)})` : ''}</th><th>vertex</th><th>position (rest${units ? `, ${esc(units)}` : ''})</th><th>meets</th></tr>${rows}</table>`;
    box.hidden = false;
  }

  // ---------- picking ----------
  // The inverse of a column-major 4×4 matrix, or null when it is singular.
  function invert4(m) {
    const a = Array.from(m, Number);
    const inv = new Array(16).fill(0);
    for (let i = 0; i < 4; i++) inv[5 * i] = 1;
    for (let c = 0; c < 4; c++) {
      let p = c;
      for (let r = c + 1; r < 4; r++) if (Math.abs(a[c * 4 + r]) > Math.abs(a[c * 4 + p])) p = r;
      if (Math.abs(a[c * 4 + p]) < 1e-300) return null;
      for (let k = 0; k < 4; k++) {
        [a[k * 4 + c], a[k * 4 + p]] = [a[k * 4 + p], a[k * 4 + c]];
        [inv[k * 4 + c], inv[k * 4 + p]] = [inv[k * 4 + p], inv[k * 4 + c]];
      }
      const d = a[c * 4 + c];
      for (let k = 0; k < 4; k++) { a[k * 4 + c] /= d; inv[k * 4 + c] /= d; }
      for (let r = 0; r < 4; r++) {
        if (r === c) continue;
        const f = a[c * 4 + r];
        if (f === 0) continue;
        for (let k = 0; k < 4; k++) { a[k * 4 + r] -= f * a[k * 4 + c]; inv[k * 4 + r] -= f * inv[k * 4 + c]; }
      }
    }
    return inv;
  }
  // The ray parameter at which o + t d meets triangle abc (Möller–Trumbore), or null.
  function rayTriangle(o, d, a, b, c) {
    const e1 = [b[0] - a[0], b[1] - a[1], b[2] - a[2]], e2 = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    const cross = (u, v) => [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
    const dot = (u, v) => u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    const p = cross(d, e2);
    const det = dot(e1, p);
    if (Math.abs(det) < 1e-300) return null;
    const s = [o[0] - a[0], o[1] - a[1], o[2] - a[2]];
    const u = dot(s, p) / det;
    if (u < 0 || u > 1) return null;
    const q = cross(s, e1);
    const v = dot(d, q) / det;
    if (v < 0 || u + v > 1) return null;
    const t = dot(e2, q) / det;
    return t > 0 ? t : null;
  }
  function pick(px, py) {
    const { m } = mvp();
    const w = canvas.clientWidth, h = canvas.clientHeight;
    const amp = lastAmp;
    let best = null, bestD = 10;
    const proj = (p, d) => {
      const x = p[0] + amp * d[0], y = p[1] + amp * d[1], z = p[2] + amp * d[2];
      const cx = m[0] * x + m[4] * y + m[8] * z + m[12];
      const cy = m[1] * x + m[5] * y + m[9] * z + m[13];
      const cw = m[3] * x + m[7] * y + m[11] * z + m[15];
      return cw > 0 ? [(cx / cw * 0.5 + 0.5) * w, (0.5 - cy / cw * 0.5) * h] : null;
    };
    for (const it of pickable) {
      const S = it.P.map((p, i) => proj(p, it.D[i]));
      const n = S.length, mm = it.closed ? n : n - 1;
      for (let j = 0; j < mm; j++) {
        const a = S[j], b = S[(j + 1) % n];
        if (!a || !b) continue;
        const dx = b[0] - a[0], dy = b[1] - a[1];
        const l2 = dx * dx + dy * dy;
        const t = l2 > 0 ? Math.max(0, Math.min(1, ((px - a[0]) * dx + (py - a[1]) * dy) / l2)) : 0;
        const d = Math.hypot(px - a[0] - t * dx, py - a[1] - t * dy);
        if (d < bestD) { bestD = d; best = it.c; }
      }
    }
    return best;
  }
  state.pick = (px, py) => {
    state.selected = pick(px, py);
    build();
    return state.selected;
  };
  // Where curve c's vertex at fraction t of its vertex list (default its middle one) is drawn
  // (CSS pixels in the canvas), for tests and tools.
  state.screenPointOf = (c, t) => {
    const it = pickable.find((x) => x.c === c);
    if (!it) return null;
    const { m } = mvp();
    const i = t === undefined ? Math.floor(it.P.length / 2)
      : Math.min(it.P.length - 1, Math.max(0, Math.round(t * (it.P.length - 1))));
    const x = it.P[i][0] + lastAmp * it.D[i][0], y = it.P[i][1] + lastAmp * it.D[i][1], z = it.P[i][2] + lastAmp * it.D[i][2];
    const cw = m[3] * x + m[7] * y + m[11] * z + m[15];
    if (!(cw > 0)) return null;
    const cx = (m[0] * x + m[4] * y + m[8] * z + m[12]) / cw, cy = (m[1] * x + m[5] * y + m[9] * z + m[13]) / cw;
    return [(cx * 0.5 + 0.5) * canvas.clientWidth, (0.5 - cy * 0.5) * canvas.clientHeight];
  };
  state.keptCurves = () => shown().curves.slice();
  // App mode: the curve being drawn or dragged (world points; null: none).
  state.previewLine = null;
  state.setPreview = (points) => { state.previewLine = points; build(); };
  // The point of the surface drawn at (px, py) (CSS pixels in the canvas), in world
  // coordinates, or null: the nearest triangle the eye's ray through the pixel hits.
  state.surfaceAt = (px, py) => {
    if (!meshPos || !meshFaces) return null;
    const { m } = mvp();
    const inv = invert4(m);
    if (!inv) return null;
    const nx = 2 * px / canvas.clientWidth - 1, ny = 1 - 2 * py / canvas.clientHeight;
    const un = (z) => {
      const v = [0, 1, 2, 3].map((i) => inv[i] * nx + inv[4 + i] * ny + inv[8 + i] * z + inv[12 + i]);
      return [v[0] / v[3], v[1] / v[3], v[2] / v[3]];
    };
    const o = un(-1), far = un(1);
    const d = [far[0] - o[0], far[1] - o[1], far[2] - o[2]];
    let best = Infinity;
    const nf = meshFaces.length / 3;
    const P = (i) => [meshPos[3 * i] - center[0], meshPos[3 * i + 1] - center[1], meshPos[3 * i + 2] - center[2]];
    for (let f = 0; f < nf; f++) {
      const a = P(meshFaces[3 * f]), b = P(meshFaces[3 * f + 1]), c = P(meshFaces[3 * f + 2]);
      const t = rayTriangle(o, d, a, b, c);
      if (t !== null && t < best) best = t;
    }
    if (!isFinite(best)) return null;
    return [0, 1, 2].map((k) => o[k] + best * d[k] + center[k]);
  };
  // Where the world point p is drawn (CSS pixels in the canvas), undeformed, or null.
  state.screenOf = (p) => {
    const { m } = mvp();
    const x = p[0] - center[0], y = p[1] - center[1], z = p[2] - center[2];
    const cw = m[3] * x + m[7] * y + m[11] * z + m[15];
    if (!(cw > 0)) return null;
    const cx = (m[0] * x + m[4] * y + m[8] * z + m[12]) / cw, cy = (m[1] * x + m[5] * y + m[9] * z + m[13]) / cw;
    return [(cx * 0.5 + 0.5) * canvas.clientWidth, (0.5 - cy * 0.5) * canvas.clientHeight];
  };
  // How curve c is drawn: 'kept', 'removed', or null when it is not drawn.
  state.drawnAs = (c) => drawn.get(c) || null;
  // App mode: the live structure replaced (fields as an iteration's, with full-length `u` and
  // `mode` arrays), drawn at once.
  state.showLive = (it) => {
    its[0] = it;
    cache.clear();
    ui.k = 0;
    ui.c = null;
    build();
  };

  // ---------- events ----------
  const slider = $('iter');
  slider.max = String(its.length - 1);
  slider.value = String(ui.k);
  state.setIteration = (k) => {
    ui.k = Math.max(0, Math.min(its.length - 1, k | 0));
    ui.c = null;
    slider.value = String(ui.k);
    build();
  };
  // Shows chosen network i (0: the answer when there is one; then the alternatives).
  state.setChosen = (i) => {
    if (!(i >= 0 && i < chosen.length)) return false;
    ui.c = i | 0;
    if (chosen[ui.c].iteration !== null) ui.k = chosen[ui.c].iteration;
    slider.value = String(ui.k);
    build();
    return true;
  };
  const list = $('chosen');
  chosen.forEach((c, i) => {
    const b = document.createElement('button');
    b.type = 'button';
    b.dataset.i = String(i);
    b.textContent = `${c.label}: ${goal.value} ${sci(c.lambda, 4)}, length ${sci(c.length, 5)}, ${c.curves.length} curves`;
    b.title = `from the ${c.source.replace('_', ' ')}` + (c.iteration !== null ? ` (iteration ${c.iteration})` : '') + `; curves ${c.curves.join(' ')}`;
    b.addEventListener('click', () => state.setChosen(i));
    list.appendChild(b);
  });
  list.hidden = chosen.length === 0;
  slider.addEventListener('input', () => state.setIteration(parseInt(slider.value, 10)));
  // Touching the slider while a chosen network is shown goes back to the iterations, even when
  // the key or click leaves its value where it was (End at the last iteration).
  const backToIterations = () => { if (ui.c !== null) state.setIteration(parseInt(slider.value, 10)); };
  slider.addEventListener('keydown', backToIterations);
  slider.addEventListener('pointerdown', backToIterations);
  $('chart').addEventListener('click', (ev) => {
    const r = ev.target.getBoundingClientRect();
    const x = (ev.clientX - r.left) / r.width;
    state.setIteration(Math.round(x * (its.length - 1)));
  });
  for (const el of document.querySelectorAll('input[name=shape]')) {
    el.addEventListener('change', () => { ui.shape = el.value; build(); });
  }
  for (const el of document.querySelectorAll('input[name=deform]')) {
    el.addEventListener('change', () => { ui.deform = el.value; build(); });
  }
  $('amp').addEventListener('input', (ev) => { ui.amp = ev.target.value / 100; updateText(); requestDraw(); });
  $('animate').addEventListener('change', (ev) => { ui.animate = ev.target.checked; requestDraw(); });
  $('overlay').addEventListener('change', (ev) => { ui.overlay = ev.target.checked; build(); });
  $('show-mesh').addEventListener('change', (ev) => { ui.mesh = ev.target.checked; requestDraw(); });
  if (D.before) $('row-before').hidden = false;
  $('show-before').addEventListener('change', (ev) => { ui.before = ev.target.checked; build(); });
  $('show-removed').addEventListener('change', (ev) => { ui.removed = ev.target.checked; build(); });
  $('show-supports').addEventListener('change', (ev) => { ui.supports = ev.target.checked; build(); });
  $('reset').addEventListener('click', () => {
    Object.assign(cam, JSON.parse(JSON.stringify(camHome)));
    cam.dist = fitDistance();
    requestDraw();
  });
  if (!meshBuf) { $('show-mesh').checked = false; $('show-mesh').disabled = true; }

  let drag = null;
  canvas.addEventListener('contextmenu', (ev) => ev.preventDefault());
  // App mode: a drawing tool (state.tool, set by app.js) takes the pointer when its `down`
  // accepts the press; the view orbits otherwise.
  let toolDrag = false;
  const at = (ev) => { const r = canvas.getBoundingClientRect(); return [ev.clientX - r.left, ev.clientY - r.top]; };
  canvas.addEventListener('dblclick', (ev) => { if (state.tool && state.tool.dblclick) state.tool.dblclick(...at(ev)); });
  canvas.addEventListener('pointerdown', (ev) => {
    if (ev.button === 0 && !ev.shiftKey && state.tool && state.tool.down(...at(ev))) {
      toolDrag = true;
      canvas.setPointerCapture(ev.pointerId);
      return;
    }
    drag = { x: ev.clientX, y: ev.clientY, x0: ev.clientX, y0: ev.clientY, pan: ev.button === 2 || ev.shiftKey };
    canvas.setPointerCapture(ev.pointerId);
  });
  canvas.addEventListener('pointermove', (ev) => {
    if (toolDrag) { state.tool.move(...at(ev)); return; }
    if (!drag) return;
    const dx = ev.clientX - drag.x, dy = ev.clientY - drag.y;
    drag.x = ev.clientX; drag.y = ev.clientY;
    if (drag.pan) {
      const { r, up } = basis();
      const s = cam.dist * 0.0015;
      for (let k = 0; k < 3; k++) cam.target[k] += (-dx * r[k] + dy * up[k]) * s;
    } else {
      cam.yaw -= dx * 0.008;
      cam.pitch = Math.max(-1.55, Math.min(1.55, cam.pitch + dy * 0.008));
    }
    requestDraw();
  });
  canvas.addEventListener('pointerup', (ev) => {
    if (toolDrag) { toolDrag = false; state.tool.up(...at(ev)); return; }
    if (drag && Math.hypot(ev.clientX - drag.x0, ev.clientY - drag.y0) < 5 && ev.button === 0) {
      const r = canvas.getBoundingClientRect();
      const c = state.pick(ev.clientX - r.left, ev.clientY - r.top);
      if (c !== null && state.onPick) state.onPick(c);
    }
    drag = null;
  });
  canvas.addEventListener('wheel', (ev) => {
    ev.preventDefault();
    cam.dist = Math.max(0.05 * size, Math.min(20 * size, cam.dist * Math.exp(ev.deltaY * 0.001)));
    requestDraw();
  }, { passive: false });
  window.addEventListener('resize', requestDraw);
  window.addEventListener('keydown', (ev) => {
    if (ev.target && ev.target.tagName === 'INPUT') return;
    if (ev.key === 'ArrowRight') state.setIteration(ui.k + 1);
    if (ev.key === 'ArrowLeft') state.setIteration(ui.k - 1);
    if (ev.key === 'Escape') { state.selected = null; build(); }
  });

  const s = D.setup;
  $('setup').textContent = [
    s.example || (s.curve_files || []).join(', '),
    `${rods.length} curves, ${V} vertices`,
    `supports ${s.supports}`,
    `r ${s.material.radius}, E ${s.material.young}, µ ${s.material.anchor_weight}`,
    D.app ? 'live: the server computes each edit' : (s.complete ? `stop: ${s.stop}` : 'run not complete'),
  ].filter(Boolean).join(' · ');
  if (D.app) {
    for (const el of [$('iter'), $('chart'), $('stat-removed').parentElement]) el.hidden = true;
    $('help').textContent = 'left drag: orbit · right drag or shift+drag: pan · wheel: zoom · click a curve to remove or restore it';
  }

  build();
  state.ready = true;
})();

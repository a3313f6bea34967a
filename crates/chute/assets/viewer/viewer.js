"use strict";
// chute viewer: plays the frames of one run in 3-D (plain WebGL 1, no library) beside the
// vz(t) and h(t) charts. The data is the JSON block #chute-data written by
// crates/chute/src/output/viewer.rs; docs/outputs.md describes the page.
//
// Test hooks: after every draw the 3-D canvas carries data-drawn-time (s, the time of the
// frame shown), data-drawn-triangles (canopy triangles drawn), data-drawn-frame and
// data-canopy-bbox (page pixels "x0,y0,x1,y1" of the canopy); errors set data-error on
// <body>. viewer.html#t=SECONDS opens paused at that time.

const ROLE_CANOPY = 0, ROLE_LINE = 1, ROLE_PAYLOAD = 2, ROLE_LOAD_SITE = 3;
const VIRIDIS = [[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]];
const FABRIC = [0.85, 0.45, 0.2], LINE_COLOUR = [0.45, 0.3, 0.2];
const PAYLOAD_COLOUR = [0.12, 0.12, 0.12], SITE_COLOUR = [0.9, 0.0, 0.67];
const FLOATS_PER_VERTEX = 9; // position, normal, colour

// ---------- data ----------

function decodeBytes(b64) {
  const s = atob(b64), out = new Uint8Array(s.length);
  for (let i = 0; i < s.length; i++) out[i] = s.charCodeAt(i);
  return out;
}
// A fresh Uint8Array starts at offset 0 of its own buffer, so the views below are aligned.
function decodeFloat32(b64) { const b = decodeBytes(b64); return new Float32Array(b.buffer, 0, b.length / 4); }
function decodeUint32(b64) { const b = decodeBytes(b64); return new Uint32Array(b.buffer, 0, b.length / 4); }

function loadRun() {
  const raw = JSON.parse(document.getElementById("chute-data").textContent);
  const run = { name: raw.name, results: raw.results, notes: raw.notes.slice(), toml: raw.scenario_toml,
    terminal: raw.terminal_velocity_mps, frames: null, series: null };
  if (raw.series) {
    run.series = { t: decodeFloat32(raw.series.t), vz: decodeFloat32(raw.series.vz), h: decodeFloat32(raw.series.h) };
  }
  const f = raw.frames;
  if (f) {
    const fr = { nodes: f.nodes, times: f.times, total: f.total,
      triangles: decodeUint32(f.triangles), segments: decodeUint32(f.segments),
      roles: f.roles ? decodeBytes(f.roles) : null,
      positions: absolutePositions(decodeFloat32(f.positions), f.origins, f.nodes), speeds: decodeFloat32(f.speeds) };
    fr.isCanopy = (i) => !fr.roles || fr.roles[i] === ROLE_CANOPY || fr.roles[i] === ROLE_LOAD_SITE;
    fr.canopyNodes = [];
    for (let i = 0; i < fr.nodes; i++) if (fr.isCanopy(i)) fr.canopyNodes.push(i);
    fr.span = boundingBox(fr, 0, null).diagonal || 1;
    run.frames = fr;
  }
  return run;
}

// Frames are embedded as Float32 offsets from a per-frame origin (Float64 in the JSON), so
// positions keep their precision however far the canopy has fallen; here they become Float64.
function absolutePositions(offsets, origins, nodes) {
  const out = new Float64Array(offsets.length);
  for (let k = 0; k < origins.length; k++) {
    for (let j = 3 * nodes * k; j < 3 * nodes * (k + 1); j++) out[j] = offsets[j] + origins[k][j % 3];
  }
  return out;
}

// Bounding box of frame k over `nodes` (all nodes when null).
function boundingBox(fr, k, nodes) {
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  const p = fr.positions, base = 3 * fr.nodes * k, n = nodes ? nodes.length : fr.nodes;
  for (let j = 0; j < n; j++) {
    const i = nodes ? nodes[j] : j;
    for (let c = 0; c < 3; c++) {
      const x = p[base + 3 * i + c];
      if (x < lo[c]) lo[c] = x;
      if (x > hi[c]) hi[c] = x;
    }
  }
  const d = Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
  return { lo, hi, centre: [0, 1, 2].map((c) => 0.5 * (lo[c] + hi[c])), diagonal: d };
}

function nodePos(fr, k, i) {
  const o = 3 * (fr.nodes * k + i), p = fr.positions;
  return [p[o], p[o + 1], p[o + 2]];
}

// ---------- colour fields ----------

// Largest principal engineering strain of triangle (a, b, c) in frame k, relative to frame 0
// (the rest shape: every run starts at rest in its rest configuration).
function triangleStrain(fr, k, a, b, c) {
  const X0 = nodePos(fr, 0, a), e1r = sub(nodePos(fr, 0, b), X0), e2r = sub(nodePos(fr, 0, c), X0);
  const x0 = nodePos(fr, k, a), e1 = sub(nodePos(fr, k, b), x0), e2 = sub(nodePos(fr, k, c), x0);
  // Rest edges in an orthonormal basis of the rest plane: A = [[p, q], [0, r]] (columns).
  const p = Math.hypot(e1r[0], e1r[1], e1r[2]);
  const q = dot(e1r, e2r) / p, r = Math.sqrt(Math.max(dot(e2r, e2r) - q * q, 1e-30));
  // C = A^-T G A^-1 with the current metric G = [[e1.e1, e1.e2], [e1.e2, e2.e2]].
  const g11 = dot(e1, e1), g12 = dot(e1, e2), g22 = dot(e2, e2);
  const i11 = 1 / p, i12 = -q / (p * r), i22 = 1 / r; // A^-1 = [[i11, i12], [0, i22]]
  const c11 = i11 * i11 * g11;
  const c12 = i11 * (i12 * g11 + i22 * g12);
  const c22 = i12 * i12 * g11 + 2 * i12 * i22 * g12 + i22 * i22 * g22;
  const lmax = 0.5 * (c11 + c22 + Math.hypot(c11 - c22, 2 * c12));
  return Math.sqrt(lmax) - 1;
}

function segmentStrain(fr, k, a, b) {
  const rest = Math.hypot(...sub(nodePos(fr, 0, b), nodePos(fr, 0, a)));
  return Math.hypot(...sub(nodePos(fr, k, b), nodePos(fr, k, a))) / rest - 1;
}

// The value of `field` for every node (speed, height) or cell (strain) of frame k.
function fieldValues(fr, field, k) {
  if (field === "speed") return fr.speeds.subarray(fr.nodes * k, fr.nodes * (k + 1));
  if (field === "height") {
    const lo = boundingBox(fr, k, fr.canopyNodes).lo[2], out = new Float32Array(fr.nodes);
    for (let i = 0; i < fr.nodes; i++) out[i] = fr.positions[3 * (fr.nodes * k + i) + 2] - lo;
    return out;
  }
  if (field === "strain") {
    const t = fr.triangles, s = fr.segments;
    const tri = new Float32Array(t.length / 3), seg = new Float32Array(s.length / 2);
    for (let j = 0; j < tri.length; j++) tri[j] = triangleStrain(fr, k, t[3 * j], t[3 * j + 1], t[3 * j + 2]);
    for (let j = 0; j < seg.length; j++) seg[j] = segmentStrain(fr, k, s[2 * j], s[2 * j + 1]);
    return { tri, seg };
  }
  return null;
}

// Colour scale of a field over all embedded frames, so colours compare across time: from 0
// to the largest value (speed, height); for strain from the 0.5th to the 99.5th percentile,
// so a few extreme cells do not leave the rest of the canopy one colour.
function fieldRange(fr, field) {
  const all = [];
  for (let k = 0; k < fr.times.length; k++) {
    const v = fieldValues(fr, field, k);
    if (field === "strain") { for (const x of v.tri) all.push(x); for (const x of v.seg) all.push(x); }
    else for (const i of fr.canopyNodes) all.push(v[i]);
  }
  all.sort((a, b) => a - b);
  const at = (q) => all[Math.min(all.length - 1, Math.floor(q * all.length))];
  let lo = field === "strain" ? Math.min(0, at(0.005)) : 0, hi = field === "strain" ? at(0.995) : all[all.length - 1];
  if (!(hi > lo)) hi = lo + 1e-9;
  return [lo, hi];
}

function viridis(s) {
  const x = Math.min(Math.max(isFinite(s) ? s : 0, 0), 1) * 4, k = Math.min(Math.floor(x), 3), f = x - k;
  return [0, 1, 2].map((c) => (VIRIDIS[k][c] + f * (VIRIDIS[k + 1][c] - VIRIDIS[k][c])) / 255);
}

// ---------- small vector and matrix helpers ----------

function sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
function cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }
function normalise(a) { const n = Math.hypot(a[0], a[1], a[2]) || 1; return [a[0] / n, a[1] / n, a[2] / n]; }

// Column-major 4×4 matrices, as WebGL expects.
function perspective(fovY, aspect, near, far) {
  const f = 1 / Math.tan(fovY / 2), d = near - far;
  return [f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) / d, -1, 0, 0, (2 * far * near) / d, 0];
}
function lookAt(eye, target, up) {
  const z = normalise(sub(eye, target)), x = normalise(cross(up, z)), y = cross(z, x);
  return [x[0], y[0], z[0], 0, x[1], y[1], z[1], 0, x[2], y[2], z[2], 0,
    -dot(x, eye), -dot(y, eye), -dot(z, eye), 1];
}
function multiply(a, b) {
  const out = new Array(16).fill(0);
  for (let c = 0; c < 4; c++) for (let r = 0; r < 4; r++) for (let k = 0; k < 4; k++) out[4 * c + r] += a[4 * k + r] * b[4 * c + k];
  return out;
}
function transform(m, p) {
  const w = m[3] * p[0] + m[7] * p[1] + m[11] * p[2] + m[15];
  return [0, 1, 2].map((r) => (m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r]) / w);
}

// ---------- geometry for one frame ----------

// Growable vertex list: position (relative to `origin`, the view target, so Float32 on the
// GPU stays precise far from the world origin), normal, colour per vertex.
function vertexList(origin) {
  return { data: [], push(p, n, c) {
    this.data.push(p[0] - origin[0], p[1] - origin[1], p[2] - origin[2], n[0], n[1], n[2], c[0], c[1], c[2]);
  } };
}

// The canopy surface: flat-shaded triangles (robust to meshes of mixed orientation).
function surfaceGeometry(fr, k, colourOf, origin) {
  const out = vertexList(origin), t = fr.triangles;
  for (let j = 0; j < t.length / 3; j++) {
    const ids = [t[3 * j], t[3 * j + 1], t[3 * j + 2]], p = ids.map((i) => nodePos(fr, k, i));
    const n = normalise(cross(sub(p[1], p[0]), sub(p[2], p[0])));
    for (let v = 0; v < 3; v++) out.push(p[v], n, colourOf.triangle(j, ids[v]));
  }
  return out.data;
}

// A six-sided prism around segment a→b: rods and lines drawn as tubes of a visible radius.
function pushTube(out, a, b, radius, colour) {
  const axis = normalise(sub(b, a)), helper = Math.abs(axis[2]) < 0.9 ? [0, 0, 1] : [1, 0, 0];
  const u = normalise(cross(axis, helper)), w = cross(axis, u), sides = 6;
  const ring = [];
  for (let s = 0; s <= sides; s++) {
    const th = (2 * Math.PI * s) / sides, n = [0, 1, 2].map((c) => Math.cos(th) * u[c] + Math.sin(th) * w[c]);
    ring.push(n);
  }
  for (let s = 0; s < sides; s++) {
    const n0 = ring[s], n1 = ring[s + 1], off = (p, n) => [0, 1, 2].map((c) => p[c] + radius * n[c]);
    const a0 = off(a, n0), a1 = off(a, n1), b0 = off(b, n0), b1 = off(b, n1);
    out.push(a0, n0, colour); out.push(b0, n0, colour); out.push(b1, n1, colour);
    out.push(a0, n0, colour); out.push(b1, n1, colour); out.push(a1, n1, colour);
  }
}

// Unit icosahedron subdivided once (80 faces): the marker spheres.
const SPHERE = (function () {
  const g = (1 + Math.sqrt(5)) / 2;
  const v = [[-1, g, 0], [1, g, 0], [-1, -g, 0], [1, -g, 0], [0, -1, g], [0, 1, g], [0, -1, -g], [0, 1, -g],
    [g, 0, -1], [g, 0, 1], [-g, 0, -1], [-g, 0, 1]].map(normalise);
  const f = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6],
    [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]];
  const tris = [];
  for (const [a, b, c] of f) {
    const m = (p, q) => normalise([0, 1, 2].map((i) => p[i] + q[i]));
    const ab = m(v[a], v[b]), bc = m(v[b], v[c]), ca = m(v[c], v[a]);
    tris.push([v[a], ab, ca], [ab, v[b], bc], [ca, bc, v[c]], [ab, bc, ca]);
  }
  return tris;
})();

function pushSphere(out, centre, radius, colour) {
  for (const tri of SPHERE) for (const n of tri) out.push([0, 1, 2].map((c) => centre[c] + radius * n[c]), n, colour);
}

// Tubes for the segments, spheres for the payload and the load sites.
function detailGeometry(fr, k, colourOf, origin) {
  const out = vertexList(origin), s = fr.segments, r = 0.004 * fr.span;
  for (let j = 0; j < s.length / 2; j++) {
    const a = s[2 * j], b = s[2 * j + 1];
    const canopy = fr.isCanopy(a) && fr.isCanopy(b);
    pushTube(out, nodePos(fr, k, a), nodePos(fr, k, b), canopy ? 2 * r : r, colourOf.segment(j, a, b, canopy));
  }
  if (fr.roles) {
    for (let i = 0; i < fr.nodes; i++) {
      if (fr.roles[i] === ROLE_PAYLOAD) pushSphere(out, nodePos(fr, k, i), 0.025 * fr.span, PAYLOAD_COLOUR);
      if (fr.roles[i] === ROLE_LOAD_SITE) pushSphere(out, nodePos(fr, k, i), 0.01 * fr.span, SITE_COLOUR);
    }
  }
  return out.data;
}

// How each triangle vertex and segment is coloured for `field` in frame k.
function colouring(fr, field, k, range) {
  const scale = (x) => viridis((x - range[0]) / (range[1] - range[0]));
  const v = fieldValues(fr, field, k);
  if (field === "speed" || field === "height") {
    return { triangle: (j, i) => scale(v[i]),
      segment: (j, a, b, canopy) => (canopy ? scale(0.5 * (v[a] + v[b])) : LINE_COLOUR) };
  }
  if (field === "strain") {
    return { triangle: (j) => scale(v.tri[j]), segment: (j) => scale(v.seg[j]) };
  }
  return { triangle: () => FABRIC, segment: (j, a, b, canopy) => (canopy ? FABRIC : LINE_COLOUR) };
}

// ---------- WebGL ----------

const VERTEX_SHADER = `
attribute vec3 aPosition; attribute vec3 aNormal; attribute vec3 aColour;
uniform mat4 uViewProjection;
varying vec3 vNormal; varying vec3 vColour; varying vec3 vWorld;
void main() {
  vNormal = aNormal; vColour = aColour; vWorld = aPosition;
  gl_Position = uViewProjection * vec4(aPosition, 1.0);
}`;
const FRAGMENT_SHADER = `
precision mediump float;
varying vec3 vNormal; varying vec3 vColour; varying vec3 vWorld;
uniform vec3 uLight; uniform float uLit;
void main() {
  vec3 n = normalize(vNormal);
  // Two-sided: a canopy has no outside, so both faces take the light.
  float diffuse = abs(dot(n, uLight));
  vec3 lit = vColour * (0.32 + 0.68 * diffuse) + vec3(0.12) * pow(diffuse, 24.0);
  gl_FragColor = vec4(mix(vColour, lit, uLit), 1.0);
}`;

function compile(gl, type, source) {
  const s = gl.createShader(type);
  gl.shaderSource(s, source);
  gl.compileShader(s);
  if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error("shader: " + gl.getShaderInfoLog(s));
  return s;
}

function createRenderer(canvas) {
  const gl = canvas.getContext("webgl", { antialias: true, preserveDrawingBuffer: true });
  if (!gl) throw new Error("this browser has no WebGL");
  const prog = gl.createProgram();
  gl.attachShader(prog, compile(gl, gl.VERTEX_SHADER, VERTEX_SHADER));
  gl.attachShader(prog, compile(gl, gl.FRAGMENT_SHADER, FRAGMENT_SHADER));
  gl.linkProgram(prog);
  if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) throw new Error("program: " + gl.getProgramInfoLog(prog));
  const loc = (n) => gl.getUniformLocation(prog, n);
  return { gl, prog, buffer: gl.createBuffer(),
    attrs: ["aPosition", "aNormal", "aColour"].map((n) => gl.getAttribLocation(prog, n)),
    uViewProjection: loc("uViewProjection"), uLight: loc("uLight"), uLit: loc("uLit") };
}

// Draw interleaved vertices as `mode` primitives; returns the number of vertices drawn.
function drawVertices(r, data, mode, lit) {
  const gl = r.gl;
  gl.bindBuffer(gl.ARRAY_BUFFER, r.buffer);
  gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(data), gl.DYNAMIC_DRAW);
  const stride = 4 * FLOATS_PER_VERTEX;
  r.attrs.forEach((a, i) => { gl.enableVertexAttribArray(a); gl.vertexAttribPointer(a, 3, gl.FLOAT, false, stride, 12 * i); });
  gl.uniform1f(r.uLit, lit ? 1 : 0);
  const count = data.length / FLOATS_PER_VERTEX;
  if (count > 0) gl.drawArrays(mode, 0, count);
  return count;
}

// A horizontal grid under the lowest node, fixed in x and y, so drift shows against it.
function gridGeometry(fr, box) {
  const step = niceStep(fr.span / 4), half = 3 * fr.span, z = box.lo[2] - 0.02 * fr.span, out = vertexList(box.centre);
  const c = [0.78, 0.78, 0.76], n = [0, 0, 1];
  const x0 = Math.floor((box.centre[0] - half) / step) * step, y0 = Math.floor((box.centre[1] - half) / step) * step;
  const lines = Math.ceil((2 * half) / step);
  for (let i = 0; i <= lines; i++) {
    const x = x0 + i * step, y = y0 + i * step;
    out.push([x, y0, z], n, c); out.push([x, y0 + lines * step, z], n, c);
    out.push([x0, y, z], n, c); out.push([x0 + lines * step, y, z], n, c);
  }
  return out.data;
}

function niceStep(x) {
  const p = Math.pow(10, Math.floor(Math.log10(x))), m = x / p;
  return (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * p;
}

// ---------- the 3-D view ----------

function resizeToDisplay(canvas) {
  const dpr = window.devicePixelRatio || 1;
  const w = Math.max(1, Math.round(canvas.clientWidth * dpr)), h = Math.max(1, Math.round(canvas.clientHeight * dpr));
  if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }
}

function cameraFrame(cam) {
  const dir = [Math.cos(cam.el) * Math.cos(cam.az), Math.cos(cam.el) * Math.sin(cam.az), Math.sin(cam.el)];
  const right = normalise(cross([0, 0, 1], dir));
  return { dir, right, up: cross(dir, right) };
}

function drawScene(app) {
  const fr = app.run.frames, r = app.renderer, gl = r.gl, canvas = app.canvas, st = app.state, k = st.frame;
  resizeToDisplay(canvas);
  gl.viewport(0, 0, canvas.width, canvas.height);
  gl.clearColor(0.965, 0.965, 0.955, 1);
  gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
  gl.enable(gl.DEPTH_TEST);
  // The camera follows the centre of the whole system: the fall is many canopy sizes long.
  const box = boundingBox(fr, k, null), dist = st.camera.distance * fr.span, cf = cameraFrame(st.camera);
  const view = lookAt(cf.dir.map((x) => x * dist), [0, 0, 0], [0, 0, 1]);
  const vp = multiply(perspective(Math.PI / 4.5, canvas.width / canvas.height, dist / 100, dist * 100), view);
  gl.useProgram(r.prog);
  gl.uniformMatrix4fv(r.uViewProjection, false, new Float32Array(vp));
  // A light over the viewer's left shoulder.
  gl.uniform3fv(r.uLight, new Float32Array(normalise([0, 1, 2].map((c) => cf.dir[c] + 0.6 * cf.up[c] - 0.4 * cf.right[c]))));
  const colourOf = colouring(fr, st.field, k, app.range(st.field));
  const triangles = drawVertices(r, surfaceGeometry(fr, k, colourOf, box.centre), gl.TRIANGLES, true) / 3;
  drawVertices(r, detailGeometry(fr, k, colourOf, box.centre), gl.TRIANGLES, true);
  drawVertices(r, gridGeometry(fr, box), gl.LINES, false);
  canvas.dataset.drawnTime = String(fr.times[k]);
  canvas.dataset.drawnFrame = String(k);
  canvas.dataset.drawnTriangles = String(triangles);
  canvas.dataset.canopyBbox = canopyScreenBox(fr, k, vp, box.centre, canvas).join(",");
  document.body.dataset.viewport = window.innerWidth + "x" + window.innerHeight;
}

// Page-pixel bounding box of the canopy nodes as drawn (for tests comparing screenshots).
function canopyScreenBox(fr, k, vp, origin, canvas) {
  const rect = canvas.getBoundingClientRect(), b = [Infinity, Infinity, -Infinity, -Infinity];
  for (const i of fr.canopyNodes) {
    const p = transform(vp, sub(nodePos(fr, k, i), origin));
    const x = rect.left + ((p[0] + 1) / 2) * rect.width, y = rect.top + ((1 - p[1]) / 2) * rect.height;
    b[0] = Math.min(b[0], x); b[1] = Math.min(b[1], y); b[2] = Math.max(b[2], x); b[3] = Math.max(b[3], y);
  }
  return b.map((x, i) => (i < 2 ? Math.floor(x) : Math.ceil(x)));
}

// ---------- charts ----------

// Round tick values between lo and hi, about `count` of them, and their step.
function niceTicks(lo, hi, count) {
  const step = niceStep((hi - lo) / count || 1), values = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + 1e-9 * step; v += step) values.push(Math.abs(v) < 1e-12 * step ? 0 : v);
  return { values, label: (v) => v.toFixed(Math.max(0, -Math.floor(Math.log10(step) + 1e-9))) };
}

function formatNumber(x) {
  if (x === 0 || !isFinite(x)) return String(x);
  const mag = Math.floor(Math.log10(Math.abs(x)));
  return mag >= -3 && mag < 5 ? x.toFixed(Math.max(0, 3 - mag)) : x.toExponential(3);
}

// Value of ys at time t (linear between samples).
function valueAt(xs, ys, t) {
  let lo = 0, hi = xs.length - 1;
  if (t <= xs[0]) return ys[0];
  if (t >= xs[hi]) return ys[hi];
  while (hi - lo > 1) { const m = (lo + hi) >> 1; if (xs[m] <= t) lo = m; else hi = m; }
  return ys[lo] + ((t - xs[lo]) / (xs[hi] - xs[lo] || 1)) * (ys[hi] - ys[lo]);
}

function drawChart(canvas, xs, ys, opts) {
  const dpr = window.devicePixelRatio || 1, W = canvas.clientWidth, H = canvas.clientHeight;
  canvas.width = Math.round(W * dpr); canvas.height = Math.round(H * dpr);
  const ctx = canvas.getContext("2d"), m = { l: 52, r: 8, t: 18, b: 24 };
  ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
  ctx.clearRect(0, 0, W, H);
  ctx.font = "11px system-ui, sans-serif";
  ctx.fillStyle = "#222";
  ctx.fillText(opts.title, m.l, 12);
  if (!xs || xs.length === 0) { ctx.fillText("no time series", m.l, H / 2); return; }
  let y0 = Infinity, y1 = -Infinity;
  for (const y of ys) { if (y < y0) y0 = y; if (y > y1) y1 = y; }
  if (opts.ref !== undefined) { y0 = Math.min(y0, opts.ref); y1 = Math.max(y1, opts.ref); }
  if (opts.fromZero) y0 = Math.min(y0, 0);
  const pad = 0.05 * (y1 - y0 || Math.abs(y1) || 1); y0 -= pad; y1 += pad;
  const x0 = xs[0], x1 = xs[xs.length - 1] > x0 ? xs[xs.length - 1] : x0 + 1;
  const px = (x) => m.l + ((x - x0) / (x1 - x0)) * (W - m.l - m.r), py = (y) => H - m.b - ((y - y0) / (y1 - y0)) * (H - m.t - m.b);
  canvas.chartToTime = (clientX) => x0 + ((clientX - canvas.getBoundingClientRect().left - m.l) / (W - m.l - m.r)) * (x1 - x0);
  ctx.strokeStyle = "#ddd"; ctx.fillStyle = "#555"; ctx.lineWidth = 1;
  const yt = niceTicks(y0, y1, 4), xt = niceTicks(x0, x1, 5);
  ctx.textAlign = "right";
  for (const v of yt.values) {
    ctx.beginPath(); ctx.moveTo(m.l, py(v)); ctx.lineTo(W - m.r, py(v)); ctx.stroke();
    ctx.fillText(yt.label(v), m.l - 4, py(v) + 4);
  }
  ctx.textAlign = "center";
  for (const v of xt.values) {
    ctx.beginPath(); ctx.moveTo(px(v), m.t); ctx.lineTo(px(v), H - m.b); ctx.stroke();
    ctx.fillText(xt.label(v), px(v), H - 8);
  }
  ctx.textAlign = "left";
  if (opts.ref !== undefined) {
    ctx.strokeStyle = "#c00"; ctx.setLineDash([6, 4]);
    ctx.beginPath(); ctx.moveTo(m.l, py(opts.ref)); ctx.lineTo(W - m.r, py(opts.ref)); ctx.stroke();
    ctx.setLineDash([]);
  }
  ctx.strokeStyle = "#1f5fbf"; ctx.lineWidth = 1.5; ctx.beginPath();
  for (let i = 0; i < xs.length; i++) (i ? ctx.lineTo : ctx.moveTo).call(ctx, px(xs[i]), py(ys[i]));
  ctx.stroke();
  if (opts.cursor !== undefined) {
    const t = opts.cursor, y = valueAt(xs, ys, t);
    ctx.strokeStyle = "#e07000"; ctx.lineWidth = 1.5;
    ctx.beginPath(); ctx.moveTo(px(t), m.t); ctx.lineTo(px(t), H - m.b); ctx.stroke();
    ctx.fillStyle = "#e07000"; ctx.beginPath(); ctx.arc(px(t), py(y), 3.5, 0, 2 * Math.PI); ctx.fill();
    ctx.fillText(formatNumber(y) + " " + opts.unit, Math.min(px(t) + 5, W - 80), m.t + 10);
  }
}

function drawCharts(app) {
  const s = app.run.series, t = app.run.frames ? app.run.frames.times[app.state.frame] : undefined;
  const ref = app.run.terminal === null ? undefined : app.run.terminal;
  drawChart(document.getElementById("chart-vz"), s && s.t, s && s.vz,
    { title: "canopy vz (m/s) vs t (s)" + (ref !== undefined ? "; dashed: v_t" : ""), unit: "m/s", cursor: t, ref });
  drawChart(document.getElementById("chart-h"), s && s.t, s && s.h,
    { title: "extended height h (m) vs t (s)", unit: "m", cursor: t, fromZero: true });
}

// ---------- playback and controls ----------

function nearestFrame(times, t) {
  let lo = 0, hi = times.length - 1;
  while (hi - lo > 1) { const m = (lo + hi) >> 1; if (times[m] <= t) lo = m; else hi = m; }
  return Math.abs(times[hi] - t) < Math.abs(t - times[lo]) ? hi : lo;
}

function render(app) {
  app.dirty = false;
  const fr = app.run.frames;
  if (fr && app.renderer) drawScene(app);
  drawCharts(app);
  if (!fr) return;
  const k = app.state.frame;
  document.getElementById("slider").value = String(k);
  document.getElementById("time").textContent = "t = " + fr.times[k].toFixed(3) + " s (frame " + (k + 1) + "/" + fr.times.length + ")";
  document.getElementById("overlay").textContent = "t = " + fr.times[k].toFixed(3) + " s";
  document.getElementById("play").textContent = app.state.playing ? "❚❚" : "▶";
}

// Show the frame nearest `t`, paused, and remember it in the address (#t=…) for links.
function seek(app, t, fromHash) {
  const fr = app.run.frames;
  if (!fr) return;
  app.state.playing = false;
  app.state.frame = nearestFrame(fr.times, t);
  app.state.time = fr.times[app.state.frame];
  if (!fromHash) rememberTime(app);
  render(app);
  // One line per opened link, so a headless test can see that console output reaches it.
  if (fromHash) console.log("chute-viewer: drew t = " + app.state.time + " s, " + app.canvas.dataset.drawnTriangles + " triangles");
}

// Put the shown time (and a colour other than the default) in the address, for links.
function rememberTime(app) {
  const field = app.state.field === "height" ? "" : "&colour=" + app.state.field;
  history.replaceState(null, "", "#t=" + app.run.frames.times[app.state.frame] + field);
}

function hashTime() {
  const m = /(?:^#|&)t=([-+0-9.eE]+)/.exec(window.location.hash);
  const t = m ? Number(m[1]) : NaN;
  return isFinite(t) ? t : null;
}

// The colour field named in the address (#…&colour=strain), if it is one of the choices.
function hashField() {
  const m = /(?:^#|&)colou?r=([a-z]+)/.exec(window.location.hash);
  return m && ["height", "speed", "strain", "none"].includes(m[1]) ? m[1] : null;
}

function togglePlay(app) {
  const fr = app.run.frames;
  if (!fr) return;
  app.state.playing = !app.state.playing;
  if (app.state.playing && app.state.frame === fr.times.length - 1) { app.state.frame = 0; app.state.time = fr.times[0]; }
  if (!app.state.playing) rememberTime(app);
  app.dirty = true;
}

function tick(app, now) {
  const fr = app.run.frames, st = app.state;
  if (st.playing && fr) {
    st.time += (Math.min(now - app.lastTick, 100) / 1000) * st.speed;
    const end = fr.times[fr.times.length - 1];
    if (st.time >= end) { st.time = end; st.playing = false; }
    const k = nearestFrame(fr.times, st.time);
    if (k !== st.frame || !st.playing) { st.frame = k; app.dirty = true; }
  }
  app.lastTick = now;
  if (app.dirty) render(app);
  requestAnimationFrame((t) => tick(app, t));
}

function bindOrbit(app) {
  const c = app.canvas, cam = app.state.camera;
  let last = null;
  c.addEventListener("pointerdown", (e) => { last = [e.clientX, e.clientY]; c.setPointerCapture(e.pointerId); });
  c.addEventListener("pointerup", () => { last = null; });
  c.addEventListener("pointermove", (e) => {
    if (!last) return;
    cam.az -= 0.01 * (e.clientX - last[0]);
    cam.el = Math.max(-1.5, Math.min(1.5, cam.el + 0.01 * (e.clientY - last[1])));
    last = [e.clientX, e.clientY];
    app.dirty = true;
  });
  c.addEventListener("wheel", (e) => {
    e.preventDefault();
    cam.distance = Math.max(0.2, Math.min(50, cam.distance * Math.exp(0.001 * e.deltaY)));
    app.dirty = true;
  }, { passive: false });
  c.addEventListener("dblclick", () => { Object.assign(cam, defaultCamera()); app.dirty = true; });
}

function bindControls(app) {
  const fr = app.run.frames, byId = (id) => document.getElementById(id);
  byId("play").addEventListener("click", () => togglePlay(app));
  byId("slider").addEventListener("input", (e) => seek(app, fr.times[Number(e.target.value)]));
  byId("speed").addEventListener("change", (e) => { app.state.speed = Number(e.target.value); });
  byId("field").addEventListener("change", (e) => {
    app.state.field = e.target.value; updateLegend(app); app.dirty = true;
    if (!app.state.playing && fr) rememberTime(app);
  });
  document.addEventListener("keydown", (e) => {
    // A focused button or list handles space itself (the play button would toggle twice).
    if (e.code === "Space" && !["BUTTON", "SELECT"].includes(e.target.tagName)) { e.preventDefault(); togglePlay(app); }
  });
  for (const id of ["chart-vz", "chart-h"]) {
    const chart = byId(id);
    const pick = (e) => { if (fr && chart.chartToTime && (e.buttons & 1)) seek(app, chart.chartToTime(e.clientX)); };
    chart.addEventListener("pointerdown", pick);
    chart.addEventListener("pointermove", pick);
  }
  window.addEventListener("hashchange", () => {
    const f = hashField();
    if (f) { app.state.field = f; byId("field").value = f; updateLegend(app); }
    const t = hashTime();
    if (t !== null) seek(app, t, true); else app.dirty = true;
  });
  window.addEventListener("resize", () => { app.dirty = true; });
}

function updateLegend(app) {
  const field = app.state.field, legend = document.getElementById("legend");
  legend.hidden = field === "none" || !app.run.frames;
  if (legend.hidden) return;
  const [lo, hi] = app.range(field), pct = field === "strain";
  const unit = { height: " m", speed: " m/s", strain: " %" }[field];
  document.getElementById("legend-title").textContent = {
    height: "height above the lowest canopy node", speed: "node speed |v|",
    strain: "largest principal strain (vs t = 0)" }[field];
  document.getElementById("legend-lo").textContent = Number((pct ? 100 * lo : lo).toPrecision(3)) + unit;
  document.getElementById("legend-hi").textContent = Number((pct ? 100 * hi : hi).toPrecision(3)) + unit;
}

function fillPanels(run) {
  const rows = document.getElementById("results");
  for (const [k, v] of run.results) {
    const tr = rows.insertRow();
    tr.insertCell().textContent = k;
    tr.insertCell().textContent = v;
  }
  // The first two rows (terminal velocity, reached), without their explanations.
  document.getElementById("headline").textContent = run.results.slice(0, 2)
    .map(([k, v]) => k + ": " + v.split(/ \(|: /)[0]).join(" · ");
  const notes = document.getElementById("notes");
  for (const n of run.notes) notes.appendChild(document.createElement("li")).textContent = n;
  if (run.toml) document.getElementById("toml").textContent = run.toml;
  else document.getElementById("scenario").hidden = true;
}

function defaultCamera() { return { az: -Math.PI / 3, el: 0.35, distance: 1.6 }; }

function reportError(err) {
  const msg = String(err && err.message ? err.message : err);
  document.body.dataset.error = msg;
  document.getElementById("overlay").textContent = "viewer error: " + msg;
  console.error("chute-viewer: " + msg);
}

function main() {
  window.addEventListener("error", (e) => { document.body.dataset.error = String(e.message); });
  const run = loadRun(), canvas = document.getElementById("scene");
  const ranges = {};
  const app = { run, canvas, renderer: null, dirty: true, lastTick: performance.now(),
    range: (field) => ranges[field] || (ranges[field] = fieldRange(run.frames, field)),
    state: { frame: 0, time: 0, playing: false, speed: 1, field: "height", camera: defaultCamera() } };
  fillPanels(run);
  if (run.frames) {
    app.renderer = createRenderer(canvas);
    const slider = document.getElementById("slider");
    slider.max = String(run.frames.times.length - 1);
    app.state.time = run.frames.times[0];
    bindOrbit(app);
  } else {
    document.getElementById("overlay").textContent = "no frames to show";
    canvas.dataset.drawnTriangles = "0";
  }
  const field = hashField();
  if (field) { app.state.field = field; document.getElementById("field").value = field; }
  bindControls(app);
  updateLegend(app);
  const t = hashTime();
  if (t !== null) seek(app, t, true);
  else { app.state.playing = !!run.frames; render(app); }
  requestAnimationFrame((now) => tick(app, now));
}

try { main(); } catch (err) { reportError(err); }

// ger view: the page. Plain WebGL2 and the DOM; no library, no request
// but to the server that made the page (none at all in a saved file).
// The scene comes from src/view.rs: a deflated, base64 packet holding a
// JSON header and binary sections (moves, stock checkpoints).
"use strict";

const body = document.body;
const $ = (id) => document.getElementById(id);
const PALETTE = [
  [0.10, 0.45, 0.85], [0.15, 0.65, 0.30], [0.55, 0.30, 0.75], [0.00, 0.60, 0.65],
  [0.80, 0.50, 0.05], [0.35, 0.35, 0.40], [0.70, 0.20, 0.55], [0.40, 0.55, 0.10],
];
const RAPID = [0.85, 0.25, 0.2];
const KIND_RAPID = 0, KIND_FEED = 1, KIND_ARC = 2;

// ---------------------------------------------------------------- decoding

async function inflate(base64) {
  const text = base64.trim();
  let bytes;
  if (Uint8Array.fromBase64) {
    bytes = Uint8Array.fromBase64(text);
  } else {
    const raw = atob(text);
    bytes = new Uint8Array(raw.length);
    for (let i = 0; i < raw.length; i++) bytes[i] = raw.charCodeAt(i);
  }
  const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream("deflate"));
  return new Uint8Array(await new Response(stream).arrayBuffer());
}

function unpack(bytes) {
  const length = bytes[0] | bytes[1] << 8 | bytes[2] << 16 | bytes[3] << 24;
  const header = JSON.parse(new TextDecoder().decode(bytes.subarray(4, 4 + length)));
  return { header, binary: bytes.subarray(4 + length) };
}

class Reader {
  constructor(bytes, at) { this.b = bytes; this.at = at; }
  varint() {
    let v = 0, shift = 0, byte;
    do {
      byte = this.b[this.at++];
      v += (byte & 0x7f) * 2 ** shift;
      shift += 7;
    } while (byte & 0x80);
    return v;
  }
  zigzag() {
    const v = this.varint();
    return v % 2 === 0 ? v / 2 : -(v + 1) / 2;
  }
}

// The moves as the GPU and the page's searches want them: every chord a
// pair of vertices, each move knowing its first pair, kind, tool, lines
// and the time it ends.
function decodeMoves(spec, binary) {
  const n = spec.count, quantum = spec.quantum_mm;
  const r = new Reader(binary, spec.offset);
  const end = spec.offset + spec.length;
  let cap = Math.max(1024, n * 2 + 16);
  let pos = new Float32Array(cap * 3);
  const kind = new Uint8Array(n), tool = new Uint16Array(n), file = new Uint16Array(n);
  const line = new Uint32Array(n), out = new Uint32Array(n), first = new Uint32Array(n + 1);
  const tEnd = new Float64Array(n);
  let v = 0;
  const push = (x, y, z) => {
    if (v >= cap) {
      cap *= 2;
      const grown = new Float32Array(cap * 3);
      grown.set(pos);
      pos = grown;
    }
    pos[v * 3] = x * quantum; pos[v * 3 + 1] = y * quantum; pos[v * 3 + 2] = z * quantum;
    v++;
  };
  let [x, y, z] = spec.start;
  let t = 0, curTool = 0, curFile = 0, curLine = 0, curOut = 0;
  for (let k = 0; k < n && r.at < end; k++) {
    const head = r.b[r.at++];
    const kd = head & 3;
    if (head & 4) curTool = r.varint();
    switch ((head >> 3) & 3) {
      case 1: curLine += 1; break;
      case 2: curLine += r.zigzag(); break;
      case 3: curFile = r.varint(); curLine = r.varint(); break;
    }
    let o = 0;
    switch ((head >> 5) & 3) {
      case 1: o = curOut + 1; break;
      case 2: o = curOut + r.zigzag(); break;
      case 3: o = curOut; break;
    }
    if (o) curOut = o;
    if (head & 128) { x += r.zigzag(); y += r.zigzag(); z += r.zigzag(); }
    first[k] = v;
    if (kd === KIND_ARC) {
      const inner = r.varint();
      for (let c = 0; c < inner; c++) {
        push(x, y, z);
        x += r.zigzag(); y += r.zigzag(); z += r.zigzag();
        push(x, y, z);
      }
    }
    push(x, y, z);
    x += r.zigzag(); y += r.zigzag(); z += r.zigzag();
    push(x, y, z);
    t += r.varint() / 1000;
    kind[k] = kd; tool[k] = curTool; file[k] = curFile; line[k] = curLine; out[k] = o; tEnd[k] = t;
  }
  first[n] = v;
  return { n, pos: pos.subarray(0, v * 3), vertices: v, kind, tool, file, line, out, tEnd, first };
}

// Every checkpoint's depths in full (16-bit fractions of depth_mm), the
// cutters as the sweep wants them, and the moves swept other than as the
// line between their drawn ends (src/view/stock.rs, `sweeps`).
function decodeStock(spec, binary, header) {
  const cells = spec.nx * spec.ny;
  const r = new Reader(binary, spec.offset);
  // One pass over the differences: where each starts, and every
  // KEEP-th checkpoint kept whole; any other is made from the one kept
  // before it (at most KEEP - 1 differences again).
  const starts = [], kept = [];
  const now = new Uint16Array(cells);
  for (let c = 0; c < spec.checkpoints.length; c++) {
    starts.push(r.at);
    applyDifference(r, now);
    if (c % KEEP === 0) kept.push(now.slice());
  }
  const last = spec.checkpoints.length - 1;
  const cutters = (header.tools || []).map((t) => ({
    r: t.radius, profile: t.profile === "ball" ? 1 : t.profile === "cone" ? 2 : 0, rise: t.rise,
  }));
  const sweeps = decodeSweeps(spec.sweeps, binary, header.moves.quantum_mm);
  const size = [spec.cell_mm, spec.cell_mm];
  return {
    spec, binary, starts, kept, cutters, sweeps, size, heights: new Float32Array(cells), shownAt: null,
    lastDepths: last >= 0 ? now : null, work: new Uint16Array(cells),
  };
}

// Checkpoints kept whole: one in KEEP.
const KEEP = 8;

// Add one checkpoint's run-length-coded difference to `depths`.
function applyDifference(r, depths) {
  const cells = depths.length;
  let k = 0;
  while (k < cells) {
    k += r.varint();
    const changed = r.varint();
    for (let e = k + changed; k < e; k++) depths[k] += r.zigzag();
  }
}

// Checkpoint c's depths (16-bit fractions of depth_mm).
function checkpointDepths(s, c) {
  if (c === s.starts.length - 1) return s.lastDepths;
  const base = c - c % KEEP;
  s.work.set(s.kept[base / KEEP]);
  for (let k = base + 1; k <= c; k++) applyDifference(new Reader(s.binary, s.starts[k]), s.work);
  return s.work;
}

function decodeSweeps(spec, binary, quantum) {
  const r = new Reader(binary, spec.offset);
  const out = new Map();
  let index = 0;
  for (let n = 0; n < spec.count; n++) {
    index += r.varint();
    const head = r.b[r.at++];
    const record = { skip: (head & 3) === 1 };
    if (head & 4) record.start = [r.zigzag() * quantum, r.zigzag() * quantum, r.zigzag() * quantum];
    if ((head & 3) === 2) {
      record.arc = { dx: r.zigzag() * quantum, dy: r.zigzag() * quantum, sweep: r.varint() / 1e6, clockwise: (head & 8) !== 0 };
    } else if ((head & 3) === 3) {
      const chords = r.varint();
      record.chords = [];
      let d = [0, 0, 0];
      for (let k = 1; k < chords; k++) {
        d = [d[0] + r.zigzag(), d[1] + r.zigzag(), d[2] + r.zigzag()];
        record.chords.push(d);
      }
    }
    out.set(index, record);
  }
  return out;
}

// ---------------------------------------------------------------- maths

function perspective(fovy, aspect, near, far) {
  const f = 1 / Math.tan(fovy / 2), nf = 1 / (near - far);
  return [f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) * nf, -1, 0, 0, 2 * far * near * nf, 0];
}
function lookAt(eye, target, up) {
  const zx = eye[0] - target[0], zy = eye[1] - target[1], zz = eye[2] - target[2];
  let l = Math.hypot(zx, zy, zz) || 1;
  const z = [zx / l, zy / l, zz / l];
  let x = [up[1] * z[2] - up[2] * z[1], up[2] * z[0] - up[0] * z[2], up[0] * z[1] - up[1] * z[0]];
  l = Math.hypot(...x) || 1;
  x = x.map((c) => c / l);
  const y = [z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]];
  const d = (a) => -(a[0] * eye[0] + a[1] * eye[1] + a[2] * eye[2]);
  return [x[0], y[0], z[0], 0, x[1], y[1], z[1], 0, x[2], y[2], z[2], 0, d(x), d(y), d(z), 1];
}
function multiply(a, b) {
  const o = new Array(16).fill(0);
  for (let c = 0; c < 4; c++)
    for (let r = 0; r < 4; r++)
      for (let k = 0; k < 4; k++) o[c * 4 + r] += a[k * 4 + r] * b[c * 4 + k];
  return o;
}
function project(m, x, y, z, w, h) {
  const cx = m[0] * x + m[4] * y + m[8] * z + m[12];
  const cy = m[1] * x + m[5] * y + m[9] * z + m[13];
  const cw = m[3] * x + m[7] * y + m[11] * z + m[15];
  if (cw <= 1e-9) return null;
  return [(cx / cw * 0.5 + 0.5) * w, (0.5 - cy / cw * 0.5) * h, cw];
}

// ---------------------------------------------------------------- WebGL

const STOCK_VS = `#version 300 es
uniform highp sampler2D heights;
uniform highp sampler2D slopes;
uniform mat4 mvp;
uniform vec2 origin, cell;
uniform int nx;
out vec3 normal;
out float depth;
uniform float top, fullDepth;
void main() {
  ivec2 at = ivec2(gl_VertexID % nx, gl_VertexID / nx);
  float z = texelFetch(heights, at, 0).r;
  vec2 slope = texelFetch(slopes, at, 0).rg;
  normal = normalize(vec3(-slope, 1.0));
  depth = (top - z) / max(fullDepth, 1e-6);
  gl_Position = mvp * vec4(origin + (vec2(at) + 0.5) * cell, z, 1.0);
}`;
const STOCK_FS = `#version 300 es
precision highp float;
in vec3 normal;
in float depth;
out vec4 color;
void main() {
  vec3 n = normalize(normal);
  float light = 0.35 + 0.65 * max(dot(n, normalize(vec3(-0.4, -0.5, 0.8))), 0.0);
  vec3 base = mix(vec3(0.80, 0.74, 0.62), vec3(0.55, 0.62, 0.72), clamp(depth, 0.0, 1.0));
  color = vec4(base * light, 1.0);
}`;
const LINE_VS = `#version 300 es
in vec3 position;
in uint info;
in float lit;
uniform mat4 mvp;
uniform vec3 tools[8];
uniform vec3 rapid;
uniform float faded, showRapids;
out vec4 tint;
void main() {
  uint kind = info >> 12u;
  vec3 c = kind == 0u ? rapid : tools[info & 7u];
  float a = kind == 0u ? 0.7 * showRapids : 1.0;
  if (lit > 0.5) { c = vec3(1.0, 0.85, 0.0); a = 1.0; }
  if (faded > 0.5 && lit < 0.5) { c = mix(c, vec3(0.75), 0.75); a *= 0.5; }
  tint = vec4(c, a);
  gl_Position = mvp * vec4(position, 1.0);
  gl_Position.z -= 0.002 * gl_Position.w;
  gl_PointSize = 9.0;
}`;
const LINE_FS = `#version 300 es
precision mediump float;
in vec4 tint;
out vec4 color;
void main() { if (tint.a <= 0.0) discard; color = tint; }`;
const PLAIN_VS = `#version 300 es
in vec3 position;
uniform mat4 mvp;
uniform float size, bias;
void main() { gl_Position = mvp * vec4(position, 1.0); gl_Position.z -= bias * gl_Position.w; gl_PointSize = size; }`;
const PLAIN_FS = `#version 300 es
precision mediump float;
uniform vec4 tint;
out vec4 color;
void main() { color = tint; }`;

function program(gl, vs, fs) {
  const p = gl.createProgram();
  for (const [type, text] of [[gl.VERTEX_SHADER, vs], [gl.FRAGMENT_SHADER, fs]]) {
    const s = gl.createShader(type);
    gl.shaderSource(s, text);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
    gl.attachShader(p, s);
  }
  gl.linkProgram(p);
  if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(p));
  const u = {};
  const count = gl.getProgramParameter(p, gl.ACTIVE_UNIFORMS);
  for (let k = 0; k < count; k++) {
    const name = gl.getActiveUniform(p, k).name.replace(/\[0\]$/, "");
    u[name] = gl.getUniformLocation(p, name);
  }
  return { p, u, a: (name) => gl.getAttribLocation(p, name) };
}

// ---------------------------------------------------------------- state

const gl = $("gl").getContext("webgl2", { antialias: true, preserveDrawingBuffer: true });
const view = {
  header: null, moves: null, stock: null, version: 0, time: 0, total: 0,
  selected: new Set(), selectedLine: 0, camera: null, ruler: null, rulerOn: false,
  playing: false, lastFrame: 0, warnLines: new Map(),
};
let glState = null;

function setupGl() {
  const stock = program(gl, STOCK_VS, STOCK_FS);
  const lines = program(gl, LINE_VS, LINE_FS);
  const plain = program(gl, PLAIN_VS, PLAIN_FS);
  return {
    stock, lines, plain,
    pathVao: gl.createVertexArray(), posBuf: gl.createBuffer(), infoBuf: gl.createBuffer(),
    litBuf: gl.createBuffer(), stockVao: gl.createVertexArray(), indexBuf: gl.createBuffer(),
    heightTex: gl.createTexture(), slopeTex: gl.createTexture(), plainVao: gl.createVertexArray(), plainBuf: gl.createBuffer(),
    indexCount: 0,
  };
}

function uploadPath(m) {
  const g = glState;
  const info = new Uint16Array(m.vertices);
  for (let k = 0; k < m.n; k++) {
    const value = (m.kind[k] === KIND_RAPID ? 0 : 1) << 12 | (m.tool[k] & 7);
    info.fill(value, m.first[k], m.first[k + 1]);
  }
  gl.bindVertexArray(g.pathVao);
  gl.bindBuffer(gl.ARRAY_BUFFER, g.posBuf);
  gl.bufferData(gl.ARRAY_BUFFER, m.pos, gl.STATIC_DRAW);
  gl.enableVertexAttribArray(g.lines.a("position"));
  gl.vertexAttribPointer(g.lines.a("position"), 3, gl.FLOAT, false, 0, 0);
  gl.bindBuffer(gl.ARRAY_BUFFER, g.infoBuf);
  gl.bufferData(gl.ARRAY_BUFFER, info, gl.STATIC_DRAW);
  gl.enableVertexAttribArray(g.lines.a("info"));
  gl.vertexAttribIPointer(g.lines.a("info"), 1, gl.UNSIGNED_SHORT, 0, 0);
  m.litFlags = new Float32Array(m.vertices);
  gl.bindBuffer(gl.ARRAY_BUFFER, g.litBuf);
  gl.bufferData(gl.ARRAY_BUFFER, m.litFlags, gl.DYNAMIC_DRAW);
  gl.enableVertexAttribArray(g.lines.a("lit"));
  gl.vertexAttribPointer(g.lines.a("lit"), 1, gl.FLOAT, false, 0, 0);
  gl.bindVertexArray(null);
}

function uploadStockMesh(s) {
  const g = glState, nx = s.spec.nx, ny = s.spec.ny;
  const index = new Uint32Array(Math.max(nx - 1, 0) * Math.max(ny - 1, 0) * 6);
  let k = 0;
  for (let j = 0; j + 1 < ny; j++)
    for (let i = 0; i + 1 < nx; i++) {
      const a = j * nx + i;
      index[k] = a; index[k + 1] = a + 1; index[k + 2] = a + nx;
      index[k + 3] = a + 1; index[k + 4] = a + nx + 1; index[k + 5] = a + nx;
      k += 6;
    }
  gl.bindVertexArray(g.stockVao);
  gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, g.indexBuf);
  gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, index, gl.STATIC_DRAW);
  gl.bindVertexArray(null);
  g.indexCount = index.length;
  gl.bindTexture(gl.TEXTURE_2D, g.heightTex);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
  gl.texImage2D(gl.TEXTURE_2D, 0, gl.R32F, nx, ny, 0, gl.RED, gl.FLOAT, s.heights);
  s.slopes = new Float32Array(nx * ny * 2);
  s.rough = new Float32Array(nx * ny * 2);
  gl.bindTexture(gl.TEXTURE_2D, g.slopeTex);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
  gl.texImage2D(gl.TEXTURE_2D, 0, gl.RG32F, nx, ny, 0, gl.RG, gl.FLOAT, s.slopes);
}

// One line of (x, y) pairs from `from` into `to`, smoothed with weights
// 1 2 3 2 1 (those that fall off the grid left out): `count` cells from
// cell `base`, `step` cells apart.
function blurLine(from, to, base, step, count) {
  const W = [1, 2, 3, 2, 1];
  for (let k = 0; k < count; k++) {
    let gx = 0, gy = 0, w = 0;
    if (k >= 2 && k + 2 < count) {
      for (let d = 0; d < 5; d++) {
        const at = 2 * (base + (k + d - 2) * step);
        gx += W[d] * from[at]; gy += W[d] * from[at + 1];
      }
      w = 9;
    } else {
      for (let d = -2; d <= 2; d++) {
        const q = k + d;
        if (q < 0 || q >= count) continue;
        const at = 2 * (base + q * step);
        gx += W[d + 2] * from[at]; gy += W[d + 2] * from[at + 1]; w += W[d + 2];
      }
    }
    const at = 2 * (base + k * step);
    to[at] = gx / w; to[at + 1] = gy / w;
  }
}

// The surface's slope (dz/dx, dz/dy) at each cell for the shading: central
// differences, then smoothed over 5 x 5 cells (weights 1 2 3 2 1 each
// way), so that a wall across the grid's rows, a staircase of cells in
// the heightmap, is lit as one wall and not as a comb of steps. The
// heights drawn are the cells' own.
function shadeSlopes(s) {
  const nx = s.spec.nx, ny = s.spec.ny, h = s.heights, rough = s.rough, out = s.slopes;
  const c2 = 2 * s.spec.cell_mm;
  for (let j = 0; j < ny; j++) {
    const up = Math.min(j + 1, ny - 1) * nx, down = Math.max(j - 1, 0) * nx, row = j * nx;
    for (let i = 0; i < nx; i++) {
      rough[2 * (row + i)] = (h[row + Math.min(i + 1, nx - 1)] - h[row + Math.max(i - 1, 0)]) / c2;
      rough[2 * (row + i) + 1] = (h[up + i] - h[down + i]) / c2;
    }
  }
  // Along the rows into `out`, then along the columns back into `rough`.
  for (let j = 0; j < ny; j++) blurLine(rough, out, j * nx, 1, nx);
  for (let i = 0; i < nx; i++) blurLine(out, rough, i, nx, ny);
  gl.bindTexture(gl.TEXTURE_2D, glState.slopeTex);
  gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, 0, nx, ny, gl.RG, gl.FLOAT, rough);
}

// ---------------------------------------------------------------- stock over time

// The move playing at time t and how far into it (1: done).
function moveAt(t) {
  const m = view.moves;
  if (m.n === 0 || t >= m.tEnd[m.n - 1]) return { index: m.n, fraction: 1 };
  let lo = 0, hi = m.n;
  while (lo < hi) {
    const mid = (lo + hi) >> 1;
    if (m.tEnd[mid] < t) lo = mid + 1; else hi = mid;
  }
  if (lo >= m.n) return { index: m.n, fraction: 1 };
  const begin = lo > 0 ? m.tEnd[lo - 1] : 0;
  const span = m.tEnd[lo] - begin;
  // A move that takes no time (a rapid without a machine) is done as
  // soon as the clock reaches it.
  const fraction = span > 0 ? Math.min(1, Math.max(0, (t - begin) / span)) : 1;
  return { index: lo, fraction };
}

// Heights (mm) of the stock when `done` moves are over and the next is
// `fraction` through: the last checkpoint at or before, swept on.
function stockAt(done, fraction) {
  const s = view.stock, spec = s.spec, m = view.moves;
  let c = -1;
  while (c + 1 < spec.checkpoints.length && spec.checkpoints[c + 1].moves <= done) c++;
  let from;
  if (s.shownAt && s.shownAt.checkpoint === c && s.shownAt.done <= done && !s.shownAt.partial) {
    from = s.shownAt.done;
  } else {
    const depths = c >= 0 ? checkpointDepths(s, c) : null;
    const scale = spec.depth_mm / 65535;
    for (let k = 0; k < s.heights.length; k++) s.heights[k] = spec.top - (depths ? depths[k] * scale : 0);
    from = c >= 0 ? spec.checkpoints[c].moves : 0;
  }
  for (let k = from; k < done; k++) sweepMove(k, 1);
  const partial = done < m.n && fraction > 0 && fraction < 1;
  if (partial) sweepMove(done, fraction);
  s.shownAt = { checkpoint: c, done, partial };
  let removed = 0;
  for (let k = 0; k < s.heights.length; k++) removed += Math.max(0, spec.top - s.heights[k]);
  return removed * spec.cell_mm * spec.cell_mm;
}

// The cut of move k (its first `fraction`) as `ger render` carves it
// (src/render.rs' segments, src/render/cutter.rs' closed forms): lines
// between the drawn ends, level arcs as arcs, other arcs as the
// render's chords; each cell lowered to the lowest the cutter reaches
// over its centre.
function sweepMove(k, fraction) {
  const m = view.moves, s = view.stock;
  const cutter = s.cutters[m.tool[k]];
  const record = s.sweeps.get(k);
  if (!cutter || (record && record.skip)) return;
  const vertex = (v) => [m.pos[v * 3], m.pos[v * 3 + 1], m.pos[v * 3 + 2]];
  const a = record && record.start ? record.start : vertex(m.first[k]);
  const b = vertex(m.first[k + 1] - 1);
  if (record && record.arc) return sweepArc(s, cutter, levelArc(record.arc, a, b, fraction));
  const points = [a];
  if (record && record.chords) {
    const q = view.header.moves.quantum_mm;
    for (const d of record.chords) points.push([a[0] + d[0] * q, a[1] + d[1] * q, a[2] + d[2] * q]);
  }
  points.push(b);
  const pieces = points.length - 1, upto = pieces * Math.min(1, fraction);
  for (let p = 0; p < Math.ceil(upto); p++) {
    const part = Math.min(1, upto - p), u = points[p], w = points[p + 1];
    sweepLine(s, lineSweep(cutter, u, part >= 1 ? w : [0, 1, 2].map((i) => u[i] + (w[i] - u[i]) * part)));
  }
}

// The height of the underside above the tip at distance d (<= radius).
function lift(c, d) {
  if (c.profile === 1) return c.r - Math.sqrt(Math.max(0, c.r * c.r - d * d));
  if (c.profile === 2) return c.rise * d;
  return 0;
}

// A cutter along the line a-b, what every cell asks worked out once
// (render/cutter.rs' LineSweep).
function lineSweep(c, a, b) {
  const vx = b[0] - a[0], vy = b[1] - a[1], dz = b[2] - a[2], length = Math.hypot(vx, vy);
  const inv = length > 1e-12 ? 1 / length : 0, slope = length > 1e-12 ? dz / length : 0;
  let k = null;
  if (c.profile === 0) k = 0;
  else if (c.profile === 1) k = -slope / Math.sqrt(1 + slope * slope);
  else if (Math.abs(slope) < c.rise) k = -slope / Math.sqrt(c.rise * c.rise - slope * slope);
  const coneSide = c.profile === 2 && k !== null ? slope * k + c.rise * Math.sqrt(1 + k * k) : 0;
  return {
    c, a, b, vx, vy, length, inv, slope, k, coneSide, incline: Math.sqrt(1 + slope * slope),
    r2: c.r * c.r, zMin: Math.min(a[2], b[2]), yMin: Math.min(a[1], b[1]), yMax: Math.max(a[1], b[1]),
  };
}

// Whether k * sqrt(q) <= c (q >= 0).
function atMost(k, q, c) {
  if (k <= 0) return c >= 0 || k * k * q >= c * c;
  return c >= 0 && k * k * q <= c * c;
}

// The lowest the cutter reaches over (x, y) along the line; null where
// it never passes over it (LineSweep::lowest).
function lowestOnLine(s, x, y) {
  const c = s.c, a = s.a;
  const wx = x - a[0], wy = y - a[1], w2 = wx * wx + wy * wy;
  if (s.inv === 0) return w2 <= s.r2 ? s.zMin + lift(c, Math.sqrt(w2)) : null;
  const along = (wx * s.vx + wy * s.vy) * s.inv;
  const h2 = Math.max(0, w2 - along * along), reach2 = s.r2 - h2;
  const start = -along, end = s.length - along;
  if (reach2 < 0 || (start > 0 && start * start > reach2) || (end < 0 && end * end > reach2)) return null;
  const slope = s.slope;
  if (c.profile === 1) {
    if (atMost(s.k, reach2, start)) return a[2] + c.r - Math.sqrt(Math.max(0, s.r2 - w2));
    if (!atMost(s.k, reach2, end)) {
      const bx = wx - s.vx, by = wy - s.vy;
      return s.b[2] + c.r - Math.sqrt(Math.max(0, s.r2 - bx * bx - by * by));
    }
    return a[2] + slope * along + c.r - Math.sqrt(reach2) * s.incline;
  }
  const reach = Math.sqrt(reach2), u0 = Math.max(start, -reach), u1 = Math.min(end, reach);
  const zFoot = a[2] + slope * along;
  if (c.profile === 0) return zFoot + slope * (slope >= 0 ? u0 : u1);
  const h = Math.sqrt(h2);
  let u;
  if (s.k !== null) {
    const kh = s.k * h;
    if (kh >= u0 && kh <= u1) return zFoot + h * s.coneSide;
    u = Math.min(Math.max(kh, u0), u1);
  } else {
    u = slope > 0 ? u0 : u1;
  }
  return zFoot + slope * u + c.rise * Math.sqrt(h2 + u * u);
}

function chordHalf(r, dy) {
  return Math.abs(dy) <= r ? Math.sqrt(r * r - dy * dy) : null;
}

function crossing(p, q, y) {
  return (p[1] - y) * (q[1] - y) <= 0 && p[1] !== q[1] ? p[0] + (y - p[1]) * (q[0] - p[0]) / (q[1] - p[1]) : null;
}

// The cells (first, last) whose centres lie in [lo, hi] along one axis.
function cellsWithin(origin, cell, n, lo, hi) {
  const first = Math.max(0, Math.ceil((lo - origin) / cell - 0.5));
  const last = Math.min(n - 1, Math.floor((hi - origin) / cell - 0.5));
  return first <= last ? [first, last] : null;
}

function lower(s, j, lo, hi, lowest) {
  const spec = s.spec, cols = cellsWithin(spec.x0, spec.cell_mm, spec.nx, lo, hi);
  if (!cols) return;
  const y = spec.y0 + (j + 0.5) * spec.cell_mm, row = j * spec.nx, heights = s.heights;
  for (let i = cols[0]; i <= cols[1]; i++) {
    const z = lowest(spec.x0 + (i + 0.5) * spec.cell_mm, y);
    if (z !== null && z < heights[row + i]) heights[row + i] = z;
  }
}

// Each row's cells within the radius of the line: the hull of the discs
// at its ends and the band between them (LineSweep::spans).
function sweepLine(st, s) {
  const spec = st.spec, r = s.c.r;
  if (s.zMin >= spec.top) return;
  const rows = cellsWithin(spec.y0, spec.cell_mm, spec.ny, s.yMin - r, s.yMax + r);
  if (!rows) return;
  const nx = -s.vy * s.inv * r, ny = s.vx * s.inv * r, band = s.inv > 0;
  const p0 = [s.a[0] + nx, s.a[1] + ny], p1 = [s.b[0] + nx, s.b[1] + ny];
  const q0 = [s.b[0] - nx, s.b[1] - ny], q1 = [s.a[0] - nx, s.a[1] - ny];
  const lowest = (x, y) => lowestOnLine(s, x, y);
  for (let j = rows[0]; j <= rows[1]; j++) {
    const y = spec.y0 + (j + 0.5) * spec.cell_mm;
    let lo = Infinity, hi = -Infinity;
    const wa = chordHalf(r, y - s.a[1]), wb = chordHalf(r, y - s.b[1]);
    if (wa !== null) { lo = s.a[0] - wa; hi = s.a[0] + wa; }
    if (wb !== null) { lo = Math.min(lo, s.b[0] - wb); hi = Math.max(hi, s.b[0] + wb); }
    if (band) {
      const x = crossing(p0, p1, y), z = crossing(q0, q1, y);
      if (x !== null) { lo = Math.min(lo, x); hi = Math.max(hi, x); }
      if (z !== null) { lo = Math.min(lo, z); hi = Math.max(hi, z); }
    }
    if (lo <= hi) lower(st, j, lo, hi, lowest);
  }
}

// The level arc of a move from a to b (its first `fraction`), as the
// render keeps it: counter-clockwise from `from` to `to` about the centre.
function levelArc(arc, a, b, fraction) {
  const cx = a[0] + arc.dx, cy = a[1] + arc.dy;
  const s = [a[0] - cx, a[1] - cy];
  let e = [b[0] - cx, b[1] - cy], sweep = arc.sweep;
  if (fraction < 1) {
    sweep *= fraction;
    const t = arc.clockwise ? -sweep : sweep;
    e = [s[0] * Math.cos(t) - s[1] * Math.sin(t), s[0] * Math.sin(t) + s[1] * Math.cos(t)];
  }
  const [from, to] = arc.clockwise ? [e, s] : [s, e];
  return { cx, cy, z: a[2], from, to, sweep, radius: Math.hypot(from[0], from[1]) };
}

// Whether the direction (x, y) from the centre is within the arc.
function covers(arc, x, y) {
  const cross = (p, u, v) => p[0] * v - p[1] * u;
  if (arc.sweep >= 2 * Math.PI - 1e-12) return true;
  if (arc.sweep <= Math.PI) return cross(arc.from, x, y) >= 0 && -cross(arc.to, x, y) >= 0;
  return !(cross(arc.to, x, y) > 0 && -cross(arc.from, x, y) > 0);
}

function arcDistance(arc, x, y) {
  const dx = x - arc.cx, dy = y - arc.cy;
  if (covers(arc, dx, dy)) return Math.abs(Math.sqrt(dx * dx + dy * dy) - arc.radius);
  const f = arc.from, t = arc.to;
  return Math.min(Math.hypot(dx - f[0], dy - f[1]), Math.hypot(dx - t[0], dy - t[1]));
}

// Each row's cells within the radius of the arc: the ring about the whole
// circle and the discs at its ends (Arc::spans).
function sweepArc(st, c, arc) {
  const spec = st.spec, r = c.r;
  if (arc.z >= spec.top) return;
  const rows = cellsWithin(spec.y0, spec.cell_mm, spec.ny, arc.cy - arc.radius - r, arc.cy + arc.radius + r);
  if (!rows) return;
  const lowest = (x, y) => {
    const d = arcDistance(arc, x, y);
    return d <= r ? arc.z + lift(c, d) : null;
  };
  for (let j = rows[0]; j <= rows[1]; j++) {
    const dy = spec.y0 + (j + 0.5) * spec.cell_mm - arc.cy;
    const outer = chordHalf(arc.radius + r, dy);
    if (outer !== null) {
      const inner = arc.radius > r ? chordHalf(arc.radius - r, dy) : null;
      if (inner !== null) {
        lower(st, j, arc.cx - outer, arc.cx - inner, lowest);
        lower(st, j, arc.cx + inner, arc.cx + outer, lowest);
      } else {
        lower(st, j, arc.cx - outer, arc.cx + outer, lowest);
      }
    }
    for (const end of [arc.from, arc.to]) {
      const w = chordHalf(r, dy - end[1]);
      if (w !== null) lower(st, j, arc.cx + end[0] - w, arc.cx + end[0] + w, lowest);
    }
  }
}

// ---------------------------------------------------------------- drawing

function camera() {
  const c = view.camera;
  const cp = Math.cos(c.pitch), sp = Math.sin(c.pitch);
  const eye = [c.target[0] + c.distance * cp * Math.cos(c.yaw), c.target[1] + c.distance * cp * Math.sin(c.yaw),
    c.target[2] + c.distance * sp];
  const up = Math.abs(sp) > 0.999 ? [-Math.cos(c.yaw), -Math.sin(c.yaw), 0] : [0, 0, 1];
  const canvas = $("gl");
  const proj = perspective(0.7, canvas.width / Math.max(1, canvas.height), c.distance / 500, c.distance * 20);
  return multiply(proj, lookAt(eye, c.target, up));
}

function draw() {
  const canvas = $("gl"), g = glState;
  const dpr = window.devicePixelRatio || 1;
  const w = Math.max(1, Math.round(canvas.clientWidth * dpr)), h = Math.max(1, Math.round(canvas.clientHeight * dpr));
  if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }
  gl.viewport(0, 0, w, h);
  gl.clearColor(0.875, 0.89, 0.91, 1);
  gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
  if (!view.moves || !view.camera) return;
  gl.enable(gl.DEPTH_TEST);
  gl.enable(gl.BLEND);
  gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
  const mvp = camera();
  view.mvp = mvp;
  const s = view.stock;
  if (s && $("show-stock").checked && g.indexCount) {
    gl.useProgram(g.stock.p);
    gl.uniformMatrix4fv(g.stock.u.mvp, false, mvp);
    gl.uniform2f(g.stock.u.origin, s.spec.min[0], s.spec.min[1]);
    gl.uniform2f(g.stock.u.cell, s.size[0], s.size[1]);
    gl.uniform1i(g.stock.u.nx, s.spec.nx);
    gl.uniform1f(g.stock.u.top, s.spec.top);
    gl.uniform1f(g.stock.u.fullDepth, s.spec.top - s.spec.bottom);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, g.heightTex);
    gl.uniform1i(g.stock.u.heights, 0);
    gl.activeTexture(gl.TEXTURE1);
    gl.bindTexture(gl.TEXTURE_2D, g.slopeTex);
    gl.uniform1i(g.stock.u.slopes, 1);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindVertexArray(g.stockVao);
    gl.drawElements(gl.TRIANGLES, g.indexCount, gl.UNSIGNED_INT, 0);
  }
  drawPath(mvp);
  drawOverlays(mvp);
  gl.bindVertexArray(null);
}

function drawPath(mvp) {
  const g = glState, m = view.moves;
  gl.useProgram(g.lines.p);
  gl.uniformMatrix4fv(g.lines.u.mvp, false, mvp);
  gl.uniform3fv(g.lines.u.tools, PALETTE.flat());
  gl.uniform3fv(g.lines.u.rapid, RAPID);
  gl.uniform1f(g.lines.u.showRapids, $("show-rapids").checked ? 1 : 0);
  gl.bindVertexArray(g.pathVao);
  const at = moveAt(view.time);
  const played = at.index >= m.n ? m.vertices : m.first[at.index] + 2 * Math.ceil((m.first[at.index + 1] - m.first[at.index]) / 2 * at.fraction);
  gl.uniform1f(g.lines.u.faded, 0);
  if (played > 0) gl.drawArrays(gl.LINES, 0, played);
  gl.uniform1f(g.lines.u.faded, 1);
  if (played < m.vertices) gl.drawArrays(gl.LINES, played, m.vertices - played);
}

// The tool where it is, the warnings' places and the ruler.
function drawOverlays(mvp) {
  const g = glState, m = view.moves;
  const points = [];
  const shapes = [];
  const at = moveAt(view.time);
  if (m.n > 0) {
    const k = Math.min(at.index, m.n - 1);
    const p = positionAt(k, at.index < m.n ? at.fraction : 1);
    const cutter = view.header.tools[m.tool[k]];
    const r = cutter ? cutter.radius : 1;
    const circle = [];
    for (let a = 0; a <= 32; a++) circle.push(p[0] + r * Math.cos(a / 16 * Math.PI), p[1] + r * Math.sin(a / 16 * Math.PI), p[2]);
    const height = Math.max(4 * r, 10);
    shapes.push({ mode: gl.LINE_STRIP, data: circle, tint: [0.1, 0.1, 0.1, 1] });
    shapes.push({ mode: gl.LINES, data: [p[0] - r, p[1], p[2], p[0] - r, p[1], p[2] + height, p[0] + r, p[1], p[2], p[0] + r, p[1], p[2] + height], tint: [0.1, 0.1, 0.1, 1] });
  }
  for (const k of view.warnLines.values()) {
    const v = m.first[k + 1] - 1;
    points.push(m.pos[v * 3], m.pos[v * 3 + 1], m.pos[v * 3 + 2]);
  }
  if (points.length) shapes.push({ mode: gl.POINTS, data: points, tint: [0.95, 0.45, 0.0, 1], size: 10 });
  if (view.ruler && view.ruler.length) {
    const data = view.ruler.flat();
    shapes.push({ mode: gl.POINTS, data, tint: [0.0, 0.0, 0.0, 1], size: 7 });
    if (view.ruler.length === 2) shapes.push({ mode: gl.LINES, data, tint: [0.0, 0.0, 0.0, 1] });
  }
  gl.useProgram(g.plain.p);
  gl.uniformMatrix4fv(g.plain.u.mvp, false, mvp);
  gl.bindVertexArray(g.plainVao);
  gl.bindBuffer(gl.ARRAY_BUFFER, g.plainBuf);
  gl.enableVertexAttribArray(g.plain.a("position"));
  gl.vertexAttribPointer(g.plain.a("position"), 3, gl.FLOAT, false, 0, 0);
  if (view.stock && $("show-stock").checked) shapes.unshift({ mode: gl.TRIANGLES, data: walls(view.stock), tint: [0.60, 0.55, 0.45, 1], bias: 0 });
  for (const shape of shapes) {
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(shape.data), gl.DYNAMIC_DRAW);
    gl.uniform4fv(g.plain.u.tint, shape.tint);
    gl.uniform1f(g.plain.u.size, shape.size || 1);
    gl.uniform1f(g.plain.u.bias, shape.bias ?? 0.004);
    gl.drawArrays(shape.mode, 0, shape.data.length / 3);
  }
}

// The stock's four sides, from its bottom up to the shown edge cells.
function walls(s) {
  const sp = s.spec, out = [];
  const side = (count, at) => {
    for (let k = 0; k + 1 < count; k++) {
      const [x0, y0, h0] = at(k), [x1, y1, h1] = at(k + 1);
      out.push(x0, y0, sp.bottom, x1, y1, sp.bottom, x1, y1, h1, x0, y0, sp.bottom, x1, y1, h1, x0, y0, h0);
    }
  };
  const x = (i) => sp.min[0] + (i + 0.5) * s.size[0], y = (j) => sp.min[1] + (j + 0.5) * s.size[1];
  side(sp.nx, (i) => [x(i), y(0), s.heights[i]]);
  side(sp.nx, (i) => [x(i), y(sp.ny - 1), s.heights[(sp.ny - 1) * sp.nx + i]]);
  side(sp.ny, (j) => [x(0), y(j), s.heights[j * sp.nx]]);
  side(sp.ny, (j) => [x(sp.nx - 1), y(j), s.heights[j * sp.nx + sp.nx - 1]]);
  return out;
}

function positionAt(k, fraction) {
  const m = view.moves;
  const pairs = (m.first[k + 1] - m.first[k]) / 2;
  const along = Math.min(pairs, pairs * fraction);
  const p = Math.min(pairs - 1, Math.floor(along));
  const part = along - p;
  const v = (m.first[k] + 2 * p) * 3;
  return [0, 1, 2].map((i) => m.pos[v + i] + (m.pos[v + 3 + i] - m.pos[v + i]) * part);
}

let drawPending = false;
function redraw() {
  if (drawPending) return;
  drawPending = true;
  requestAnimationFrame(() => { drawPending = false; draw(); });
}

// ---------------------------------------------------------------- time

function setTime(t) {
  const m = view.moves;
  view.time = Math.max(0, Math.min(view.total, t));
  $("scrub").value = view.total > 0 ? (view.time / view.total) * 1000 : 1000;
  $("clock").textContent = `${clock(view.time)} / ${clock(view.total)}`;
  if (view.stock) {
    const at = moveAt(view.time);
    const done = at.index >= m.n ? m.n : at.index + (at.fraction >= 1 ? 1 : 0);
    const removed = stockAt(done, at.index >= m.n ? 0 : at.fraction);
    body.dataset.gerRemovedMm3 = removed.toFixed(3);
    gl.bindTexture(gl.TEXTURE_2D, glState.heightTex);
    gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, 0, view.stock.spec.nx, view.stock.spec.ny, gl.RED, gl.FLOAT, view.stock.heights);
    shadeSlopes(view.stock);
  } else {
    body.dataset.gerRemovedMm3 = "0";
  }
  redraw();
}

function clock(seconds) {
  const s = Math.max(0, seconds);
  if (s >= 3600) {
    const w = Math.round(s);
    return `${Math.floor(w / 3600)}:${String(Math.floor(w / 60) % 60).padStart(2, "0")}:${String(w % 60).padStart(2, "0")}`;
  }
  return `${Math.floor(s / 60)}:${(s % 60).toFixed(1).padStart(4, "0")}`;
}

function tick(now) {
  if (!view.playing) return;
  const dt = view.lastFrame ? (now - view.lastFrame) / 1000 : 0;
  view.lastFrame = now;
  setTime(view.time + dt * Number($("speed").value));
  if (view.time >= view.total) { view.playing = false; $("play").textContent = "Play"; return; }
  requestAnimationFrame(tick);
}

function stepMove(by) {
  const m = view.moves;
  if (!m || m.n === 0) return;
  const at = moveAt(view.time);
  let k = at.index >= m.n ? m.n - 1 : at.index - (at.fraction >= 1 ? 0 : 1);
  k = Math.max(-1, Math.min(m.n - 1, k + by));
  setTime(k < 0 ? 0 : m.tEnd[k]);
  if (k >= 0) selectMove(k);
}

// ---------------------------------------------------------------- code panes

class CodePane {
  constructor(element, onClick) {
    this.el = element; this.lines = []; this.marks = new Map(); this.lit = new Set();
    this.spacer = document.createElement("div");
    this.el.appendChild(this.spacer);
    this.shown = new Map();
    this.el.addEventListener("scroll", () => this.render());
    this.el.addEventListener("click", (e) => {
      const row = e.target.closest(".line");
      if (row) onClick(Number(row.dataset.line));
    });
  }
  set(text) {
    this.lines = text === null ? [] : text.split("\n");
    if (this.lines.length && this.lines[this.lines.length - 1] === "") this.lines.pop();
    this.spacer.style.height = `${this.lines.length * 16 + 4}px`;
    for (const row of this.shown.values()) row.remove();
    this.shown.clear();
    this.render();
  }
  render() {
    const first = Math.max(0, Math.floor(this.el.scrollTop / 16) - 10);
    const last = Math.min(this.lines.length, first + Math.ceil(this.el.clientHeight / 16) + 20);
    for (const [n, row] of this.shown) if (n < first + 1 || n > last) { row.remove(); this.shown.delete(n); }
    for (let n = first + 1; n <= last; n++) {
      let row = this.shown.get(n);
      if (!row) {
        row = document.createElement("div");
        row.className = "line";
        row.dataset.line = n;
        row.style.top = `${(n - 1) * 16}px`;
        const no = document.createElement("span");
        no.className = "no";
        no.textContent = n;
        row.append(no, this.lines[n - 1]);
        this.el.appendChild(row);
        this.shown.set(n, row);
      }
      row.classList.toggle("lit", this.lit.has(n));
      row.classList.toggle("error", this.marks.get(n) === "error");
      row.classList.toggle("warning", this.marks.get(n) === "warning");
    }
  }
  reveal(n) {
    if (!n) return;
    const y = (n - 1) * 16;
    if (y < this.el.scrollTop || y > this.el.scrollTop + this.el.clientHeight - 32)
      this.el.scrollTop = Math.max(0, y - this.el.clientHeight / 3);
    this.render();
  }
}

const sourcePane = new CodePane($("source"), (n) => { selectLine(n); history.replaceState(null, "", `#L${n}`); });
const outputPane = new CodePane($("output"), (n) => selectOutputLine(n));

// ---------------------------------------------------------------- selection

function light(moves, line, outLines) {
  const m = view.moves;
  view.selected = new Set(moves);
  m.litFlags.fill(0);
  for (const k of moves) m.litFlags.fill(1, m.first[k], m.first[k + 1]);
  gl.bindBuffer(gl.ARRAY_BUFFER, glState.litBuf);
  gl.bufferData(gl.ARRAY_BUFFER, m.litFlags, gl.DYNAMIC_DRAW);
  body.dataset.gerSelectedMoves = String(moves.length);
  sourcePane.lit = new Set(line ? [line] : []);
  outputPane.lit = new Set(outLines);
  sourcePane.reveal(line);
  outputPane.reveal(outLines[0]);
  sourcePane.render();
  outputPane.render();
  redraw();
}

function selectLine(n) {
  const m = view.moves;
  const moves = [];
  const outs = new Set();
  if (m) for (let k = 0; k < m.n; k++) if (m.file[k] === 0 && m.line[k] === n) { moves.push(k); if (m.out[k]) outs.add(m.out[k]); }
  if (!m || moves.length === 0) {
    // A line with no move: the output lines it made, by their N word.
    const text = view.header && view.header.output ? outputPane.lines : [];
    text.forEach((l, i) => { if (new RegExp(`^\\s*N${n}\\b`).test(l)) outs.add(i + 1); });
  }
  view.selectedLine = n;
  light(moves, n, [...outs].sort((a, b) => a - b));
  $("readout").textContent = moves.length ? `line ${n}: ${moves.length} move${moves.length === 1 ? "" : "s"}` : `line ${n}: no move`;
}

function selectOutputLine(o) {
  const m = view.moves;
  let line = 0;
  if (m) for (let k = 0; k < m.n; k++) if (m.out[k] === o) { line = m.file[k] === 0 ? m.line[k] : 0; break; }
  if (!line) {
    const match = /^\s*N(\d+)/.exec(outputPane.lines[o - 1] || "");
    if (match) line = Number(match[1]);
  }
  if (line) selectLine(line);
  outputPane.lit = new Set([o]);
  outputPane.render();
}

function selectMove(k) {
  const m = view.moves;
  const name = view.header.files[m.file[k]] || "?";
  const [x, y, z] = positionAt(k, 1);
  light([k], m.file[k] === 0 ? m.line[k] : 0, m.out[k] ? [m.out[k]] : []);
  const kinds = ["rapid", "feed", "arc"];
  $("readout").textContent = `move ${k + 1} (${kinds[m.kind[k]]}, T${view.header.tools[m.tool[k]]?.number ?? "?"}) ` +
    `${name}:${m.line[k]}  output line ${m.out[k] || "-"}\nends X${x.toFixed(3)} Y${y.toFixed(3)} Z${z.toFixed(3)} at ${clock(m.tEnd[k])}`;
}

// The move whose drawn chord passes nearest the pointer (within 8 px).
function pickMove(px, py) {
  const m = view.moves, mvp = view.mvp, canvas = $("gl");
  if (!m || !mvp) return -1;
  const dpr = window.devicePixelRatio || 1, w = canvas.width, h = canvas.height;
  px *= dpr; py *= dpr;
  let best = -1, bestD = 8 * dpr;
  const rapids = $("show-rapids").checked;
  for (let k = 0; k < m.n; k++) {
    if (!rapids && m.kind[k] === KIND_RAPID) continue;
    for (let v = m.first[k]; v < m.first[k + 1]; v += 2) {
      const a = project(mvp, m.pos[v * 3], m.pos[v * 3 + 1], m.pos[v * 3 + 2], w, h);
      const b = project(mvp, m.pos[v * 3 + 3], m.pos[v * 3 + 4], m.pos[v * 3 + 5], w, h);
      if (!a || !b) continue;
      const dx = b[0] - a[0], dy = b[1] - a[1], l2 = dx * dx + dy * dy;
      const t = l2 > 0 ? Math.max(0, Math.min(1, ((px - a[0]) * dx + (py - a[1]) * dy) / l2)) : 0;
      const d = Math.hypot(a[0] + dx * t - px, a[1] + dy * t - py);
      if (d < bestD) { bestD = d; best = k; }
    }
  }
  return best;
}

// The point the ruler takes: the nearest drawn path vertex or stock cell
// centre under the pointer (within 12 px), the nearer the camera first.
function pickPoint(px, py) {
  const m = view.moves, mvp = view.mvp, canvas = $("gl");
  const dpr = window.devicePixelRatio || 1, w = canvas.width, h = canvas.height;
  px *= dpr; py *= dpr;
  let best = null, bestScore = Infinity;
  const consider = (x, y, z) => {
    const p = project(mvp, x, y, z, w, h);
    if (!p) return;
    const d = Math.hypot(p[0] - px, p[1] - py);
    if (d > 12 * dpr) return;
    const score = d + p[2] * 1e-6;
    if (score < bestScore) { bestScore = score; best = [x, y, z]; }
  };
  for (let v = 0; v < m.vertices; v++) consider(m.pos[v * 3], m.pos[v * 3 + 1], m.pos[v * 3 + 2]);
  const s = view.stock;
  if (s && $("show-stock").checked) {
    for (let j = 0; j < s.spec.ny; j++)
      for (let i = 0; i < s.spec.nx; i++)
        consider(s.spec.min[0] + (i + 0.5) * s.size[0], s.spec.min[1] + (j + 0.5) * s.size[1], s.heights[j * s.spec.nx + i]);
  }
  return best;
}

// ---------------------------------------------------------------- camera

function bounds() {
  const m = view.moves, s = view.stock;
  if (m.bounds) return m.bounds;
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (let v = 0; v < m.vertices; v++)
    for (let i = 0; i < 3; i++) {
      const c = m.pos[v * 3 + i];
      if (c < lo[i]) lo[i] = c;
      if (c > hi[i]) hi[i] = c;
    }
  if (s) {
    const sp = s.spec;
    [[sp.min[0], sp.min[1], sp.bottom], [sp.max[0], sp.max[1], sp.top]].forEach((p) => p.forEach((c, i) => {
      lo[i] = Math.min(lo[i], c); hi[i] = Math.max(hi[i], c);
    }));
  }
  m.bounds = isFinite(lo[0]) ? [lo, hi] : [[-10, -10, -10], [10, 10, 10]];
  return m.bounds;
}

const PRESETS = {
  top: [-Math.PI / 2, Math.PI / 2 - 1e-4],
  front: [-Math.PI / 2, 0],
  side: [0, 0],
  iso: [-Math.PI / 4, Math.atan(1 / Math.SQRT2)],
};

function preset(name) {
  const [lo, hi] = bounds();
  const target = [0, 1, 2].map((i) => (lo[i] + hi[i]) / 2);
  const radius = Math.max(1e-3, Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) / 2);
  const [yaw, pitch] = PRESETS[name] || PRESETS.iso;
  view.camera = { target, distance: radius / Math.sin(0.35) * 1.05, yaw, pitch };
  redraw();
}

function wireCamera() {
  const canvas = $("gl");
  let drag = null;
  canvas.addEventListener("contextmenu", (e) => e.preventDefault());
  canvas.addEventListener("pointerdown", (e) => {
    drag = { x: e.clientX, y: e.clientY, moved: false, pan: e.button === 2 || e.shiftKey || e.button === 1 };
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener("pointermove", (e) => {
    if (!drag || !view.camera) return;
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    if (Math.abs(dx) + Math.abs(dy) > 2) drag.moved = true;
    drag.x = e.clientX; drag.y = e.clientY;
    const c = view.camera;
    if (drag.pan) {
      const scale = c.distance * 0.0015;
      const right = [-Math.sin(c.yaw), Math.cos(c.yaw), 0];
      const up = [-Math.sin(c.pitch) * Math.cos(c.yaw), -Math.sin(c.pitch) * Math.sin(c.yaw), Math.cos(c.pitch)];
      for (let i = 0; i < 3; i++) c.target[i] += (-dx * right[i] + dy * up[i]) * scale;
    } else {
      c.yaw -= dx * 0.008;
      c.pitch = Math.max(-Math.PI / 2 + 1e-4, Math.min(Math.PI / 2 - 1e-4, c.pitch + dy * 0.008));
    }
    redraw();
  });
  canvas.addEventListener("pointerup", (e) => {
    const wasClick = drag && !drag.moved;
    drag = null;
    if (!wasClick || !view.moves) return;
    const rect = canvas.getBoundingClientRect();
    const x = e.clientX - rect.left, y = e.clientY - rect.top;
    if (view.rulerOn) return rulerPick(x, y);
    const k = pickMove(x, y);
    if (k >= 0) selectMove(k);
  });
  canvas.addEventListener("wheel", (e) => {
    e.preventDefault();
    if (view.camera) { view.camera.distance *= Math.exp(e.deltaY * 0.001); redraw(); }
  }, { passive: false });
}

function rulerPick(x, y) {
  const p = pickPoint(x, y);
  if (!p) return;
  if (!view.ruler || view.ruler.length === 2) view.ruler = [];
  view.ruler.push(p);
  const f = (q) => `X${q[0].toFixed(3)} Y${q[1].toFixed(3)} Z${q[2].toFixed(3)}`;
  if (view.ruler.length === 2) {
    const [a, b] = view.ruler;
    const d = [0, 1, 2].map((i) => b[i] - a[i]);
    $("readout").textContent = `ruler: ${Math.hypot(...d).toFixed(3)} mm  (dX ${d[0].toFixed(3)} dY ${d[1].toFixed(3)} dZ ${d[2].toFixed(3)})\nfrom ${f(a)}\nto   ${f(b)}`;
  } else {
    $("readout").textContent = `ruler: from ${f(p)}; pick the second point`;
  }
  redraw();
}

// ---------------------------------------------------------------- facts

function showFacts(h) {
  const m = view.moves;
  const rows = [];
  if (m && m.n) {
    const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    for (let k = 0; k < m.n; k++) {
      if (m.kind[k] === KIND_RAPID) continue;
      for (let v = m.first[k]; v < m.first[k + 1]; v++)
        for (let i = 0; i < 3; i++) { lo[i] = Math.min(lo[i], m.pos[v * 3 + i]); hi[i] = Math.max(hi[i], m.pos[v * 3 + i]); }
    }
    if (isFinite(lo[0]))
      rows.push(["cut size", `X ${(hi[0] - lo[0]).toFixed(3)}  Y ${(hi[1] - lo[1]).toFixed(3)}  Z ${(hi[2] - lo[2]).toFixed(3)} mm`],
        ["cut from", `X ${lo[0].toFixed(3)} Y ${lo[1].toFixed(3)} Z ${lo[2].toFixed(3)}`], ["cut to", `X ${hi[0].toFixed(3)} Y ${hi[1].toFixed(3)} Z ${hi[2].toFixed(3)}`]);
  }
  if (h.time_s !== undefined) rows.push(["run time", `${clock(h.time_s)} (${h.time_basis})`]);
  if (h.figures) rows.push(["cut / rapid", `${h.figures.cut_mm.toFixed(1)} mm / ${h.figures.rapid_mm.toFixed(1)} mm`]);
  const figuresByTool = new Map((h.figures ? h.figures.tools : []).map((t) => [t.tool, t]));
  (h.tools || []).forEach((t, i) => {
    const f = figuresByTool.get(t.number);
    const swatch = `<span class="swatch" style="background:rgb(${PALETTE[i % 8].map((c) => Math.round(c * 255)).join(",")})"></span>`;
    rows.push([`${swatch}tool ${t.number}`, `${t.profile} &#8960;${(t.radius * 2).toFixed(3)} mm` + (f ? `, cut ${f.cut_mm.toFixed(1)} mm` : "")]);
  });
  $("figures").innerHTML = "<h3>figures</h3><table>" + rows.map(([a, b]) => `<tr><td>${a}</td><td>${b}</td></tr>`).join("") + "</table>";
  const list = $("diagnostics");
  list.innerHTML = "<h3>diagnostics</h3>";
  sourcePane.marks = new Map();
  view.warnLines = new Map();
  for (const d of h.diagnostics || []) {
    const row = document.createElement("div");
    row.className = `diagnostic ${d.severity}`;
    const place = d.line ? `${h.files[d.file] || ""}:${d.line}: ` : "";
    row.textContent = `${place}${d.severity}: ${d.message}`;
    row.title = d.rendered;
    if (d.line && d.file === 0) {
      row.addEventListener("click", () => { selectLine(d.line); history.replaceState(null, "", `#L${d.line}`); });
      if (sourcePane.marks.get(d.line) !== "error") sourcePane.marks.set(d.line, d.severity === "note" ? undefined : d.severity);
      if (m && d.severity !== "note") {
        const k = findLine(d.line);
        if (k >= 0) view.warnLines.set(d.line, k);
      }
    }
    list.appendChild(row);
  }
  if (!(h.diagnostics || []).length) list.insertAdjacentHTML("beforeend", "<div>none</div>");
  $("notes").innerHTML = "<h3>drawn simplified</h3>" + (h.notes || []).map((n) => `<div>${escapeHtml(n)}</div>`).join("");
}

function findLine(n) {
  const m = view.moves;
  for (let k = 0; k < m.n; k++) if (m.file[k] === 0 && m.line[k] === n) return k;
  return -1;
}

function escapeHtml(text) {
  return text.replace(/[&<>"]/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", "\"": "&quot;" })[c]);
}

// ---------------------------------------------------------------- loading

async function fetchPayload() {
  const embedded = $("ger-data");
  if (embedded) return embedded.textContent;
  const response = await fetch("scene", { cache: "no-store" });
  return response.text();
}

// A scene in: drawn, or (a program with errors) its errors shown over the
// last good picture.
async function load(payload, version) {
  const { header, binary } = unpack(await inflate(payload));
  view.last = { payload, version };
  sourcePane.set(header.source.text);
  $("source-title").textContent = header.source.name;
  const failed = header.moves === undefined;
  if (failed) {
    const errors = (header.diagnostics || []).filter((d) => d.severity === "error");
    $("banner").textContent = errors.map((d) => d.rendered).join("\n") || "the program has errors";
    // The last good picture's figures and notes stay with it.
    showFacts(view.header ? { ...view.header, files: header.files, diagnostics: header.diagnostics } : header);
    sourcePane.render();
    const first = errors.find((d) => d.file === 0 && d.line);
    if (first) sourcePane.reveal(first.line);
    body.dataset.gerVersion = String(version);
    body.dataset.gerState = "error";
    redraw();
    return;
  }
  $("banner").textContent = "";
  outputPane.set(header.output);
  const moves = decodeMoves(header.moves, binary);
  const stock = header.stock ? decodeStock(header.stock, binary, header) : null;
  const keepCamera = view.camera !== null;
  view.header = header; view.moves = moves; view.stock = stock;
  // The clock's sum of rounded steps may pass the run time by a hair.
  view.total = Math.max(header.time_s || 0, moves.n ? moves.tEnd[moves.n - 1] : 0);
  uploadPath(moves);
  if (stock) uploadStockMesh(stock);
  if (!keepCamera) preset("iso");
  showFacts(header);
  body.dataset.gerMoves = String(moves.n);
  body.dataset.gerTimeS = String(header.time_s);
  applyHash(keepCamera);
  body.dataset.gerVersion = String(version);
  draw();
  // The time from navigation to the first picture (benches/view.rs).
  if (window.gerReadyMs === undefined) window.gerReadyMs = performance.now();
  body.dataset.gerState = "ready";
}

function applyHash(keepTime) {
  const hash = decodeURIComponent(location.hash.slice(1));
  let match;
  if ((match = /^L(\d+)$/.exec(hash))) {
    if (!keepTime) setTime(view.total);
    selectLine(Number(match[1]));
  } else if ((match = /^t=([0-9.]+)$/.exec(hash))) {
    setTime(Number(match[1]));
  } else if (keepTime && hash !== "end") {
    setTime(view.time);
  } else {
    setTime(view.total);
  }
  if (!/^L\d+$/.test(hash) && view.selectedLine) selectLine(view.selectedLine);
}

// The server's version, asked again and again: a change is fetched and
// drawn in place (the camera stays).
async function follow(version) {
  for (;;) {
    try {
      const response = await fetch(`version?after=${version}`, { cache: "no-store" });
      const next = Number(await response.text());
      if (next !== version) {
        version = next;
        await load(await fetchPayload(), version);
      }
    } catch (e) {
      $("status").textContent = "server gone";
      await new Promise((r) => setTimeout(r, 1000));
    }
  }
}

function wireControls() {
  document.querySelectorAll("[data-preset]").forEach((b) => b.addEventListener("click", () => preset(b.dataset.preset)));
  $("play").addEventListener("click", () => {
    view.playing = !view.playing;
    $("play").textContent = view.playing ? "Pause" : "Play";
    if (view.playing) {
      if (view.time >= view.total) setTime(0);
      view.lastFrame = 0;
      requestAnimationFrame(tick);
    }
  });
  $("step").addEventListener("click", () => stepMove(1));
  $("step-back").addEventListener("click", () => stepMove(-1));
  $("scrub").addEventListener("input", () => setTime(Number($("scrub").value) / 1000 * view.total));
  $("show-rapids").addEventListener("change", redraw);
  $("show-stock").addEventListener("change", redraw);
  $("ruler").addEventListener("click", () => {
    view.rulerOn = !view.rulerOn;
    $("ruler").classList.toggle("on", view.rulerOn);
    view.ruler = null;
    $("readout").textContent = view.rulerOn ? "ruler: pick the first point" : "";
    redraw();
  });
  window.addEventListener("hashchange", () => { if (view.moves) applyHash(true); });
  window.addEventListener("resize", redraw);
  document.addEventListener("keydown", (e) => {
    if (e.key === " " && e.target === body) { e.preventDefault(); $("play").click(); }
  });
}

async function main() {
  if (!gl) {
    $("banner").textContent = "this browser has no WebGL2: the part cannot be drawn";
    body.dataset.gerState = "error";
    return;
  }
  // A context the browser takes away (a busy or reset GPU) is asked back
  // and the scene uploaded again.
  $("gl").addEventListener("webglcontextlost", (e) => {
    e.preventDefault();
    body.dataset.gerState = "loading";
  });
  $("gl").addEventListener("webglcontextrestored", () => {
    glState = setupGl();
    if (view.last) load(view.last.payload, view.last.version);
  });
  glState = setupGl();
  wireCamera();
  wireControls();
  const served = !$("ger-data");
  let version = 1;
  if (served) version = Number(await (await fetch("version", { cache: "no-store" })).text());
  await load(await fetchPayload(), version);
  if (served) follow(version);
}

main().catch((e) => {
  $("banner").textContent = `the page failed: ${e && e.stack ? e.stack : e}`;
  body.dataset.gerState = "error";
});

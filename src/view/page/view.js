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

// Every checkpoint's depths in full (16-bit fractions of depth_mm).
function decodeStock(spec, binary) {
  const cells = spec.nx * spec.ny;
  const r = new Reader(binary, spec.offset);
  const checkpoints = [];
  let before = new Uint16Array(cells);
  for (let c = 0; c < spec.checkpoints.length; c++) {
    const now = before.slice();
    let k = 0;
    while (k < cells) {
      k += r.varint();
      const changed = r.varint();
      for (let e = k + changed; k < e; k++) now[k] += r.zigzag();
    }
    checkpoints.push(now);
    before = now;
  }
  const area = new Float64Array(cells);
  const cell = spec.exact.cell_mm;
  for (let j = 0; j < spec.ny; j++) {
    const h = Math.min(spec.block, spec.exact.ny - j * spec.block);
    for (let i = 0; i < spec.nx; i++) {
      const w = Math.min(spec.block, spec.exact.nx - i * spec.block);
      area[j * spec.nx + i] = w * h * cell * cell;
    }
  }
  const size = [
    (spec.max[0] - spec.min[0]) / spec.exact.nx * spec.block,
    (spec.max[1] - spec.min[1]) / spec.exact.ny * spec.block,
  ];
  return { spec, checkpoints, area, size, heights: new Float32Array(cells), shownAt: null };
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
uniform mat4 mvp;
uniform vec2 origin, cell;
uniform int nx;
out vec3 normal;
out float depth;
uniform float top, fullDepth;
float h(int i, int j) {
  ivec2 s = textureSize(heights, 0);
  return texelFetch(heights, ivec2(clamp(i, 0, s.x - 1), clamp(j, 0, s.y - 1)), 0).r;
}
void main() {
  int i = gl_VertexID % nx, j = gl_VertexID / nx;
  float z = h(i, j);
  normal = normalize(vec3((h(i - 1, j) - h(i + 1, j)) / (2.0 * cell.x),
                          (h(i, j - 1) - h(i, j + 1)) / (2.0 * cell.y), 1.0));
  depth = (top - z) / max(fullDepth, 1e-6);
  gl_Position = mvp * vec4(origin + (vec2(i, j) + 0.5) * cell, z, 1.0);
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
    heightTex: gl.createTexture(), plainVao: gl.createVertexArray(), plainBuf: gl.createBuffer(),
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
      index.set([a, a + 1, a + nx, a + 1, a + nx + 1, a + nx], k);
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
  const key = `${c}`;
  let from;
  if (s.shownAt && s.shownAt.key === key && s.shownAt.done <= done && s.shownAt.partial === 0) {
    from = s.shownAt.done;
  } else {
    const depths = c >= 0 ? s.checkpoints[c] : null;
    const scale = spec.depth_mm / 65535;
    for (let k = 0; k < s.heights.length; k++) s.heights[k] = spec.top - (depths ? depths[k] * scale : 0);
    from = c >= 0 ? spec.checkpoints[c].moves : 0;
  }
  for (let k = from; k < done; k++) sweepMove(k, 1);
  const partial = done < m.n && fraction > 0 && fraction < 1 ? fraction : 0;
  s.shownAt = { key, done, partial };
  if (partial) {
    sweepMove(done, partial);
    s.shownAt = null;
  }
  let removed = 0;
  for (let k = 0; k < s.heights.length; k++) removed += Math.max(0, spec.top - s.heights[k]) * s.area[k];
  return removed;
}

// Lower the shown cells the cutter reaches along move k (its first
// `fraction`): the lowest of the cutter's underside over each cell centre,
// at the stretch's ends and its closest point.
function sweepMove(k, fraction) {
  const m = view.moves, s = view.stock, spec = s.spec;
  const cutter = view.header.tools[m.tool[k]];
  if (!cutter) return;
  const r = cutter.radius;
  let a = m.first[k], b = m.first[k + 1];
  const pairs = (b - a) / 2;
  const upto = fraction >= 1 ? pairs : pairs * fraction;
  for (let p = 0; p < Math.ceil(upto); p++) {
    const v = (a + p * 2) * 3, w = v + 3;
    const part = Math.min(1, upto - p);
    const x0 = m.pos[v], y0 = m.pos[v + 1], z0 = m.pos[v + 2];
    const x1 = x0 + (m.pos[w] - x0) * part, y1 = y0 + (m.pos[w + 1] - y0) * part, z1 = z0 + (m.pos[w + 2] - z0) * part;
    sweepLine(spec, s, cutter, r, x0, y0, z0, x1, y1, z1);
  }
}

// The cutter's underside above its tip at distance d (d <= radius).
function lift(profile, r, rise, d) {
  if (profile === 1) return r - Math.sqrt(Math.max(0, r * r - d * d));
  if (profile === 2) return rise * d;
  return 0;
}

function sweepLine(spec, s, cutter, r, x0, y0, z0, x1, y1, z1) {
  const [cw, ch] = s.size;
  const profile = cutter.profile === "ball" ? 1 : cutter.profile === "cone" ? 2 : 0, rise = cutter.rise;
  const dx = x1 - x0, dy = y1 - y0, dz = z1 - z0, len2 = dx * dx + dy * dy;
  const i0 = Math.max(0, Math.floor((Math.min(x0, x1) - r - spec.min[0]) / cw - 0.5));
  const i1 = Math.min(spec.nx - 1, Math.ceil((Math.max(x0, x1) + r - spec.min[0]) / cw - 0.5));
  const j0 = Math.max(0, Math.floor((Math.min(y0, y1) - r - spec.min[1]) / ch - 0.5));
  const j1 = Math.min(spec.ny - 1, Math.ceil((Math.max(y0, y1) + r - spec.min[1]) / ch - 0.5));
  if (Math.min(z0, z1) >= spec.top) return;
  const heights = s.heights, r2 = r * r, nx = spec.nx;
  for (let j = j0; j <= j1; j++) {
    const py = spec.min[1] + (j + 0.5) * ch;
    for (let i = i0; i <= i1; i++) {
      const px = spec.min[0] + (i + 0.5) * cw;
      // The closest point of the line to the cell's centre, and the
      // stretch within the radius around it: the lowest is at one of them.
      const tc = len2 > 0 ? Math.min(1, Math.max(0, ((px - x0) * dx + (py - y0) * dy) / len2)) : 0;
      const cx = x0 + dx * tc - px, cy = y0 + dy * tc - py, dc2 = cx * cx + cy * cy;
      if (dc2 > r2) continue;
      const half = len2 > 0 ? Math.sqrt((r2 - dc2) / len2) : 0;
      let best = Infinity;
      for (let n = 0; n < 3; n++) {
        const t = n === 0 ? tc : n === 1 ? Math.max(0, tc - half) : Math.min(1, tc + half);
        const qx = x0 + dx * t - px, qy = y0 + dy * t - py, d2 = qx * qx + qy * qy;
        if (d2 <= r2 * (1 + 1e-9)) {
          const z = z0 + dz * t + (profile === 0 ? 0 : lift(profile, r, rise, Math.sqrt(Math.min(d2, r2))));
          if (z < best) best = z;
        }
      }
      const k = j * nx + i;
      if (best < heights[k]) heights[k] = best;
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
  if (!isFinite(lo[0])) return [[-10, -10, -10], [10, 10, 10]];
  return [lo, hi];
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
    showFacts(header);
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
  const stock = header.stock ? decodeStock(header.stock, binary) : null;
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

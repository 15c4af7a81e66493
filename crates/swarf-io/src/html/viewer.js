// swarf's report viewer: WebGL2, no third-party code. Reads the JSON in #data (meshes and
// lines quantised to u16 over the scene's box, zlib-compressed, base64) and draws them with
// an orbit camera, a section plane and clickable markers tied to the defect list's rows.
(function () {
  'use strict';
  const data = JSON.parse(document.getElementById('data').textContent);
  const canvas = document.getElementById('view');
  const lineBox = document.getElementById('line');
  const rowsEl = Array.from(document.querySelectorAll('#defects tr.row'));
  const sc = data.scene;
  const lo = sc.min, hi = sc.max;
  const span = [0, 1, 2].map(k => Math.max(hi[k] - lo[k], 1e-9));
  const radius = 0.5 * Math.hypot(span[0], span[1], span[2]);
  let selected = -1;

  function showRow(i) {
    selected = i;
    rowsEl.forEach((r, k) => r.classList.toggle('sel', k === i));
    const ref = data.rows[i];
    if (!ref) { lineBox.textContent = 'no program line (stock no move cut)'; return; }
    const src = data.source.find(s => s.file === ref.file && s.line === ref.line);
    lineBox.textContent = ref.file + ':' + ref.line + ': ' + (src ? src.text : '');
    if (typeof draw === 'function') draw();
  }
  rowsEl.forEach((r, k) => r.addEventListener('click', () => showRow(k)));

  const gl = canvas.getContext('webgl2', { antialias: true, preserveDrawingBuffer: true });
  let draw = null;
  if (!gl) {
    lineBox.textContent = 'This browser has no WebGL2: the 3-D view is not available.';
    return;
  }

  function b64(s) {
    const bin = atob(s);
    const u = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; i++) u[i] = bin.charCodeAt(i);
    return u;
  }
  async function inflate(s) {
    const stream = new Blob([b64(s)]).stream().pipeThrough(new DecompressionStream('deflate'));
    return new Response(stream).arrayBuffer();
  }

  const vs = `#version 300 es
    in vec3 aPos; in vec3 aCol;
    uniform mat4 uMVP; uniform vec3 uLo; uniform vec3 uSpan; uniform float uPointSize;
    out vec3 vCol; out vec3 vWorld;
    void main() {
      vWorld = uLo + aPos * uSpan;
      vCol = aCol;
      gl_Position = uMVP * vec4(vWorld, 1.0);
      gl_PointSize = uPointSize;
    }`;
  const fs = `#version 300 es
    precision highp float;
    in vec3 vCol; in vec3 vWorld;
    uniform int uAxis; uniform float uCut; uniform int uLit; uniform vec3 uLight;
    out vec4 outColor;
    void main() {
      if (uAxis >= 0 && vWorld[uAxis] > uCut) discard;
      vec3 c = vCol;
      if (uLit == 1) {
        vec3 n = normalize(cross(dFdx(vWorld), dFdy(vWorld)));
        c *= 0.35 + 0.65 * abs(dot(n, uLight));
      }
      outColor = vec4(c, 1.0);
    }`;
  function shader(type, src) {
    const s = gl.createShader(type);
    gl.shaderSource(s, src);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
    return s;
  }
  const prog = gl.createProgram();
  gl.attachShader(prog, shader(gl.VERTEX_SHADER, vs));
  gl.attachShader(prog, shader(gl.FRAGMENT_SHADER, fs));
  gl.linkProgram(prog);
  if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(prog));
  const U = n => gl.getUniformLocation(prog, n);
  const loc = { pos: gl.getAttribLocation(prog, 'aPos'), col: gl.getAttribLocation(prog, 'aCol') };

  function buffer(target, bytes) {
    const b = gl.createBuffer();
    gl.bindBuffer(target, b);
    gl.bufferData(target, bytes, gl.STATIC_DRAW);
    return b;
  }
  // A vertex array: positions (u16 normalised, or f32 in [0, 1]) and colours (u8 normalised,
  // or one constant colour).
  function vao(pos, posType, col, constCol) {
    const v = gl.createVertexArray();
    gl.bindVertexArray(v);
    gl.bindBuffer(gl.ARRAY_BUFFER, buffer(gl.ARRAY_BUFFER, pos));
    gl.enableVertexAttribArray(loc.pos);
    gl.vertexAttribPointer(loc.pos, 3, posType, posType !== gl.FLOAT, 0, 0);
    if (col) {
      gl.bindBuffer(gl.ARRAY_BUFFER, buffer(gl.ARRAY_BUFFER, col));
      gl.enableVertexAttribArray(loc.col);
      gl.vertexAttribPointer(loc.col, 3, gl.UNSIGNED_BYTE, true, 0, 0);
    } else {
      gl.disableVertexAttribArray(loc.col);
      gl.vertexAttrib3f(loc.col, constCol[0], constCol[1], constCol[2]);
    }
    return v;
  }

  const meshes = [], lines = [];
  let markers = null;
  const cam = { yaw: -0.6, pitch: 0.6, dist: 2.6 * radius, pan: [0, 0, 0] };
  const centre = [0, 1, 2].map(k => lo[k] + 0.5 * span[k]);

  function mul(a, b) {
    const o = new Float32Array(16);
    for (let i = 0; i < 4; i++)
      for (let j = 0; j < 4; j++) {
        let s = 0;
        for (let k = 0; k < 4; k++) s += a[k * 4 + j] * b[i * 4 + k];
        o[i * 4 + j] = s;
      }
    return o;
  }
  function view() {
    const cp = Math.cos(cam.pitch), sp = Math.sin(cam.pitch);
    const cy = Math.cos(cam.yaw), sy = Math.sin(cam.yaw);
    const dir = [cp * cy, cp * sy, sp]; // from the target to the eye; Z up
    const target = [0, 1, 2].map(k => centre[k] + cam.pan[k]);
    const eye = [0, 1, 2].map(k => target[k] + cam.dist * dir[k]);
    const f = dir.map(x => -x);
    const up = [0, 0, 1];
    let s = [f[1] * up[2] - f[2] * up[1], f[2] * up[0] - f[0] * up[2], f[0] * up[1] - f[1] * up[0]];
    const sl = Math.hypot(s[0], s[1], s[2]) || 1;
    s = s.map(x => x / sl);
    const u = [s[1] * f[2] - s[2] * f[1], s[2] * f[0] - s[0] * f[2], s[0] * f[1] - s[1] * f[0]];
    const m = new Float32Array([
      s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0, s[2], u[2], -f[2], 0,
      -(s[0] * eye[0] + s[1] * eye[1] + s[2] * eye[2]),
      -(u[0] * eye[0] + u[1] * eye[1] + u[2] * eye[2]),
      f[0] * eye[0] + f[1] * eye[1] + f[2] * eye[2], 1]);
    const aspect = canvas.width / Math.max(canvas.height, 1);
    const near = Math.max(cam.dist - 2 * radius, cam.dist * 0.01), far = cam.dist + 2 * radius;
    const t = 1 / Math.tan(0.4);
    const p = new Float32Array([t / aspect, 0, 0, 0, 0, t, 0, 0, 0, 0, (far + near) / (near - far), -1,
      0, 0, 2 * far * near / (near - far), 0]);
    return { mvp: mul(p, m), dir, s, u };
  }

  const axisEl = document.getElementById('axis'), cutEl = document.getElementById('cut');
  const pathEl = document.getElementById('showpath');
  draw = function () {
    const w = canvas.clientWidth, h = canvas.clientHeight;
    if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }
    gl.viewport(0, 0, canvas.width, canvas.height);
    gl.clearColor(1, 1, 1, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    gl.useProgram(prog);
    const v = view();
    gl.uniformMatrix4fv(U('uMVP'), false, v.mvp);
    gl.uniform3fv(U('uLo'), lo);
    gl.uniform3fv(U('uSpan'), span);
    gl.uniform3fv(U('uLight'), v.dir);
    const axis = parseInt(axisEl.value, 10);
    gl.uniform1i(U('uAxis'), axis);
    gl.uniform1f(U('uCut'), axis >= 0 ? lo[axis] + span[axis] * cutEl.value / 1000 + 1e-9 : 0);
    gl.uniform1f(U('uPointSize'), 1);
    gl.uniform1i(U('uLit'), 1);
    for (const m of meshes) {
      gl.bindVertexArray(m.vao);
      gl.drawElements(gl.TRIANGLES, m.count, gl.UNSIGNED_INT, 0);
    }
    gl.uniform1i(U('uLit'), 0);
    if (pathEl.checked)
      for (const l of lines) {
        gl.bindVertexArray(l.vao);
        // A constant attribute is global state, not the vertex array's: set it per draw.
        gl.vertexAttrib3f(loc.col, l.colour[0], l.colour[1], l.colour[2]);
        gl.drawArrays(gl.LINES, 0, l.count);
      }
    if (markers) {
      gl.disable(gl.DEPTH_TEST);
      gl.uniform1i(U('uAxis'), -1);
      gl.bindVertexArray(markers.vao);
      gl.uniform1f(U('uPointSize'), 7);
      gl.drawArrays(gl.POINTS, 0, markers.count);
      if (selected >= 0) {
        const k = sc.markers.findIndex(m => m.row === selected);
        if (k >= 0) { gl.uniform1f(U('uPointSize'), 15); gl.drawArrays(gl.POINTS, k, 1); }
      }
    }
    gl.bindVertexArray(null);
  };

  // Mouse: rotate, pan, zoom, click to pick a marker.
  let drag = null;
  canvas.addEventListener('contextmenu', e => e.preventDefault());
  canvas.addEventListener('pointerdown', e => {
    drag = { x: e.clientX, y: e.clientY, pan: e.button === 2 || e.shiftKey, moved: 0 };
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener('pointermove', e => {
    if (!drag) return;
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    drag.x = e.clientX; drag.y = e.clientY; drag.moved += Math.abs(dx) + Math.abs(dy);
    if (drag.pan) {
      const v = view(), k = cam.dist / canvas.clientHeight;
      for (let i = 0; i < 3; i++) cam.pan[i] += (-dx * v.s[i] + dy * v.u[i]) * k;
    } else {
      cam.yaw -= dx * 0.01;
      cam.pitch = Math.max(-1.55, Math.min(1.55, cam.pitch + dy * 0.01));
    }
    draw();
  });
  canvas.addEventListener('pointerup', e => {
    if (drag && drag.moved < 4) pick(e);
    drag = null;
  });
  canvas.addEventListener('wheel', e => {
    e.preventDefault();
    cam.dist *= Math.exp(e.deltaY * 0.001);
    draw();
  }, { passive: false });
  function pick(e) {
    const r = canvas.getBoundingClientRect();
    const x = e.clientX - r.left, y = e.clientY - r.top;
    const m = view().mvp;
    let best = -1, bd = 144;
    sc.markers.forEach((mk, k) => {
      const p = mk.p;
      const cx = m[0] * p[0] + m[4] * p[1] + m[8] * p[2] + m[12];
      const cy = m[1] * p[0] + m[5] * p[1] + m[9] * p[2] + m[13];
      const cw = m[3] * p[0] + m[7] * p[1] + m[11] * p[2] + m[15];
      if (cw <= 0) return;
      const sx = (cx / cw * 0.5 + 0.5) * r.width, sy = (0.5 - cy / cw * 0.5) * r.height;
      const d = (sx - x) ** 2 + (sy - y) ** 2;
      if (d < bd) { bd = d; best = k; }
    });
    if (best >= 0) showRow(sc.markers[best].row);
  }
  axisEl.addEventListener('change', () => draw());
  cutEl.addEventListener('input', () => draw());
  pathEl.addEventListener('change', () => draw());
  document.getElementById('reset').addEventListener('click', () => {
    Object.assign(cam, { yaw: -0.6, pitch: 0.6, dist: 2.6 * radius, pan: [0, 0, 0] });
    draw();
  });
  window.addEventListener('resize', () => draw());

  (async function load() {
    for (const m of sc.meshes) {
      const [pos, col, idx] = await Promise.all([inflate(m.positions), inflate(m.colors), inflate(m.indices)]);
      const v = vao(new Uint16Array(pos), gl.UNSIGNED_SHORT, new Uint8Array(col));
      gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, buffer(gl.ELEMENT_ARRAY_BUFFER, new Uint32Array(idx)));
      gl.bindVertexArray(null);
      meshes.push({ vao: v, count: 3 * m.triangles });
    }
    for (const [key, colour] of [['feed', [0.1, 0.35, 0.9]], ['rapid', [0.9, 0.2, 0.1]]]) {
      const l = sc[key];
      if (l.segments > 0) {
        const pos = await inflate(l.positions);
        lines.push({ vao: vao(new Uint16Array(pos), gl.UNSIGNED_SHORT, null, colour), count: 2 * l.segments, colour });
        gl.bindVertexArray(null);
      }
    }
    if (sc.markers.length > 0) {
      const pos = new Float32Array(3 * sc.markers.length), col = new Uint8Array(3 * sc.markers.length);
      sc.markers.forEach((m, k) => {
        for (let i = 0; i < 3; i++) {
          pos[3 * k + i] = (m.p[i] - lo[i]) / span[i];
          col[3 * k + i] = Math.round(255 * m.c[i]);
        }
      });
      markers = { vao: vao(pos, gl.FLOAT, col), count: sc.markers.length };
      gl.bindVertexArray(null);
    }
    draw();
    document.body.dataset.viewer = 'ready';
  })();
})();

// render.js — the WebGL2 side: GPU buffers per primitive, one shading program (half-
// Lambert with a headlight for triangles, unlit lines), the ground grid, and picking by
// drawing ids into an offscreen framebuffer and reading one pixel.
const VERTEX = `#version 300 es
layout(location=0) in vec3 aPos; layout(location=1) in vec3 aNormal;
uniform mat4 uModelView, uProj; uniform mat3 uNormal;
out vec3 vNormal, vView;
void main() { vec4 p = uModelView * vec4(aPos, 1.0); vView = p.xyz; vNormal = uNormal * aNormal; gl_Position = uProj * p; }`;
const SHADE = `#version 300 es
precision highp float;
in vec3 vNormal, vView; uniform vec4 uColor; uniform int uLit; out vec4 outColor;
void main() {
  if (uLit == 0) { outColor = uColor; return; }
  // Headlight: the light sits at the eye; double-sided, so the normal's sign does not matter.
  float d = abs(dot(normalize(vNormal), normalize(-vView)));
  float h = 0.5 * d + 0.5;
  outColor = vec4(uColor.rgb * (0.15 + 0.85 * h * h), uColor.a);
}`;
const ID = `#version 300 es
precision highp float; uniform vec4 uColor; out vec4 outColor; void main() { outColor = uColor; }`;
const MODES = [0, 1, 2, 3, 4]; // glTF's modes are WebGL's: points, lines, loop, strip, triangles
const BACKGROUND = [0.80, 0.84, 0.89, 1];

function compile(gl, vs, fs) {
  const p = gl.createProgram();
  for (const [type, src] of [[gl.VERTEX_SHADER, vs], [gl.FRAGMENT_SHADER, fs]]) {
    const s = gl.createShader(type);
    gl.shaderSource(s, src); gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
    gl.attachShader(p, s);
  }
  gl.linkProgram(p);
  if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(p));
  const u = {};
  for (const name of ['uModelView', 'uProj', 'uNormal', 'uColor', 'uLit']) u[name] = gl.getUniformLocation(p, name);
  return { p, u };
}

function upload(gl, prim) {
  const vao = gl.createVertexArray();
  gl.bindVertexArray(vao);
  const attr = (loc, data) => {
    gl.bindBuffer(gl.ARRAY_BUFFER, gl.createBuffer());
    gl.bufferData(gl.ARRAY_BUFFER, data, gl.STATIC_DRAW);
    gl.enableVertexAttribArray(loc);
    gl.vertexAttribPointer(loc, 3, gl.FLOAT, false, 0, 0);
  };
  attr(0, prim.positions instanceof Float32Array ? prim.positions : new Float32Array(prim.positions));
  if (prim.normals) attr(1, prim.normals);
  let type = null, count = prim.positions.length / 3;
  if (prim.indices) {
    const idx = prim.indices instanceof Int8Array || prim.indices instanceof Int16Array ? new Uint32Array(prim.indices) : prim.indices;
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, gl.createBuffer());
    gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, idx, gl.STATIC_DRAW);
    type = idx instanceof Uint8Array ? gl.UNSIGNED_BYTE : idx instanceof Uint16Array ? gl.UNSIGNED_SHORT : gl.UNSIGNED_INT;
    count = idx.length;
  }
  gl.bindVertexArray(null);
  return { vao, type, count, mode: MODES[prim.mode] === undefined ? 4 : prim.mode, lit: prim.mode === 4 && !!prim.normals, color: prim.color };
}

// Whether WebGL2 runs on a software rasterizer (SwiftShader, llvmpipe): asked of a
// throwaway context, since a canvas keeps the attributes of its first one.
function softwareRenderer() {
  const gl = document.createElement('canvas').getContext('webgl2');
  const info = gl && gl.getExtension('WEBGL_debug_renderer_info');
  const name = info ? String(gl.getParameter(info.UNMASKED_RENDERER_WEBGL)) : '';
  // Let the throwaway context go now rather than at the page's end.
  const lose = gl && gl.getExtension('WEBGL_lose_context');
  if (lose) lose.loseContext();
  return /swiftshader|llvmpipe|software/i.test(name);
}

function createRenderer(canvas, asset) {
  // Multisampling doubles a software rasterizer's frame time (the chain of 100 plays at
  // 11-14 frames/s with it in headless Chromium's SwiftShader, 22-26 without); a GPU
  // keeps it.
  const gl = canvas.getContext('webgl2', { antialias: !softwareRenderer() });
  if (!gl) return null;
  const shade = compile(gl, VERTEX, SHADE), ids = compile(gl, VERTEX, ID);
  const meshes = asset.meshes.map(m => m.map(p => upload(gl, p)));
  // What is drawn: every node with a mesh, in node order (its index + 1 is its pick id).
  const drawn = asset.nodes.filter(n => n.mesh !== undefined && meshes[n.mesh]);
  let grid = null, pickFb = null, pickSize = [0, 0];

  function setGrid(lines, color) {
    grid = upload(gl, { mode: 1, positions: new Float32Array(lines), normals: null, indices: null, color });
  }
  function drawItem(prog, g, modelView, proj, color, lit) {
    gl.uniformMatrix4fv(prog.u.uModelView, false, modelView);
    gl.uniformMatrix4fv(prog.u.uProj, false, proj);
    gl.uniformMatrix3fv(prog.u.uNormal, false, m3normal(modelView));
    gl.uniform4fv(prog.u.uColor, color);
    gl.uniform1i(prog.u.uLit, lit ? 1 : 0);
    gl.bindVertexArray(g.vao);
    if (!g.lit) gl.vertexAttrib3f(1, 0, 0, 1);
    if (g.type !== null) gl.drawElements(g.mode, g.count, g.type, 0); else gl.drawArrays(g.mode, 0, g.count);
  }
  // Draws the nodes `visible` accepts; with `pick`, their ids into the pick framebuffer.
  function draw(view, proj, visible, pick) {
    const w = canvas.width, h = canvas.height, prog = pick ? ids : shade;
    gl.bindFramebuffer(gl.FRAMEBUFFER, pick ? pickFb : null);
    gl.viewport(0, 0, w, h);
    if (pick) gl.clearColor(0, 0, 0, 0); else gl.clearColor(...BACKGROUND);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    gl.useProgram(prog.p);
    // The grid first and without depth: lines lying in its plane (outlines at ground
    // level) are drawn over it instead of fighting it for depth.
    if (grid && !pick) { gl.depthMask(false); drawItem(prog, grid, view, proj, grid.color, false); gl.depthMask(true); }
    const late = [];
    for (const n of drawn) {
      if (!visible(n) || !n.world) continue;
      const mv = m4mul(view, n.world);
      for (const g of meshes[n.mesh]) {
        const id = n.index + 1, color = pick ? [(id & 255) / 255, ((id >> 8) & 255) / 255, ((id >> 16) & 255) / 255, 1] : g.color;
        if (!pick && g.color[3] < 1) late.push([g, mv]); else drawItem(prog, g, mv, proj, color, g.lit && !pick);
      }
    }
    // Translucent meshes last, blended, not writing depth.
    if (late.length) {
      gl.enable(gl.BLEND); gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA); gl.depthMask(false);
      for (const [g, mv] of late) drawItem(prog, g, mv, proj, g.color, g.lit);
      gl.disable(gl.BLEND); gl.depthMask(true);
    }
    gl.bindVertexArray(null);
  }
  // The node drawn at canvas pixel (x, y) from the top left, or null.
  function pickAt(x, y, view, proj, visible) {
    const w = canvas.width, h = canvas.height;
    if (!pickFb || pickSize[0] !== w || pickSize[1] !== h) {
      pickFb = gl.createFramebuffer();
      gl.bindFramebuffer(gl.FRAMEBUFFER, pickFb);
      const tex = gl.createRenderbuffer(), depth = gl.createRenderbuffer();
      gl.bindRenderbuffer(gl.RENDERBUFFER, tex); gl.renderbufferStorage(gl.RENDERBUFFER, gl.RGBA8, w, h);
      gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.RENDERBUFFER, tex);
      gl.bindRenderbuffer(gl.RENDERBUFFER, depth); gl.renderbufferStorage(gl.RENDERBUFFER, gl.DEPTH_COMPONENT24, w, h);
      gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, depth);
      pickSize = [w, h];
    }
    draw(view, proj, visible, true);
    // A few pixels around the pointer, the nearest id winning: lines are one pixel wide.
    const R = 3, x0 = Math.max(0, Math.floor(x) - R), y0 = Math.max(0, Math.floor(h - 1 - y) - R);
    const rw = Math.min(w - x0, 2 * R + 1), rh = Math.min(h - y0, 2 * R + 1), px = new Uint8Array(4 * rw * rh);
    if (rw > 0 && rh > 0) gl.readPixels(x0, y0, rw, rh, gl.RGBA, gl.UNSIGNED_BYTE, px);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    let best = 0, bestD = Infinity;
    for (let j = 0; j < rh; j++)
      for (let i = 0; i < rw; i++) {
        const k = 4 * (j * rw + i), id = px[k] + (px[k + 1] << 8) + (px[k + 2] << 16);
        const d = (x0 + i - Math.floor(x)) ** 2 + (y0 + j - Math.floor(h - 1 - y)) ** 2;
        if (id && d < bestD) { best = id; bestD = d; }
      }
    return best ? asset.nodes[best - 1] || null : null;
  }
  return { gl, draw, pickAt, setGrid, drawn, background: BACKGROUND };
}

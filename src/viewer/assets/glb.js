// glb.js — reads a glTF binary: chunks, accessors, the node tree, meshes, materials and
// the animation's samplers. Throws an Error saying what is wrong; draws nothing.
const COMPONENTS = { SCALAR: 1, VEC2: 2, VEC3: 3, VEC4: 4, MAT2: 4, MAT3: 9, MAT4: 16 };
const ARRAYS = { 5120: Int8Array, 5121: Uint8Array, 5122: Int16Array, 5123: Uint16Array, 5125: Uint32Array, 5126: Float32Array };

function readGlb(bytes) {
  const dv = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  if (bytes.length < 20 || dv.getUint32(0, true) !== 0x46546c67) throw new Error('not a glTF binary (no "glTF" header)');
  if (dv.getUint32(4, true) !== 2) throw new Error('glTF version ' + dv.getUint32(4, true) + ', not 2');
  let json = null, bin = new Uint8Array(0);
  for (let at = 12; at + 8 <= bytes.length;) {
    const len = dv.getUint32(at, true), type = dv.getUint32(at + 4, true), body = bytes.subarray(at + 8, at + 8 + len);
    if (type === 0x4e4f534a) json = JSON.parse(new TextDecoder().decode(body));
    else if (type === 0x004e4942) bin = body;
    at += 8 + len;
  }
  if (!json) throw new Error('the glTF binary has no JSON chunk');
  return buildAsset(json, bin);
}

// One accessor as a flat typed array (strides undone, copies made aligned).
function accessor(json, bin, index) {
  const a = (json.accessors || [])[index];
  if (!a) throw new Error('accessor ' + index + ' missing');
  const n = COMPONENTS[a.type], T = ARRAYS[a.componentType];
  if (!n || !T) throw new Error('accessor ' + index + ': unsupported type ' + a.type + '/' + a.componentType);
  const out = new T(a.count * n);
  if (a.bufferView === undefined) return out;
  const v = json.bufferViews[a.bufferView], size = T.BYTES_PER_ELEMENT;
  const start = (v.byteOffset || 0) + (a.byteOffset || 0), stride = v.byteStride || n * size;
  if (start + stride * (a.count - 1) + n * size > bin.length) throw new Error('accessor ' + index + ' runs past the binary chunk');
  // Tightly packed and aligned (what mbfx writes): one copy of the bytes.
  if (stride === n * size && (bin.byteOffset + start) % size === 0)
    return new T(bin.buffer.slice(bin.byteOffset + start, bin.byteOffset + start + a.count * n * size));
  const src = new DataView(bin.buffer, bin.byteOffset);
  const get = { 1: 'getInt8', 2: 'getInt16', 4: 'getUint32' };
  for (let i = 0; i < a.count; i++)
    for (let k = 0; k < n; k++) {
      const off = start + i * stride + k * size;
      out[i * n + k] = T === Float32Array ? src.getFloat32(off, true)
        : T === Uint8Array ? src.getUint8(off) : T === Uint16Array ? src.getUint16(off, true)
        : T === Uint32Array ? src.getUint32(off, true) : src[get[size]](off, true);
    }
  return out;
}

function buildAsset(json, bin) {
  const acc = i => accessor(json, bin, i);
  const materials = (json.materials || []).map(m =>
    ((m.pbrMetallicRoughness || {}).baseColorFactor || [1, 1, 1, 1]).slice());
  const meshes = (json.meshes || []).map(m => m.primitives.map(p => ({
    mode: p.mode === undefined ? 4 : p.mode,
    positions: acc(p.attributes.POSITION),
    normals: p.attributes.NORMAL !== undefined ? acc(p.attributes.NORMAL) : null,
    indices: p.indices !== undefined ? acc(p.indices) : null,
    color: p.material !== undefined ? materials[p.material] || [1, 1, 1, 1] : [0.8, 0.8, 0.8, 1],
  })));
  const nodes = (json.nodes || []).map((n, i) => {
    const extras = n.extras || {};
    return {
      index: i, name: n.name || 'node ' + i, viewName: extras.adams_view_name || null,
      role: (extras.mbfx && extras.mbfx.role) || null, mesh: n.mesh, children: n.children || [],
      matrix: n.matrix || null, parent: null,
      t: (n.translation || [0, 0, 0]).slice(), r: (n.rotation || [0, 0, 0, 1]).slice(), s: (n.scale || [1, 1, 1]).slice(),
    };
  });
  nodes.forEach(n => n.children.forEach(c => { if (nodes[c]) nodes[c].parent = n; }));
  const scene = (json.scenes || [])[json.scene || 0];
  const roots = scene ? scene.nodes : nodes.filter(n => !n.parent).map(n => n.index);
  nodes.forEach(n => { n.base = { t: n.t.slice(), r: n.r.slice(), s: n.s.slice() }; });
  const anim = (json.animations || [])[0];
  const channels = [];
  if (anim) for (const c of anim.channels) {
    const s = anim.samplers[c.sampler], node = nodes[c.target.node];
    if (!node || !['translation', 'rotation', 'scale'].includes(c.target.path)) continue;
    channels.push({ node, path: c.target.path, input: acc(s.input), output: acc(s.output),
      step: s.interpolation === 'STEP', cubic: s.interpolation === 'CUBICSPLINE', n: c.target.path === 'rotation' ? 4 : 3 });
  }
  // The key times of all channels (for frame-by-frame), each input accessor read once.
  const seen = new Set(), keys = [];
  if (anim) for (const c of anim.channels) {
    const s = anim.samplers[c.sampler];
    if (seen.has(s.input)) continue;
    seen.add(s.input);
    for (const t of acc(s.input)) keys.push(t);
  }
  keys.sort((a, b) => a - b);
  const times = keys.filter((t, i) => i === 0 || t > keys[i - 1]);
  return { nodes, roots: roots.map(i => nodes[i]).filter(Boolean), meshes, channels, times,
    duration: times.length ? times[times.length - 1] : 0, start: times.length ? Math.min(0, times[0]) : 0 };
}

// Sets every animated node's TRS at time t (clamped to each channel's keys).
function sampleAt(asset, t) {
  for (const c of asset.channels) {
    const inp = c.input, n = c.n, w = c.cubic ? 3 : 1, val = k => Array.from(c.output.subarray((k * w + (c.cubic ? 1 : 0)) * n, (k * w + (c.cubic ? 1 : 0)) * n + n));
    let v;
    if (t <= inp[0]) v = val(0);
    else if (t >= inp[inp.length - 1]) v = val(inp.length - 1);
    else {
      let lo = 0, hi = inp.length - 1;
      while (hi - lo > 1) { const mid = (lo + hi) >> 1; if (inp[mid] <= t) lo = mid; else hi = mid; }
      const u = (t - inp[lo]) / (inp[hi] - inp[lo]);
      v = c.step ? val(lo) : n === 4 ? slerp(val(lo), val(hi), u) : lerp(val(lo), val(hi), u);
    }
    c.node[c.path === 'translation' ? 't' : c.path === 'rotation' ? 'r' : 's'] = v;
  }
}

// World matrices of every node reachable from the scene's roots.
function worldMatrices(asset) {
  const visit = (n, parent) => {
    n.world = m4mul(parent, n.matrix || m4trs(n.t, n.r, n.s));
    for (const c of n.children) if (asset.nodes[c]) visit(asset.nodes[c], n.world);
  };
  for (const r of asset.roots) visit(r, m4());
}

// The role a node is drawn for: its own extras' or its nearest ancestor's.
function roleOf(n) { for (; n; n = n.parent) if (n.role) return n.role; return 'graphic'; }

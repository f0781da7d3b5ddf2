// viewer.js — the page's controller: reads the inlined .glb and columns, drives the
// camera (orbit, pan, zoom, fit), the clock (play, speed, loop, slider, frame keys), the
// role toggles, hover names and the test hooks of the URL fragment.
(function main() {
  const $ = id => document.getElementById(id), body = document.body;
  const hook = parseHash(location.hash);
  const state = { t: 0, playing: false, speed: 1, loop: true, show: { glyph: true, arrow: true } };
  const stats = { fps: null, frames: 0, ms: 0, drawMs: 0, readyMs: null };
  window.mbfxViewer = { state, stats };

  let asset = null, renderer = null;
  try {
    asset = readGlb(base64Bytes($('glb').textContent));
    renderer = createRenderer($('gl'), asset);
    if (!renderer) $('nogl').hidden = false;
  } catch (e) {
    $('error').textContent = 'The animation cannot be shown: ' + e.message;
    $('error').hidden = false;
  }
  body.dataset.webgl = renderer ? '1' : '0';
  if (hook.hide) for (const r of hook.hide.split(',')) if (r in state.show) state.show[r] = false;
  $('glyphs').checked = state.show.glyph; $('arrows').checked = state.show.arrow;
  const visible = n => { const r = roleOf(n); return !(r in state.show) || state.show[r]; };

  // The clock's range and keys: the animation's, or the chart's times without one.
  const data = JSON.parse($('chart-data').textContent);
  const chartTimes = ((data.columns || [])[0] || []).filter(t => t !== null);
  const keys = asset && asset.times.length ? asset.times : chartTimes;
  const t0 = keys.length ? Math.min(0, keys[0]) : 0, t1 = keys.length ? keys[keys.length - 1] : 0;
  const digits = Math.min(6, Math.max(0, 3 - Math.floor(Math.log10(Math.max(Math.abs(t1), Math.abs(t0), 1e-9)))));
  const slider = $('slider');
  slider.min = t0; slider.max = t1; slider.step = 'any';
  const chart = createChart($('chart'), $('columns'), data, t => { pause(); setTime(t); });
  // `#col=REQ1.F2,REQ1.F3`: the chart opens on these columns (a link to a curve).
  if (hook.col) {
    const want = hook.col.split(',');
    for (const o of $('columns').options) o.selected = want.includes(o.textContent);
    $('columns').dispatchEvent(new Event('change'));
  }

  let dirty = true;
  function setTime(t) {
    state.t = Math.min(Math.max(t, t0), t1);
    if (asset) sampleAt(asset, state.t);
    slider.value = state.t;
    $('time').textContent = state.t.toFixed(digits) + ' s';
    $('time').dataset.t = state.t;
    chart.setTime(state.t);
    dirty = true;
  }
  function play() {
    if (t1 <= t0) return;
    if (!state.loop && state.t >= t1) setTime(t0);
    state.playing = true; $('play').textContent = '❚❚'; $('play').title = 'pause (Space)';
  }
  function pause() { state.playing = false; $('play').textContent = '▶'; $('play').title = 'play (Space)'; }
  function advance(dt) {
    let t = state.t + dt;
    if (t > t1) {
      if (state.loop) t = t0 + (t - t0) % (t1 - t0);
      else { t = t1; pause(); }
    }
    setTime(t);
  }
  function stepKey(dir) {
    pause();
    const eps = 1e-9 * Math.max(1, Math.abs(t1));
    let k = null;
    if (dir > 0) k = keys.find(x => x > state.t + eps);
    else for (const x of keys) if (x < state.t - eps) k = x;
    if (k !== undefined && k !== null) setTime(k);
  }

  // Camera: orbit about a target, y up; fitted to what is drawn.
  const cam = { target: [0, 0, 0], dist: 1, yaw: 0.6, pitch: 0.45, fov: 0.8, radius: 1 };
  window.mbfxViewer.camera = cam;
  function eye() {
    const c = Math.cos(cam.pitch);
    return [cam.target[0] + cam.dist * c * Math.sin(cam.yaw), cam.target[1] + cam.dist * Math.sin(cam.pitch), cam.target[2] + cam.dist * c * Math.cos(cam.yaw)];
  }
  function matrices() {
    const cv = $('gl'), aspect = cv.width / Math.max(cv.height, 1);
    const near = Math.max(cam.dist * 0.01, 1e-6), far = cam.dist * 10 + cam.radius * 10;
    return { view: m4lookAt(eye(), cam.target, [0, 1, 0]), proj: m4perspective(cam.fov, aspect, near, far) };
  }
  function bounds() {
    const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    for (const n of renderer.drawn) {
      if (!visible(n) || !n.world) continue;
      for (const prim of asset.meshes[n.mesh]) {
        const p = prim.positions;
        for (let i = 0; i + 2 < p.length; i += 3) {
          const w = m4point(n.world, [p[i], p[i + 1], p[i + 2]]);
          for (let k = 0; k < 3; k++) { lo[k] = Math.min(lo[k], w[k]); hi[k] = Math.max(hi[k], w[k]); }
        }
      }
    }
    return lo[0] <= hi[0] ? { lo, hi } : { lo: [-0.5, -0.5, -0.5], hi: [0.5, 0.5, 0.5] };
  }
  function fit() {
    if (!renderer) return;
    worldMatrices(asset);
    const b = bounds(), cv = $('gl');
    cam.target = [0, 1, 2].map(k => (b.lo[k] + b.hi[k]) / 2);
    cam.radius = Math.max(Math.hypot(b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]) / 2, 1e-6);
    const half = Math.min(cam.fov / 2, Math.atan(Math.tan(cam.fov / 2) * cv.clientWidth / Math.max(cv.clientHeight, 1)));
    cam.dist = cam.radius / Math.sin(half);
    dirty = true;
  }
  // The ground grid: a round spacing near a tenth of the scene's size, at its lowest point.
  function makeGrid() {
    const b = bounds(), size = Math.hypot(b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]) || 1;
    const step = niceStep(size, 10), y = b.lo[1];
    const cx = Math.round((b.lo[0] + b.hi[0]) / 2 / step) * step, cz = Math.round((b.lo[2] + b.hi[2]) / 2 / step) * step;
    const n = Math.ceil(Math.max(b.hi[0] - b.lo[0], b.hi[2] - b.lo[2]) / 2 / step) + 3, lines = [];
    for (let i = -n; i <= n; i++) {
      lines.push(cx + i * step, y, cz - n * step, cx + i * step, y, cz + n * step);
      lines.push(cx - n * step, y, cz + i * step, cx + n * step, y, cz + i * step);
    }
    renderer.setGrid(lines, [0.62, 0.66, 0.72, 1]);
    $('gridstep').textContent = '· grid ' + Number(step.toPrecision(3)) + ' m';
    body.dataset.grid = step;
  }

  function render() {
    const cv = $('gl'), dpr = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(cv.clientWidth * dpr)), h = Math.max(1, Math.round(cv.clientHeight * dpr));
    if (cv.width !== w || cv.height !== h) { cv.width = w; cv.height = h; dirty = true; }
    if (!dirty) return false;
    worldMatrices(asset);
    const m = matrices();
    renderer.draw(m.view, m.proj, visible, false);
    dirty = false;
    return true;
  }
  let hoverAt = null;
  function hover() {
    if (!hoverAt) return;
    const [x, y] = hoverAt, dpr = window.devicePixelRatio || 1, m = matrices();
    hoverAt = null;
    const n = renderer.pickAt(x * dpr, y * dpr, m.view, m.proj, visible), tip = $('tip');
    tip.hidden = !n;
    if (n) { tip.textContent = describe(n); tip.style.left = (x + 14) + 'px'; tip.style.top = (y + 10) + 'px'; }
  }

  // Start: the fragment's time, the first frame, then the loop.
  setTime(hook.t !== undefined ? hook.t : t0);
  if (renderer) {
    worldMatrices(asset);
    const keep = state.t;
    if (asset.channels.length) { sampleAt(asset, t0); worldMatrices(asset); }
    makeGrid(); fit();
    setTime(keep);
  }
  if (hook.play || hook.fps) play();
  let last = null, fpsStart = null, drawSum = 0;
  function frame(now) {
    if (state.playing && last !== null) advance((now - last) / 1000 * state.speed);
    last = now;
    if (renderer) {
      const a = performance.now(), drew = render();
      drawSum += performance.now() - a;
      hover();
      if (drew && body.dataset.ready !== '1') firstFrame();
    }
    if (hook.fps) {
      if (fpsStart === null) { fpsStart = now; stats.frames = 0; drawSum = 0; }
      else stats.frames++;
      if (now - fpsStart >= 2000 && stats.fps === null) {
        stats.ms = now - fpsStart; stats.fps = stats.frames * 1000 / stats.ms; stats.drawMs = drawSum / Math.max(stats.frames, 1);
        body.dataset.fps = stats.fps.toFixed(1); body.dataset.drawMs = stats.drawMs.toFixed(2);
      }
    }
    requestAnimationFrame(frame);
  }
  function firstFrame() {
    if (hook.probe) {
      const n = asset.nodes.find(x => x.name === hook.probe);
      body.dataset.probe = n && n.world ? n.world.map(v => +v.toPrecision(7)).join(',') : 'none';
    }
    if (hook.pick) {
      const [x, y] = hook.pick.split(',').map(Number), m = matrices(), dpr = window.devicePixelRatio || 1;
      const n = renderer.pickAt(x * dpr, y * dpr, m.view, m.proj, visible);
      body.dataset.pick = n ? n.name : 'none';
      dirty = true; render();
    }
    const r = $('gl').getBoundingClientRect();
    body.dataset.pane = [r.left, r.top, r.width, r.height].map(Math.round).join(',');
    stats.readyMs = performance.now();
    body.dataset.ready = '1';
  }
  if (!renderer) { chart.draw(); body.dataset.ready = '1'; }
  requestAnimationFrame(frame);

  // Controls.
  $('play').onclick = () => { state.playing ? pause() : play(); $('play').blur(); };
  slider.oninput = () => { pause(); setTime(+slider.value); };
  $('speed').onchange = () => { state.speed = +$('speed').value; };
  $('loop').onchange = () => { state.loop = $('loop').checked; };
  $('fit').onclick = () => { fit(); $('fit').blur(); };
  $('glyphs').onchange = () => { state.show.glyph = $('glyphs').checked; dirty = true; };
  $('arrows').onchange = () => { state.show.arrow = $('arrows').checked; dirty = true; };
  window.addEventListener('resize', () => { dirty = true; chart.draw(); });
  document.addEventListener('keydown', e => {
    const tag = e.target.tagName, typing = tag === 'SELECT' || (tag === 'INPUT' && e.target.type === 'range');
    if (e.key === ' ' && tag !== 'SELECT') { e.preventDefault(); state.playing ? pause() : play(); }
    else if (e.key === 'ArrowRight' && !typing) { e.preventDefault(); stepKey(1); }
    else if (e.key === 'ArrowLeft' && !typing) { e.preventDefault(); stepKey(-1); }
    else if (e.key === 'f' && tag !== 'SELECT') fit();
  });
  const cv = $('gl');
  let drag = null;
  cv.addEventListener('contextmenu', e => e.preventDefault());
  cv.addEventListener('pointerdown', e => {
    drag = { x: e.clientX, y: e.clientY, pan: e.button === 2 || e.shiftKey };
    cv.setPointerCapture(e.pointerId); $('tip').hidden = true;
  });
  cv.addEventListener('pointerup', e => { drag = null; cv.releasePointerCapture(e.pointerId); });
  cv.addEventListener('pointermove', e => {
    const r = cv.getBoundingClientRect();
    if (!drag) { hoverAt = [e.clientX - r.left, e.clientY - r.top]; return; }
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    drag.x = e.clientX; drag.y = e.clientY;
    if (drag.pan) {
      const v = matrices().view, k = 2 * cam.dist * Math.tan(cam.fov / 2) / Math.max(cv.clientHeight, 1);
      for (let i = 0; i < 3; i++) cam.target[i] += (-v[i * 4] * dx + v[i * 4 + 1] * dy) * k;
    } else {
      cam.yaw -= dx * 0.008;
      cam.pitch = Math.min(1.55, Math.max(-1.55, cam.pitch + dy * 0.008));
    }
    dirty = true;
  });
  cv.addEventListener('pointerleave', () => { $('tip').hidden = true; });
  cv.addEventListener('wheel', e => { e.preventDefault(); cam.dist *= Math.exp(e.deltaY * 0.0015); dirty = true; }, { passive: false });
})();

// `#t=0.5&play&fps&probe=PART/2&pick=x,y&hide=glyph&col=REQ1.F2` as an object.
function parseHash(hash) {
  const out = {};
  for (const part of hash.replace(/^#/, '').split('&')) {
    if (!part) continue;
    const [k, v] = part.split('=');
    out[decodeURIComponent(k)] = v === undefined ? true : decodeURIComponent(v);
  }
  if (out.t !== undefined) { out.t = parseFloat(out.t); if (!isFinite(out.t)) delete out.t; }
  for (const k of ['probe', 'pick', 'hide', 'col']) if (out[k] === true) delete out[k];
  return out;
}
function base64Bytes(text) {
  const s = atob(text.replace(/\s+/g, '')), out = new Uint8Array(s.length);
  for (let i = 0; i < s.length; i++) out[i] = s.charCodeAt(i);
  return out;
}
// A node's name and adams_view_name, then its ancestors' up to the root.
function describe(n) {
  const parts = [];
  for (; n && n.name !== 'mbfx'; n = n.parent) parts.push(n.viewName ? n.name + ' “' + n.viewName + '”' : n.name);
  return parts.join(' — ');
}

// chart.js — the linked chart pane: the chosen columns against time on a 2D canvas, a
// cursor at the animation's time, and a click that moves the animation there.
const CURVE_COLORS = ['#1f5fa8', '#c2451e', '#2a8a3e', '#8a3ea8', '#a8871f', '#1f8a8a'];

// A round step (1, 2 or 5 × 10^k) giving about `n` ticks over `span`.
function niceStep(span, n) {
  const raw = span / n, p = Math.pow(10, Math.floor(Math.log10(raw))), f = raw / p;
  return (f < 1.5 ? 1 : f < 3.5 ? 2 : f < 7.5 ? 5 : 10) * p;
}
function tickLabel(v, step) {
  const d = Math.max(0, -Math.floor(Math.log10(step) + 1e-9));
  return Math.abs(v) < step * 1e-6 ? '0' : v.toFixed(Math.min(d, 10));
}

function createChart(canvas, select, data, onPick) {
  const names = data.names || [], cols = data.columns || [];
  const time = cols[0] || [];
  names.forEach((name, i) => {
    if (i === 0) return;
    const o = document.createElement('option');
    o.value = i; o.textContent = name; o.selected = i === 1;
    select.appendChild(o);
  });
  let cursor = 0, frame = null;
  const chosen = () => Array.from(select.selectedOptions).map(o => +o.value);

  // The curves are drawn once per choice and size into `base`; each time step only
  // copies it and draws the cursor (a playing animation moves the cursor every frame).
  const base = document.createElement('canvas');
  let baseKey = '';
  function drawBase(w, h, dpr) {
    base.width = canvas.width; base.height = canvas.height;
    const g = base.getContext('2d');
    g.setTransform(dpr, 0, 0, dpr, 0, 0);
    g.font = '11px sans-serif';
    const picked = chosen();
    frame = null;
    if (!time.length || !picked.length) {
      g.fillStyle = '#555';
      g.fillText(time.length ? 'choose a column on the left' : 'no columns recorded', 12, 20);
      return;
    }
    let t0 = Infinity, t1 = -Infinity, y0 = Infinity, y1 = -Infinity;
    for (const t of time) if (t !== null) { t0 = Math.min(t0, t); t1 = Math.max(t1, t); }
    for (const c of picked) for (const v of cols[c]) if (v !== null) { y0 = Math.min(y0, v); y1 = Math.max(y1, v); }
    if (!(t1 > t0)) t1 = t0 + 1;
    if (!(y1 >= y0)) { y0 = 0; y1 = 1; }
    if (y1 === y0) { y0 -= Math.abs(y0) * 0.5 || 0.5; y1 += Math.abs(y1) * 0.5 || 0.5; }
    // A column that varies only in its last digits (a constant with rounding noise) is
    // drawn on a span of a millionth of its size, not zoomed into the noise, so its
    // tick labels stay short enough to read.
    const least = 1e-6 * Math.max(Math.abs(y0), Math.abs(y1));
    if (y1 - y0 < least) { const mid = (y0 + y1) / 2; y0 = mid - least / 2; y1 = mid + least / 2; }
    const pad = (y1 - y0) * 0.05; y0 -= pad; y1 += pad;
    const L = 62, R = 10, T = 18, B = 20;
    const X = t => L + (t - t0) / (t1 - t0) * (w - L - R), Y = v => T + (y1 - v) / (y1 - y0) * (h - T - B);
    frame = { t0, t1, L, R, T, B, w, h, X };
    g.strokeStyle = '#d8dde3'; g.fillStyle = '#444'; g.lineWidth = 1;
    const ys = niceStep(y1 - y0, 4);
    for (let v = Math.ceil(y0 / ys) * ys; v <= y1; v += ys) {
      g.beginPath(); g.moveTo(L, Y(v)); g.lineTo(w - R, Y(v)); g.stroke();
      g.textAlign = 'right'; g.fillText(tickLabel(v, ys), L - 4, Y(v) + 4);
    }
    const xs = niceStep(t1 - t0, 6);
    g.textAlign = 'center';
    for (let t = Math.ceil(t0 / xs) * xs; t <= t1 + xs * 1e-9; t += xs) g.fillText(tickLabel(t, xs), X(t), h - 6);
    g.strokeStyle = '#888'; g.strokeRect(L, T, w - L - R, h - T - B);
    picked.forEach((c, k) => {
      const color = CURVE_COLORS[k % CURVE_COLORS.length];
      g.strokeStyle = color; g.lineWidth = 1.5; g.beginPath();
      let pen = false;
      for (let i = 0; i < time.length; i++) {
        const v = cols[c][i];
        if (v === null || time[i] === null) { pen = false; continue; }
        if (pen) g.lineTo(X(time[i]), Y(v)); else g.moveTo(X(time[i]), Y(v));
        pen = true;
      }
      g.stroke();
      g.fillStyle = color; g.textAlign = 'left';
      g.fillText(names[c], L + 6 + k * 150, T - 5);
    });
  }
  function draw() {
    const dpr = window.devicePixelRatio || 1, w = canvas.clientWidth, h = canvas.clientHeight;
    if (canvas.width !== Math.round(w * dpr) || canvas.height !== Math.round(h * dpr)) {
      canvas.width = Math.round(w * dpr); canvas.height = Math.round(h * dpr);
    }
    const key = [canvas.width, canvas.height, chosen().join()].join('/');
    if (key !== baseKey) { drawBase(w, h, dpr); baseKey = key; }
    const g = canvas.getContext('2d');
    g.setTransform(1, 0, 0, 1, 0, 0);
    g.clearRect(0, 0, canvas.width, canvas.height);
    g.drawImage(base, 0, 0);
    if (!frame) return;
    g.setTransform(dpr, 0, 0, dpr, 0, 0);
    g.strokeStyle = '#d02020'; g.lineWidth = 1;
    const cx = frame.X(Math.min(Math.max(cursor, frame.t0), frame.t1));
    g.beginPath(); g.moveTo(cx, frame.T); g.lineTo(cx, frame.h - frame.B); g.stroke();
  }
  canvas.addEventListener('click', e => {
    if (!frame) return;
    const r = canvas.getBoundingClientRect(), x = e.clientX - r.left;
    const u = (x - frame.L) / (frame.w - frame.L - frame.R);
    onPick(frame.t0 + Math.min(Math.max(u, 0), 1) * (frame.t1 - frame.t0));
  });
  select.addEventListener('change', draw);
  return { draw, setTime(t) { cursor = t; draw(); } };
}

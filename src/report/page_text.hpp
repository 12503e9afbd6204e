// SPDX-License-Identifier: Apache-2.0
#pragma once
// The report page's fixed text: its style sheet and the script that draws it. The script is our
// own (no charting library to ship): every time plot shares one view (drag to zoom, the wheel
// zooms around the pointer, a double click or "Reset zoom" shows the whole run) and one time
// cursor (the pointer's time: a line on every plot, the values in the legends, the boat on the
// map with the plan it followed then). The map pans (drag) and zooms (wheel) on its own.
// After drawing, each plot element (class "plot") carries data-rendered="true", data-points (the
// values drawn) and, on time plots, data-t0/data-t1 (the view, seconds from the first tick).

namespace coxswain::report {

inline constexpr const char* kPageStyle = R"CSS(
body{font-family:sans-serif;margin:16px;color:#222;background:#fff}
h1{font-size:20px;margin:0 0 6px}h2{font-size:16px;margin:18px 0 4px}
svg.plot{border:1px solid #ccc;background:#fcfcfc;display:block;user-select:none}
svg.time{cursor:crosshair}svg#track{cursor:move}
table{border-collapse:collapse;font-size:12px}td,th{border:1px solid #ddd;padding:2px 6px;text-align:left}
table#summary{font-size:14px;margin:4px 0 8px}table#summary th{background:#f4f4f4}
.passed{color:#080;font-weight:bold}.failed{color:#b00;font-weight:bold}
.legend span{margin-right:12px;font-size:12px}.legend .value{color:#000;margin-left:4px}
.note{font-size:12px;color:#555}
#toolbar{position:sticky;top:0;background:#fff;border-bottom:1px solid #ddd;padding:4px 0;
  font-size:12px;z-index:1}#toolbar button{margin-right:8px}
)CSS";

inline constexpr const char* kPageScript = R"JS(
'use strict';
const D = JSON.parse(document.getElementById('report-data').textContent);
const NS = 'http://www.w3.org/2000/svg';
function showError(m) {
  const e = document.getElementById('error');
  e.textContent += (e.textContent ? '; ' : '') + m;
}
window.addEventListener('error', ev => showError('script error: ' + ev.message));
function el(parent, name, attrs, text) {
  const e = document.createElementNS(NS, name);
  for (const k in attrs) e.setAttribute(k, attrs[k]);
  if (text !== undefined) e.textContent = text;
  parent.appendChild(e);
  return e;
}
function clear(node) { while (node.firstChild) node.removeChild(node.firstChild); }
function fin(v) { return v !== null && v !== undefined && isFinite(v); }
function fmt(v, digits) { return fin(v) ? (+v).toFixed(digits) : '-'; }
const TS = D.t;
const FULL = TS.length > 1 && TS[TS.length - 1] > TS[0] ? [TS[0], TS[TS.length - 1]]
                                                       : [TS.length ? TS[0] : 0, (TS.length ? TS[0] : 0) + 1];
const MIN_SPAN = 0.05;
const view = {t0: FULL[0], t1: FULL[1], cursor: null};
const plots = [];
// First index whose time is at least t.
function lowerIndex(t) {
  let lo = 0, hi = TS.length;
  while (lo < hi) { const m = (lo + hi) >> 1; if (TS[m] < t) lo = m + 1; else hi = m; }
  return lo;
}
function nearestIndex(t) {
  const i = lowerIndex(t);
  if (i <= 0) return 0;
  if (i >= TS.length) return TS.length - 1;
  return t - TS[i - 1] < TS[i] - t ? i - 1 : i;
}
// The samples in view, with one more on each side so lines run to the edges.
function visible() { return [Math.max(0, lowerIndex(view.t0) - 1), Math.min(TS.length, lowerIndex(view.t1) + 1)]; }
function extent(arrays, i0, i1) {
  let lo = Infinity, hi = -Infinity;
  for (const a of arrays) for (let i = i0; i < i1; i++) { const v = a[i]; if (fin(v)) { lo = Math.min(lo, v); hi = Math.max(hi, v); } }
  if (!isFinite(lo)) { lo = 0; hi = 1; }
  if (hi - lo < 1e-9) { lo -= 0.5; hi += 0.5; }
  return [lo, hi];
}
function niceTicks(lo, hi, n) {
  const raw = (hi - lo) / n, mag = Math.pow(10, Math.floor(Math.log10(raw)));
  const step = [1, 2, 5, 10].map(s => s * mag).find(s => s >= raw) || raw;
  const out = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + step * 1e-6; v += step) out.push(v);
  return {ticks: out, digits: Math.max(0, -Math.floor(Math.log10(step)))};
}
// A time plot's frame: the shared time axis, the start and calibration marks, the cursor line,
// the mouse handlers. `drawBody(p, i0, i1)` draws the data and returns how many values it drew.
function timePlot(id, drawBody, legendSeries) {
  const svg = document.getElementById(id);
  if (!svg) return null;
  svg.classList.add('time');
  const p = {id, svg, W: +svg.getAttribute('width'), H: +svg.getAttribute('height'),
             L: 64, R: 10, T: 16, B: 26, drawBody, legendSeries: legendSeries || [], values: []};
  p.x = t => p.L + (t - view.t0) / (view.t1 - view.t0) * (p.W - p.L - p.R);
  p.t = x => view.t0 + (x - p.L) / (p.W - p.L - p.R) * (view.t1 - view.t0);
  const legend = document.getElementById(id + '-legend');
  if (legend) for (const s of p.legendSeries) {
    const sp = document.createElement('span');
    sp.style.color = s.color; sp.textContent = '\u25A0 ' + s.name;
    const v = document.createElement('span'); v.className = 'value'; sp.appendChild(v);
    legend.appendChild(sp); p.values.push(v);
  }
  attachTimeMouse(p);
  plots.push(p);
  return p;
}
function renderTimePlot(p) {
  clear(p.svg);
  const {W, H, L, R, T, B} = p;
  const ax = niceTicks(view.t0, view.t1, 8);
  for (const tv of ax.ticks) {
    el(p.svg, 'line', {x1: p.x(tv), x2: p.x(tv), y1: T, y2: H - B, stroke: '#eee'});
    el(p.svg, 'text', {x: p.x(tv), y: H - 12, 'font-size': 10, 'text-anchor': 'middle'}, tv.toFixed(ax.digits));
  }
  el(p.svg, 'text', {x: W - R, y: H - 2, 'font-size': 10, 'text-anchor': 'end'}, 'time (s)');
  const E = D.events;
  if (fin(E.start_t) && E.start_t > view.t0) {
    const x1 = Math.min(p.x(E.start_t), W - R);
    el(p.svg, 'rect', {x: L, y: T, width: Math.max(0, x1 - L), height: H - T - B, fill: '#f1f1f1', class: 'before-start'});
  }
  if (fin(E.calibration_t) && E.calibration_t >= view.t0 && E.calibration_t <= view.t1) {
    el(p.svg, 'line', {x1: p.x(E.calibration_t), x2: p.x(E.calibration_t), y1: T, y2: H - B,
                       stroke: '#888', 'stroke-dasharray': '3 3', class: 'calibration'});
  }
  const [i0, i1] = visible();
  const drawn = p.drawBody(p, i0, i1);
  p.cursorLine = el(p.svg, 'line', {x1: 0, x2: 0, y1: T, y2: H - B, stroke: '#000', 'stroke-width': 1,
                                    class: 'cursor', visibility: 'hidden'});
  p.selection = el(p.svg, 'rect', {x: 0, y: T, width: 0, height: H - T - B, fill: 'rgba(60,120,220,0.2)',
                                   visibility: 'hidden', class: 'selection'});
  p.svg.setAttribute('data-rendered', 'true');
  p.svg.setAttribute('data-points', String(drawn));
  p.svg.setAttribute('data-t0', view.t0.toFixed(3));
  p.svg.setAttribute('data-t1', view.t1.toFixed(3));
}
function yAxis(p, y0, y1, top, bottom, label) {
  const Y = y => bottom - (y - y0) / (y1 - y0) * (bottom - top);
  const ax = niceTicks(y0, y1, Math.max(2, Math.round((bottom - top) / 30)));
  for (const yv of ax.ticks) {
    el(p.svg, 'line', {x1: p.L, x2: p.W - p.R, y1: Y(yv), y2: Y(yv), stroke: '#eee'});
    el(p.svg, 'text', {x: p.L - 4, y: Y(yv) + 3, 'font-size': 10, 'text-anchor': 'end'}, yv.toFixed(ax.digits));
  }
  if (label) el(p.svg, 'text', {x: 4, y: top - 4, 'font-size': 10}, label);
  return Y;
}
// One series as a path; NaN lifts the pen. `wrap`: a jump over 180 (heading crossing +-180) too.
function seriesPath(p, s, Y, i0, i1) {
  let d = '', pen = false, prev = null, points = 0;
  for (let i = i0; i < i1; i++) {
    const y = s.ys[i];
    if (!fin(y)) { pen = false; continue; }
    if (s.wrap && pen && Math.abs(y - prev) > 180) pen = false;
    const x = p.x(TS[i]).toFixed(1);
    if (s.step && pen) d += 'L' + x + ' ' + Y(prev).toFixed(1);
    d += (pen ? 'L' : 'M') + x + ' ' + Y(y).toFixed(1);
    pen = true; prev = y; points++;
  }
  el(p.svg, 'path', {d, fill: 'none', stroke: s.color, 'stroke-width': 1.2, 'clip-path': 'url(#' + p.id + '-clip)'});
  return points;
}
function clipTo(p, top, bottom) {
  const defs = el(p.svg, 'defs', {});
  const cp = el(defs, 'clipPath', {id: p.id + '-clip'});
  el(cp, 'rect', {x: p.L, y: top, width: p.W - p.L - p.R, height: bottom - top});
}
function linePlot(id, series, ylabel, yrange) {
  return timePlot(id, (p, i0, i1) => {
    const top = p.T, bottom = p.H - p.B;
    const [y0, y1] = yrange || extent(series.map(s => s.ys), i0, i1);
    clipTo(p, top, bottom);
    const Y = yAxis(p, y0, y1, top, bottom, ylabel);
    let n = 0;
    for (const s of series) n += seriesPath(p, s, Y, i0, i1);
    return n;
  }, series);
}
// Stacked lanes, each with its own scale, so a 100 Hz line does not flatten a 1 Hz one.
function lanePlot(id, lanes) {
  return timePlot(id, (p, i0, i1) => {
    const h = (p.H - p.T - p.B) / Math.max(1, lanes.length);
    clipTo(p, p.T, p.H - p.B);
    let n = 0;
    lanes.forEach((s, k) => {
      const top = p.T + k * h + 10, bottom = p.T + (k + 1) * h - 2;
      el(p.svg, 'line', {x1: p.L, x2: p.W - p.R, y1: bottom + 1, y2: bottom + 1, stroke: '#ccc'});
      el(p.svg, 'text', {x: p.L + 4, y: top - 1, 'font-size': 10, fill: s.color}, s.name);
      if (s.bool) {
        const Y = y => bottom - y * (bottom - top);
        el(p.svg, 'text', {x: p.L - 4, y: Y(1) + 3, 'font-size': 10, 'text-anchor': 'end'}, s.on || 'on');
        el(p.svg, 'text', {x: p.L - 4, y: Y(0) + 3, 'font-size': 10, 'text-anchor': 'end'}, s.off || 'off');
        n += seriesPath(p, s, Y, i0, i1);
      } else {
        const [y0, y1] = extent([s.ys], i0, i1);
        const Y = y => bottom - (y - y0) / (y1 - y0) * (bottom - top);
        el(p.svg, 'text', {x: p.L - 4, y: Y(y1) + 8, 'font-size': 10, 'text-anchor': 'end'}, fmt(y1, 1));
        el(p.svg, 'text', {x: p.L - 4, y: Y(y0), 'font-size': 10, 'text-anchor': 'end'}, fmt(y0, 1));
        n += seriesPath(p, s, Y, i0, i1);
      }
    });
    return n;
  }, lanes);
}
function statesPlot(id) {
  const names = [...new Set(D.paths.map(s => s.path))];
  const hue = i => 'hsl(' + (i * 67 % 360) + ',60%,55%)';
  return timePlot(id, (p, i0, i1) => {
    const rowH = Math.max(10, (p.H - p.T - p.B) / Math.max(1, names.length));
    clipTo(p, p.T, p.H - p.B);
    let n = 0;
    D.paths.forEach((s, i) => {
      const end = i + 1 < D.paths.length ? D.paths[i + 1].t : FULL[1];
      if (end < view.t0 || s.t > view.t1) return;
      const row = names.indexOf(s.path);
      const x0 = Math.max(p.L, p.x(s.t)), x1 = Math.min(p.W - p.R, p.x(end));
      const r = el(p.svg, 'rect', {x: x0, y: p.T + row * rowH, width: Math.max(1, x1 - x0), height: rowH - 2, fill: hue(row)});
      el(r, 'title', {}, s.path);
      n++;
    });
    names.forEach((name, i) => el(p.svg, 'text', {x: p.L + 2, y: p.T + i * rowH + rowH / 2 + 3, 'font-size': 10}, name));
    return n;
  });
}
function stateAt(t) {
  let s = null;
  for (const x of D.paths) { if (x.t <= t) s = x.path; else break; }
  return s;
}
function zoom(a, b) {
  let t0 = Math.max(FULL[0], Math.min(a, b)), t1 = Math.min(FULL[1], Math.max(a, b));
  if (t1 - t0 < MIN_SPAN) { const c = (t0 + t1) / 2; t0 = c - MIN_SPAN / 2; t1 = c + MIN_SPAN / 2; }
  view.t0 = t0; view.t1 = t1;
  renderAll();
}
function setCursor(t) {
  view.cursor = fin(t) ? Math.max(FULL[0], Math.min(FULL[1], t)) : null;
  updateCursor();
}
function localX(svg, ev) {
  const r = svg.getBoundingClientRect();
  return (ev.clientX - r.left) * (+svg.getAttribute('width') / r.width);
}
function attachTimeMouse(p) {
  let dragFrom = null;
  p.svg.addEventListener('mousedown', ev => { if (ev.button === 0) { dragFrom = localX(p.svg, ev); ev.preventDefault(); } });
  p.svg.addEventListener('mousemove', ev => {
    const x = localX(p.svg, ev);
    if (dragFrom !== null) {
      p.selection.setAttribute('x', Math.min(x, dragFrom));
      p.selection.setAttribute('width', Math.abs(x - dragFrom));
      p.selection.setAttribute('visibility', 'visible');
    }
    setCursor(p.t(x));
  });
  p.svg.addEventListener('mouseup', ev => {
    if (dragFrom === null) return;
    const x = localX(p.svg, ev), from = dragFrom;
    dragFrom = null;
    p.selection.setAttribute('visibility', 'hidden');
    if (Math.abs(x - from) > 3) zoom(p.t(from), p.t(x));
  });
  p.svg.addEventListener('mouseleave', () => { dragFrom = null; if (p.selection) p.selection.setAttribute('visibility', 'hidden'); });
  p.svg.addEventListener('wheel', ev => {
    ev.preventDefault();
    const t = p.t(localX(p.svg, ev)), f = ev.deltaY < 0 ? 0.8 : 1.25;
    zoom(t - (t - view.t0) * f, t + (view.t1 - t) * f);
  }, {passive: false});
  p.svg.addEventListener('dblclick', () => zoom(FULL[0], FULL[1]));
}
// The map: the course, the mission, what the lidar saw, the track (the estimate before the start
// calibration apart, dashed: it is the uncorrected GPS, not a place the boat jumped from) and, at
// the cursor, the boat, its goal and the plan it followed.
const track = {svg: document.getElementById('track')};
function trackExtent() {
  const es = [], ns = [];
  const add = (n, e) => { if (fin(n) && fin(e)) { ns.push(n); es.push(e); } };
  D.track.north.forEach((n, i) => add(n, D.track.east[i]));
  const C = D.course || {};
  for (const w of (C.walls || [])) for (const q of w) add(q[0], q[1]);
  for (const b of (C.buoys || [])) add(b.n, b.e);
  for (const w of (C.waypoints || [])) add(w.n, w.e);
  for (const m of D.map.marks) add(m.n, m.e);
  for (const a of D.map.areas) for (const q of a.points) add(q[0], q[1]);
  if (ns.length === 0) for (const s of D.segments) { add(s[0], s[1]); add(s[2], s[3]); }
  const [e0, e1] = extent([es], 0, es.length), [n0, n1] = extent([ns], 0, ns.length);
  const W = +track.svg.getAttribute('width'), H = +track.svg.getAttribute('height');
  const span = Math.max(e1 - e0, n1 - n0) + 4;
  return {cx: (e0 + e1) / 2, cy: (n0 + n1) / 2, k: Math.min(W, H) / span};
}
function renderTrack() {
  const svg = track.svg;
  clear(svg);
  const W = +svg.getAttribute('width'), H = +svg.getAttribute('height');
  const m = track.map;
  const X = e => W / 2 + (e - m.cx) * m.k, Y = n => H / 2 - (n - m.cy) * m.k;
  track.X = X; track.Y = Y;
  let points = 0;
  const poly = (pts, attrs) => el(svg, 'polyline', Object.assign({points: pts.map(q => X(q[1]).toFixed(1) + ',' + Y(q[0]).toFixed(1)).join(' '), fill: 'none'}, attrs));
  let seg = '';
  for (const s of D.segments) { seg += 'M' + X(s[1]).toFixed(1) + ' ' + Y(s[0]).toFixed(1) + 'L' + X(s[3]).toFixed(1) + ' ' + Y(s[2]).toFixed(1); points++; }
  if (seg) el(svg, 'path', {d: seg, stroke: '#bbb', 'stroke-width': 1, fill: 'none', class: 'lidar'});
  for (const a of D.map.areas) {
    const pts = a.points.concat(a.points.length ? [a.points[0]] : []);
    const r = poly(pts, a.kind === 'no-go' ? {stroke: '#c33', fill: 'rgba(200,50,50,0.12)', 'stroke-width': 1.5}
                                            : {stroke: '#2a7', 'stroke-dasharray': '6 3', 'stroke-width': 1.5});
    el(r, 'title', {}, a.label);
    points += a.points.length;
  }
  const C = D.course || {};
  for (const w of (C.walls || [])) { poly(w, {stroke: '#444', 'stroke-width': 2}); points += w.length; }
  for (const b of (C.buoys || [])) {
    el(svg, 'circle', {cx: X(b.e), cy: Y(b.n), r: Math.max(2, b.r * m.k), fill: b.colour || 'orange', stroke: '#333'});
    points++;
  }
  for (const w of (C.waypoints || [])) {
    el(svg, 'circle', {cx: X(w.e), cy: Y(w.n), r: Math.max(2, w.r * m.k), fill: 'none', stroke: '#07c', 'stroke-dasharray': '4 3'});
    points++;
  }
  for (const mk of D.map.marks) {
    const colour = mk.kind === 'slip' ? '#80c' : '#07c';
    el(svg, 'circle', {cx: X(mk.e), cy: Y(mk.n), r: 3, fill: colour, class: 'mark'});
    el(svg, 'text', {x: X(mk.e) + 5, y: Y(mk.n) - 5, 'font-size': 10, fill: colour}, mk.label);
    points++;
  }
  const cal = D.events.calibration_t;
  const zoomed = view.t0 > FULL[0] || view.t1 < FULL[1];
  const paths = {pre: '', post: '', window: ''};
  const pen = {pre: false, post: false, window: false};
  for (let i = 0; i < TS.length; i++) {
    const n = D.track.north[i], e = D.track.east[i];
    const part = fin(cal) && TS[i] < cal ? 'pre' : 'post';
    const inWindow = zoomed && TS[i] >= view.t0 && TS[i] <= view.t1;
    for (const key of ['pre', 'post', 'window']) {
      const on = key === 'window' ? inWindow : key === part;
      if (!on || !fin(n) || !fin(e)) { pen[key] = false; continue; }
      paths[key] += (pen[key] ? 'L' : 'M') + X(e).toFixed(1) + ' ' + Y(n).toFixed(1);
      pen[key] = true;
    }
    if (fin(n) && fin(e)) points++;
  }
  if (paths.pre) el(svg, 'path', {d: paths.pre, fill: 'none', stroke: '#999', 'stroke-width': 1.5, 'stroke-dasharray': '4 3', class: 'precalibration'});
  el(svg, 'path', {d: paths.post, fill: 'none', stroke: '#d22', 'stroke-width': 1.5, class: 'track'});
  if (paths.window) el(svg, 'path', {d: paths.window, fill: 'none', stroke: '#700', 'stroke-width': 3.5, class: 'in-view'});
  if (C.start) el(svg, 'circle', {cx: X(C.start[1]), cy: Y(C.start[0]), r: 4, fill: '#2a2'});
  // The scale bar: the longest 1, 2 or 5 times a power of ten that fits in 100 px.
  const most = 100 / m.k, mag = Math.pow(10, Math.floor(Math.log10(most)));
  const metres = [5, 2, 1].map(f => f * mag).find(v => v <= most);
  el(svg, 'line', {x1: 10, x2: 10 + metres * m.k, y1: H - 10, y2: H - 10, stroke: '#000', 'stroke-width': 2});
  el(svg, 'text', {x: 10, y: H - 14, 'font-size': 11}, metres + ' m, north up');
  track.dynamic = el(svg, 'g', {class: 'at-cursor'});
  svg.setAttribute('data-rendered', 'true');
  svg.setAttribute('data-points', String(points));
  svg.setAttribute('data-scale', m.k.toFixed(4));
}
function planAt(t) {
  let plan = null;
  for (const p of D.plans) { if (p.t <= t) plan = p; else break; }
  return plan;
}
function updateTrackCursor() {
  const g = track.dynamic, X = track.X, Y = track.Y;
  if (!g) return;
  clear(g);
  const t = view.cursor !== null ? view.cursor : view.t1;
  const plan = planAt(t);
  if (plan && plan.points.length > 1) {
    el(g, 'polyline', {points: plan.points.map(q => X(q[1]).toFixed(1) + ',' + Y(q[0]).toFixed(1)).join(' '),
                       fill: 'none', stroke: '#15c', 'stroke-width': 1.5, 'stroke-dasharray': '6 3', class: 'plan'});
  }
  if (view.cursor === null || TS.length === 0) return;
  const i = nearestIndex(view.cursor);
  const n = D.track.north[i], e = D.track.east[i];
  if (fin(D.goal_n[i])) {
    const gx = X(D.goal_e[i]), gy = Y(D.goal_n[i]);
    el(g, 'path', {d: `M${gx - 5} ${gy - 5}L${gx + 5} ${gy + 5}M${gx - 5} ${gy + 5}L${gx + 5} ${gy - 5}`, stroke: '#15c', 'stroke-width': 2, class: 'goal'});
  }
  if (fin(n) && fin(e)) {
    const bx = X(e), by = Y(n);
    el(g, 'circle', {cx: bx, cy: by, r: 5, fill: '#fff', stroke: '#000', 'stroke-width': 2, class: 'boat'});
    const h = D.heading[i];
    if (fin(h)) {
      const a = h * Math.PI / 180;
      el(g, 'line', {x1: bx, y1: by, x2: bx + 14 * Math.sin(a), y2: by - 14 * Math.cos(a), stroke: '#000', 'stroke-width': 2});
    }
  }
}
function attachTrackMouse() {
  const svg = track.svg;
  let from = null;
  const local = ev => {
    const r = svg.getBoundingClientRect();
    return [(ev.clientX - r.left) * (+svg.getAttribute('width') / r.width), (ev.clientY - r.top) * (+svg.getAttribute('height') / r.height)];
  };
  svg.addEventListener('mousedown', ev => { if (ev.button === 0) { from = local(ev); ev.preventDefault(); } });
  svg.addEventListener('mousemove', ev => {
    if (from === null) return;
    const [x, y] = local(ev);
    track.map.cx -= (x - from[0]) / track.map.k;
    track.map.cy += (y - from[1]) / track.map.k;
    from = [x, y];
    renderTrack(); updateTrackCursor();
  });
  const end = () => { from = null; };
  svg.addEventListener('mouseup', end);
  svg.addEventListener('mouseleave', end);
  svg.addEventListener('wheel', ev => {
    ev.preventDefault();
    const [x, y] = local(ev), W = +svg.getAttribute('width'), H = +svg.getAttribute('height');
    const m = track.map, f = ev.deltaY < 0 ? 1.25 : 0.8;
    const e = m.cx + (x - W / 2) / m.k, n = m.cy - (y - H / 2) / m.k;
    m.k *= f;
    m.cx = e - (x - W / 2) / m.k; m.cy = n + (y - H / 2) / m.k;
    renderTrack(); updateTrackCursor();
  }, {passive: false});
  svg.addEventListener('dblclick', () => { track.map = trackExtent(); renderTrack(); updateTrackCursor(); });
}
function updateCursor() {
  const c = view.cursor;
  const i = c === null || TS.length === 0 ? -1 : nearestIndex(c);
  for (const p of plots) {
    const inside = c !== null && c >= view.t0 && c <= view.t1;
    if (p.cursorLine) {
      p.cursorLine.setAttribute('x1', inside ? p.x(c) : 0);
      p.cursorLine.setAttribute('x2', inside ? p.x(c) : 0);
      p.cursorLine.setAttribute('visibility', inside ? 'visible' : 'hidden');
    }
    p.legendSeries.forEach((s, k) => {
      if (!p.values[k]) return;
      const v = i < 0 ? null : s.ys[i];
      p.values[k].textContent = i < 0 ? '' : (s.bool ? (fin(v) ? (v > 0.5 ? (s.on || 'on') : (s.off || 'off')) : '-') : fmt(v, s.digits === undefined ? 2 : s.digits));
    });
  }
  const readout = document.getElementById('cursor-readout');
  readout.textContent = i < 0 ? 'move the pointer over a plot for the values at one time' :
      't = ' + c.toFixed(2) + ' s, state ' + (stateAt(c) || '-') + ', heading ' + fmt(D.heading[i], 1) +
      ' deg (desired ' + fmt(D.desired[i], 1) + '), speed ' + fmt(D.speed[i], 2) + ' m/s, battery ' + fmt(D.power.supply_v[i], 2) + ' V';
  updateTrackCursor();
}
function renderAll() {
  for (const p of plots) renderTimePlot(p);
  renderTrack();
  document.getElementById('view-range').textContent =
      'showing ' + view.t0.toFixed(2) + ' .. ' + view.t1.toFixed(2) + ' s of ' + FULL[0].toFixed(2) + ' .. ' + FULL[1].toFixed(2) + ' s';
  updateCursor();
}
function healthTable() {
  const tb = document.getElementById('health-table');
  if (D.health.length === 0) tb.insertRow().insertCell().textContent = 'no device health in the recording';
  for (const h of D.health) {
    const row = tb.insertRow();
    [h.device, h.states.join(', '), h.final_state, h.frames_ok, h.checksum_errors, h.framing_errors, h.reopen_count]
      .forEach(v => { row.insertCell().textContent = v; });
  }
  const tr = document.getElementById('transitions');
  for (const x of D.transitions) {
    const row = tr.insertRow();
    [x.t.toFixed(2), x.from, x.to, x.reason].forEach(v => { row.insertCell().textContent = v; });
  }
}
try {
  const colours = ['#c33', '#39c', '#3a3', '#a6c', '#c90'];
  linePlot('heading', [{name: 'heading', ys: D.heading, color: '#c33', wrap: true, digits: 1},
                       {name: 'desired heading', ys: D.desired, color: '#36c', wrap: true, digits: 1}], 'deg (0 north, clockwise)');
  linePlot('pulses', [{name: 'servo/port (us)', ys: D.pulse0, color: '#a6c', step: true, digits: 0},
                      {name: 'thrust/starboard (us)', ys: D.pulse1, color: '#c60', step: true, digits: 0}], 'pulse (us)');
  linePlot('speed', [{name: 'GNSS ground speed (m/s)', ys: D.speed, color: '#093'}], 'm/s');
  statesPlot('states');
  lanePlot('health', D.rates.map((r, k) => ({name: r.device + ' (Hz)', ys: r.rate_hz, color: colours[k % 5], digits: 1})));
  lanePlot('power', [{name: 'battery (V)', ys: D.power.supply_v, color: '#c60'},
                     {name: 'e-stop', ys: D.power.estop, color: '#c00', bool: true, on: 'pressed', off: 'clear'},
                     {name: 'RC link', ys: D.power.rc_present, color: '#36c', bool: true, on: 'present', off: 'lost'},
                     {name: 'mode', ys: D.power.autonomous, color: '#093', bool: true, on: 'auto', off: 'manual'},
                     {name: 'Arduino failsafe', ys: D.power.failsafe, color: '#a6c', bool: true, on: 'neutral', off: 'ok'}]);
  linePlot('timing', [{name: 'tick interval (ms)', ys: D.tick_dt_ms, color: '#555'}], 'ms');
  linePlot('gnss', [{name: 'h_acc (m)', ys: D.h_acc, color: '#c33'},
                    {name: 'satellites', ys: D.sats, color: '#36c', step: true, digits: 0},
                    {name: 'fix type', ys: D.fix_type, color: '#093', step: true, digits: 0}], 'h_acc m / count / type');
  track.map = trackExtent();
  attachTrackMouse();
  document.getElementById('reset-zoom').addEventListener('click', () => zoom(FULL[0], FULL[1]));
  healthTable();
  renderAll();
} catch (e) {
  showError('drawing failed: ' + e);
}
)JS";

}  // namespace coxswain::report

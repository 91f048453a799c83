"""The pages' own JavaScript (run after plotly.js has drawn ``#scene``; reads
``window.SIMGRASP``). ``document.body.dataset.ready`` becomes ``"1"`` once a page is live."""

from __future__ import annotations

WHEN_DRAWN = """
function whenDrawn(start) {
  const gd = document.getElementById('scene');
  if (!gd || !gd.on || !gd._fullData) { setTimeout(() => whenDrawn(start), 50); return; }
  start(gd);
  document.body.dataset.ready = '1';
}
function showRecord(record) {
  document.getElementById('record').textContent = JSON.stringify(record, null, 1);
}
"""

FILTER_SCRIPT = (
    WHEN_DRAWN
    + """
// A trace with meta {outcome, failure} is drawn while both its boxes are checked.
function applyFilters(gd) {
  const on = {};
  document.querySelectorAll('input[data-filter]').forEach(box => {
    on[box.dataset.filter + ':' + box.value] = box.checked;
  });
  const indices = [], visible = [];
  gd.data.forEach((trace, i) => {
    if (!trace.meta || trace.meta.outcome === undefined) return;
    indices.push(i);
    const shown = on['outcome:' + trace.meta.outcome] !== false &&
                  on['failure:' + trace.meta.failure] !== false;
    visible.push(shown ? true : false);
  });
  Plotly.restyle(gd, {visible: visible}, indices);
}
whenDrawn(gd => {
  document.querySelectorAll('input[data-filter]').forEach(box =>
    box.addEventListener('change', () => applyFilters(gd)));
  gd.on('plotly_click', event => {
    const point = event.points[0];
    const records = window.SIMGRASP.records || {};
    if (point && point.customdata !== undefined && records[point.customdata] !== undefined) {
      showRecord(records[point.customdata]);
    }
  });
});
"""
)

REPLAY_SCRIPT = (
    WHEN_DRAWN
    + """
// Replay: the object's mesh (object frame) moved by each sample's pose, the gripper's boxes
// (world frame per sample) swapped in; the slider picks the sample.
function rotate(q, v) {
  const [w, x, y, z] = q, [a, b, c] = v;
  const tx = 2 * (y * c - z * b), ty = 2 * (z * a - x * c), tz = 2 * (x * b - y * a);
  return [a + w * tx + y * tz - z * ty, b + w * ty + z * tx - x * tz,
          c + w * tz + x * ty - y * tx];
}
function placed(vertices, pose) {
  const xs = [], ys = [], zs = [], q = pose.slice(3, 7);
  for (let i = 0; i < vertices.length; i += 3) {
    const p = rotate(q, [vertices[i], vertices[i + 1], vertices[i + 2]]);
    xs.push(p[0] + pose[0]); ys.push(p[1] + pose[1]); zs.push(p[2] + pose[2]);
  }
  return [xs, ys, zs];
}
function phaseAt(t) {
  let name = '';
  (window.SIMGRASP.replay.phases || []).forEach(p => { if (t >= p.t - 1e-9) name = p.name; });
  return name;
}
function showSample(gd, k) {
  const data = window.SIMGRASP, replay = data.replay;
  const [ox, oy, oz] = placed(data.object_vertices, replay.object_pose[k]);
  const g = data.gripper_vertices[k];
  const gx = [], gy = [], gz = [];
  for (let i = 0; i < g.length; i += 3) { gx.push(g[i]); gy.push(g[i + 1]); gz.push(g[i + 2]); }
  Plotly.restyle(gd, {x: [ox, gx], y: [oy, gy], z: [oz, gz]},
                 [data.object_trace, data.gripper_trace]);
  const t = replay.t[k];
  document.getElementById('clock').textContent =
    't = ' + t.toFixed(2) + ' s, ' + phaseAt(t) + ', opening ' +
    (1000 * replay.opening[k]).toFixed(1) + ' mm';
}
whenDrawn(gd => {
  const slider = document.getElementById('time');
  if (!slider) return;
  slider.addEventListener('input', () => showSample(gd, Number(slider.value)));
  let timer = null;
  document.getElementById('play').addEventListener('click', () => {
    if (timer) { clearInterval(timer); timer = null; return; }
    timer = setInterval(() => {
      const next = (Number(slider.value) + 1) % (Number(slider.max) + 1);
      slider.value = next; showSample(gd, next);
    }, 1000 / window.SIMGRASP.replay.rate_hz);
  });
  showSample(gd, Number(slider.value));
});
"""
)

"""The report page's script: trial rows filtered by the check boxes, a clicked row's record
shown and its trial drawn (the object's mesh placed by the record's ``object_pose``
``[x y z qw qx qy qz]``, world frame, and the grasp's wireframe)."""

from __future__ import annotations

from simgrasp.viewer.layer_filters import LAYER_SCRIPT

REPORT_SCRIPT = (
    LAYER_SCRIPT
    + """
function poseApply(pose, v, scale) {
  const [tx, ty, tz, w, x, y, z] = pose;
  const r = [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
             2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
             2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)];
  const out = {x: [], y: [], z: []};
  for (let n = 0; n < v.length; n += 3) {
    const a = v[n] * scale, b = v[n + 1] * scale, c = v[n + 2] * scale;
    out.x.push(r[0] * a + r[1] * b + r[2] * c + tx);
    out.y.push(r[3] * a + r[4] * b + r[5] * c + ty);
    out.z.push(r[6] * a + r[7] * b + r[8] * c + tz);
  }
  return out;
}
function trialTraces(view) {
  const traces = [], mesh = window.SIMGRASP.meshes[view.mesh];
  if (mesh && view.object_pose) {
    const p = poseApply(view.object_pose, mesh.v, mesh.scale);
    const f = mesh.f;
    traces.push({type: 'mesh3d', x: p.x, y: p.y, z: p.z, name: view.mesh, color: '#9a9a9a',
      i: f.filter((_, n) => n % 3 === 0), j: f.filter((_, n) => n % 3 === 1),
      k: f.filter((_, n) => n % 3 === 2), flatshading: true, showlegend: true,
      lighting: {ambient: 0.55, diffuse: 0.7}, hoverinfo: 'name'});
  }
  if (view.wireframe) {
    const w = view.wireframe, line = {x: [], y: [], z: []};
    for (let n = 0; n < w.length; n += 6) {
      line.x.push(w[n], w[n + 3], null);
      line.y.push(w[n + 1], w[n + 4], null);
      line.z.push(w[n + 2], w[n + 5], null);
    }
    traces.push({type: 'scatter3d', mode: 'lines', name: 'grasp', ...line,
      line: {color: view.color, width: 6}, hoverinfo: 'skip'});
  }
  return traces;
}
function selectTrial(gd, k) {
  document.querySelectorAll('tr.trial').forEach(row => {
    row.style.outline = row.dataset.trial === String(k) ? '2px solid black' : '';
  });
  document.body.dataset.selected = String(k);
  showRecord(window.SIMGRASP.records[k]);
  Plotly.react(gd, trialTraces(window.SIMGRASP.views[k]), gd.layout);
}
function applyRows() {
  const on = boxStates();
  let shown = 0;
  document.querySelectorAll('tr.trial').forEach(row => {
    const visible = ['object', 'setting', 'outcome'].every(
      g => on[g + ':' + row.dataset[g]] !== false);
    row.style.display = visible ? '' : 'none';
    shown += visible ? 1 : 0;
  });
  document.body.dataset.shownTrials = String(shown);
}
whenDrawn(gd => {
  document.querySelectorAll('input[data-filter]').forEach(b =>
    b.addEventListener('change', applyRows));
  document.querySelectorAll('tr.trial').forEach(row => {
    row.style.cursor = 'pointer';
    row.addEventListener('click', () => selectTrial(gd, Number(row.dataset.trial)));
  });
  applyRows();
  const first = window.SIMGRASP.views.findIndex(v => v.wireframe);
  if (window.SIMGRASP.views.length) selectTrial(gd, Math.max(first, 0));
});
"""
)

"""The trial page's script: places the moving bodies' vertices at each replay frame.

Reads ``window.SIMGRASP.replay`` (per frame: ``t`` s, ``object_pose`` and ``tcp_pose`` as
``[x y z qw qx qy qz]`` in the world frame, ``opening`` m; ``phases``: name and start time) and
``gripper_side`` (per gripper vertex: -1, 0, +1, its y shift in units of ``opening / 2``).
A trace with ``meta.body`` ``"object"`` or ``"gripper"`` holds its vertices in that body's
frame; ``window.showFrame(k)`` draws frame ``k`` (the slider and the play button call it) and
sets ``document.body.dataset.frame`` and the ``#phase`` label.
"""

from __future__ import annotations

from simgrasp.viewer.scripts import WHEN_DRAWN

REPLAY_SCRIPT = (
    WHEN_DRAWN
    + """
function rotation(p) {  // [x y z qw qx qy qz] -> row-major 3x3
  const [w, x, y, z] = [p[3], p[4], p[5], p[6]];
  return [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
          2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
          2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)];
}
function placed(body, pose, shift) {
  const r = rotation(pose), n = body.x.length;
  const x = new Float32Array(n), y = new Float32Array(n), z = new Float32Array(n);
  for (let v = 0; v < n; v++) {
    const lx = body.x[v], ly = body.y[v] + (shift ? shift[v] : 0), lz = body.z[v];
    x[v] = r[0] * lx + r[1] * ly + r[2] * lz + pose[0];
    y[v] = r[3] * lx + r[4] * ly + r[5] * lz + pose[1];
    z[v] = r[6] * lx + r[7] * ly + r[8] * lz + pose[2];
  }
  return [x, y, z];
}
function phaseAt(phases, t, rate) {  // a phase starting within half a frame of t is on
  let name = phases.length ? phases[0].name : '';
  phases.forEach(p => { if (t + 0.5 / rate >= p.t) name = p.name; });
  return name;
}
whenDrawn(gd => {
  const data = window.SIMGRASP, replay = data.replay;
  const bodies = [];
  gd.data.forEach((trace, i) => {
    if (!trace.meta || !trace.meta.body) return;
    const full = gd._fullData.find(f => f.index === i) || trace;
    bodies.push({index: i, body: trace.meta.body,
                 x: Float32Array.from(full.x), y: Float32Array.from(full.y),
                 z: Float32Array.from(full.z)});
  });
  const slider = document.getElementById('slider');
  window.showFrame = k => {
    k = Math.max(0, Math.min(replay.t.length - 1, Math.round(k)));
    const half = replay.opening[k] / 2;
    const shift = data.gripper_side.map(s => s * half);
    const xs = [], ys = [], zs = [];
    bodies.forEach(b => {
      const gripper = b.body === 'gripper';
      const pose = gripper ? replay.tcp_pose[k] : replay.object_pose[k];
      const [x, y, z] = placed(b, pose, gripper ? shift : null);
      xs.push(x); ys.push(y); zs.push(z);
    });
    Plotly.restyle(gd, {x: xs, y: ys, z: zs}, bodies.map(b => b.index));
    const t = replay.t[k], phase = phaseAt(replay.phases, t, data.rate_hz);
    slider.value = k;
    document.getElementById('time').textContent = 't = ' + t.toFixed(2) + ' s';
    document.getElementById('phase').textContent = phase;
    document.body.dataset.frame = String(k);
    document.body.dataset.phase = phase;
  };
  slider.addEventListener('input', () => window.showFrame(Number(slider.value)));
  let timer = null;
  document.getElementById('play').addEventListener('click', () => {
    if (timer) { clearInterval(timer); timer = null; return; }
    if (Number(slider.value) >= replay.t.length - 1) window.showFrame(0);
    timer = setInterval(() => {
      const next = Number(slider.value) + 1;
      if (next >= replay.t.length) { clearInterval(timer); timer = null; return; }
      window.showFrame(next);
    }, 1000 / data.rate_hz);
  });
  showRecord(data.record);
  window.showFrame(0);
});
"""
)
"""The trial page's script (module docstring)."""

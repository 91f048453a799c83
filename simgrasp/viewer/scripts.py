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

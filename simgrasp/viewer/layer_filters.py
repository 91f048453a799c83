"""Check boxes that show and hide a page's traces by their ``meta.filters`` (the detection and
report pages).

A trace whose ``meta`` is ``{"filters": {"layer": "candidates", "kind": "ellipsoid"}}`` is drawn
while every box it names (``data-filter="layer" value="candidates"``, ...) is checked; a group
without a box on the page does not hide it. Python sets each trace's first visibility from the
same rule, so the page opens as its boxes say.
"""

from __future__ import annotations

import html
from typing import Any

import plotly.graph_objects as go

from simgrasp.viewer.scripts import WHEN_DRAWN


def box(group: str, value: str, text: str, count: int | None = None, checked: bool = True) -> str:
    """A filter check box (``data-filter`` names its group, ``value`` what it shows)."""
    shown = f"{text} ({count})" if count is not None else text
    state = " checked" if checked else ""
    return (
        f'<label><input type="checkbox"{state} data-filter="{html.escape(group)}" '
        f'value="{html.escape(value)}"> {html.escape(shown)}</label>'
    )


def apply_initial(figure: go.Figure, unchecked: set[tuple[str, str]]) -> None:
    """Hide the traces that name an unchecked (group, value) box."""
    for trace in figure.data:
        filters = (trace.meta or {}).get("filters", {}) if isinstance(trace.meta, dict) else {}
        if any((group, value) in unchecked for group, value in filters.items()):
            trace.visible = False


def filters_meta(**filters: Any) -> dict[str, Any]:
    """A trace's ``meta`` naming its filter boxes."""
    return {"filters": {k: str(v) for k, v in filters.items()}}


LAYER_SCRIPT = (
    WHEN_DRAWN
    + """
function boxStates() {
  const on = {};
  document.querySelectorAll('input[data-filter]').forEach(b => {
    on[b.dataset.filter + ':' + b.value] = b.checked;
  });
  return on;
}
function applyLayers(gd) {
  const on = boxStates(), indices = [], visible = [];
  gd.data.forEach((trace, i) => {
    if (!trace.meta || !trace.meta.filters) return;
    indices.push(i);
    visible.push(Object.entries(trace.meta.filters).every(([g, v]) => on[g + ':' + v] !== false));
  });
  if (indices.length) Plotly.restyle(gd, {visible: visible}, indices);
}
function onRecordClick(gd) {
  gd.on('plotly_click', event => {
    const point = event.points[0], records = window.SIMGRASP.records || {};
    if (point && point.customdata !== undefined && records[point.customdata] !== undefined) {
      showRecord(records[point.customdata]);
    }
  });
}
"""
)
"""The functions the detection and report pages' scripts share (after ``WHEN_DRAWN``)."""

"""One self-contained HTML page around a plotly figure: plotly.js inlined (the copy the plotly
package ships), no MathJax, no request to any other address, a side panel of controls and a
record box, and the page's own script.

Every page's figure sits in ``<div id="scene">``; ``window.SIMGRASP`` holds the page's data
(what its script reads); buttons and check boxes carry ``data-*`` attributes the script and the
browser tests use.
"""

from __future__ import annotations

import html
import json
from typing import Any

import plotly.graph_objects as go
import plotly.io as pio

PLOT_CONFIG: dict[str, Any] = {
    "displaylogo": False,
    "responsive": True,
    "topojsonURL": "",
    "scrollZoom": True,
}
"""plotly.js settings of every page: no links out, no topojson fetch (no map trace anyway)."""

STYLE = """
body { font-family: sans-serif; margin: 0; display: flex; height: 100vh; }
#side { width: 320px; padding: 10px; overflow-y: auto; border-right: 1px solid #ccc;
        font-size: 13px; }
#main { flex: 1; display: flex; flex-direction: column; min-width: 0; }
#scene { flex: 1; min-height: 400px; }
#record { white-space: pre-wrap; font-family: monospace; font-size: 11px;
          background: #f6f6f6; padding: 6px; }
table { border-collapse: collapse; font-size: 12px; }
td, th { border: 1px solid #ccc; padding: 2px 6px; }
label { display: block; }
"""


def figure_div(figure: go.Figure) -> str:
    """The figure as a ``<div id="scene">`` with plotly.js inlined before it."""
    return pio.to_html(
        figure,
        include_plotlyjs=True,
        include_mathjax=False,
        full_html=False,
        div_id="scene",
        config=PLOT_CONFIG,
        default_width="100%",
        default_height="100%",
    )


def page_html(
    title: str, figure: go.Figure | None, side: str, data: dict[str, Any], script: str
) -> str:
    """A whole page: ``side`` (HTML) in the left panel, the figure right of it with the record
    box under it, ``data`` as ``window.SIMGRASP`` and ``script`` run once the figure is drawn."""
    body = figure_div(figure) if figure is not None else ""
    payload = json.dumps(data, separators=(",", ":")).replace("</", "<\\/")
    return f"""<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>{html.escape(title)}</title>
<style>{STYLE}</style></head>
<body><div id="side"><h3>{html.escape(title)}</h3>{side}</div>
<div id="main">{body}<div id="record">click a grasp or a point for its record</div></div>
<script>window.SIMGRASP = {payload};</script>
<script>{script}</script>
</body></html>
"""


def scene_layout(figure: go.Figure, title: str | None = None) -> go.Figure:
    """Equal axis scales in meters, a white background, the legend inside."""
    figure.update_layout(
        scene={
            "aspectmode": "data",
            "xaxis_title": "x (m)",
            "yaxis_title": "y (m)",
            "zaxis_title": "z (m)",
        },
        margin={"l": 0, "r": 0, "t": 30 if title else 0, "b": 0},
        title=title,
        legend={"x": 0.0, "y": 1.0},
        paper_bgcolor="white",
        uirevision="keep",
    )
    return figure


def checkbox(group: str, value: str, text: str, count: int | None = None) -> str:
    """A checked filter box (``data-filter`` names its group, ``value`` what it shows)."""
    shown = f"{text} ({count})" if count is not None else text
    return (
        f'<label><input type="checkbox" checked data-filter="{html.escape(group)}" '
        f'value="{html.escape(value)}"> {html.escape(shown)}</label>'
    )


def table_html(header: list[str], rows: list[list[Any]]) -> str:
    """A plain HTML table of already formatted cells (escaped here)."""
    head = "".join(f"<th>{html.escape(str(h))}</th>" for h in header)
    body = "".join(
        "<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in row) + "</tr>" for row in rows
    )
    return f"<table><tr>{head}</tr>{body}</table>"

"""The page of an ``evaluate`` or ``demo`` output folder: the report's tables and plots and each
trial one click away.

The left panel holds filters (object, setting, outcome), the table of trials (object, setting,
seed, outcome, failure mode, on handle), then ``report.md`` (as HTML) and the folder's plots
(PNGs inlined as ``data:`` URIs). Clicking a row shows the trial's record and draws it (world
frame, meters): the object's mesh at its pose in the trial and the executed grasp as a gripper
wireframe in its outcome color. Meshes are stored once per object in the object's frame and
placed by each record's ``object_pose`` in the page's script. A generated tool's mesh is built
again from its name; a YCB object's only from the local YCB data (``SIMGRASP_YCB_DIR``), so a
page of YCB trials holds the YCB meshes and is not for committing; without the data the trial
is drawn without its object. ``trials.jsonl`` is only read (a torn last line is left out).
"""

from __future__ import annotations

import base64
import html
import json
from collections import Counter
from pathlib import Path
from typing import Any

import numpy as np
import plotly.graph_objects as go

from simgrasp.errors import SimgraspError
from simgrasp.transforms import pose7_to_matrix
from simgrasp.viewer.grasp_page import outcome, wireframes
from simgrasp.viewer.layer_filters import box
from simgrasp.viewer.markdown import markdown_html
from simgrasp.viewer.page import page_html, scene_layout
from simgrasp.viewer.report_script import REPORT_SCRIPT
from simgrasp.viewer.shapes import COLORS

NO_GRASP_COLOR = "#7f7f7f"


def read_trials(path: Path) -> list[dict[str, Any]]:
    """The records of ``path/trials.jsonl`` in file order (read only: a torn last line, which
    the next run cuts off, is left out; any other bad line is one line naming it)."""
    lines = (path / "trials.jsonl").read_text(encoding="utf-8", errors="replace").splitlines()
    records = []
    for number, line in enumerate(lines, start=1):
        if not line.strip():
            continue
        try:
            record = json.loads(line)
        except json.JSONDecodeError:
            if number == len(lines):
                continue
            raise SimgraspError(f"{path}/trials.jsonl line {number} is not a JSON record") from None
        if not isinstance(record, dict) or "object" not in record:
            raise SimgraspError(f"{path}/trials.jsonl line {number} is not a trial record")
        records.append(record)
    return records


def setting_of(record: dict[str, Any]) -> str:
    """The trial's sweep setting: detector, then what is not the default (gripper, sensor,
    perception, clutter), then the noise."""
    parts = [str(record.get("detector", "?"))]
    if record.get("gripper", "builtin") != "builtin":
        parts.append(str(record["gripper"]))
    if record.get("sensor", "ideal") != "ideal":
        parts.append(str(record["sensor"]))
    if record.get("perception") not in (None, "auto", "mask") or record.get("distractors"):
        parts.append(str(record.get("perception")))
    return "+".join(parts) + f" σ{record.get('noise', 0)}"


def trial_outcome(record: dict[str, Any]) -> str:
    return "no_grasp" if record.get("grasp") is None else outcome(record)


def _mesh_payload(name: str, ycb_dir: str | None) -> dict[str, Any] | None:
    """The object's mesh (object frame; vertices in mm as integers to keep the page small),
    or None when it cannot be built here (a YCB object without the local data)."""
    from simgrasp.assets.registry import load_object

    try:
        mesh = load_object(name, ycb_dir).mesh
    except (SimgraspError, FileNotFoundError):
        return None
    vertices = np.round(np.asarray(mesh.vertices) * 1e4).astype(int)  # 0.1 mm
    faces = np.asarray(mesh.faces)
    return {"v": vertices.ravel().tolist(), "f": faces.ravel().tolist(), "scale": 1e-4}


def _wireframe(record: dict[str, Any], geometries: dict[str, Any]) -> list[float] | None:
    """The executed grasp's gripper wireframe (world frame, its 4 segments' ends flattened)."""
    if record.get("grasp") is None:
        return None
    from simgrasp.grippers import make_gripper

    name = record.get("gripper", "builtin")
    if name not in geometries:
        try:
            geometries[name] = make_gripper(name).planning_geometry()
        except SimgraspError:
            geometries[name] = None
    if geometries[name] is None:
        return None
    world_T_tcp = pose7_to_matrix(record["grasp"])[None]
    width = np.array([record.get("grasp_width") or geometries[name].max_opening])
    segments = wireframes(world_T_tcp, width, geometries[name])
    return np.round(segments.ravel(), 5).tolist()


def _row(k: int, record: dict[str, Any]) -> str:
    kind = trial_outcome(record)
    color = COLORS.get(kind, NO_GRASP_COLOR)
    cells = [
        record["object"], setting_of(record), record.get("seed", ""),
        f'<span style="color:white;background:{color};padding:0 3px">{kind}</span>',
        record.get("failure") or "", "yes" if record.get("on_handle") else "no",
    ]  # fmt: skip
    tds = "".join(
        f"<td>{c}</td>" if i == 3 else f"<td>{html.escape(str(c))}</td>"
        for i, c in enumerate(cells)
    )
    attrs = (
        f'data-trial="{k}" data-object="{html.escape(record["object"])}" '
        f'data-setting="{html.escape(setting_of(record))}" data-outcome="{kind}"'
    )
    return f'<tr class="trial" {attrs}>{tds}</tr>'


def _filters(records: list[dict[str, Any]]) -> str:
    out = []
    for group, of in (("object", lambda r: r["object"]), ("setting", setting_of)):
        counts = Counter(of(r) for r in records)
        out.append(f"<h4>{group}</h4>" + "".join(box(group, v, v, n) for v, n in counts.items()))
    counts = Counter(trial_outcome(r) for r in records)
    out.append(
        "<h4>outcome</h4>"
        + "".join(box("outcome", k, k.replace("_", " "), n) for k, n in sorted(counts.items()))
    )
    return "".join(out)


def _plots(path: Path) -> str:
    images = []
    for png in sorted(path.glob("*.png")):
        data = base64.b64encode(png.read_bytes()).decode()
        images.append(
            f'<figure><img alt="{html.escape(png.name)}" style="max-width:100%" '
            f'src="data:image/png;base64,{data}"><figcaption>{html.escape(png.name)}'
            "</figcaption></figure>"
        )
    return "".join(images)


def report_page(path: Path, ycb_dir: str | None = None) -> str:
    """The whole page of the evaluate or demo folder ``path``."""
    records = read_trials(path)
    names = sorted({r.get("object_asset") or r["object"] for r in records})
    meshes = {n: _mesh_payload(n, ycb_dir) for n in names}
    geometries: dict[str, Any] = {}
    views = [
        {
            "mesh": r.get("object_asset") or r["object"],
            "object_pose": r.get("object_pose"),
            "wireframe": _wireframe(r, geometries),
            "color": COLORS.get(trial_outcome(r), NO_GRASP_COLOR),
        }
        for r in records
    ]
    header = "".join(
        f"<th>{h}</th>" for h in ("object", "setting", "seed", "outcome", "failure", "on handle")
    )
    table = f'<table id="trials"><tr>{header}</tr>'
    table += "".join(_row(k, r) for k, r in enumerate(records)) + "</table>"
    side = (
        "<style>#side { width: 46%; }</style>"
        + f"<p>{path}: {len(records)} trials; click a row for its record and 3D view</p>"
        + _filters(records)
        + "<h4>trials</h4>"
        + table
        + '<div id="report">'
        + markdown_html((path / "report.md").read_text(encoding="utf-8"))
        + _plots(path)
        + "</div>"
    )
    figure = scene_layout(go.Figure())
    data = {"records": records, "views": views, "meshes": meshes}
    return page_html(f"{path.name}: {len(records)} trials", figure, side, data, REPORT_SCRIPT)

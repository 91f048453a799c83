"""The page of a trial record (``trial --record --json > t.json``): the table, the object (its
mesh and handle label) and the gripper replayed over the trial with a time slider, the phase
names on it, and the trial's record in the side panel.

World frame, meters, seconds. Each moving body's mesh is sent once in its own frame (the
object's in its mesh frame, the gripper's in its TCP frame, trace ``meta.body`` naming it); the
replay sends per frame only the object's pose, the TCP's pose and the jaw opening, and the
page's script (:mod:`simgrasp.viewer.replay_script`) places the vertices. The gripper is drawn
as its planning geometry (:class:`~simgrasp.grippers.geometry.GripperGeometry`): a palm box and
two finger boxes whose inner faces sit ``opening / 2`` either side of the TCP along its +y:
exactly the built-in gripper's model boxes (``tests/test_trial_page.py``), the boxes the
planner checks for the Robotiq and the Franka hand (simplified, their meshes are not drawn).
"""

from __future__ import annotations

import html
import json
from pathlib import Path
from typing import Any

import numpy as np
import plotly.graph_objects as go
import trimesh
from numpy.typing import NDArray

from simgrasp.errors import SimgraspError
from simgrasp.grippers.geometry import GripperGeometry
from simgrasp.viewer.page import page_html, scene_layout, table_html
from simgrasp.viewer.replay_script import REPLAY_SCRIPT
from simgrasp.viewer.shapes import handle_traces, mesh_trace

RECORD_FIELDS = (
    "object", "gripper", "seed", "detector", "success", "failure", "on_handle",
    "handle_fraction", "lift_height", "slip_lift", "slip_perturb", "grasp_width", "sim_time",
    "handles", "grasp_candidates",
)  # fmt: skip
"""The record's fields in the side panel's table (the whole record, less the replay, is in the
record box)."""
TABLE_HALF = 0.3
"""Half size (m) of the piece of table drawn around the object's start."""
GRIPPER_COLOR = "#5b6f8a"


def read_trial(path: Path) -> dict[str, Any]:
    """The trial record at ``path``, with its replay (one-line errors otherwise)."""
    try:
        record = json.loads(path.read_text())
    except json.JSONDecodeError:
        raise SimgraspError(f"{path}: not a JSON trial record") from None
    if "replay" not in record:
        raise SimgraspError(
            f"{path}: the trial record has no replay states; rerun the trial with --record "
            f"(simgrasp trial {record.get('object', 'OBJECT')} ... --record --json > {path.name})"
        )
    if not record["replay"]:
        raise SimgraspError(
            f"{path}: no grasp was executed in this trial (failure {record['failure']}): "
            "nothing to replay"
        )
    return record


def box_vertices(low: NDArray[np.float64], high: NDArray[np.float64]) -> trimesh.Trimesh:
    """An axis-aligned box from corner ``low`` to corner ``high``."""
    box = trimesh.creation.box(extents=high - low)
    return box.apply_translation((low + high) / 2)


def gripper_mesh(geometry: GripperGeometry) -> tuple[trimesh.Trimesh, NDArray[np.int8]]:
    """The gripper's boxes in its TCP frame at opening 0, and each vertex's side (-1 left
    finger, +1 right, 0 palm): a vertex's y moves by ``side * opening / 2``."""
    half_x, back = geometry.finger_width / 2, -geometry.finger_length
    palm_x, palm_y, palm_z = (v / 2 for v in geometry.palm_size)
    palm = box_vertices(
        np.array([-palm_x, -palm_y, back - 2 * palm_z]), np.array([palm_x, palm_y, back])
    )
    fingers = [
        box_vertices(
            np.array([-half_x, min(0.0, side * geometry.finger_thickness), back]),
            np.array([half_x, max(0.0, side * geometry.finger_thickness), geometry.pad_reach]),
        )
        for side in (-1, 1)
    ]
    sides = np.concatenate([np.zeros(len(palm.vertices)), -np.ones(8), np.ones(8)]).astype(np.int8)
    boxes = trimesh.util.concatenate([palm, *fingers])
    assert isinstance(boxes, trimesh.Trimesh)
    return boxes, sides


def scene_ranges(record: dict[str, Any], radius: float) -> dict[str, list[float]]:
    """Fixed axis ranges (m, world frame) holding the object and the gripper over the whole
    replay (so the view does not rescale while it plays) and the table top under them."""
    replay = record["replay"]
    centers = np.array([p[:3] for p in replay["object_pose"] + replay["tcp_pose"]])
    reach = radius + 0.02
    low, high = centers.min(axis=0) - reach, centers.max(axis=0) + reach
    top = replay["table"]["center"][2] + replay["table"]["half_size"][2]
    low[2] = min(low[2], top - 0.03)
    return {axis: [float(low[k]), float(high[k])] for k, axis in enumerate("xyz")}


def table_trace(record: dict[str, Any]) -> go.Mesh3d:
    """The top 1 cm of the table box, the piece under the object's start (world frame)."""
    table = record["replay"]["table"]
    center, half = np.array(table["center"]), np.array(table["half_size"])
    start = np.array(record["replay"]["object_pose"][0][:3])
    cut = np.minimum(half[:2], TABLE_HALF)
    low = np.array([*(start[:2] - cut), center[2] + half[2] - 0.01])
    high = np.array([*(start[:2] + cut), center[2] + half[2]])
    return mesh_trace(box_vertices(low, high), name="table", color="#c8b48c")


def trial_figure(record: dict[str, Any], asset: Any) -> tuple[go.Figure, NDArray[np.int8]]:
    """The figure (table, object, handle label, gripper, TCP path) and the gripper vertices'
    sides; the moving traces in their own frames (module docstring)."""
    replay = record["replay"]
    geometry = GripperGeometry(
        **{**replay["gripper"], "palm_size": tuple(replay["gripper"]["palm_size"])}
    )
    gripper, sides = gripper_mesh(geometry)
    figure = go.Figure([table_trace(record)])
    figure.add_trace(mesh_trace(asset.mesh, name=asset.name, meta={"body": "object"}))
    for trace in handle_traces(asset.handle, np.eye(4)):
        figure.add_trace(trace.update(meta={"body": "object"}))
    figure.add_trace(
        mesh_trace(gripper, name=f"gripper ({record['gripper']})", color=GRIPPER_COLOR,
                   meta={"body": "gripper"})
    )  # fmt: skip
    path = np.array([p[:3] for p in replay["tcp_pose"]])
    figure.add_trace(
        go.Scatter3d(
            x=path[:, 0], y=path[:, 1], z=path[:, 2], mode="lines", name="TCP path",
            line={"color": "#ff7f0e", "width": 3, "dash": "dot"}, hoverinfo="skip",
        )
    )  # fmt: skip
    radius = max(
        float(np.linalg.norm(asset.mesh.vertices, axis=1).max()),
        float(np.linalg.norm(gripper.vertices, axis=1).max()) + geometry.max_opening / 2,
    )
    ranges = scene_ranges(record, radius)
    scene_layout(figure)
    spans = [high - low for low, high in ranges.values()]
    figure.update_layout(
        scene={
            **{f"{axis}axis": {"range": ranges[axis], "autorange": False} for axis in "xyz"},
            "aspectmode": "manual",
            "aspectratio": dict(zip("xyz", (s / max(spans) for s in spans), strict=True)),
        }
    )
    return figure, sides


def _side_panel(record: dict[str, Any]) -> str:
    replay = record["replay"]
    markers = "".join(
        f'<span style="position:absolute;left:{_share(replay, p["t"]):.1f}%" '
        f'title="{html.escape(p["name"])} at {p["t"]:.2f} s">|</span>'
        for p in replay["phases"]
    )
    rows = [[key, _cell(record[key])] for key in RECORD_FIELDS if key in record]
    return (
        '<div><button id="play" type="button">play</button> '
        '<span id="time">t = 0.00 s</span></div>'
        f'<input id="slider" type="range" min="0" max="{len(replay["t"]) - 1}" value="0" '
        'step="1" style="width:100%">'
        f'<div style="position:relative;height:14px">{markers}</div>'
        '<p>phase: <b id="phase"></b></p>'
        "<h4>phases</h4>"
        + table_html(
            ["phase", "from (s)"], [[p["name"], f"{p['t']:.2f}"] for p in replay["phases"]]
        )
        + "<h4>trial record</h4>"
        + table_html(["field", "value"], rows)
    )


def _share(replay: dict[str, Any], time: float) -> float:
    """Where ``time`` (s) falls on the slider, in percent of its length."""
    first, last = replay["t"][0], replay["t"][-1]
    return 100.0 * min(max((time - first) / max(last - first, 1e-9), 0.0), 1.0)


def _cell(value: Any) -> str:
    return f"{value:.4g}" if isinstance(value, float) else str(value)


def trial_page(path: Path, ycb_dir: str | None = None) -> str:
    """The whole page of the trial record at ``path``."""
    from simgrasp.assets.registry import load_object

    record = read_trial(path)
    asset = load_object(record["object"], ycb_dir)
    figure, sides = trial_figure(record, asset)
    verdict = {True: "held", False: f"failed ({record['failure']})", None: "sim unstable"}
    title = f"{asset.name}: trial seed {record['seed']}, {verdict[record['success']]}"
    replay = record["replay"]
    data = {
        "replay": {k: replay[k] for k in ("t", "object_pose", "tcp_pose", "opening", "phases")},
        "rate_hz": replay["rate_hz"],
        "gripper_side": sides.tolist(),
        "record": {k: v for k, v in record.items() if k != "replay"},
    }
    return page_html(title, figure, _side_panel(record), data, REPLAY_SCRIPT)

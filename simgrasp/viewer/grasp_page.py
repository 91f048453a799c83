"""The page of a ``label-grasps`` output folder: the object, its handle label and every grasp
as a gripper wireframe colored by outcome, with filters and each grasp's record.

Object frame (the mesh's, meters). Grasps are read back from ``labels.jsonl`` (each record holds
its world TCP pose and the object's world pose; ``invalid`` rows, never executed, and
``sim_unstable`` ones are not drawn). One line trace and one TCP marker trace per (outcome,
failure mode): held on the handle green, held elsewhere blue, failed red, as ``labels.png``.
"""

from __future__ import annotations

import json
import sys
from collections import Counter
from pathlib import Path
from typing import Any

import numpy as np
import plotly.graph_objects as go
from numpy.typing import NDArray

from simgrasp.errors import SimgraspError
from simgrasp.grippers.geometry import GripperGeometry
from simgrasp.transforms import invert_transform, pose7_to_matrix
from simgrasp.viewer.page import checkbox, page_html, scene_layout
from simgrasp.viewer.scripts import FILTER_SCRIPT
from simgrasp.viewer.shapes import COLORS, handle_traces, lines_trace, mesh_trace

RECORD_FIELDS = (
    "index", "success", "failure", "on_handle", "handle_fraction", "lift_height",
    "slip_lift", "slip_perturb", "grasp", "grasp_width", "sim_time",
)  # fmt: skip
"""The fields of a label record shown on click (contact points and timings left out)."""


def read_labels(path: Path) -> tuple[dict[str, Any], list[dict[str, Any]]]:
    """``run.json`` and the drawable label records of a label-grasps folder."""
    run = json.loads((path / "run.json").read_text())
    records = []
    lines = (path / "labels.jsonl").read_text().splitlines()
    for number, line in enumerate(lines, start=1):
        if not line.strip():
            continue
        try:
            record = json.loads(line)
        except json.JSONDecodeError:
            if number == len(lines):  # a killed run's last line: label-grasps rewrites it
                print(f"note: {path}/labels.jsonl: left out a torn last line", file=sys.stderr)
                continue
            raise SimgraspError(f"{path}/labels.jsonl line {number} is not JSON") from None
        if "grasp" in record and record["failure"] not in ("invalid", "sim_unstable"):
            records.append(record)
    return run, records


def outcome(record: dict[str, Any]) -> str:
    if record["success"]:
        return "on_handle" if record["on_handle"] else "off_handle"
    return "failed"


def _group(record: dict[str, Any]) -> tuple[str, str]:
    """(outcome, failure mode or ``held``) of a record: its trace pair."""
    return outcome(record), record["failure"] or "held"


def wireframes(
    object_T_tcp: NDArray[np.float64], widths: NDArray[np.float64], geometry: GripperGeometry
) -> NDArray[np.float64]:
    """(N, 4, 2, 3) segments per grasp (object frame): both fingers from their tips to the
    palm, the bar joining them, a stem back through the palm."""
    count = len(widths)
    half, tip, back = widths / 2, geometry.pad_reach, -geometry.finger_length
    stem = back - geometry.palm_size[2]
    points = np.zeros((count, 4, 2, 3))
    points[:, 0, :, 1] = -half[:, None]
    points[:, 1, :, 1] = half[:, None]
    points[:, 0:2, 0, 2], points[:, 0:2, 1, 2] = tip, back
    points[:, 2, 0, 1], points[:, 2, 1, 1] = -half, half
    points[:, 2, :, 2] = back
    points[:, 3, 0, 2], points[:, 3, 1, 2] = back, stem
    rotated = np.einsum("nij,nksj->nksi", object_T_tcp[:, :3, :3], points)
    return rotated + object_T_tcp[:, None, None, :3, 3]


def object_frame_grasps(records: list[dict[str, Any]]) -> NDArray[np.float64]:
    """(N, 4, 4) ``object_T_tcp`` of each record (from its world TCP and object poses)."""
    return np.stack(
        [
            invert_transform(pose7_to_matrix(r["object_pose"])) @ pose7_to_matrix(r["grasp"])
            for r in records
        ]
    ).reshape(-1, 4, 4)


def grasp_figure(
    asset: Any, records: list[dict[str, Any]], geometry: GripperGeometry
) -> tuple[go.Figure, Counter[tuple[str, str]]]:
    """The figure (object, handle label, one trace pair per outcome and failure) and the
    count of each group."""
    figure = go.Figure([mesh_trace(asset.mesh, name=asset.name)])
    figure.add_traces(handle_traces(asset.handle, np.eye(4)))
    groups = Counter(_group(r) for r in records)
    if records:
        segments = wireframes(
            object_frame_grasps(records), np.array([r["grasp_width"] for r in records]), geometry
        )
    for kind, failure in sorted(groups):
        chosen = [i for i, r in enumerate(records) if _group(r) == (kind, failure)]
        name = f"{kind.replace('_', ' ')}: {failure.replace('_', ' ')} ({len(chosen)})"
        meta = {"outcome": kind, "failure": failure}
        group = f"{kind}/{failure}"
        figure.add_trace(
            lines_trace(segments[chosen], name, COLORS[kind], meta=meta, legendgroup=group)
        )
        tcp = segments[chosen, 2].mean(axis=1)  # the middle of the bar behind the fingers
        figure.add_trace(
            go.Scatter3d(
                x=tcp[:, 0], y=tcp[:, 1], z=tcp[:, 2], mode="markers",
                marker={"size": 2.5, "color": COLORS[kind]}, name=name, showlegend=False,
                legendgroup=group, meta=meta,
                customdata=[records[i]["index"] for i in chosen],
                hovertemplate="grasp %{customdata}<extra>" + name + "</extra>",
            )
        )  # fmt: skip
    return figure, groups


def grasp_page(path: Path, ycb_dir: str | None = None) -> str:
    """The whole page of the label-grasps folder ``path``."""
    from simgrasp.assets.registry import load_object
    from simgrasp.grippers import make_gripper

    run, records = read_labels(path)
    asset = load_object(run["object"], ycb_dir)
    geometry = make_gripper(run["gripper"]).planning_geometry()
    figure, groups = grasp_figure(asset, records, geometry)
    title = f"{asset.name}: {len(records)} grasps ({run['gripper']}, {run['protocol']})"
    scene_layout(figure)
    kinds: Counter[str] = Counter()
    failures: Counter[str] = Counter()
    for (kind, failure), count in groups.items():
        kinds[kind] += count
        failures[failure] += count
    side = (
        "<h4>outcome</h4>"
        + "".join(checkbox("outcome", k, k.replace("_", " "), n) for k, n in sorted(kinds.items()))
        + "<h4>failure mode</h4>"
        + "".join(
            checkbox("failure", f, f.replace("_", " "), n) for f, n in sorted(failures.items())
        )
        + f"<p>protocol {run['protocol']}, seed {run['seed']}, placement {run['placement']}</p>"
    )
    shown = {r["index"]: {k: r.get(k) for k in RECORD_FIELDS} for r in records}
    return page_html(title, figure, side, {"records": shown}, FILTER_SCRIPT)

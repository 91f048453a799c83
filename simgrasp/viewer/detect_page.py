"""The page of a ``simgrasp detect CLOUD --json > d.json`` result, drawn over its input cloud.

The JSON's ``input`` (written by ``detect --json``) names the cloud by its resolved path and
its units; a cloud moved together with its JSON is found beside it by name. With ``--segment``
the input records the segmentation settings too, and the scene is segmented again here (the
same deterministic call) to color its points per segment; the objects found are checked
against the recorded ones. Cloud frame, meters. Layers: the points (at most
:data:`MAX_POINTS`, a seeded subsample keeping a scene's object points first; the panel says
so), the candidates (neighborhood centers, one marker trace per quadric kind, and their axes
as short segments), the handles (the axis over the stretch its candidates cover, and the
center marked with the score), and the segments; each has a check box, and so has each
quadric kind.
"""

from __future__ import annotations

import json
from collections import Counter
from pathlib import Path
from typing import Any

import numpy as np
import plotly.graph_objects as go
from numpy.typing import NDArray

from simgrasp.errors import SimgraspError
from simgrasp.viewer.layer_filters import LAYER_SCRIPT, apply_initial, box, filters_meta
from simgrasp.viewer.page import page_html, scene_layout
from simgrasp.viewer.shapes import lines_trace

MAX_POINTS = 40_000
"""Points drawn at most (a seeded subsample of a larger cloud)."""
KIND_COLORS = {
    "real_ellipsoid": "#9467bd",
    "hyperboloid_one_sheet": "#17becf",
    "real_elliptic_cylinder": "#ff7f0e",
    "cylinder_shell": "#8c564b",
}
"""Candidate colors per quadric kind (tab: purple, cyan, orange; brown for ten Pas's shells);
any other kind is pink."""
OTHER_KIND = "#e377c2"
HANDLE_COLOR = "#d62728"
SEGMENT_COLORS = ("#2ca02c", "#1f77b4", "#bcbd22", "#98df8a", "#aec7e8", "#dbdb8d", "#ffbb78")
"""Object segments, label 2 first (cycled): greens, blues and olives, none a kind's color."""
TABLE_COLOR = "#c7c7c7"
AXIS_HALF_M = 0.008
"""Half length of a drawn candidate axis (m)."""


def _report_or_none(path: Path) -> dict[str, Any] | None:
    try:
        report = json.loads(path.read_text())
    except (json.JSONDecodeError, UnicodeDecodeError):
        return None
    keys = ("detector", "handles", "candidates")
    return report if isinstance(report, dict) and all(k in report for k in keys) else None


def input_cloud(path: Path, report: dict[str, Any]) -> Path:
    """The recorded input cloud of the detection JSON ``path``, or the file of that name
    beside it, with the bytes it was detected on where the report records their SHA-256; one
    line naming what is missing or changed otherwise."""
    from simgrasp.runs.identity import file_digest

    recorded = report.get("input", {}).get("path")
    if recorded is None:
        raise SimgraspError(
            f"{path}: records no input cloud (written before `detect --json` kept it); "
            "run `simgrasp detect CLOUD --json` again"
        )
    digest = report["input"].get("sha256")
    changed = []
    for candidate in (Path(recorded), path.parent / Path(recorded).name):
        if not candidate.is_file():
            continue
        if digest is None or file_digest(candidate) == digest:
            return candidate
        changed.append(candidate)
    if changed:
        raise SimgraspError(
            f"{path}: its input cloud {changed[0]} changed since the detection; run "
            "`simgrasp detect CLOUD --json` again"
        )
    raise SimgraspError(
        f"{path}: its input cloud {recorded} is gone (and no {Path(recorded).name} beside it)"
    )


def _scene_points(cloud: Path, report: dict[str, Any]) -> tuple[NDArray[np.float64], Any]:
    """(N, 3) points (m) and, for a ``--segment`` detection, the segmentation labels (N,)."""
    from simgrasp.perception.cloud_file import MeshReadConfig, read_object_cloud
    from simgrasp.perception.depth_image import DepthImageConfig

    record = report["input"]
    settings = record.get("segmentation")
    depth = DepthImageConfig(**record.get("depth", {}))
    if settings is None:
        mesh = MeshReadConfig(**record.get("mesh", {}))
        units, seed = record.get("units", "m"), record.get("seed", 0)
        points, _ = read_object_cloud(cloud, units, depth, mesh, seed)
        return points, None
    from simgrasp.perception.scene_cloud import read_scene
    from simgrasp.perception.segmentation.segment import segment_scene
    from simgrasp.perception.segmentation.segment_config import SegmentConfig

    scene = read_scene(cloud, depth)
    segmentation = segment_scene(scene, SegmentConfig(**settings))
    found = [o.label for o in segmentation.objects]
    recorded = [o["label"] for o in report["segmentation"]["objects"]]
    if found != recorded:
        raise SimgraspError(
            f"{cloud}: segments into objects {found} now, the detection recorded {recorded}"
        )
    return scene.points.astype(np.float64), segmentation.labels


def _subsample(first: NDArray[np.bool_], limit: int = MAX_POINTS) -> NDArray[np.int64]:
    """Indices of at most ``limit`` points, sorted: the ``first`` ones (the objects of a
    scene) before the rest (its table), each drawn by a seeded subsample when too many."""
    rng = np.random.default_rng(0)
    chosen: list[NDArray[np.int64]] = []
    for group in (np.flatnonzero(first), np.flatnonzero(~first)):
        room = limit - int(sum(len(c) for c in chosen))
        chosen.append(group if len(group) <= room else rng.choice(group, room, replace=False))
    return np.sort(np.concatenate(chosen))


def _points_trace(
    points: NDArray[np.float64], name: str, color: str, size: float = 1.6, **extra: Any
) -> go.Scatter3d:
    p = points.astype(np.float32)
    return go.Scatter3d(
        x=p[:, 0], y=p[:, 1], z=p[:, 2], mode="markers", name=name, hoverinfo="skip",
        marker={"size": size, "color": color}, **extra,
    )  # fmt: skip


def point_traces(points: NDArray[np.float64], labels: Any) -> list[go.Scatter3d]:
    """The plain points (layer ``points``) and, with labels, the table and each segment
    (layer ``segments``; one trace per label, meta ``segment``)."""
    traces = [_points_trace(points, "points", "#7f7f7f", meta=filters_meta(layer="points"))]
    if labels is None:
        return traces
    for label in sorted(set(np.unique(labels).tolist()) - {0}):
        color = TABLE_COLOR if label == 1 else SEGMENT_COLORS[(label - 2) % len(SEGMENT_COLORS)]
        name = "table" if label == 1 else f"object {label}"
        meta = filters_meta(layer="segments", segment=label)
        size = 1.2 if label == 1 else 2.5
        traces.append(_points_trace(points[labels == label], name, color, size, meta=meta))
    return traces


def candidate_traces(candidates: list[dict[str, Any]]) -> list[go.Scatter3d]:
    """Per quadric kind: the centers (click: the candidate's record) and the axes."""
    traces = []
    for kind in sorted({c["kind"] for c in candidates}):
        chosen = [i for i, c in enumerate(candidates) if c["kind"] == kind]
        color = KIND_COLORS.get(kind, OTHER_KIND)
        centers = np.array([candidates[i]["center"] for i in chosen])
        axes = np.array([candidates[i]["axis"] for i in chosen])
        name = f"{kind.replace('_', ' ')} ({len(chosen)})"
        traces.append(
            go.Scatter3d(
                x=centers[:, 0], y=centers[:, 1], z=centers[:, 2], mode="markers", name=name,
                marker={"size": 3.5, "color": color}, customdata=[f"c{i}" for i in chosen],
                hovertemplate="candidate %{customdata}<extra>" + kind + "</extra>",
                meta=filters_meta(layer="candidates", kind=kind), legendgroup=kind,
            )
        )  # fmt: skip
        segments = np.stack([centers - AXIS_HALF_M * axes, centers + AXIS_HALF_M * axes], axis=1)
        meta = filters_meta(layer="axes", kind=kind)
        traces.append(
            lines_trace(segments, name, color, 3, meta=meta, legendgroup=kind, showlegend=False)
        )
    return traces


def handle_traces(handles: list[dict[str, Any]]) -> list[go.Scatter3d]:
    """Each handle's axis over its span (or one width either side) and its center with the
    score (click: the handle's record)."""
    if not handles:
        return []
    segments, centers = [], []
    for h in handles:
        center, axis = np.array(h["center"]), np.array(h["axis"])
        low, high = h.get("span", (-h["width"], h["width"]))
        segments.append([center + min(low, -0.005) * axis, center + max(high, 0.005) * axis])
        centers.append(center)
    meta = filters_meta(layer="handles")
    name = f"handles ({len(handles)})"
    line = lines_trace(np.array(segments), name, HANDLE_COLOR, 8, meta=meta, legendgroup="h")
    at = np.array(centers)
    marker = go.Scatter3d(
        x=at[:, 0], y=at[:, 1], z=at[:, 2], mode="markers+text", name=name, showlegend=False,
        marker={"size": 5, "color": HANDLE_COLOR}, text=[f"{h['score']:.2f}" for h in handles],
        customdata=[f"h{i}" for i in range(len(handles))], meta=meta, legendgroup="h",
        hovertemplate="handle %{customdata}, score %{text}<extra></extra>",
    )  # fmt: skip
    return [line, marker]


def _side(report: dict[str, Any], cloud: Path, shown: int, total: int, segmented: bool) -> str:
    kinds = Counter(c["kind"] for c in report["candidates"])
    layers = [("points", "points", not segmented), ("segments", "segments", True)]
    layers = layers if segmented else layers[:1]
    layers += [("candidates", "candidate centers", True), ("axes", "candidate axes", True)]
    layers += [("handles", "handles (score)", True)]
    text = f"{shown} of {total} points shown" + (" (seeded subsample)" if shown < total else "")
    return (
        f"<p>{cloud}</p><p>{text}; detector {report['detector']}, "
        f"{len(report['candidates'])} candidates, {len(report['handles'])} handles</p>"
        + "<h4>layers</h4>"
        + "".join(box("layer", v, t, checked=c) for v, t, c in layers)
        + "<h4>quadric kind</h4>"
        + "".join(box("kind", k, k.replace("_", " "), n) for k, n in sorted(kinds.items()))
    )


def detect_page(path: Path) -> str:
    """The whole page of the detection JSON ``path``."""
    report = _report_or_none(path)
    if report is None:
        raise SimgraspError(f"{path}: not a `simgrasp detect --json` output")
    cloud = input_cloud(path, report)
    points, labels = _scene_points(cloud, report)
    finite = np.isfinite(points).all(axis=1)
    objects = np.zeros(int(finite.sum()), bool) if labels is None else labels[finite] >= 2
    chosen = _subsample(objects)
    kept = points[finite][chosen]
    figure = go.Figure(point_traces(kept, None if labels is None else labels[finite][chosen]))
    figure.add_traces(candidate_traces(report["candidates"]))
    figure.add_traces(handle_traces(report["handles"]))
    segmented = labels is not None
    apply_initial(figure, {("layer", "points")} if segmented else set())
    scene_layout(figure)
    records = {f"c{i}": c for i, c in enumerate(report["candidates"])}
    records.update({f"h{i}": h for i, h in enumerate(report["handles"])})
    title = f"{cloud.name}: {len(report['handles'])} handles ({report['detector']})"
    side = _side(report, cloud, len(kept), int(finite.sum()), segmented)
    script = LAYER_SCRIPT + "whenDrawn(gd => { document.querySelectorAll('input[data-filter]')"
    script += ".forEach(b => b.addEventListener('change', () => applyLayers(gd)));"
    script += " onRecordClick(gd); });\n"
    return page_html(title, figure, side, {"records": records}, script)

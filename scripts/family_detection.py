"""Handle detection on the tool families, seen in simulation: per family kind, candidate
accuracy and top-handle rate with an ideal and a Kinect-class sensor, on single views and on
fused clouds.

Each object (``gen_<kind>_s<N>`` for the seeds asked; seeds from 100 on were never used to
train or tune anything) is placed on the table as the sweeps place it (``--placement``:
``stable``, a rest pose drawn by its probability, or ``upright``), seen by the chain's four
cameras (``simgrasp.scenes``: MuJoCo rendering, the CoACD model from the cache), each depth
image passed through the sensor model. A single view is one camera's pixels of the object
(each of the four cameras is one run); the fused cloud is the four views fused, as the grasp
chain plans on. Detection is what ``simgrasp detect`` runs by default
(:func:`simgrasp.api.detect_handles`) on a single view, seen from its camera: the
single-view detector. On the fused cloud, with normals toward the cameras, it is what the
grasp chain runs (``simgrasp evaluate``): the quadric detector's preset ``two_scales``
(:mod:`simgrasp.handles.presets`). Scored in the object's
frame against its exact label: candidate accuracy (share of candidate centers on the handle,
pooled over runs) and whether the top-ranked handle's center is on it. Rows go to
``rows.jsonl`` as they finish (a rerun keeps the whole scenes made under the same detector
settings, classifier and meshes); ``family_detection.md`` is the table.

    python scripts/family_detection.py --seeds 100,101,102 --out docs/results/families/detection
"""

from __future__ import annotations

import hashlib
import json
from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from generated_labels import add_row, kept_rows, mesh_key

from simgrasp.assets.families import FAMILY_KINDS
from simgrasp.assets.generated import ALL_GENERATED_KINDS
from simgrasp.assets.placement import PLACEMENTS, Placement
from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked
from simgrasp.config.values import to_plain
from simgrasp.errors import SimgraspError
from simgrasp.handles.presets import chain_quadric, single_view_preset
from simgrasp.runs.identity import file_digest

SENSORS = ("ideal", "kinect")
VIEWS = 4
FUSED = chain_quadric()
"""The fused cloud's detector: the grasp chain's (the preset ``two_scales``)."""
SCENE_ROWS = len(SENSORS) * (VIEWS + 1)
"""Rows of one scene: per sensor, each single view and the fused cloud."""


def settings_key() -> str:
    """The detector defaults and the classifier file the rows were made with."""
    single = single_view_preset()
    given = {
        "fused": to_plain(FUSED),
        "single_view": to_plain(single),
        "classifier": file_digest(single.classifier_path()) if single.classifier else None,
    }
    return hashlib.sha256(json.dumps(given, sort_keys=True).encode()).hexdigest()[:16]


def _score(detection: Any, object_T_world: np.ndarray, label: Any) -> dict[str, Any]:
    """Candidates, candidates on the label, handles and whether the top one is on it."""
    moved = detection.moved(object_T_world)
    centers = moved.candidate_centers
    top = moved.handles[0].center[None] if moved.handles else np.zeros((0, 3))
    return {
        "candidates": len(centers),
        "on_handle": int(label.contains(centers).sum()) if len(centers) else 0,
        "handles": len(moved.handles),
        "top_on_handle": bool(label.contains(top).any()),
    }


def measure_scene(
    kind: str, seed: int, placement: Placement, renderers: Any
) -> list[dict[str, Any]]:
    """The rows of one object seen in one scene (rendered by the ``renderers``, a
    :class:`~simgrasp.scenes.kept_renderer.RendererKeeper`): per sensor, each single view and
    the fused cloud (see the module doc)."""
    from simgrasp.api import detect_handles
    from simgrasp.assets.model import model_for
    from simgrasp.grippers import make_gripper
    from simgrasp.perception.sensors.settings import SensorSettings
    from simgrasp.scenes.config import SceneConfig
    from simgrasp.scenes.observe import (
        CLOUD_VOXEL,
        object_cloud,
        render_views,
        sensed_views,
        viewpoint_normals,
    )
    from simgrasp.scenes.scene import build_scene

    model = model_for(f"gen_{kind}_s{seed}")
    scene = build_scene(
        model, make_gripper("builtin"), SceneConfig(num_views=VIEWS, placement=placement), seed
    )
    object_T_world = np.linalg.inv(scene.world_T_object)
    frames = render_views(scene, renderers.renderer_for(scene))
    rows = []
    for sensor in SENSORS:
        seen = sensed_views(frames, SensorSettings(kind=sensor), seed)
        for view in (*range(VIEWS), "fused"):
            chosen = seen if view == "fused" else [seen[view]]
            cloud = object_cloud(chosen, [scene.object_body], voxel_size=CLOUD_VOXEL)
            row = {"sensor": sensor, "view": view, "points": len(cloud)}
            if len(cloud) < 50:
                row.update(candidates=0, on_handle=0, handles=0, top_on_handle=False)
            elif view == "fused":
                normals = viewpoint_normals(cloud)
                found = detect_handles(
                    cloud.points_world, normals, config=FUSED, seed=seed, single_view=False
                )
                row.update(_score(found, object_T_world, model.asset.handle))
            else:
                eye = cloud.viewpoints_world[0]
                found = detect_handles(cloud.points_world, seed=seed, viewpoint=eye)
                row.update(_score(found, object_T_world, model.asset.handle))
            rows.append(row)
    return rows


def _cell(rows: list[dict[str, Any]]) -> str:
    """Pooled candidate accuracy and (top handles on the handle / runs)."""
    candidates = sum(r["candidates"] for r in rows)
    accuracy = f"{sum(r['on_handle'] for r in rows) / candidates:.2f}" if candidates else "—"
    return f"{accuracy} ({sum(r['top_on_handle'] for r in rows)}/{len(rows)})"


def table(rows: list[dict[str, Any]]) -> str:
    """Per kind and placement: a cell per sensor x single view / fused cloud."""
    heads = [f"{s} {v}" for s in SENSORS for v in ("single views", "fused")]
    lines = ["| kind | placement | " + " | ".join(heads) + " |", "|---" * (2 + len(heads)) + "|"]
    groups = dict.fromkeys((r["kind"], r["placement"]) for r in rows)
    for kind, placement in groups:
        chosen = [r for r in rows if r["kind"] == kind and r["placement"] == placement]
        cells = [
            _cell([r for r in chosen if r["sensor"] == s and (r["view"] == "fused") == fused])
            for s in SENSORS
            for fused in (False, True)
        ]
        lines.append(f"| {kind} | {placement} | " + " | ".join(cells) + " |")
    cells = [
        _cell([r for r in rows if r["sensor"] == s and (r["view"] == "fused") == fused])
        for s in SENSORS
        for fused in (False, True)
    ]
    lines.append("| **all** | | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    kinds: tuple[str, ...] = FAMILY_KINDS
    """Generated kinds to measure."""
    seeds: tuple[int, ...] = (100, 101, 102)
    """Object (and scene) seeds."""
    placements: tuple[str, ...] = ("stable",)
    """Rest-pose policies (stable, upright)."""
    upright_kinds: tuple[str, ...] = ("cup", "jug", "kettle")
    """Kinds also measured standing upright (beside --placements)."""
    out: Path = Path("docs/results/families/detection")
    """Folder of ``rows.jsonl`` and ``family_detection.md``."""


def _plan(options: Options) -> list[tuple[str, int, Placement]]:
    """Every (kind, seed, placement) asked for."""
    unknown = [k for k in (*options.kinds, *options.upright_kinds) if k not in ALL_GENERATED_KINDS]
    bad = [p for p in options.placements if p not in PLACEMENTS]
    if unknown or bad:
        raise SimgraspError(f"unknown kinds {unknown} or placements {bad}")
    plan = []
    for kind in options.kinds:
        places = list(options.placements)
        if kind in options.upright_kinds and "upright" not in places:
            places.append("upright")
        plan += [(kind, seed, p) for p in places for seed in options.seeds]
    return plan  # type: ignore[return-value]


def _measure(
    path: Path,
    done: list[dict[str, Any]],
    scene: tuple[str, int, Placement],
    renderers: Any,
    mesh: str,
    key: str,
) -> None:
    """Measure one scene and append its rows (a scene torn by a kill is measured again)."""
    kind, seed, placement = scene
    for row in measure_scene(kind, seed, placement, renderers):
        named = {"object": f"gen_{kind}_s{seed}", "kind": kind, "seed": seed}
        full = {**named, "placement": placement, **row, "mesh": mesh, "settings": key}
        done.append(full)
        add_row(path, full)


def run(options: Options) -> str:
    """Measure every scene not yet in ``rows.jsonl`` under these settings; the table."""
    from simgrasp.assets.generated import generate_tool
    from simgrasp.scenes.kept_renderer import RendererKeeper

    key = settings_key()
    options.out.mkdir(parents=True, exist_ok=True)
    path = options.out / "rows.jsonl"
    meshes: dict[tuple[str, int], str] = {}

    def mesh_of(kind: str, seed: int) -> str:
        if (kind, seed) not in meshes:
            meshes[kind, seed] = mesh_key(generate_tool(kind, seed))
        return meshes[kind, seed]

    done = kept_rows(
        path, lambda r: r.get("settings") == key and r["mesh"] == mesh_of(r["kind"], r["seed"])
    )
    counts = Counter((r["kind"], r["seed"], r["placement"]) for r in done)
    have = {scene for scene, count in counts.items() if count == SCENE_ROWS}
    done = [r for r in done if (r["kind"], r["seed"], r["placement"]) in have]
    plan = _plan(options)
    with RendererKeeper() as renderers:
        for kind, seed, placement in plan:
            if (kind, seed, placement) not in have:
                _measure(path, done, (kind, seed, placement), renderers, mesh_of(kind, seed), key)
    wanted = {(k, s, p) for k, s, p in plan}
    text = table([r for r in done if (r["kind"], r["seed"], r["placement"]) in wanted])
    (options.out / "family_detection.md").write_text(text)
    return text


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    raise SystemExit(main())

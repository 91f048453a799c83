"""The ToolKinect scans turned about their viewing axis: whether ``simgrasp detect``'s verdict
on a scan depends on the camera's roll.

Each scan of ``$SIMGRASP_REAL_DIR/toolkinect`` (its points and normals as ``detect`` reads
them, no viewpoint given: a one-sided scan is one view from its frame's origin) is turned by
0, 30, ..., 330 degrees about the line from the origin through its centroid, detected with
``simgrasp detect``'s default (seed 0; ``--grid-rolls``
voxel grids pooled, 1 the view's own grid), the candidates turned back and scored against
``models/handles/toolkinect_handles.json``. One JSON line per scan: top handles on the handle
over the rolls, pooled accuracy, the detectors that ran, and each roll's (candidates, on the
handle, top on it).

    SIMGRASP_REAL_DIR=../shared/real python scripts/roll_survey_scans.py --grid-rolls 1
"""

from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np

from simgrasp.assets.real import default_real_dir
from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked, PositiveInt
from simgrasp.handles import detect
from simgrasp.handles.detector_config import DetectorConfig
from simgrasp.handles.presets import single_view_preset
from simgrasp.handles.single_view.grid_rolls import roll_about
from simgrasp.labels import load_label_file
from simgrasp.perception.cloud_io import read_cloud
from simgrasp.resources import model_path


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    grid_rolls: PositiveInt = 1
    """Voxel grids the single-view detector pools (the default's setting replaced)."""
    rolls: PositiveInt = 12
    """Camera rolls per scan, evenly over a turn."""
    seed: int = 0


def run(options: Options) -> None:
    labels = load_label_file(model_path("handles", "toolkinect_handles.json"))
    settings = DetectorConfig().chosen()
    single = single_view_preset(grid_rolls=options.grid_rolls)
    for scan in sorted((default_real_dir() / "toolkinect").glob("*.ply")):
        points, normals = read_cloud(scan)
        axis = points.mean(axis=0) / np.linalg.norm(points.mean(axis=0))
        per = []
        for k in range(options.rolls):
            rotation = roll_about(axis, np.zeros(3), 2 * np.pi * k / options.rolls)[:3, :3]
            turned = None if normals is None else normals @ rotation.T
            found = detect(points @ rotation.T, turned, settings, options.seed, single_view=single)
            centers = found.candidate_centers @ rotation
            top = np.array([h.center for h in found.handles[:1]]).reshape(-1, 3) @ rotation
            label = labels[scan.stem]
            on = int(label.contains(centers).sum()) if len(centers) else 0
            per.append((len(centers), on, bool(label.contains(top).any()), found.detector))
        candidates, on_handle = sum(p[0] for p in per), sum(p[1] for p in per)
        print(
            json.dumps(
                {
                    "scan": scan.stem,
                    "tops": sum(p[2] for p in per),
                    "rolls": options.rolls,
                    "accuracy": round(on_handle / max(candidates, 1), 3),
                    "detectors": sorted({p[3] for p in per}),
                    "per_roll": [[c, o, int(t)] for c, o, t, _ in per],
                }
            ),
            flush=True,
        )


def main(argv: list[str] | None = None) -> int:
    return script_main(Options, run, __doc__.splitlines()[0], argv)


if __name__ == "__main__":
    raise SystemExit(main())

"""The real single-view clouds of a manifest turned about their viewing axis: whether the
single-view default's verdict depends on the camera's roll.

Each cloud of ``models/handles/real_detect.toml`` is turned by 0, 30, ..., 330 degrees about
the line from its viewpoint through its centroid (the same capture, the camera rolled),
detected as ``detect-eval --real``'s ``default`` rows are (``--grid-rolls`` voxel grids pooled;
1 is the view's own grid), the candidates turned back and scored against the cloud's label.
One JSON line per cloud: top handles on the handle over the rolls,
pooled accuracy, the rolls that ended in the fallback, and each roll's (candidates, on the
handle, top on it).

    python scripts/roll_survey.py --grid-rolls 1
"""

from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np

from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked, PositiveInt
from simgrasp.evaluation.real_detect import detect_named
from simgrasp.evaluation.real_manifest import load_real_cloud, read_manifest
from simgrasp.handles.presets import single_view_preset
from simgrasp.handles.single_view.detector import FALLBACK_DETECTOR
from simgrasp.handles.single_view.grid_rolls import roll_about


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    grid_rolls: PositiveInt = 1
    """Voxel grids the single-view detector pools (the default's setting replaced)."""
    rolls: PositiveInt = 12
    """Camera rolls per cloud, evenly over a turn."""
    seed: int = 0


def run(options: Options) -> None:
    single = single_view_preset(grid_rolls=options.grid_rolls)
    for cloud in read_manifest():
        points = load_real_cloud(cloud)
        eye = np.asarray(cloud.viewpoint, dtype=float)
        axis = points.mean(axis=0) - eye
        axis /= np.linalg.norm(axis)
        per = []
        for k in range(options.rolls):
            rolled_T_view = roll_about(axis, eye, 2 * np.pi * k / options.rolls)
            rolled = points @ rolled_T_view[:3, :3].T + rolled_T_view[:3, 3]
            found = detect_named(rolled, "default", options.seed, eye, single)
            back = np.linalg.inv(rolled_T_view)
            centers = found.candidate_centers @ back[:3, :3].T + back[:3, 3]
            top = np.array([h.center for h in found.handles[:1]]).reshape(-1, 3)
            top = top @ back[:3, :3].T + back[:3, 3]
            on = int(cloud.label.contains(centers).sum()) if len(centers) else 0
            held = bool(cloud.label.contains(top).any())
            per.append((len(centers), on, held, found.detector == FALLBACK_DETECTOR))
        candidates, on_handle = sum(p[0] for p in per), sum(p[1] for p in per)
        print(
            json.dumps(
                {
                    "cloud": cloud.name,
                    "grid_rolls": options.grid_rolls,
                    "tops": sum(p[2] for p in per),
                    "rolls": options.rolls,
                    "accuracy": round(on_handle / max(candidates, 1), 3),
                    "fallbacks": sum(p[3] for p in per),
                    "per_roll": [[c, o, int(t)] for c, o, t, _ in per],
                }
            ),
            flush=True,
        )


def main(argv: list[str] | None = None) -> int:
    return script_main(Options, run, __doc__.splitlines()[0], argv)


if __name__ == "__main__":
    raise SystemExit(main())

"""Scene segmentation on osd-learn against its per-point labels: ours (grid) and the plain
baseline (RANSAC plane + Open3D DBSCAN on a 5 mm voxel grid), measured in the same run.

    python scripts/segment_osd.py [--data DIR] [--out docs/results/segment-osd] [--repeats 3]

Writes ``scenes.csv`` (one row per scene and method: parts, objects, mean and minimum part
IoU, CPU and wall ms) and ``summary.md`` / ``summary.json`` (mean part IoU, share of parts with
IoU >= 0.8, ms per scene). Numbers only: no data or labels are written. Times are the least
of ``--repeats`` runs of one scene on one thread (reading the file excluded); CPU time is the
figure on a shared machine, where wall time also counts waiting for the core.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")  # one core, before numpy and Open3D load

import csv  # noqa: E402
import json  # noqa: E402
from dataclasses import dataclass  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Literal  # noqa: E402

from simgrasp.assets.real import default_real_dir  # noqa: E402
from simgrasp.config.arguments import script_main  # noqa: E402
from simgrasp.config.checks import Checked, PositiveInt  # noqa: E402
from simgrasp.errors import SimgraspError  # noqa: E402
from simgrasp.evaluation.segment_eval import (  # noqa: E402
    SceneScore,
    osd_scenes,
    score_scene,
    summarize,
)

Method = Literal["grid", "dbscan"]
METHODS: dict[Method, str] = {"grid": "ours (grid cuts)", "dbscan": "baseline (plane + DBSCAN)"}


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    data: Path = default_real_dir() / "osd-learn"
    """Folder of the osd-learn scenes (default: under $SIMGRASP_REAL_DIR, else ../shared/real)."""
    out: Path = Path("docs/results/segment-osd")
    """Folder of scenes.csv, summary.md and summary.json."""
    repeats: PositiveInt = 3
    """Runs of each scene per method; its times are the least of them."""


def run(options: Options) -> str:
    """Both methods on every scene, written; the summary table."""
    scenes = osd_scenes(options.data)
    if not scenes:
        raise SimgraspError(f"no learn*.pcd scenes in {options.data}")
    scores = {m: [score_scene(p, m, repeats=options.repeats) for p in scenes] for m in METHODS}
    options.out.mkdir(parents=True, exist_ok=True)
    _write_scenes(options.out / "scenes.csv", scores)
    summary = {m: summarize(s) for m, s in scores.items()}
    (options.out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    (options.out / "summary.md").write_text(_summary_md(summary))
    return _summary_md(summary)


def main(argv: list[str] | None = None) -> int:
    return script_main(Options, run, __doc__.splitlines()[0], argv)


def _write_scenes(path: Path, scores: dict[Method, list[SceneScore]]) -> None:
    with path.open("w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(
            ["scene", "method", "parts", "objects", "mean_iou", "min_iou", "cpu_ms", "wall_ms"]
        )
        for method, rows in scores.items():
            for s in rows:
                ious = s.part_ious or (0.0,)
                writer.writerow(
                    [
                        s.scene,
                        method,
                        len(s.part_ious),
                        s.objects,
                        f"{sum(ious) / len(ious):.3f}",
                        f"{min(ious):.3f}",
                        f"{s.seconds * 1000:.1f}",
                        f"{s.wall_seconds * 1000:.1f}",
                    ]
                )


def _summary_md(summary: dict[Method, dict[str, float]]) -> str:
    lines = [
        "| method | scenes | parts | mean IoU | share IoU >= 0.8 | median CPU ms | mean CPU ms "
        "| median wall ms | side parts (on their object's ground truth) |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for method, s in summary.items():
        lines.append(
            f"| {METHODS[method]} | {s['scenes']} | {s['parts']} | {s['mean_iou']:.3f} | "
            f"{s['share_iou_0.8']:.3f} | {s['median_ms']:.1f} | {s['mean_ms']:.1f} | "
            f"{s['median_wall_ms']:.1f} | {s['side_parts']} ({s['side_parts_right']}) |"
        )
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    raise SystemExit(main())

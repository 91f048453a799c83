"""How the default detector's real-cloud figures hold when the capture is made worse.

Issue 26's real-mug goal is checked on captures we do not have: other sensors, distances and
densities. This script takes the clouds of the real-data manifest
(``models/handles/real_detect.toml``: the two held-out mugs, the five tune knives) and
degrades each one as another capture might, from a seed:

- ``half`` / ``quarter``: a random half or quarter of the points (a sparser or farther sensor);
- ``noise1mm`` / ``noise2mm``: Gaussian range noise of 1 or 2 mm along each point's ray from
  the viewpoint (a noisier sensor);
- ``holes``: the points within 15 mm of three random points removed (dropouts);
- ``viewpoint10cm``: the viewpoint given 10 cm off in a random direction (a wrong or guessed
  sensor pose: normals are turned toward it).

Then ``detect``'s default runs on it (:func:`simgrasp.evaluation.real_detect.score_cloud`),
once per seed. For each cloud and degradation it reports the candidate accuracy pooled over
the seeds and in how many seeds the top handle is on the labeled handle. Nothing is tuned on
these runs. Rows go to ``rows.jsonl`` as they finish, so a rerun keeps them.
``robustness.md`` is the table.

    SIMGRASP_REAL_DIR=../shared/real python scripts/real_robustness.py \\
        --out docs/results/real-detect/robustness
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked, PositiveInt
from simgrasp.evaluation.real_detect import score_cloud
from simgrasp.evaluation.real_manifest import RealCloud, load_real_cloud, read_manifest
from simgrasp.seeding import rng_for

DEGRADATIONS = ("as captured", "half", "quarter", "noise1mm", "noise2mm", "holes", "viewpoint10cm")
"""The ways a capture is made worse (module docstring), in table order."""
HOLE_RADIUS = 0.015
"""Radius (m) of each of the three holes."""


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    manifest: Path | None = None
    """Real-data manifest (default: the shipped models/handles/real_detect.toml)."""
    real_dir: Path | None = None
    """Real data root (default: $SIMGRASP_REAL_DIR, else ../shared/real)."""
    seeds: PositiveInt = 5
    """Seeds 0 .. seeds - 1: each draws its degradation and seeds its detection."""
    out: Path = Path("docs/results/real-detect/robustness")
    """Folder of rows.jsonl and robustness.md."""


def degraded(
    points: NDArray[np.float64], viewpoint: NDArray[np.float64], kind: str, rng: np.random.Generator
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``points`` (N, 3, m) and ``viewpoint`` (3,) after degradation ``kind``."""
    if kind == "as captured":
        return points, viewpoint
    if kind in ("half", "quarter"):
        keep = len(points) // (2 if kind == "half" else 4)
        return points[np.sort(rng.choice(len(points), keep, replace=False))], viewpoint
    if kind in ("noise1mm", "noise2mm"):
        rays = points - viewpoint
        rays /= np.linalg.norm(rays, axis=1, keepdims=True)
        sigma = 0.001 if kind == "noise1mm" else 0.002
        return points + rays * rng.normal(0.0, sigma, (len(points), 1)), viewpoint
    if kind == "holes":
        centers = points[rng.choice(len(points), 3, replace=False)]
        gaps = np.linalg.norm(points[:, None] - centers[None], axis=2).min(axis=1)
        return points[gaps > HOLE_RADIUS], viewpoint
    if kind == "viewpoint10cm":
        direction = rng.normal(size=3)
        return points, viewpoint + 0.1 * direction / np.linalg.norm(direction)
    raise ValueError(kind)


def measure(cloud: RealCloud, points: NDArray[np.float64], kind: str, seed: int) -> dict[str, Any]:
    """One row: the default detector on ``cloud`` degraded by ``kind`` from ``seed``."""
    rng = rng_for(seed, "real_robustness", kind, cloud.name)
    worse, viewpoint = degraded(points, cloud.viewpoint, kind, rng)
    row = score_cloud(replace(cloud, viewpoint=viewpoint), worse, "default", seed)
    return {**asdict(row), "degradation": kind}


def run(options: Options) -> str:
    """Measure every (cloud, degradation, seed) not yet in ``rows.jsonl``; the table."""
    clouds = read_manifest(options.manifest, options.real_dir)
    options.out.mkdir(parents=True, exist_ok=True)
    rows_file = options.out / "rows.jsonl"
    rows = [json.loads(line) for line in rows_file.open()] if rows_file.is_file() else []
    done = {(r["cloud"], r["degradation"], r["seed"]) for r in rows}
    with rows_file.open("a") as log:
        for cloud in clouds:
            points = load_real_cloud(cloud)
            for kind in DEGRADATIONS:
                for seed in range(options.seeds):
                    if (cloud.name, kind, seed) in done:
                        continue
                    rows.append(measure(cloud, points, kind, seed))
                    log.write(json.dumps(rows[-1]) + "\n")
                    log.flush()
    text = table(rows, [c.name for c in clouds], options.seeds)
    (options.out / "robustness.md").write_text(text)
    return text


def table(rows: list[dict[str, Any]], names: list[str], seeds: int) -> str:
    """Per cloud (split in brackets) and degradation: pooled candidate accuracy and the
    seeds whose top handle is on the handle."""
    head = "| cloud | " + " | ".join(DEGRADATIONS) + " |\n"
    head += "|---|" + "---|" * len(DEGRADATIONS) + "\n"
    lines = []
    for name in names:
        mine = [r for r in rows if r["cloud"] == name and r["seed"] < seeds]
        cells = []
        for kind in DEGRADATIONS:
            these = [r for r in mine if r["degradation"] == kind]
            found = sum(r["candidates"] for r in these)
            accuracy = f"{sum(r['on_handle'] for r in these) / found:.2f}" if found else "-"
            tops = sum(r["top_on_handle"] for r in these)
            cells.append(f"{accuracy}, {tops} of {len(these)}")
        split = mine[0]["split"] if mine else "?"
        lines.append(f"| {name} ({split}) | " + " | ".join(cells) + " |")
    legend = (
        "Each cell: candidate accuracy pooled over the seeds, and the seeds whose top handle "
        "lies on the labeled handle.\n\n"
    )
    return legend + head + "\n".join(lines) + "\n"


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    raise SystemExit(main())

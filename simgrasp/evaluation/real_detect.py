"""Handle detection on the real clouds of a manifest (:mod:`simgrasp.evaluation.real_manifest`):
per cloud, detector setting and seed, candidate accuracy (share of candidate centers inside a
labeled handle, the paper's Table I measure) and whether the top handle's center is on one;
summed per data set, per split (tune / holdout) and overall.

The settings compared are named (:data:`NAMED_CONFIGS`): the quadric detector's default, its
presets (kept to reproduce old runs) and ten Pas's detector. Normals face the manifest's
viewpoint; nothing else about the capture is told to the detector.
"""

from __future__ import annotations

import csv
import time
from collections.abc import Callable, Iterable
from dataclasses import asdict, dataclass, fields
from pathlib import Path

import numpy as np

from simgrasp.errors import SimgraspError
from simgrasp.evaluation.real_manifest import RealCloud, load_real_cloud
from simgrasp.handles import detect
from simgrasp.handles.config import QuadricDetectorConfig
from simgrasp.handles.detection import Detection
from simgrasp.handles.detector_config import DetectorName
from simgrasp.handles.single_view import SingleViewConfig, detect_single_view
from simgrasp.handles.tenpas_config import TenPasConfig

Setting = QuadricDetectorConfig | TenPasConfig | SingleViewConfig
NAMED_CONFIGS: dict[str, Callable[[], Setting]] = {
    "default": QuadricDetectorConfig,
    "multi_view": QuadricDetectorConfig,
    "paper": QuadricDetectorConfig.paper,
    "two_scales": QuadricDetectorConfig.two_scales,
    "camera_cloud": QuadricDetectorConfig.camera_cloud,
    "noisy_camera_cloud": QuadricDetectorConfig.noisy_camera_cloud,
    "real_depth": QuadricDetectorConfig.real_depth,
    "tenpas": TenPasConfig,
    "standoff": SingleViewConfig,
    "standoff_axis": lambda: SingleViewConfig(anchor="axis"),
    "standoff_measured": lambda: SingleViewConfig(anchor="consistent", min_width_spacings=2.0),
    "learned": SingleViewConfig.learned,
    "learned_bars": SingleViewConfig.learned_bars,
}
"""The detector settings ``detect-eval --real --real-configs`` can compare, by name.
``default`` is what ``simgrasp detect`` runs: the quadric detector's defaults, and on a
cloud measured to be one view (every real capture) the single-view detector with
:meth:`SingleViewConfig.learned`, its ``real_depth()`` fallback where the classifier keeps
nothing; ``learned`` is that classifier alone, without the view test or the fallback
(``learned_bars``: the first classifier and its settings, the ``learned`` of runs before 4
December 2026);
``multi_view`` is the quadric detector's defaults on every cloud (the ``default`` of runs
before 3 December 2026)."""


@dataclass(frozen=True)
class RealDetectRow:
    """One detection: cloud, setting, seed and its score (``top_on_handle`` False when no
    handle was found; ``detect_s`` wall seconds)."""

    cloud: str
    dataset: str
    split: str
    config: str
    seed: int
    points: int
    candidates: int
    on_handle: int
    handles: int
    top_on_handle: bool
    detect_s: float

    @property
    def accuracy(self) -> float:
        return self.on_handle / self.candidates if self.candidates else float("nan")


def config_by_name(name: str) -> Setting:
    """The named detector setting; one line listing the names when unknown."""
    if name not in NAMED_CONFIGS:
        raise SimgraspError(
            f"unknown detector setting {name!r}; choose from {', '.join(NAMED_CONFIGS)}"
        )
    return NAMED_CONFIGS[name]()


def detect_named(
    points: np.ndarray,
    name: str,
    seed: int,
    viewpoint: np.ndarray,
    single_view: SingleViewConfig | None = None,
) -> Detection:
    """Detect on a single view seen from ``viewpoint`` with the named setting; for
    ``default``, ``single_view`` replaces :meth:`SingleViewConfig.learned` (another trained
    classifier, ``scripts/compare_candidate_classifiers.py``)."""
    config = config_by_name(name)
    if isinstance(config, SingleViewConfig):
        return detect_single_view(points, config, seed, viewpoint)
    kind: DetectorName = "tenpas" if isinstance(config, TenPasConfig) else "quadric"
    if name != "default":
        single_view = None
    elif single_view is None:
        single_view = SingleViewConfig.learned()
    return detect(
        points, None, config, seed, detector=kind, viewpoint=viewpoint, single_view=single_view
    )


def score_cloud(
    cloud: RealCloud,
    points: np.ndarray,
    name: str,
    seed: int,
    single_view: SingleViewConfig | None = None,
) -> RealDetectRow:
    """Detect with setting ``name`` (``single_view`` as :func:`detect_named` takes it) and
    seed ``seed`` on ``points`` (the cloud as loaded)."""
    start = time.perf_counter()
    detection = detect_named(points, name, seed, cloud.viewpoint, single_view)
    elapsed = time.perf_counter() - start
    centers = detection.candidate_centers
    top = detection.handles[0].center[None] if detection.handles else np.zeros((0, 3))
    return RealDetectRow(
        cloud=cloud.name,
        dataset=cloud.dataset,
        split=cloud.split,
        config=name,
        seed=seed,
        points=len(points),
        candidates=len(centers),
        on_handle=int(cloud.label.contains(centers).sum()) if len(centers) else 0,
        handles=len(detection.handles),
        top_on_handle=bool(cloud.label.contains(top).any()),
        detect_s=elapsed,
    )


def read_done(path: Path) -> list[RealDetectRow]:
    """Rows already written to ``path`` (a run killed midway loses none)."""
    if not path.is_file():
        return []
    with path.open() as handle:
        return [
            RealDetectRow(
                cloud=raw["cloud"],
                dataset=raw["dataset"],
                split=raw["split"],
                config=raw["config"],
                seed=int(raw["seed"]),
                points=int(raw["points"]),
                candidates=int(raw["candidates"]),
                on_handle=int(raw["on_handle"]),
                handles=int(raw["handles"]),
                top_on_handle=raw["top_on_handle"] == "True",
                detect_s=float(raw["detect_s"]),
            )
            for raw in csv.DictReader(handle)
        ]


def run_real_detect(
    clouds: list[RealCloud], configs: Iterable[str], seeds: range, out_csv: Path
) -> list[RealDetectRow]:
    """Every cloud x setting x seed, appended to ``out_csv`` as it finishes; rows already
    there are kept and not redone."""
    configs = tuple(configs)
    for name in configs:
        config_by_name(name)
    done = read_done(out_csv)
    have = {(r.cloud, r.config, r.seed) for r in done}
    out_csv.parent.mkdir(parents=True, exist_ok=True)
    new_file = not out_csv.is_file()
    with out_csv.open("a", newline="") as handle:
        writer = csv.DictWriter(handle, [f.name for f in fields(RealDetectRow)])
        if new_file:
            writer.writeheader()
        for cloud in clouds:
            todo = [(c, s) for c in configs for s in seeds if (cloud.name, c, s) not in have]
            if not todo:
                continue
            points = load_real_cloud(cloud)
            for name, seed in todo:
                row = score_cloud(cloud, points, name, seed)
                writer.writerow(asdict(row))
                handle.flush()
                done.append(row)
    wanted = {c.name for c in clouds}
    return [r for r in done if r.cloud in wanted and r.config in configs and r.seed in seeds]


def pooled_score(rows: list[RealDetectRow]) -> tuple[float, int, int]:
    """Pooled candidate accuracy, seeds with the top handle on a handle, and runs."""
    candidates = sum(r.candidates for r in rows)
    pooled = sum(r.on_handle for r in rows) / candidates if candidates else 0.0
    return pooled, sum(r.top_on_handle for r in rows), len(rows)


def _cell(rows: list[RealDetectRow]) -> str:
    accuracy, top, runs = pooled_score(rows)
    return f"{accuracy:.2f} ({top}/{runs})"


def tables(rows: list[RealDetectRow]) -> str:
    """Markdown: per cloud, per data set, per split and overall, one column per setting;
    a cell is the pooled candidate accuracy and (runs with the top handle on a handle / runs)."""
    configs = list(dict.fromkeys(r.config for r in rows))
    groups: list[tuple[str, Callable[[RealDetectRow], str]]] = [
        ("cloud", lambda r: f"{r.cloud} ({r.split})"),
        ("data set", lambda r: f"{r.dataset} ({r.split})"),
        ("split", lambda r: r.split),
        ("all", lambda r: "all"),
    ]
    parts = []
    for title, key in groups:
        names = list(dict.fromkeys(key(r) for r in rows))
        lines = [f"| {title} | " + " | ".join(configs) + " |"]
        lines.append("|---" * (len(configs) + 1) + "|")
        for name in names:
            cells = [_cell([r for r in rows if key(r) == name and r.config == c]) for c in configs]
            lines.append(f"| {name} | " + " | ".join(cells) + " |")
        parts.append("\n".join(lines))
    return "\n\n".join(parts)

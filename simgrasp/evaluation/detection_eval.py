"""Detection accuracy on object meshes (YCB or generated) over noise levels and seeds (the
paper's Tables I, II and Fig. 8), for one or more detectors.

Clouds are sampled from each mesh's surface in the mesh frame (where the labels live), then
perturbed with the paper's multiplicative noise about the cloud's centroid, then handed to the
detector without normals (the detector estimates them, oriented outward). The resumable run
over every object, detector, noise level and seed is :mod:`simgrasp.evaluation.detection_run`.
"""

from __future__ import annotations

import csv
import time
from collections.abc import Iterable, Sequence
from dataclasses import asdict, dataclass, fields
from pathlib import Path

import numpy as np

from simgrasp.assets.object import ObjectAsset
from simgrasp.assets.registry import load_object
from simgrasp.handles import DetectorName, default_config, detect
from simgrasp.handles.accuracy import detection_accuracy, handle_recall
from simgrasp.perception import multiplicative_noise, sample_surface
from simgrasp.seeding import rng_for

CLOUD_POINTS = 30000


@dataclass(frozen=True)
class EvalRecord:
    """One detector run on one noisy cloud of one object."""

    object: str
    detector: str
    sigma: float
    seed: int
    points: int
    neighborhoods: int
    candidates: int
    handles: int
    accuracy: float
    handle_recall: bool
    t_voxelize: float
    t_normals: float
    t_sample: float
    t_fit: float
    t_test: float
    t_cluster: float
    t_total: float


def object_cloud(mesh_points: np.ndarray, sigma: float, seed: int, object_id: str) -> np.ndarray:
    """The noisy cloud of one object: multiplicative noise N(1, sigma) about its centroid."""
    if sigma == 0:
        return mesh_points
    centroid = mesh_points.mean(axis=0)
    rng = rng_for(seed, "detect_eval", object_id, "noise", round(sigma * 1e6))
    return centroid + multiplicative_noise(mesh_points - centroid, sigma, rng)


def evaluate_detection(
    asset: ObjectAsset,
    detector: DetectorName,
    sigma: float,
    seed: int,
    gripper_max_opening: float | None = None,
) -> EvalRecord:
    """Run ``detector`` on the cloud of ``asset`` of one seed (its surface sample) and noise
    level, scoring against the object's own handle label."""
    config = default_config(detector, gripper_max_opening)
    clean, _ = sample_surface(
        asset.mesh, CLOUD_POINTS, rng_for(seed, "detect_eval", asset.name, "sample")
    )
    cloud = object_cloud(clean, sigma, seed, asset.name)
    start = time.perf_counter()
    detection = detect(cloud, None, config, seed, detector=detector)
    total = time.perf_counter() - start
    steps = detection.timings_s
    return EvalRecord(
        object=asset.name,
        detector=detector,
        sigma=float(sigma),
        seed=int(seed),
        points=len(cloud),
        neighborhoods=detection.neighborhoods,
        candidates=len(detection.candidates),
        handles=len(detection.handles),
        accuracy=detection_accuracy(detection, asset.handle),
        handle_recall=handle_recall(detection, asset.handle),
        t_voxelize=steps.get("voxelize", 0.0),
        t_normals=steps.get("normals", 0.0),
        t_sample=steps.get("sample", 0.0),
        t_fit=steps.get("fit", 0.0),
        t_test=steps.get("test", 0.0),
        t_cluster=steps.get("cluster", 0.0),
        t_total=total,
    )


def evaluate_object(
    object_id: str,
    detector: DetectorName,
    sigmas: Sequence[float],
    seeds: Sequence[int],
    ycb_dir: str | None = None,
    gripper_max_opening: float | None = None,
) -> list[EvalRecord]:
    """Run ``detector`` on every (sigma, seed) cloud of one object (YCB id or generated tool),
    seed-major."""
    asset = load_object(object_id, ycb_dir=ycb_dir)
    return [
        evaluate_detection(asset, detector, sigma, seed, gripper_max_opening)
        for seed in seeds
        for sigma in sigmas
    ]


def write_csv(records: Iterable[EvalRecord], path: Path) -> Path:
    """Write one row per record."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=[f.name for f in fields(EvalRecord)])
        writer.writeheader()
        for record in records:
            writer.writerow(asdict(record))
    return path


def _mean_std(values: Sequence[float]) -> str:
    finite = np.asarray([v for v in values if np.isfinite(v)])
    if len(finite) == 0:
        return "—"
    return f"{finite.mean():.2f} ± {finite.std():.2f}"


def _finite_mean(values: Sequence[float]) -> float:
    """Mean of the finite values (a seed without candidates has NaN accuracy); NaN, a gap in a
    plot, when no seed had one."""
    finite = [v for v in values if np.isfinite(v)]
    return float(np.mean(finite)) if finite else float("nan")


def accuracy_tables(records: Sequence[EvalRecord]) -> str:
    """Markdown: per detector, Table I (sigma = smallest) and Table II (accuracy vs sigma) as
    mean ± std over seeds, then candidates, handle recall and timings per object."""
    lines: list[str] = []
    objects = list(dict.fromkeys(r.object for r in records))
    short = [o.split("_", 1)[1].replace("_", " ") for o in objects]
    for detector in dict.fromkeys(r.detector for r in records):
        mine = [r for r in records if r.detector == detector]
        sigmas = sorted({r.sigma for r in mine})
        seeds = len({r.seed for r in mine})
        header = "| σ | " + " | ".join(short) + " | mean |"
        rule = "|---" * (len(objects) + 2) + "|"
        lines += [f"### {detector}: detection accuracy (mean ± std over {seeds} seeds)", ""]
        lines += [header, rule]
        for sigma in sigmas:
            cells: list[str] = []
            means: list[float] = []
            for obj in objects:
                values = [r.accuracy for r in mine if r.object == obj and r.sigma == sigma]
                cells.append(_mean_std(values))
                finite = [v for v in values if np.isfinite(v)]
                means.append(float(np.mean(finite)) if finite else 0.0)
            lines.append(f"| {sigma:g} | " + " | ".join(cells) + f" | {np.mean(means):.2f} |")
        lines += ["", f"### {detector}: per object at σ = {sigmas[0]:g}", ""]
        lines += [
            "| object | candidates | handles | handle recall | neighborhoods | total s |",
            "|---|---|---|---|---|---|",
        ]
        for obj in objects:
            rows = [r for r in mine if r.object == obj and r.sigma == sigmas[0]]
            recall = sum(r.handle_recall for r in rows)
            lines.append(
                f"| {obj} | {np.mean([r.candidates for r in rows]):.1f} | "
                f"{np.mean([r.handles for r in rows]):.1f} | {recall}/{len(rows)} | "
                f"{np.mean([r.neighborhoods for r in rows]):.0f} | "
                f"{np.median([r.t_total for r in rows]):.3f} |"
            )
        lines.append("")
    return "\n".join(lines)


def plot_accuracy_vs_noise(records: Sequence[EvalRecord], path: Path) -> Path:
    """The paper's Fig. 8: accuracy vs sigma per object (mean over seeds), one panel per
    detector."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    detectors = list(dict.fromkeys(r.detector for r in records))
    objects = list(dict.fromkeys(r.object for r in records))
    fig, axes = plt.subplots(
        1, len(detectors), figsize=(7 * len(detectors), 5), squeeze=False, sharey=True
    )
    for ax, detector in zip(axes[0], detectors, strict=True):
        for obj in objects:
            rows = [r for r in records if r.detector == detector and r.object == obj]
            sigmas = sorted({r.sigma for r in rows})
            means = [_finite_mean([r.accuracy for r in rows if r.sigma == s]) for s in sigmas]
            ax.plot(sigmas, means, marker="o", label=obj)
        ax.set_title(f"{detector}: detection accuracy vs noise")
        ax.set_xlabel("σ (multiplicative noise)")
        ax.set_ylabel("accuracy (share of candidates on the handle)")
        ax.set_ylim(-0.02, 1.02)
        ax.grid(alpha=0.3)
    axes[0][-1].legend(fontsize=8, loc="lower left")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path

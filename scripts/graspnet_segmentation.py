"""The segmenter on a real cluttered RealSense frame nobody tuned on: GraspNet-1Billion's example
frame (``$SIMGRASP_REAL_DIR/graspnet-example``, 1280 x 720), segmented whole with each named
setting and scored per object against the nine objects drawn by hand before any scoring
(``models/handles/graspnet_objects.json``, :mod:`simgrasp.evaluation.frame_objects`): an
object's part IoU is its best IoU with any predicted segment, as on osd-learn
(``segment_eval.part_ious``). Writes ``segmentation.csv`` and ``segmentation.md`` to ``--out``;
``--picture`` also writes a review picture of the labels (derived from the frame: keep it out
of the repository).

    python scripts/graspnet_segmentation.py --out docs/results/real-scene
"""

from __future__ import annotations

import csv
import time
from dataclasses import dataclass
from pathlib import Path
from typing import TypedDict

import numpy as np

from simgrasp.assets.graspnet_frame import GRASPNET_EXAMPLE, read_graspnet_frame
from simgrasp.assets.real import default_real_dir
from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked
from simgrasp.evaluation.frame_objects import read_frame_objects, table_heights, truth_labels
from simgrasp.evaluation.segment_eval import part_ious
from simgrasp.perception.scene_cloud import scene_from_array
from simgrasp.perception.segmentation.segment import segment_scene
from simgrasp.perception.segmentation.segment_config import SegmentConfig
from simgrasp.resources import model_path

SETTINGS = {
    "default": SegmentConfig(),
    "default, unscaled (reference_footprint 0: before 5 December 2026)": SegmentConfig(
        reference_footprint=0.0
    ),
    "default, fragments dropped (fragment_passes 0: before 4 December 2026)": SegmentConfig(
        fragment_passes=0
    ),
    "cut_close_px 1": SegmentConfig(cut_close_px=1),
    "simulated()": SegmentConfig.simulated(),
}
"""The settings scored, fixed before the first scoring (none is chosen on this frame)."""


class Row(TypedDict):
    """One drawn object under one setting: a row of ``segmentation.csv``."""

    setting: str
    object: str
    pixels: int
    part_iou: float
    """Its best IoU with any predicted segment (4 decimals)."""
    segments: int
    """Segments of the whole frame."""
    cpu_ms: float
    """CPU time of the frame's segmentation (ms, 1 decimal)."""


def picture(grid: np.ndarray, labels: np.ndarray, heights: np.ndarray, path: Path) -> None:
    """The height image (0-12 cm, grey) with each labeled object tinted, for review."""
    from PIL import Image

    grey = np.clip(np.nan_to_num(heights, nan=0.0) / 0.12, 0.0, 1.0)
    image = np.dstack([grey * 255.0] * 3)
    palette = np.random.default_rng(0).integers(60, 255, (int(labels.max()) // 10 + 1, 3))
    tinted = labels.reshape(grid.shape[:2]) > 0
    image[tinted] = (
        0.45 * image[tinted] + 0.55 * palette[labels.reshape(grid.shape[:2])[tinted] // 10]
    )
    Image.fromarray(image.astype(np.uint8)).save(path)


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    real_dir: Path | None = None
    """Real data root (default: $SIMGRASP_REAL_DIR, else ../shared/real)."""
    out: Path = Path("out/real-scene")
    """Folder of segmentation.csv and segmentation.md."""
    picture: Path | None = None
    """Write the labels' review picture here (an image file; derived from the frame)."""


def run(options: Options) -> str:
    """Each setting's segmentation of the frame scored per drawn object; the table."""
    options.out.mkdir(parents=True, exist_ok=True)
    grid = read_graspnet_frame((options.real_dir or default_real_dir()) / GRASPNET_EXAMPLE)
    annotation = read_frame_objects(model_path("handles", "graspnet_objects.json"))
    truth = truth_labels(grid, annotation)
    if options.picture:
        picture(grid, truth, table_heights(grid, annotation), options.picture)
    names = [drawn.name for drawn in annotation.objects]
    sizes = np.bincount(truth // 10, minlength=len(names) + 2)[2:]  # object i: label 10 (i + 2)
    rows: list[Row] = []
    for setting, config in SETTINGS.items():
        start = time.process_time()
        segmentation = segment_scene(scene_from_array(grid, source="graspnet-example"), config)
        cpu_ms = 1000.0 * (time.process_time() - start)
        ious = part_ious(truth, segmentation.labels)
        for name, size, iou in zip(names, sizes, ious, strict=True):
            rows.append(
                {
                    "setting": setting,
                    "object": name,
                    "pixels": int(size),
                    "part_iou": round(float(iou), 4),
                    "segments": len(segmentation.objects),
                    "cpu_ms": round(cpu_ms, 1),
                }
            )
    with (options.out / "segmentation.csv").open("w", newline="") as stream:
        writer = csv.DictWriter(stream, list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    lines = [
        "| setting | " + " | ".join(names) + " | mean part IoU | objects under 0.5 | segments |",
        "|---" * (len(names) + 4) + "|",
    ]
    for setting in SETTINGS:
        mine = [r for r in rows if r["setting"] == setting]
        scores = [r["part_iou"] for r in mine]
        cells = " | ".join(f"{iou:.2f}" for iou in scores)
        under = sum(iou < 0.5 for iou in scores)
        lines.append(
            f"| {setting} | {cells} | {np.mean(scores):.3f} | {under} | {mine[0]['segments']} |"
        )
    (options.out / "segmentation.md").write_text("\n".join(lines) + "\n")
    return "\n".join(lines)


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    raise SystemExit(main())

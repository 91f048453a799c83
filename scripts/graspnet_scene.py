"""A real cluttered RealSense frame nobody tuned on, through ``simgrasp detect --segment``:
GraspNet-1Billion's example frame (``$SIMGRASP_REAL_DIR/graspnet-example``, 1280 x 720), the
whole frame segmented as ``detect --segment`` does (default segmentation), then handles
detected on each object. Scored on the power drill, whose grip was boxed by hand before any
detector ran on the frame (``models/handles/graspnet_handles.json``): the drill is the whole
object (with its side parts) holding most of the label's points; per seed, the share of that
object's candidates inside the grip label and whether its top handle is. Writes
``results.csv`` and ``report.md`` to ``--out``.

    python scripts/graspnet_scene.py --seeds 5 --out docs/results/real-scene
"""

from __future__ import annotations

import csv
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from simgrasp.assets.graspnet_frame import GRASPNET_EXAMPLE, read_graspnet_frame
from simgrasp.assets.real import default_real_dir
from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked, PositiveInt
from simgrasp.handles import QuadricDetectorConfig, SingleViewConfig
from simgrasp.handles.presets import quadric_preset, single_view_preset
from simgrasp.handles.scene_detect import detect_in_scene
from simgrasp.labels import HandleLabel, load_label_file
from simgrasp.resources import model_path

SETTINGS: dict[str, tuple[QuadricDetectorConfig, SingleViewConfig | None]] = {
    "default": (QuadricDetectorConfig(), single_view_preset()),
    "multi_view (former default, --single-view false)": (QuadricDetectorConfig(), None),
    "real_depth (the pots' preset, --single-view false)": (
        quadric_preset("real_depth"),
        None,
    ),
}


def score(
    frame: Path, grip: HandleLabel, in_grip: np.ndarray, name: str, seed: int
) -> dict[str, object]:
    """One ``detect --segment`` run on ``frame`` scored on the drill's ``grip`` label
    (``in_grip``: which of the frame's pixels lie in it)."""
    config, single_view = SETTINGS[name]
    start = time.perf_counter()
    result = detect_in_scene(frame, config, seed, single_view=single_view)
    elapsed = time.perf_counter() - start
    segmentation = result.segmentation
    hits = {  # a whole object's mask holds its side parts
        whole: int((segmentation.object_mask(whole) & in_grip).sum())
        for whole in segmentation.whole_objects()
    }
    drill = max(hits, key=lambda k: hits[k])
    (detection,) = [d for k, d in result.detections if k == drill]
    centers = detection.candidate_centers
    top = detection.handles[0].center[None] if detection.handles else np.zeros((0, 3))
    return {
        "setting": name,
        "seed": seed,
        "objects": len(list(segmentation.whole_objects())),
        "drill_object": drill,
        "grip_points_in_object": hits[drill],
        "grip_points": int(in_grip.sum()),
        "detector": detection.detector,
        "candidates": len(centers),
        "on_grip": int(grip.contains(centers).sum()) if len(centers) else 0,
        "top_on_grip": bool(grip.contains(top).any()),
        "seconds": round(elapsed, 2),
    }


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    seeds: PositiveInt = 5
    """Detection seeds 0 .. seeds - 1 per setting."""
    real_dir: Path | None = None
    """Real data root (default: $SIMGRASP_REAL_DIR, else ../shared/real)."""
    out: Path = Path("out/real-scene")
    """Folder of results.csv and report.md."""


def run(options: Options) -> str:
    """Each setting's detection on the frame, per seed, scored on the drill; the table."""
    options.out.mkdir(parents=True, exist_ok=True)
    grid = read_graspnet_frame((options.real_dir or default_real_dir()) / GRASPNET_EXAMPLE)
    labels = load_label_file(model_path("handles", "graspnet_handles.json"))
    grip = labels["graspnet_example_drill"]
    in_grip = grip.contains(np.nan_to_num(grid.reshape(-1, 3), nan=1e3))
    with tempfile.TemporaryDirectory() as folder:  # the derived cloud never leaves it
        frame = Path(folder) / "frame.npy"
        np.save(frame, grid)
        rows = [
            score(frame, grip, in_grip, name, s) for name in SETTINGS for s in range(options.seeds)
        ]
    with (options.out / "results.csv").open("w", newline="") as stream:
        writer = csv.DictWriter(stream, list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    lines = [
        "| setting | drill's candidates on the grip | top handle on the grip | median s |",
        "|---|---|---|---|",
    ]
    for name in SETTINGS:
        mine = [r for r in rows if r["setting"] == name]
        candidates = sum(int(r["candidates"]) for r in mine)  # type: ignore[call-overload]
        on = sum(int(r["on_grip"]) for r in mine)  # type: ignore[call-overload]
        accuracy = f"{on / candidates:.2f} ({on}/{candidates})" if candidates else "none"
        tops = sum(bool(r["top_on_grip"]) for r in mine)
        seconds = float(np.median([float(r["seconds"]) for r in mine]))  # type: ignore[arg-type]
        lines.append(f"| {name} | {accuracy} | {tops} / {len(mine)} | {seconds:.1f} |")
    (options.out / "report.md").write_text("\n".join(lines) + "\n")
    return "\n".join(lines)


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    raise SystemExit(main())

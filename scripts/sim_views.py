"""Does the simulator predict real detection? The YCB mug (025_mug) in simulated single views
posed like the two real mug captures of ``detect-eval --real`` (the GPD table mug: upright,
0.78 m, 32 degrees above the table; the AffordanceGrasp mug: lying, handle flat beside it,
0.30 m straight above), through the kinect and stereo sensor models, scored as the real clouds
are; writes ``sim_views.csv`` and ``sim_views.md`` (sim beside real) to ``--out``.

    python scripts/sim_views.py --seeds 5 --out docs/results/real-detect
"""

from __future__ import annotations

import argparse
import csv
from dataclasses import asdict, fields
from pathlib import Path

from simgrasp.evaluation.real_detect import RealDetectRow, read_done
from simgrasp.evaluation.sim_views import REAL_CAPTURE_VIEWS, score_view

CONFIGS = (
    "default",
    "multi_view",
    "two_scales",
    "camera_cloud",
    "noisy_camera_cloud",
    "real_depth",
    "standoff",
    "standoff_axis",
    "standoff_measured",
    "learned",
    "learned_bars",
)


def _cell(rows: list[RealDetectRow]) -> str:
    candidates = sum(r.candidates for r in rows)
    accuracy = sum(r.on_handle for r in rows) / candidates if candidates else 0.0
    return f"{accuracy:.2f} ({sum(r.top_on_handle for r in rows)}/{len(rows)})"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--out", type=Path, default=Path("out/sim-views"))
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    rows = []
    with (args.out / "sim_views.csv").open("w", newline="") as handle:
        writer = csv.DictWriter(handle, [f.name for f in fields(RealDetectRow)])
        writer.writeheader()
        for views in REAL_CAPTURE_VIEWS.values():
            for view in views:
                for config in CONFIGS:
                    for seed in range(args.seeds):
                        rows.append(score_view(view, config, seed))
                        writer.writerow(asdict(rows[-1]))
    real = read_done(args.out / "real_detect.csv")
    header = ["real capture / simulated view", *CONFIGS]
    lines = ["| " + " | ".join(header) + " |", "|---" * len(header) + "|"]
    for cloud, views in REAL_CAPTURE_VIEWS.items():
        seen = [_cell([r for r in real if r.cloud == cloud and r.config == c]) for c in CONFIGS]
        lines.append(f"| real {cloud} | " + " | ".join(seen) + " |")
        for view in views:
            cells = [
                _cell([r for r in rows if r.cloud == view.name and r.config == c]) for c in CONFIGS
            ]
            lines.append(f"| sim {view.name} | " + " | ".join(cells) + " |")
    text = "\n".join(lines)
    (args.out / "sim_views.md").write_text(text + "\n")
    print(text)


if __name__ == "__main__":
    main()

"""Does the simulator predict real detection? The YCB mug (025_mug) in simulated single views
posed like the two real mug captures of ``detect-eval --real`` (the GPD table mug: upright,
0.78 m, 32 degrees above the table; the AffordanceGrasp mug: lying, handle flat beside it,
0.30 m straight above), through the kinect and stereo sensor models, scored as the real clouds
are; writes ``sim_views.csv`` and ``sim_views.md`` (sim beside real) to ``--out``.

    python scripts/sim_views.py --seeds 5 --out docs/results/real-detect
"""

from __future__ import annotations

import csv
from dataclasses import asdict, dataclass, fields
from pathlib import Path

from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked, PositiveInt
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
    "learned",
)


def _cell(rows: list[RealDetectRow]) -> str:
    candidates = sum(r.candidates for r in rows)
    accuracy = sum(r.on_handle for r in rows) / candidates if candidates else 0.0
    return f"{accuracy:.2f} ({sum(r.top_on_handle for r in rows)}/{len(rows)})"


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    seeds: PositiveInt = 5
    """Seeds 0 .. seeds - 1 of each simulated view and setting."""
    out: Path = Path("out/sim-views")
    """Folder of sim_views.csv and sim_views.md (the real rows are read from its
    real_detect.csv)."""


def run(options: Options) -> str:
    """Score every view, setting and seed; the table, sim beside real."""
    options.out.mkdir(parents=True, exist_ok=True)
    rows = []
    with (options.out / "sim_views.csv").open("w", newline="") as handle:
        writer = csv.DictWriter(handle, [f.name for f in fields(RealDetectRow)])
        writer.writeheader()
        for views in REAL_CAPTURE_VIEWS.values():
            for view in views:
                for config in CONFIGS:
                    for seed in range(options.seeds):
                        rows.append(score_view(view, config, seed))
                        writer.writerow(asdict(rows[-1]))
    real = read_done(options.out / "real_detect.csv")
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
    (options.out / "sim_views.md").write_text(text + "\n")
    return text


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    raise SystemExit(main())

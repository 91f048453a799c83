"""Where our ``--protocol acronym`` verdicts and FleX's part, by grasp geometry (issue 25).

Among the grasps our simulator held in a ``label-grasps`` run of ACRONYM files, FleX's
success rate by the width our fingers closed to (the spread of our recorded contacts along
the closing axis, m) and, for grasps closed wider than ``--wide`` (a mug's body, not its wall
or handle), by how well the object's surface faces the jaws: per side of the grasp, the largest
``|cos|`` between the mesh's face normal at a contact and the closing axis (1: the surface
squarely across the jaws; under 0.71: outside a friction cone of coefficient 1). Each row is
split by the tune / held-out halves of ``docs/results/acronym/halves.json``. Nothing is
tuned here; it reads the label directories and the files' FleX labels only.

    python scripts/acronym_disagreement.py --grasps $SIMGRASP_ACRONYM_DIR/affordance/grasps \\
        --labels-dir out/acronym/affordance --out docs/results/acronym/disagreement.md
"""

from __future__ import annotations

import json
from collections import defaultdict
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import trimesh

from simgrasp.assets.registry import load_object
from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked
from simgrasp.grasping.labeling.grasp_files import carried_object, reference_labels
from simgrasp.transforms import pose7_to_matrix

WIDTH_BINS = (0.0, 0.004, 0.008, 0.015, 0.03, 0.09)
"""Closed widths (m) of the first table's rows."""
FACING_BINS = (0.0, 0.5, 0.71, 0.95, 1.01)
"""``|cos|`` bins of the second table's rows (0.71: a friction cone of coefficient 1)."""
HALVES = Path(__file__).resolve().parents[1] / "docs/results/acronym/halves.json"


def held_grasps(grasp_file: Path, labels_dir: Path) -> list[tuple[bool, float, float]]:
    """(FleX success, closed width m, worse side's best facing |cos|) of every grasp of
    ``grasp_file`` that our run held with recorded contacts."""
    reference = reference_labels(grasp_file)
    spec = carried_object(grasp_file)
    if reference is None or spec is None:
        raise SystemExit(f"{grasp_file}: no FleX labels or no object")
    flex = reference[0]
    mesh = load_object(spec).mesh
    rows = []
    with (labels_dir / grasp_file.stem / "labels.jsonl").open() as handle:
        for line in handle:
            record = json.loads(line)
            contacts = np.asarray(record.get("contact_points_object") or [], dtype=float)
            if not record["success"] or len(contacts) < 2:
                continue
            world_T_object = pose7_to_matrix(record["object_pose"])
            world_T_tcp = pose7_to_matrix(record["grasp"])
            closing = world_T_object[:3, :3].T @ world_T_tcp[:3, 1]  # TCP +y: the closing axis
            along = contacts @ closing
            middle = (along.max() + along.min()) / 2
            _, _, faces = trimesh.proximity.closest_point(mesh, contacts)
            facing = np.abs(mesh.face_normals[faces] @ closing)
            sides = [facing[along > middle], facing[along <= middle]]
            worse = min(float(side.max()) if len(side) else 0.0 for side in sides)
            rows.append((bool(flex[record["index"]]), float(np.ptp(along)), worse))
    return rows


def table(title: str, column: str, bins: tuple[float, ...], cells: dict) -> list[str]:
    """A markdown table: rows the bins, columns the (half, category) keys of ``cells``."""
    keys = sorted(cells)
    head = " | ".join(f"{half}, {category}" for half, category in keys)
    lines = [f"### {title}", "", f"| {column} | {head} |"]
    lines.append("|---" * (len(keys) + 1) + "|")
    for low, high in zip(bins, bins[1:], strict=False):
        row = []
        for key in keys:
            values = [flex for flex, x in cells[key] if low <= x < high]
            row.append(f"{np.mean(values):.2f} ({len(values)})" if values else "-")
        lines.append(f"| {low:g} - {high:g} | " + " | ".join(row) + " |")
    return [*lines, ""]


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    grasps: Path
    """Folder of ACRONYM .h5 files."""
    labels_dir: Path
    """The label-grasps run (its --out) of those files."""
    wide: float = 0.03
    """Closed width (m) from which a grasp is a body grasp (the second table)."""
    out: Path
    """Markdown file to write."""


def run(options: Options) -> str:
    """FleX's success rate by closed width and by facing; the tables."""
    tune = set(json.loads(HALVES.read_text())["tune/files"])
    widths, facings = defaultdict(list), defaultdict(list)
    for grasp_file in sorted(options.grasps.glob("*.h5")):
        if not (options.labels_dir / grasp_file.stem / "labels.jsonl").is_file():
            continue
        key = ("tune" if grasp_file.name in tune else "held-out", grasp_file.name.split("_")[0])
        for flex, width, facing in held_grasps(grasp_file, options.labels_dir):
            widths[key].append((flex, width))
            if width >= options.wide:
                facings[key].append((flex, facing))
    lines = [
        "# FleX's success rate among the grasps our simulator held (cell: rate (grasps))",
        "",
        *table("By the width our fingers closed to (m)", "closed width", WIDTH_BINS, widths),
        *table(
            f"Grasps closed wider than {options.wide:g} m, by how squarely the surface faces the "
            "jaws",
            "worse side's \\|cos\\|",
            FACING_BINS,
            facings,
        ),
    ]
    options.out.write_text("\n".join(lines))
    return "\n".join(lines)


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    raise SystemExit(main())

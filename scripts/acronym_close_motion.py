"""How far the object moves while the jaws close, per integrator, on ACRONYM's grasps (issue 25).

For each tune-half file of ``docs/results/acronym/halves.json`` (or ``--half held_out``), its
first ``--max-grasps`` grasps are labeled with ``--protocol acronym --gripper franka_panda``
as ``label-grasps`` does, with the protocol's ``integrator`` and ``impratio`` replaced by the
options', recording the object's displacement during the close (the close phase alone: from
the open jaws at the grasp to the end of the squeeze). Prints, per category and FleX label,
how many grasps end ``missed`` (not both fingers on the object after the close) and how many
of those moved the object more than ``THROWN`` m, with FleX's own median closing motion
(``object_motion_during_closing_linear``) for them; writes the table to ``--out``.

    python scripts/acronym_close_motion.py --integrator implicitfast --impratio 0.5 \\
        --out docs/results/acronym/close_motion_implicitfast.md
    python scripts/acronym_close_motion.py --integrator discrete --impratio 0.25 \\
        --out docs/results/acronym/close_motion_discrete.md
"""

from __future__ import annotations

import json
import os
from collections import defaultdict
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Literal

import h5py
import numpy as np

import simgrasp.grasping.trials.trial as trial_module
from simgrasp.assets.model import model_for
from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked, PositiveInt
from simgrasp.grasping.labeling.grasp_files import carried_object, reference_labels
from simgrasp.grasping.labeling.grasp_sets import FRANKA_T_TCP
from simgrasp.grasping.labeling.labeling import GraspLabeler, LabelConfig

THROWN = 0.1
"""m: a grasp that moved the object farther than this while closing threw it."""
HALVES = Path(__file__).resolve().parents[1] / "docs/results/acronym/halves.json"
FLEX_CLOSING = "grasps/qualities/flex/object_motion_during_closing_linear"
ACRONYM_DIR = Path(os.environ.get("SIMGRASP_ACRONYM_DIR", "../shared/acronym"))
"""The ACRONYM data root: ``$SIMGRASP_ACRONYM_DIR``, else ``../shared/acronym``."""


def _recording_close(moved: list[float]) -> Callable[[Any], Any]:
    """The trial's close phase, appending the object's displacement (m) to ``moved``."""
    close = trial_module._close

    def recorded(trial: Any) -> Any:
        start = trial.scene.object_pose()[:3, 3].copy()
        failure = close(trial)
        moved.append(float(np.linalg.norm(trial.scene.object_pose()[:3, 3] - start)))
        return failure

    return recorded


def label_file(
    path: Path, first: int, integrator: Literal["implicitfast", "discrete"], impratio: float
) -> list[tuple]:
    """(FleX success, our failure, close displacement m, FleX closing motion m) per grasp."""
    moved: list[float] = []
    trial_module._close = _recording_close(moved)  # type: ignore[assignment]
    flex = reference_labels(path)
    if flex is None:
        raise SystemExit(f"{path}: no FleX labels")
    with h5py.File(path) as handle:
        poses = np.asarray(handle["grasps/transforms"][()])
        closing = np.asarray(handle[FLEX_CLOSING][()])
    config = LabelConfig(carried_object(path) or "", gripper="franka_panda", protocol="acronym")
    labeler = GraspLabeler(model_for(config.object), config)
    labeler.trial_config = replace(labeler.trial_config, integrator=integrator, impratio=impratio)
    rows = []
    for index in range(min(first, len(poses))):
        moved.clear()
        record = labeler.label(index, poses[index] @ FRANKA_T_TCP, float("nan"))
        motion = moved[0] if moved else float("nan")
        rows.append((bool(flex[0][index]), record["failure"], motion, float(closing[index])))
    return rows


def table(rows: dict[str, list[tuple]], title: str) -> list[str]:
    """Markdown rows: per category and FleX label, missed grasps and thrown ones."""
    lines = [
        f"### {title}",
        "",
        "| category | FleX | grasps | `missed` | thrown (moved > 0.1 m while closing) "
        "| FleX's median closing motion of the thrown (m) |",
        "|---|---|---|---|---|---|",
    ]
    for category, chosen in sorted(rows.items()):
        for flex in (True, False):
            mine = [r for r in chosen if r[0] == flex]
            missed = [r for r in mine if r[1] == "missed"]
            thrown = [r for r in missed if r[2] > THROWN]
            median = f"{np.median([r[3] for r in thrown]):.3f}" if thrown else "-"
            label = "success" if flex else "failure"
            lines.append(
                f"| {category} | {label} | {len(mine)} | {len(missed)} | {len(thrown)} | {median} |"
            )
    return [*lines, ""]


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    grasps: Path = ACRONYM_DIR / "affordance" / "grasps"
    """Folder of the ACRONYM grasp files (by default affordance/grasps under
    $SIMGRASP_ACRONYM_DIR, else under ../shared/acronym)."""
    half: Literal["tune", "held_out"] = "tune"
    """Half of docs/results/acronym/halves.json whose files are labeled."""
    max_grasps: PositiveInt = 500
    """Grasps labeled per file (its first ones)."""
    integrator: Literal["implicitfast", "discrete"]
    """MuJoCo integrator replacing the acronym protocol's."""
    impratio: float
    """MuJoCo impratio (frictional to normal constraint impedance) replacing the protocol's."""
    out: Path
    """Markdown file the table is written to."""


def run(options: Options) -> str:
    """Label the half's files under the options' integrator and impratio; the table."""
    files = json.loads(HALVES.read_text())[f"{options.half}/files"]
    rows: dict[str, list[tuple]] = defaultdict(list)
    for name in files:
        path = options.grasps / name
        if not path.is_file():
            raise SystemExit(f"no such grasp file: {path} (set SIMGRASP_ACRONYM_DIR)")
        rows[name.split("_")[0]] += label_file(
            path, options.max_grasps, options.integrator, options.impratio
        )
    title = (
        f"{options.half} half, first {options.max_grasps} grasps of each file, integrator "
        f"{options.integrator}, impratio {options.impratio:g}"
    )
    text = "\n".join(table(rows, title))
    options.out.write_text(text)
    return text


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    raise SystemExit(main())

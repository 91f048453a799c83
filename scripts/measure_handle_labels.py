"""Automatic handle labels measured on the ACRONYM affordance files (issue 25 item 2).

For every ``grasps/*.h5`` of the folder: the automatic label of its scaled mesh
(``simgrasp label-handles`` with default settings), then, with the Franka pads' contacts
approximated geometrically (simgrasp.evaluation.acronym_handles), per category (Mug, Knife)
and per half of the files (sorted names; ``tune``: even indices, on which the settings were
chosen; ``held-out``: odd indices), the share of the handle subset scored on the handle and
the share of the other successful subsets scored off it. Goals: >= 0.90 and >= 0.95.

The subsets are AffordanceGrasp's: mugs ``good_grasp`` on the handle against ``good_pour``,
``good_wrap``, ``good_contain``. For knives the files' ``good_cut`` grasps hold the handle and
``good_grasp`` the blade (see the README written beside the results), so two knife rows are
given: as the issue words it (``good_grasp`` as the handle subset) and by where the grasps are.
``--labels-dir DIR`` restricts every subset to the grasps our simulator held
(``DIR/<file stem>/labels.jsonl``, rows with ``index`` and ``success``; files without one
are left out; grasps without a row count as not held); with ``--on-handle trial`` as well, a
grasp is on the handle when its trial scored it so (the fingers' contacts in the simulator
against the label the run used: the automatic one, for these meshes), not by the pads'
geometric sweep; with ``--on-handle contacts``, the trials' recorded finger contacts scored
again against the label made now (to try labeler settings, given as flags such as
``--label.segments 4``, on a finished run). Writes
``handle_labels.md`` and ``per_file.json`` (counts only: no mesh-derived geometry).

    python scripts/measure_handle_labels.py --out docs/results/handle-labels
"""

from __future__ import annotations

import hashlib
import json
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal

from simgrasp.assets.auto_handles import LABELER_VERSION
from simgrasp.autolabel.auto_label import auto_handle_label
from simgrasp.autolabel.config import AutoLabelConfig
from simgrasp.config.arguments import script_main
from simgrasp.config.tree import flatten
from simgrasp.errors import SimgraspError
from simgrasp.evaluation.acronym_handles import (
    held_from_labels,
    read_acronym,
    subset_shares,
    trial_labels,
    trial_subset_shares,
)

GOAL_ON, GOAL_OFF = 0.90, 0.95
HANDLE_SUBSETS = {
    ("Mug", "as worded"): "good_grasp",
    ("Knife", "as worded"): "good_grasp",
    ("Knife", "by location"): "good_cut",
}


OnHandle = Literal["geometric", "trial", "contacts"]


@dataclass(frozen=True, kw_only=True)
class Options:
    data: Path = Path(os.environ.get("SIMGRASP_ACRONYM_DIR", "../shared/acronym")) / "affordance"
    """Folder holding ``grasps/`` (default: ``$SIMGRASP_ACRONYM_DIR/affordance``)."""
    out: Path = Path("docs/results/handle-labels")
    """Folder of ``handle_labels.md`` and ``per_file.json``."""
    labels_dir: Path | None = None
    """A label run's folder: only the grasps it held count."""
    on_handle: OnHandle = "geometric"
    """Who scores on_handle: the pads' geometric sweep, the run's trials, or the run's recorded
    contacts against the label made now (the last two need ``--labels-dir``)."""
    half: Literal["tune", "held-out", "all"] = "all"
    """Measure only the files of this half (a settings search looks at ``tune`` only)."""
    label: AutoLabelConfig = field(default_factory=AutoLabelConfig)


def settings_key(options: Options) -> str:
    """What a row was measured under: the labeler's settings and version, the held-grasp
    folder and who scores on_handle."""
    given = {
        "label": flatten(options.label),
        "labeler_version": LABELER_VERSION,
        "labels_dir": str(options.labels_dir),
        "on_handle": options.on_handle,
    }
    return hashlib.sha256(json.dumps(given, sort_keys=True).encode()).hexdigest()[:16]


def measure(options: Options) -> list[dict[str, object]]:
    """One row per file: its half, category and per-subset counts. Resumes from
    ``per_file.json``, reusing only rows measured under today's settings (others rerun)."""
    labels_dir, on_handle = options.labels_dir, options.on_handle
    done_file = options.out / "per_file.json"
    key = settings_key(options)
    done = {r["file"]: r for r in json.loads(done_file.read_text())} if done_file.exists() else {}
    rows = []
    for index, path in enumerate(sorted((options.data / "grasps").glob("*.h5"))):
        half = "tune" if index % 2 == 0 else "held-out"
        if options.half not in (half, "all"):
            continue
        if done.get(path.stem, {}).get("settings") == key:
            rows.append(done[path.stem])
            continue
        labels = labels_dir / path.stem / "labels.jsonl" if labels_dir is not None else None
        if labels is not None and not labels.is_file():
            print(f"{path.stem}: no {labels}, left out", flush=True)
            continue
        item = read_acronym(path)
        if on_handle == "trial" and labels is not None:
            shares = trial_subset_shares(item, *trial_labels(labels, len(item.object_T_hands)))
            boxes = None
        elif on_handle == "contacts" and labels is not None:
            result = auto_handle_label(item.mesh, item.name, options.label)
            scored = trial_labels(labels, len(item.object_T_hands), result.label)
            shares = trial_subset_shares(item, *scored)
            boxes = len(result.label.regions)
        else:
            result = auto_handle_label(item.mesh, item.name, options.label)
            held = None if labels is None else held_from_labels(labels, len(item.object_T_hands))
            shares = subset_shares(item, result.label, held=held)
            boxes = len(result.label.regions)
        row = {
            "file": path.stem,
            "half": half,
            "category": path.stem.split("_")[0],
            "boxes": boxes,
            "subsets": shares,
            "settings": key,
        }
        rows.append(row)
        print(row["file"], row["half"], shares, flush=True)
        done_file.write_text(json.dumps(rows, indent=1) + "\n")
    return rows


def _pooled(rows: list[dict], keys: list[str]) -> tuple[int, int]:
    """(on-handle count, grasps) of ``keys`` summed over ``rows``."""
    on = sum(int(r["subsets"].get(k, {}).get("on_handle", 0)) for r in rows for k in keys)
    total = sum(int(r["subsets"].get(k, {}).get("grasps", 0)) for r in rows for k in keys)
    return on, total


def table(rows: list[dict]) -> str:
    """The markdown table: per category, reading and half, both shares against the goals."""
    lines = [
        "| category | handle subset | half | files | handle grasps on handle "
        f"(goal >= {GOAL_ON}) | other successes off handle (goal >= {GOAL_OFF}) |",
        "|---|---|---|---|---|---|",
    ]
    for (category, reading), handle_key in HANDLE_SUBSETS.items():
        for half in ("tune", "held-out", "all"):
            chosen = [r for r in rows if r["category"] == category and half in (r["half"], "all")]
            keys = sorted({k for r in chosen for k in r["subsets"]})
            on, n_on = _pooled(chosen, [handle_key])
            off, n_off = _pooled(chosen, [k for k in keys if k != handle_key])
            share_on = f"{on / n_on:.3f} ({on}/{n_on})" if n_on else "-"
            share_off = f"{1 - off / n_off:.3f} ({n_off - off}/{n_off})" if n_off else "-"
            lines.append(
                f"| {category} | {handle_key} ({reading}) | {half} | {len(chosen)} | "
                f"{share_on} | {share_off} |"
            )
    return "\n".join(lines) + "\n"


def run(options: Options) -> str:
    """Measure (see the module doc), write ``handle_labels.md``; the table and the boxes per
    file."""
    if options.on_handle != "geometric" and options.labels_dir is None:
        raise SimgraspError(
            f"--on-handle {options.on_handle} needs --labels-dir (the trials' records)"
        )
    options.out.mkdir(parents=True, exist_ok=True)
    rows = measure(options)
    text = table(rows)
    (options.out / "handle_labels.md").write_text(text)
    return f"{text}\nper-file boxes: {[r['boxes'] for r in rows]}"


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    raise SystemExit(main())

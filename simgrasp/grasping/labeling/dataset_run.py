"""Label a whole data set of grasp files in one run: each file into ``OUT/<file stem>/``, one
``OUT/summary.json`` over all of them, written when every file is done (a run removes an
earlier one first, so a run that stopped midway leaves none).

Each file is a :func:`~simgrasp.grasping.label_run.label_grasp_set` run of its own directory,
so a killed run resumes file by file and grasp by grasp (rerun the same command); a file whose
labels are complete costs only reading them. Every file's directory is checked against this
run's settings before any is labeled (a changed setting is refused before it mixes any), and
each is held (:func:`~simgrasp.runs.out_dir.claim_out_dir`) while it is labeled, so a
single-file run on it is refused meanwhile, as is this run on one another run holds. The
worker processes (or the Ray session) stay up from one file to the next; each file's run
builds its object's labeler in them. Files that name their object (ACRONYM, GraspGen)
are labeled on it; others on OBJECT. Where a file carries reference labels (FleX's), the
summary adds their agreement (:mod:`simgrasp.grasping.labeling.agreement`).
"""

from __future__ import annotations

import json
import sys
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from simgrasp.errors import DataNotFoundError, SimgraspError
from simgrasp.grasping.labeling.grasp_sets import GraspSet, read_grasp_set
from simgrasp.grasping.labeling.labeling import LabelConfig

SUMMARY_FILE = "summary.json"


def object_for(options: Any, grasp_file: Path) -> LabelConfig:
    """The label settings of one grasp file: its own object (ACRONYM, GraspGen) unless OBJECT
    was given, with the mesh options folded in."""
    from simgrasp.grasping.labeling.grasp_files import carried_object

    config: LabelConfig = options.label
    if config.object:
        try:
            names_its_own = carried_object(grasp_file, options.mesh_root) is not None
        except DataNotFoundError:  # it names a mesh that is not here: OBJECT stands in for it
            names_its_own = True
        if names_its_own:
            print(
                f"note: {grasp_file.name} names its own object; labeling {config.object} "
                "instead, as given (leave OBJECT out to use the file's)",
                file=sys.stderr,
            )
        return replace(config, object=options.object_name(config.object))
    name = carried_object(grasp_file, options.mesh_root)
    if not name:
        raise SimgraspError(f"{grasp_file} names no object: give OBJECT")
    return replace(config, object=options.object_name(name))


def grasps_for(grasp_file: Path, max_grasps: int | None) -> GraspSet:
    """The first ``max_grasps`` grasps of a file (all for None); a file without a valid grasp
    among them is an error naming it (and the first row's problem)."""
    grasps = read_grasp_set(grasp_file).first(max_grasps)
    if grasps.valid.any():
        return grasps
    reason = next((f"row {i}: {p}" for i, p in grasps.problems.items()), "it has no rows")
    raise SimgraspError(f"{grasp_file}: no row of the grasp file is a valid grasp ({reason})")


def checked_files(files: list[Path], options: Any) -> list[tuple[LabelConfig, GraspSet]]:
    """Each file's label settings (:func:`object_for`) and grasps, every file read once and
    checked first (:func:`grasps_for`, :func:`check_export`), and so is its directory under
    ``options.out``, if it has one, against this run's settings (:func:`check_run_dir`): a bad
    file or a changed setting stops a data set's run before it starts, not midway."""
    from simgrasp.grasping.labeling.label_run import check_run_dir, run_identity

    checked = []
    for grasp_file in files:
        config = object_for(options, grasp_file)
        grasps = grasps_for(grasp_file, options.max_grasps)
        if options.export:
            check_export(grasp_file, options.export)
        check_run_dir(options.out / grasp_file.stem, run_identity(grasps, config, grasp_file))
        checked.append((config, grasps))
    return checked


def label_files(files: list[Path], options: Any, command: list[str]) -> int:
    """Label every file of a data set (module docstring; ``command``: the invocation recorded
    with the output directory); prints one line per file."""
    from simgrasp.runs.engine import RunConfig, workers_kept_up
    from simgrasp.runs.out_dir import claim_out_dir

    if options.out is None:
        raise SimgraspError("--grasps with several files needs --out DIR")
    checked = checked_files(files, options)
    rows = []
    run = RunConfig(options.workers, options.backend, options.address)
    with claim_out_dir(options.out, command), workers_kept_up(run):
        # an earlier run's summary would stand for this one if it stops before the end
        (options.out / SUMMARY_FILE).unlink(missing_ok=True)
        # the workers stay up from one file's object to the next
        for grasp_file, (config, grasps) in zip(files, checked, strict=True):
            rows.append(label_file(grasp_file, config, grasps, options, command))
            print(f"{grasp_file.name}: {_line(rows[-1])}", file=sys.stderr)
    total = _totals(rows)
    (options.out / SUMMARY_FILE).write_text(json.dumps({"files": rows, **total}, indent=2) + "\n")
    sys.stdout.write(f"{len(rows)} files: {_line(total)}\noutput       {options.out}\n")
    return 0


def label_file(
    grasp_file: Path, config: LabelConfig, grasps: GraspSet, options: Any, command: list[str]
) -> dict[str, Any]:
    """Label ``grasps``, one file's, into ``OUT/<file stem>/``, holding that directory
    (:func:`~simgrasp.runs.out_dir.claim_out_dir`: refused, naming the holder, while another
    run is on it); return its summary row."""
    from simgrasp.grasping.labeling.label_run import label_grasp_set
    from simgrasp.runs.out_dir import claim_out_dir

    out = options.out / grasp_file.stem
    with claim_out_dir(out, command):
        summary, _ = label_grasp_set(
            grasps,
            config,
            out,
            grasp_file=grasp_file,
            ycb_dir=options.ycb_dir,
            workers=options.workers,
            backend=options.backend,
            address=options.address,
            progress=False,
        )
        if options.export:
            export_run(grasp_file, out, options.export, options.out)
    return _row(grasp_file, out, summary)


def _row(grasp_file: Path, out: Path, summary: dict[str, Any]) -> dict[str, Any]:
    """One file's summary line: counts, speed and, with reference labels, agreement."""
    from simgrasp.grasping.labeling.agreement import agreement
    from simgrasp.grasping.labeling.grasp_files import reference_labels

    keys = ("grasps", "invalid", "sim_unstable", "scored", "success", "trial_wall_s")
    row: dict[str, Any] = {"file": grasp_file.name, "dir": out.name}
    row.update({k: summary[k] for k in keys})
    reference = reference_labels(grasp_file)
    if reference is not None:
        ours, score, scored = _our_labels(out)
        row["agreement"] = agreement(reference[0][: len(ours)][scored], ours[scored], score[scored])
    return row


def _our_labels(out: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(success, score, scored) of a label directory's ``labels.npz``; without a ``score``
    the success itself (0/1) ranks."""
    with np.load(out / "labels.npz") as labels:
        success = labels["success"]
        scored = ~np.isin(labels["failure"], ("invalid", "sim_unstable"))
        score = labels["score"] if "score" in labels.files else success.astype(float)
    return success, score, scored


def _totals(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """Counts over all files and the speed per core (executed grasps over their wall time)."""
    keys = ("grasps", "invalid", "sim_unstable", "scored", "success", "trial_wall_s")
    total: dict[str, Any] = {k: sum(r[k] for r in rows) for k in keys}
    executed = total["grasps"] - total["invalid"]
    total["grasps_per_core_s"] = executed / total["trial_wall_s"] if total["trial_wall_s"] else None
    return total


def _line(row: dict[str, Any]) -> str:
    text = f"{row['success']} of {row['scored']} scored held ({row['grasps']} grasps)"
    if "agreement" in row:
        a = row["agreement"]
        text += f", agreement {a['accuracy']:.3f} (balanced {a['balanced_accuracy']:.3f})"
    return text


def check_export(grasp_file: Path, fmt: str) -> None:
    """Raise unless ``grasp_file`` is of the format ``--export fmt`` writes back."""
    from simgrasp.grasping.labeling.grasp_files import is_graspgen

    wanted = "acronym" if grasp_file.suffix.lower() in (".h5", ".hdf5") else None
    wanted = "graspgen" if is_graspgen(grasp_file) else wanted
    if wanted != fmt:
        raise SimgraspError(f"--export {fmt} needs {fmt} grasp files, not {grasp_file}")


def export_run(grasp_file: Path, out: Path, fmt: str, top: Path) -> Path:
    """Write ``grasp_file`` with the labels of directory ``out`` added (``top/export/``)."""
    from simgrasp.grasping.labeling.grasp_files import EXPORT_DIR, export_labels

    check_export(grasp_file, fmt)
    success, score, _ = _our_labels(out)
    with np.load(out / "labels.npz") as labels:
        on_handle = labels["on_handle"]
    qualities = {"object_in_gripper": success, "score": score, "on_handle": on_handle}
    return export_labels(grasp_file, top / EXPORT_DIR, qualities)

"""Agreement of two labelings of one grasp set (e.g. the ``fast`` and ``full`` protocols).

Reads the ``labels.npz`` of two ``label-grasps`` output directories (same grasps, same order).
Grasps that either run could not score (``invalid`` or ``sim_unstable``) are left out; over the
rest, the confusion matrix of the ``success`` verdicts and the agreement (the share of equal
verdicts), and the agreement of ``on_handle`` among grasps both runs held. Two runs of different
grasp files or of different objects (``run.json``) are refused, and so are labels compared with
a grasp file's own that were made on another object than the file names.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from simgrasp.errors import DataNotFoundError, SimgraspError

UNSCORED = ("invalid", "sim_unstable")


def load_labels(out_dir: Path) -> dict[str, np.ndarray]:
    path = Path(out_dir) / "labels.npz"
    if not path.is_file():
        raise DataNotFoundError(f"{path} does not exist: label the grasps with label-grasps first")
    with np.load(path) as labels:
        return {key: labels[key] for key in labels.files}


def compare_labels(reference_dir: Path, other_dir: Path) -> dict[str, Any]:
    """Confusion counts of ``success`` (reference x other) and agreements, over the grasps
    both label (a run of a file's first N grasps against one of more: the first N); two
    directories made from different grasp files (``run.json``) are refused."""
    from simgrasp.grasping.labeling.label_run import labeled_file_digest

    digests = labeled_file_digest(reference_dir), labeled_file_digest(other_dir)
    if None not in digests and digests[0] != digests[1]:
        raise SimgraspError(f"{reference_dir} and {other_dir} label different grasp files")
    first, second = labeled_object(reference_dir), labeled_object(other_dir)
    if first is not None and second is not None and not same_object(first, second):
        raise SimgraspError(
            f"{reference_dir} labels {object_label(first)} but {other_dir} labels "
            f"{object_label(second)}"
        )
    reference, other = load_labels(reference_dir), load_labels(other_dir)
    common = min(len(reference["success"]), len(other["success"]))
    reference = {key: values[:common] for key, values in reference.items()}
    other = {key: values[:common] for key, values in other.items()}
    scored = ~np.isin(reference["failure"], UNSCORED) & ~np.isin(other["failure"], UNSCORED)
    ref, oth = reference["success"][scored], other["success"][scored]
    both = reference["success"] & other["success"] & scored
    same_handle = reference["on_handle"][both] == other["on_handle"][both]
    return {
        "scored": int(scored.sum()),
        "held_held": int(np.sum(ref & oth)),
        "held_failed": int(np.sum(ref & ~oth)),
        "failed_held": int(np.sum(~ref & oth)),
        "failed_failed": int(np.sum(~ref & ~oth)),
        "agreement": float(np.mean(ref == oth)) if len(ref) else 0.0,
        "on_handle_agreement": float(np.mean(same_handle)) if len(same_handle) else 0.0,
    }


def labeled_object(out_dir: Path) -> str | None:
    """The object a label directory's grasps were labeled on (its ``run.json``), or None when
    it does not say (no or an unreadable ``run.json``)."""
    from simgrasp.grasping.labeling.label_run import RUN_FILE

    try:
        name = json.loads((Path(out_dir) / RUN_FILE).read_text()).get("object")
    except (OSError, ValueError, AttributeError):
        return None
    return name if isinstance(name, str) else None


def object_label(name: str) -> str:
    """An object name as its object is called: a generated tool with its size seed
    (``gen_hammer`` is ``gen_hammer_s0``), without another handle label file
    (``NAME?handles=FILE``); a mesh spec as it is."""
    from simgrasp.assets.mesh_object import is_mesh_spec, split_spec
    from simgrasp.scenes.clutter_sets import canonical_name

    return name if is_mesh_spec(name) else canonical_name(split_spec(name)[0])


def same_object(first: str, second: str) -> bool:
    """Whether two object names are one object: the same :func:`object_label`, or mesh specs
    of one mesh file (by its name: runs may read it from other folders) at one scale. Mass,
    friction and the handle label are conditions two labelings may compare."""
    from simgrasp.assets.mesh_object import is_mesh_spec, parse_mesh_spec

    if is_mesh_spec(first) and is_mesh_spec(second):
        one, two = parse_mesh_spec(first), parse_mesh_spec(second)
        return one.path.name == two.path.name and math.isclose(one.factor, two.factor, rel_tol=1e-6)
    return object_label(first) == object_label(second)


def check_reference_object(ours_dir: Path, reference: Path) -> None:
    """Refuse the labels of grasp file ``reference`` under ``ours_dir`` (a label-grasps output,
    :func:`~simgrasp.grasping.labeling.reference_compare.labels_dir_of`) made on another object
    than the one the file names: compared with the file's own labels, they would score another
    object's grasps. The file is read first (a file that is none is named whole). Nothing is
    checked when either does not say (no object in ``run.json``, a file that names none, or
    whose mesh is not where the file says: ``--mesh-root``)."""
    from simgrasp.grasping.labeling.grasp_files import carried_object
    from simgrasp.grasping.labeling.reference_compare import labels_dir_of

    try:
        theirs = carried_object(reference)
    except DataNotFoundError:
        return
    labels_dir = labels_dir_of(ours_dir, reference)
    ours = labeled_object(labels_dir)
    if ours is not None and theirs is not None and not same_object(ours, theirs):
        raise SimgraspError(
            f"{labels_dir} labels {object_label(ours)} but {reference.name} holds grasps of "
            f"{theirs}"
        )


def confusion_text(comparison: dict[str, Any], reference: str, other: str) -> str:
    """The comparison as a small table (rows: reference verdicts, columns: other's)."""
    c = comparison
    return "\n".join(
        [
            f"{'':16} {other + ' held':>14} {other + ' failed':>14}",
            f"{reference + ' held':16} {c['held_held']:14d} {c['held_failed']:14d}",
            f"{reference + ' failed':16} {c['failed_held']:14d} {c['failed_failed']:14d}",
            f"agreement {c['agreement']:.3f} over {c['scored']} scored grasps; on_handle "
            f"agreement {c['on_handle_agreement']:.3f} among grasps both held",
        ]
    )

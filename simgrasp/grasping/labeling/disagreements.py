"""Grasps where our labels and a grasp file's own (FleX's ``object_in_gripper``) disagree: a
few of each kind, picked by seed, replayed with pictures of their key moments so a person
can see why (``simgrasp compare-labels OURS --reference FILE --examples DIR``).

The two kinds: the reference held the object and we did not (``reference_held``), and we
held it and the reference did not (``ours_held``). Grasps we could not score (``invalid``,
``sim_unstable``) are not disagreements. Each example is replayed with the label run's own
settings (its ``summary.json``: object, gripper, protocol, seed, placement, free floating) on
the same code path as ``label-grasps``; its record says whether the replay gave the stored
verdict.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, fields
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from simgrasp.errors import SimgraspError
from simgrasp.seeding import rng_for

if TYPE_CHECKING:
    from simgrasp.grasping.labeling.grasp_sets import GraspSet
    from simgrasp.grasping.labeling.labeling import GraspLabeler

Kind = Literal["reference_held", "ours_held"]
KINDS: tuple[Kind, ...] = ("reference_held", "ours_held")
VIEW_DISTANCE = 0.35
"""Camera to TCP in the pictures (m): a hand and a mug fill the frame."""


@dataclass(frozen=True)
class Disagreement:
    """One grasp the two label sets disagree on.

    Attributes:
        file: the grasp file's name.
        index: the grasp's row in it.
        kind: who held the object (:data:`KINDS`).
        our_failure: why our trial failed (``""`` when we held it).
        our_score: how firmly we held it (0-1; 0 when we did not).
        reference_shaking_m: the reference's object motion during its shake (m), where the
            file records it (ACRONYM's ``object_motion_during_shaking_linear``), else None.
    """

    file: str
    index: int
    kind: Kind
    our_failure: str
    our_score: float
    reference_shaking_m: float | None


def find_disagreements(labels_dir: Path, grasp_file: Path) -> list[Disagreement]:
    """The scored grasps of ``labels_dir`` (a label-grasps run of ``grasp_file``) whose verdict
    differs from the file's own label, in row order."""
    from simgrasp.grasping.labeling.dataset_run import _our_labels
    from simgrasp.grasping.labeling.grasp_files import reference_labels

    reference = reference_labels(grasp_file)
    if reference is None:
        raise SimgraspError(f"{grasp_file} has no reference labels (object_in_gripper)")
    truth, shaking = reference
    success, score, scored = _our_labels(labels_dir)
    with np.load(labels_dir / "labels.npz") as labels:
        failure = labels["failure"]
    count = min(len(success), len(truth))
    rows = np.flatnonzero(scored[:count] & (success[:count] != truth[:count]))
    return [
        Disagreement(
            file=grasp_file.name,
            index=int(i),
            kind="reference_held" if truth[i] else "ours_held",
            our_failure=str(failure[i]),
            our_score=float(score[i]),
            reference_shaking_m=None if shaking is None else float(shaking[i]),
        )
        for i in rows
    ]


def pick_examples(found: list[Disagreement], per_kind: int, seed: int) -> list[Disagreement]:
    """Up to ``per_kind`` of each kind, drawn without replacement from ``seed``; kinds in
    :data:`KINDS` order, each kind's picks in file and row order."""
    picked: list[Disagreement] = []
    for kind in KINDS:
        mine = [d for d in found if d.kind == kind]
        chosen = rng_for(seed, "disagreement_examples", kind).permutation(len(mine))[:per_kind]
        picked += [mine[i] for i in sorted(chosen)]
    return picked


def labeler_of(labels_dir: Path) -> GraspLabeler:
    """A labeler with the settings of the label run in ``labels_dir`` (its ``summary.json``
    holds every :class:`LabelConfig` field)."""
    import json

    from simgrasp.assets.model import model_for
    from simgrasp.grasping.labeling.labeling import GraspLabeler, LabelConfig

    run = json.loads((labels_dir / "summary.json").read_text())
    config = LabelConfig(**{f.name: run[f.name] for f in fields(LabelConfig)})
    return GraspLabeler(model_for(config.object), config)


def replay(labeler: GraspLabeler, grasps: GraspSet, index: int) -> tuple[list, dict]:
    """Rerun row ``index`` of ``grasps`` with ``labeler``, seen across the jaws at the TCP:
    (key frames as (H, W, 3) uint8 pictures, the trial record)."""
    from simgrasp.scenes.kept_renderer import RendererKeeper
    from simgrasp.scenes.key_frames import FrameRecorder

    object_T_tcp = grasps.object_T_tcp[index]
    world_T_tcp = labeler.world_T_object @ object_T_tcp
    across = world_T_tcp[:3, 0]  # across the jaws, normal to the approach and the closing
    view = -across if across[2] > 0 else across  # from above
    with RendererKeeper() as renderers:
        frames = FrameRecorder(
            renderers, VIEW_DISTANCE, aim_world=world_T_tcp[:3, 3], view_world=view
        )
        record = labeler.label(index, object_T_tcp, grasps.width[index], frames)
    return frames.frames, record


def write_examples(
    ours: Path, grasp_files: list[Path], out: Path, per_kind: int, seed: int
) -> list[dict[str, Any]]:
    """Pick ``per_kind`` disagreements of each kind over all ``grasp_files`` (their label runs
    under ``ours``), replay them (one labeler and one read of each file that holds one), and
    write one picture each to ``out`` (``<kind>_<file stem>_<row>.png``) and
    ``out/examples.json``; returns its entries."""
    import json

    from simgrasp.grasping.labeling.grasp_sets import read_grasp_set
    from simgrasp.grasping.labeling.reference_compare import labels_dir_of
    from simgrasp.plots.disagreement import plot_disagreement

    runs = {f.name: (f, labels_dir_of(ours, f)) for f in grasp_files}
    found = [d for f, run in runs.values() for d in find_disagreements(run, f)]
    out.mkdir(parents=True, exist_ok=True)
    replayers: dict[str, tuple[GraspLabeler, GraspSet]] = {}
    entries = []
    for example in pick_examples(found, per_kind, seed):
        if example.file not in replayers:
            grasp_file, labels_dir = runs[example.file]
            replayers[example.file] = (labeler_of(labels_dir), read_grasp_set(grasp_file))
        frames, record = replay(*replayers[example.file], example.index)
        stem = Path(example.file).stem
        path = out / f"{example.kind}_{stem[:40]}_{example.index}.png"
        replayed = "held" if record["success"] else f"failed ({record['failure']})"
        plot_disagreement(frames, _caption(example, replayed), path)
        entry = {**asdict(example), "picture": path.name, "replay": replayed}
        entry["replay_matches"] = bool(record["success"]) == (example.kind == "ours_held")
        entries.append(entry)
    (out / "examples.json").write_text(json.dumps(entries, indent=1) + "\n")
    return entries


def _caption(example: Disagreement, replayed: str) -> str:
    """Two lines: the grasp and each side's verdict."""
    reference = "held" if example.kind == "reference_held" else "dropped"
    if example.reference_shaking_m is not None:
        reference += f", object moved {100 * example.reference_shaking_m:.1f} cm in its shake"
    ours = f"held, score {example.our_score:.2f}" if example.kind == "ours_held" else "dropped"
    if example.our_failure:
        ours += f" ({example.our_failure})"
    return (
        f"{example.file} row {example.index}\n"
        f"reference: {reference}   ours: {ours}   replay: {replayed}"
    )

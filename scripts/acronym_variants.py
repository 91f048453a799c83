"""Physics variants of the ``acronym`` protocol measured on a small tune subset (issue 25).

For each named tune-half file (``docs/results/acronym/halves.json``) it draws ``--per-class``
FleX successes and as many FleX failures among the file's first 500 grasps (seeded, so every
variant sees the same grasps), labels them with ``--protocol acronym --gripper franka_panda``
as ``label-grasps`` does (one scene per file, the file's hand poses mapped to our TCP), once
per variant, and prints accuracy and balanced accuracy against FleX's ``object_in_gripper``
per category, with the failures of the FleX successes we drop and the count of FleX failures
we hold. A variant changes one thing on the compiled model or the trial settings:

- ``base``: the committed protocol;
- ``mu<F>``: the fingers' sliding friction (the pads take priority over the object's 1.0);
- ``tors<T>`` / ``condim3``: the fingers' torsional friction (m), or no torsion at all;
- ``force<N>``: the jaws' force limit (N; it also slows their opening);
- ``shake_big``: twice the shake (6 cm, 0.3 rad);
- ``fine_hulls``: CoACD at threshold 0.05, up to 32 hulls, preprocess resolution 50;
- ``tight_hulls``: CoACD at threshold 0.05, no cap on the hull count, no voxel remeshing
  (the ACRONYM meshes are watertight): the hulls fill less of a mug's cavity;
- ``no_remesh``: CoACD's default threshold and hull cap, without its voxel remeshing (which
  CoACD's ``auto`` runs on these watertight meshes, thickening a 3 mm blade to about 6 mm);
- ``imp<R>``: the trial's ``impratio``; ``width<M>``: the fingers' ``solimp`` ramp (m,
  ``TrialConfig.finger_solimp_width``); ``tc<S>``: the fingers' contact time constant (s);
  ``noslip<N>``: MuJoCo's noslip iterations (friction without creep);
- ``massfloor<KG>``: the object at least this heavy (mass and inertia scaled together): a
  soft contact's creep under the jaws' own sideways push goes as one over the object's mass,
  which FleX's particles do not share;
- ``fileinertia``: the object's principal moments as its file gives them (a thin knife's
  smallest moment is otherwise raised to mass x ``MIN_RADIUS_OF_GYRATION``^2);
- ``margin<M>``: the object's collision geoms get a contact margin of M (m) with no gap, so
  they push back from M away: the object inflated by M, as a particle or SDF simulator's
  collision distance inflates its shapes.

Variants join with ``+`` (``width0.007+imp0.45``, ``tight_hulls+width0.01``: hulls first).
``--per-class 0`` labels every one of a file's first 500 grasps, and ``--files tune`` names
the tune half of ``halves.json``:

    python scripts/acronym_variants.py --variants base,mu0.3,condim3 --per-class 20
    python scripts/acronym_variants.py --files tune --per-class 0 --variants base,imp0.25+width0.001
"""

from __future__ import annotations

import json
import os
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import h5py
import mujoco
import numpy as np

from simgrasp.assets.decompose import DecompositionConfig
from simgrasp.assets.model import (
    MIN_RADIUS_OF_GYRATION,
    ObjectModel,
    build_object_model,
    model_for,
)
from simgrasp.assets.registry import load_object
from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked, NonNegativeInt
from simgrasp.grasping.labeling.grasp_files import carried_object, reference_labels
from simgrasp.grasping.labeling.grasp_sets import FRANKA_T_TCP
from simgrasp.grasping.labeling.labeling import GraspLabeler, LabelConfig

FIRST = 500
"""The committed run labels each affordance file's first 500 grasps: the subset is drawn there."""
DEFAULT_FILES = (
    "Mug_1ea9ea99ac8ed233bf355ac8109b9988_0.00016407252808445613.h5",
    "Mug_40f9a6cc6b2c3b3a78060a3a3a55e18f_0.0006670441940038386.h5",
    "Mug_b7841572364fd9ce1249ffc39a0c3c0b_0.0003944227048461527.h5",
    "Mug_cf777e14ca2c7a19b4aad3cc5ce7ee8_0.0014629281758254072.h5",
    "Knife_38c843d1075bd351e652fa812161367_0.016712266939760273.h5",
    "Knife_89e8bae10847eb8a8721ead1444fbb07_0.01976018915084059.h5",
)
FINGERS = ("gripper/left_finger", "gripper/right_finger")
HALVES = Path(__file__).resolve().parents[1] / "docs" / "results" / "acronym" / "halves.json"
"""The committed split of the affordance files into a tune and a held-out half."""
ACRONYM_DIR = Path(os.environ.get("SIMGRASP_ACRONYM_DIR", "../shared/acronym"))
"""The ACRONYM data root: ``$SIMGRASP_ACRONYM_DIR``, else ``../shared/acronym``."""
FINE_HULLS = DecompositionConfig(threshold=0.05, max_convex_hull=32, preprocess_resolution=50)
TIGHT_HULLS = DecompositionConfig(threshold=0.05, max_convex_hull=-1, preprocess_mode="off")
NO_REMESH = DecompositionConfig(preprocess_mode="off")
HULLS = {"fine_hulls": FINE_HULLS, "tight_hulls": TIGHT_HULLS, "no_remesh": NO_REMESH}
Variant = Callable[[GraspLabeler], None]
Row = tuple[str, bool, bool, str | None]
"""(category, FleX success, our success, our failure)."""


def _fingers(labeler: GraspLabeler, column: int, value: float, condim: int | None = None) -> None:
    model = labeler.scene.model
    for name in FINGERS:
        geom = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, name)
        if geom < 0:
            raise SystemExit(f"no geom {name!r} in the scene")
        model.geom_friction[geom, column] = value
        if condim is not None:
            model.geom_condim[geom] = condim


def _force(labeler: GraspLabeler, newtons: float) -> None:
    model = labeler.scene.model
    model.actuator_forcerange[labeler.scene.gripper.actuator] = (-newtons, newtons)


def _shake_big(labeler: GraspLabeler) -> None:
    trial = labeler.trial_config
    assert trial.shake is not None
    shake = replace(trial.shake, linear_amplitude=0.06, angular_amplitude=0.3)
    labeler.trial_config = replace(trial, shake=shake)


def _trial(labeler: GraspLabeler, **changes: Any) -> None:
    labeler.trial_config = replace(labeler.trial_config, **changes)


def _contact_time(labeler: GraspLabeler, seconds: float) -> None:
    model = labeler.scene.model
    left, right = labeler.scene.gripper.finger_geoms
    model.geom_solref[list(left + right), 0] = seconds


def _noslip(labeler: GraspLabeler, iterations: float) -> None:
    labeler.scene.model.opt.noslip_iterations = int(iterations)


def _mass_floor(labeler: GraspLabeler, kilograms: float) -> None:
    model, body = labeler.scene.model, labeler.scene.object_body
    factor = max(1.0, kilograms / float(model.body_mass[body]))
    model.body_mass[body] *= factor
    model.body_inertia[body] *= factor
    mujoco.mj_setConst(model, mujoco.MjData(model))


def _file_inertia(labeler: GraspLabeler, path: Path) -> None:
    """The object's principal moments as its file gives them: the smallest one of a thin
    knife is otherwise raised to mass x ``MIN_RADIUS_OF_GYRATION``^2."""
    model, body = labeler.scene.model, labeler.scene.object_body
    with h5py.File(path) as handle:
        moments = np.linalg.eigvalsh(np.asarray(handle["object/inertia"][()]))
    floor = float(model.body_mass[body]) * MIN_RADIUS_OF_GYRATION**2
    floored = np.isclose(model.body_inertia[body], floor, rtol=1e-6)
    model.body_inertia[body][floored] = moments[0]
    mujoco.mj_setConst(model, mujoco.MjData(model))


def _margin(labeler: GraspLabeler, meters: float) -> None:
    model, body = labeler.scene.model, labeler.scene.object_body
    geoms = np.flatnonzero(model.geom_bodyid == body)
    model.geom_margin[geoms] = meters
    model.geom_gap[geoms] = 0.0


def _together(changes: list[Variant]) -> Variant:
    def apply(labeler: GraspLabeler) -> None:
        for change in changes:
            change(labeler)

    return apply


def variant(name: str) -> Variant:
    """The change ``name`` makes to a freshly built labeler (module docstring)."""
    if "+" in name:
        return _together([variant(part) for part in name.split("+")])
    if name == "base" or name in HULLS or name == "fileinertia":
        return lambda labeler: None
    if name == "shake_big":
        return _shake_big
    if name == "condim3":
        return lambda labeler: _fingers(labeler, 1, 0.0, condim=3)
    for prefix, apply in (
        ("mu", lambda lab, v: _fingers(lab, 0, v)),
        ("tors", lambda lab, v: _fingers(lab, 1, v)),
        ("force", _force),
        ("imp", lambda lab, v: _trial(lab, impratio=v)),
        ("width", lambda lab, v: _trial(lab, finger_solimp_width=v)),
        ("tc", _contact_time),
        ("noslip", _noslip),
        ("massfloor", _mass_floor),
        ("margin", _margin),
    ):
        if name.startswith(prefix):
            value = float(name[len(prefix) :])
            return lambda labeler, v=value, f=apply: f(labeler, v)  # type: ignore[misc]
    raise SystemExit(f"unknown variant {name!r}")


def subset(path: Path, per_class: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(indices, hand poses, FleX labels) of the seeded balanced draw among the first grasps."""
    labels = reference_labels(path)
    if labels is None:
        raise SystemExit(f"{path} has no FleX labels")
    flex = labels[0][:FIRST]
    if per_class == 0:
        chosen: list[int] = list(range(len(flex)))
        with h5py.File(path) as handle:
            return np.array(chosen), np.asarray(handle["grasps/transforms"][()]), flex
    rng = np.random.default_rng(0)
    chosen = []
    for cls in (True, False):
        pool = np.flatnonzero(flex == cls)
        chosen += list(rng.choice(pool, min(per_class, len(pool)), replace=False))
    with h5py.File(path) as handle:
        poses = np.asarray(handle["grasps/transforms"][()])
    return np.array(chosen), poses, flex


def label_variant(name: str, files: list[Path], per_class: int) -> list[Row]:
    """Every subset grasp of ``files`` labeled under variant ``name``."""
    change, rows = variant(name), []
    for path in files:
        indices, poses, flex = subset(path, per_class)
        config = LabelConfig(carried_object(path) or "", gripper="franka_panda", protocol="acronym")
        hulls = [HULLS[part] for part in name.split("+") if part in HULLS]
        if hulls:
            model: ObjectModel = build_object_model(load_object(config.object), hulls[0])
        else:
            model = model_for(config.object)
        labeler = GraspLabeler(model, config)
        change(labeler)
        if "fileinertia" in name.split("+"):
            _file_inertia(labeler, path)
        for i in indices:
            record = labeler.label(int(i), poses[i] @ FRANKA_T_TCP, float("nan"))
            rows.append(
                (path.name.split("_")[0], bool(flex[i]), bool(record["success"]), record["failure"])
            )
    return rows


def summary(name: str, rows: list[Row]) -> str:
    """One line: accuracy / balanced accuracy per category and overall, what we get wrong."""
    parts = [name]
    for category in ("Mug", "Knife", ""):
        chosen = [r for r in rows if r[0].startswith(category)]
        if not chosen:
            continue
        ref, ours = np.array([r[1] for r in chosen]), np.array([r[2] for r in chosen])
        balanced = (np.mean(ours[ref]) + np.mean(~ours[~ref])) / 2
        parts.append(f"{category or 'all'} {np.mean(ref == ours):.3f}/{balanced:.3f}")
    dropped: Counter[Any] = Counter(r[3] for r in rows if r[1] and not r[2])
    held = sum(1 for r in rows if not r[1] and r[2])
    parts.append(f"FleX successes we fail: {dict(dropped)}; FleX failures we hold: {held}")
    return " | ".join(parts)


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    grasps: Path = ACRONYM_DIR / "affordance" / "grasps"
    """Folder of the ACRONYM grasp files (by default affordance/grasps under
    $SIMGRASP_ACRONYM_DIR, else under ../shared/acronym)."""
    files: tuple[str, ...] = DEFAULT_FILES
    """Tune-half grasp files to label, or ``tune``: every file of the tune half."""
    variants: tuple[str, ...] = ("base",)
    """Variants to measure, each joining changes with ``+`` (the module doc)."""
    per_class: NonNegativeInt = 20
    """FleX successes and as many failures drawn per file (0: all of its first 500 grasps)."""


def run(options: Options) -> None:
    """Label each file's subset once per variant; print a summary line per variant."""
    names = list(options.files)
    if options.files == ("tune",):
        halves = json.loads(HALVES.read_text())
        names = list(halves["tune/files"])
    files = [options.grasps / name for name in names]
    missing = [str(f) for f in files if not f.is_file()]
    if missing:
        raise SystemExit(f"no such grasp file: {missing[0]} (set SIMGRASP_ACRONYM_DIR)")
    for name in options.variants:
        print(summary(name, label_variant(name, files, options.per_class)), flush=True)


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    raise SystemExit(main())

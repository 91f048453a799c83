"""The ``acronym`` protocol's contacts for light objects (``TrialConfig.light_contacts``):
friction without creep at the pads' Coulomb limit below 6 g, the soft contacts above. Real
MuJoCo trials of the Franka hand on a wedge, the shape of a knife's taper."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import trimesh

from simgrasp._mujoco import mujoco
from simgrasp.assets.model import model_for
from simgrasp.grasping.labeling.labeling import GraspLabeler, LabelConfig
from simgrasp.grasping.trials.protocol import PROTOCOLS
from simgrasp.grasping.trials.trial import CONES
from simgrasp.grasping.trials.trial_config import ACRONYM_TRIAL

OBJECT_T_TCP = np.eye(4)
"""The TCP at the wedge's middle: closing across its thickness (y), the pads along its taper
(x), approaching along z."""


def _wedge(folder: Path) -> Path:
    """A 40 mm long, 20 mm high wedge, 12 mm thick at x = -20 mm and 2 mm at x = +20 mm: a
    squeeze across it pushes it toward its thick end."""
    corners = [
        (x, side * thickness / 2, z)
        for x, thickness in ((-0.02, 0.012), (0.02, 0.002))
        for side in (-1, 1)
        for z in (-0.01, 0.01)
    ]
    path = folder / "wedge.stl"
    trimesh.convex.convex_hull(np.array(corners)).export(path)
    return path


def _label(wedge: Path, grams: float, light: bool) -> tuple[dict, GraspLabeler]:
    name = f"{wedge}?mass={grams / 1000}"
    config = LabelConfig(object=name, gripper="franka_panda", protocol="acronym")
    labeler = GraspLabeler(model_for(name), config)
    if not light:
        labeler.trial_config = replace(labeler.trial_config, light_contacts=None)
    return labeler.label(0, OBJECT_T_TCP, np.nan), labeler


def test_a_light_wedge_creeps_in_soft_friction_and_stays_without_creep(tmp_path: Path) -> None:
    """A 1 g wedge squeezed across its taper: the soft friction lets the squeeze's sideways
    share (about 0.13 of it) push it along the pads through the shake, about 2 cm (score
    under 0.5: ``1 / (1 + motion / 1 cm)``); friction without creep at a Coulomb limit of 0.5
    holds it within about 2 mm (score over 0.8), with the damping that keeps a light object
    from spinning up. A full-protocol trial after it in the same scene gets the mounted
    scene's contacts and undamped free joint back."""
    wedge = _wedge(tmp_path)
    soft, _ = _label(wedge, 1.0, light=False)
    held, labeler = _label(wedge, 1.0, light=True)
    assert soft["success"] is True and held["success"] is True
    assert soft["score"] < 0.5 < 0.8 < held["score"]
    light = ACRONYM_TRIAL.light_contacts
    assert light is not None and light.below == 0.006
    model, gripper = labeler.scene.model, labeler.scene.gripper
    fingers = list(gripper.finger_geoms[0] + gripper.finger_geoms[1])
    assert model.opt.noslip_iterations == light.noslip_iterations
    assert model.opt.cone == CONES[light.cone]
    assert set(model.geom_friction[fingers, 0]) == {light.finger_friction}
    turn = slice(labeler.scene.object_dof + 3, labeler.scene.object_dof + 6)
    moment = model.body_inertia[labeler.scene.object_body].max()
    np.testing.assert_allclose(model.dof_damping[turn], moment / light.spin_decay_time)
    labeler.trial_config, labeler.phases = PROTOCOLS["full"].config, PROTOCOLS["full"].phases
    labeler.label(1, OBJECT_T_TCP, np.nan)
    assert model.opt.noslip_iterations == 0
    assert model.opt.cone == mujoco.mjtCone.mjCONE_ELLIPTIC
    np.testing.assert_array_equal(model.geom_friction[fingers], gripper.finger_friction)
    assert not model.dof_damping[turn].any()
    assert 1.0 in gripper.finger_friction[:, 0]  # the finger hulls' own


def test_objects_from_6_g_up_keep_the_soft_contacts(tmp_path: Path) -> None:
    """A 10 g wedge gets exactly the trial it had before light contacts existed."""
    wedge = _wedge(tmp_path)
    records = [_label(wedge, 10.0, light)[0] for light in (True, False)]
    for record in records:
        record.pop("timings_s")
    assert records[0] == records[1]

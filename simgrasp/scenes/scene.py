"""Grasp scenes: a table, one object resting on it, lights, depth cameras and a floating gripper.

World frame: z up, the table top is the plane ``z = config.table_top_z`` (default 0), centered
on the world origin; the object rests near the origin at a seeded stable pose (any, or only
upright ones: ``SceneConfig.placement``) and yaw. The gripper is parked ``config.park_height``
above the table, jaws down, out of the cameras' views.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from simgrasp._mujoco import mujoco
from simgrasp.assets.placement import Placement
from simgrasp.assets.stable import sample_rest_pose
from simgrasp.errors import SimgraspError
from simgrasp.grippers.base import Gripper
from simgrasp.grippers.mount import BoundGripper, attach_gripper
from simgrasp.scenes.camera import add_camera, default_viewpoints
from simgrasp.scenes.config import SceneConfig
from simgrasp.scenes.table import OBJECT_NAME, TABLE_NAME, table_spec
from simgrasp.seeding import rng_for
from simgrasp.transforms import make_transform, matrix_to_pose7

if TYPE_CHECKING:
    from simgrasp.assets.model import ObjectModel
    from simgrasp.scenes.clutter import Distractor

GRIPPER_PREFIX = "gripper/"
"""Shadow map texels a side (MuJoCo's default 4096 took ~45 ms per renderer on software GL,
every scene; depth frames ignore shadows, and pictures keep crisp ones at 640 x 480)."""


@dataclass(frozen=True)
class Scene:
    """A compiled grasp scene and the ids needed to control and score it.

    ``world_T_object`` is the object's initial pose (4x4, world frame); ``spec`` is kept so the
    scene can be exported with :meth:`export_xml`.
    """

    spec: mujoco.MjSpec = field(repr=False)
    model: mujoco.MjModel = field(repr=False)
    data: mujoco.MjData = field(repr=False)
    object_model: ObjectModel = field(repr=False)
    gripper: BoundGripper
    object_body: int
    object_qpos: int
    """Address of the object's free joint in ``qpos`` (x y z qw qx qy qz)."""
    object_dof: int
    table_geom: int
    world_T_object: NDArray[np.float64] = field(repr=False)
    parked_world_T_tcp: NDArray[np.float64] = field(repr=False)
    cameras: tuple[str, ...]
    config: SceneConfig
    seed: int
    distractors: tuple[Distractor, ...] = ()
    """The settled distractors of a cluttered scene (``config.clutter``), in body order."""

    @property
    def object_name(self) -> str:
        return self.object_model.asset.name

    @cached_property
    def rest_pose7(self) -> NDArray[np.float64]:
        """``world_T_object`` as ``[x, y, z, qw, qx, qy, qz]`` (qw >= 0), converted once."""
        return matrix_to_pose7(self.world_T_object)

    def object_pose(self) -> NDArray[np.float64]:
        """Current ``world_T_object`` (4x4) from ``data``."""
        body = self.object_body
        return make_transform(self.data.xmat[body].reshape(3, 3), self.data.xpos[body])

    def reset(self) -> None:
        """Back to the initial state (object at rest pose, gripper parked), kinematics updated."""
        mujoco.mj_resetData(self.model, self.data)
        mujoco.mj_forward(self.model, self.data)

    def export_xml(self, path: Path) -> Path:
        """Write the scene as MJCF to ``path`` (meshes inline as in the spec); returns it."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(self.spec.to_xml())
        return path


def parked_tcp(config: SceneConfig) -> NDArray[np.float64]:
    """Parking pose of the TCP: above the table center, approach (+z) pointing down."""
    height = config.table_top_z + config.park_height
    return make_transform(np.diag([1.0, -1.0, -1.0]), [0.0, 0.0, height])


def build_scene(
    object_model: ObjectModel, gripper: Gripper, config: SceneConfig | None = None, seed: int = 0
) -> Scene:
    """Build and compile a scene with ``object_model`` resting on the table.

    The rest pose comes from ``sample_rest_pose`` (seeded by ``seed``), then a seeded yaw about
    world z; the object's footprint is centered on the table origin. With ``config.clutter``,
    distractors are dropped around it and settled (:mod:`simgrasp.scenes.clutter`).
    """
    config = config or SceneConfig()
    spec = table_spec(object_model.asset.name, config)
    world_T_object = _rest_pose(object_model, config, seed, sample_rest_pose)
    distractors: tuple[Distractor, ...] = ()
    if config.clutter:
        from simgrasp.scenes.clutter import clutter_layout

        layout = clutter_layout(object_model, world_T_object, config, seed)
        world_T_object, distractors = layout.world_T_target, layout.distractors
    object_model.add_to(spec, world_T_object, name=OBJECT_NAME)
    for distractor in distractors:
        distractor.model.add_to(spec, distractor.world_T_object, name=distractor.body)

    cameras = config.cameras or tuple(default_viewpoints(world_T_object[:3, 3], n=config.num_views))
    for camera in cameras:
        add_camera(spec, camera)

    parked = parked_tcp(config)
    handles = attach_gripper(spec, gripper, parked, prefix=GRIPPER_PREFIX)
    try:
        model = spec.compile()
    except ValueError as exc:
        raise SimgraspError(
            f"cannot compile the scene for {object_model.asset.name!r}: {exc}"
        ) from exc
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)

    object_body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, OBJECT_NAME)
    joint = int(model.body_jntadr[object_body])
    if object_body < 0 or joint < 0 or model.jnt_type[joint] != mujoco.mjtJoint.mjJNT_FREE:
        raise SimgraspError(f"object {object_model.asset.name!r} was not added as a free body")
    return Scene(
        spec=spec,
        model=model,
        data=data,
        object_model=object_model,
        gripper=handles.bind(model),
        object_body=object_body,
        object_qpos=int(model.jnt_qposadr[joint]),
        object_dof=int(model.jnt_dofadr[joint]),
        table_geom=mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, TABLE_NAME),
        world_T_object=world_T_object,
        parked_world_T_tcp=parked,
        cameras=tuple(c.name for c in cameras),
        config=config,
        seed=seed,
        distractors=distractors,
    )


def _rest_pose(
    object_model: ObjectModel,
    config: SceneConfig,
    seed: int,
    sampler: Callable[[ObjectModel, np.random.Generator, Placement], NDArray[np.float64]],
) -> NDArray[np.float64]:
    """Seeded stable pose on the table top, turned by a seeded yaw about its own center."""
    rng = rng_for(seed, "scene", "rest_pose")
    world_T_object = np.asarray(sampler(object_model, rng, config.placement))
    world_T_object = world_T_object.copy()
    if config.random_yaw:
        yaw = rng_for(seed, "scene", "yaw").uniform(-np.pi, np.pi)
        world_R_yaw = Rotation.from_euler("z", yaw).as_matrix()
        world_T_object[:3, :3] = world_R_yaw @ world_T_object[:3, :3]
    # Center the object's footprint (the xy bounds of its rotated mesh) on the table origin.
    vertices_rotated = object_model.asset.mesh.vertices @ world_T_object[:3, :3].T
    footprint_center = (vertices_rotated.min(axis=0) + vertices_rotated.max(axis=0)) / 2
    world_T_object[:2, 3] = -footprint_center[:2]
    world_T_object[2, 3] += config.table_top_z
    return world_T_object

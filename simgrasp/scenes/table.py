"""The table every scene stands on: a box whose top is the plane ``z = config.table_top_z``
(world frame, z up, meters), centered on the world origin, with two lights; the scene
(:mod:`simgrasp.scenes.scene`) and the clutter settling (:mod:`simgrasp.scenes.clutter`) add
their objects to it."""

from __future__ import annotations

from simgrasp._mujoco import mujoco
from simgrasp.scenes.config import SceneConfig

OBJECT_NAME = "object"
"""The body name of the scene's target object."""
TABLE_NAME = "table"
"""The table's geom name."""
SHADOW_MAP_SIZE = 2048


def table_spec(object_name: str, config: SceneConfig) -> mujoco.MjSpec:
    """A new scene spec with the table (top at ``config.table_top_z``) and two lights."""
    spec = mujoco.MjSpec()
    spec.modelname = f"scene_{object_name}"
    spec.visual.headlight.ambient = [0.3, 0.3, 0.3]
    spec.visual.quality.shadowsize = SHADOW_MAP_SIZE

    hx, hy, hz = config.table_half_size
    spec.worldbody.add_geom(
        name=TABLE_NAME,
        type=mujoco.mjtGeom.mjGEOM_BOX,
        size=[hx, hy, hz],
        pos=[0.0, 0.0, config.table_top_z - hz],
        friction=[config.table_friction, 0.005, 0.0001],
        rgba=[0.55, 0.45, 0.35, 1.0],
    )
    spec.worldbody.add_light(
        name="key", pos=[0.4, -0.4, 1.5], dir=[-0.3, 0.3, -1.0], diffuse=[0.7, 0.7, 0.7]
    )
    spec.worldbody.add_light(
        name="fill", pos=[-0.5, 0.5, 1.2], dir=[0.4, -0.4, -1.0], diffuse=[0.3, 0.3, 0.3]
    )
    return spec

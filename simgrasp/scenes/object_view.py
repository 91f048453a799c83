"""A picture of one object model: its visual mesh and its collision hulls, side by side, with
the labeled handle region drawn in translucent red (MuJoCo offscreen renderer)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image

from simgrasp._mujoco import mujoco
from simgrasp.assets.model import ObjectModel
from simgrasp.labels import Capsule
from simgrasp.transforms import rotation_to_quat_wxyz

LABEL_GROUP = 4
LABEL_RGBA = (1.0, 0.1, 0.1, 0.35)


def _add_label_geoms(body: mujoco.MjsBody, model: ObjectModel, name: str) -> None:
    for i, region in enumerate(model.asset.handle.regions):
        common = dict(
            name=f"{name}_label{i}", group=LABEL_GROUP, contype=0, conaffinity=0, rgba=LABEL_RGBA
        )
        if isinstance(region, Capsule):
            body.add_geom(
                type=mujoco.mjtGeom.mjGEOM_CAPSULE,
                fromto=np.concatenate([region.p0, region.p1]),
                size=[region.radius, 0, 0],
                **common,
            )
        else:
            body.add_geom(
                type=mujoco.mjtGeom.mjGEOM_BOX,
                pos=region.center,
                quat=rotation_to_quat_wxyz(region.object_R_box),
                size=region.half_extents,
                **common,
            )


def show_object(model: ObjectModel, out: Path, size: int) -> None:
    """Write ``out`` (PNG): the visual mesh and the colored collision hulls side by side, each
    ``size`` pixels square, with the labeled handle drawn in translucent red."""
    spec = mujoco.MjSpec()
    spec.visual.headlight.ambient = [0.4, 0.4, 0.4]
    spec.visual.global_.offwidth = 2 * size
    spec.visual.global_.offheight = size
    body = model.add_to(spec, np.eye(4), name="object")
    _add_label_geoms(body, model, "object")
    if model.asset.handle.whole_object:
        spec.geom("object_visual").rgba = [1.0, 0.45, 0.45, 1.0]
    compiled = spec.compile()
    data = mujoco.MjData(compiled)
    mujoco.mj_forward(compiled, data)
    camera = mujoco.MjvCamera()
    bounds = model.asset.mesh.bounds
    camera.lookat[:] = bounds.mean(axis=0)
    camera.distance = 2.2 * float(np.linalg.norm(bounds[1] - bounds[0]))
    camera.azimuth, camera.elevation = 135.0, -35.0
    panels = []
    with mujoco.Renderer(compiled, height=size, width=size) as renderer:
        for groups in ((2, LABEL_GROUP), (3, LABEL_GROUP)):
            option = mujoco.MjvOption()
            option.geomgroup[:] = 0
            for group in groups:
                option.geomgroup[group] = 1
            renderer.update_scene(data, camera=camera, scene_option=option)
            panels.append(renderer.render())
    out.parent.mkdir(parents=True, exist_ok=True)
    Image.fromarray(np.concatenate(panels, axis=1)).save(out)

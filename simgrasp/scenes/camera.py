"""Depth cameras in MuJoCo scenes: where they are, how they are added, and their world pose.

A :class:`CameraSpec` places a pinhole camera at ``pos`` looking at ``lookat`` (world frame,
meters) with the image "up" direction as close to world +z as possible. :func:`add_camera`
adds it to an ``mujoco.MjSpec`` as a fixed world camera; :func:`world_T_cam` reads the pose
of any model camera back from ``MjData`` in the OpenCV camera convention of
:mod:`simgrasp.perception.camera` (x right, y down, z forward).
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np

from simgrasp._mujoco import mujoco
from simgrasp.errors import SimgraspError
from simgrasp.perception.camera import CameraIntrinsics, cv_T_mujoco
from simgrasp.scenes.camera_spec import CameraSpec
from simgrasp.scenes.views import check_views
from simgrasp.transforms import make_transform

_WORLD_UP = np.array([0.0, 0.0, 1.0])


def add_camera(spec: mujoco.MjSpec, camera_spec: CameraSpec) -> mujoco.MjsCamera:
    """Add ``camera_spec`` to ``spec`` as a fixed world-body camera and return it.

    The camera's ``resolution`` is set to the image size (so renderers can recover the
    intrinsics from the compiled model) and the offscreen framebuffer is enlarged if needed.
    """
    if any(cam.name == camera_spec.name for cam in spec.cameras):
        raise SimgraspError(f"the scene already has a camera named {camera_spec.name!r}")
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, camera_spec.world_R_mjcam.ravel())
    camera = spec.worldbody.add_camera(
        name=camera_spec.name,
        pos=list(camera_spec.pos),
        quat=list(quat),
        fovy=camera_spec.fovy_deg,
        resolution=[camera_spec.width, camera_spec.height],
    )
    global_ = spec.visual.global_
    global_.offwidth = max(global_.offwidth, camera_spec.width)
    global_.offheight = max(global_.offheight, camera_spec.height)
    return camera


def default_viewpoints(
    target_world: np.ndarray | tuple[float, float, float],
    distance: float = 0.6,
    elevation_deg: float = 40.0,
    n: int = 1,
    *,
    azimuth0_deg: float = -150.0,
    rng: np.random.Generator | None = None,
    fovy_deg: float = 58.0,
    width: int = 640,
    height: int = 480,
) -> list[CameraSpec]:
    """Tabletop views of ``target_world`` (meters, world frame), named ``view0``, ``view1``...

    Cameras sit ``distance`` meters from the target, ``elevation_deg`` above the table plane,
    at azimuths ``azimuth0_deg + k * 360 / n`` (degrees about world +z, 0 = on the +x side);
    the default first azimuth gives an oblique front view rather than a face-on one. With
    ``rng``, each camera is jittered by up to +-10 deg azimuth, +-5 deg elevation and +-5 %
    distance (reproducible from the generator).
    """
    target = np.asarray(target_world, dtype=np.float64)
    if target.shape != (3,) or not np.all(np.isfinite(target)):
        raise SimgraspError(f"target_world must be 3 finite numbers, got {target_world!r}")
    check_views(n)
    if not distance > 0:
        raise SimgraspError(f"distance must be positive, got {distance}")
    if not 0.0 < elevation_deg < 90.0:
        raise SimgraspError(f"elevation_deg must be in (0, 90), got {elevation_deg}")
    views = []
    for k in range(n):
        azimuth, elevation, dist = azimuth0_deg + k * 360.0 / n, elevation_deg, distance
        if rng is not None:
            azimuth += rng.uniform(-10.0, 10.0)
            elevation = float(np.clip(elevation + rng.uniform(-5.0, 5.0), 1.0, 89.0))
            dist *= 1.0 + rng.uniform(-0.05, 0.05)
        az, el = math.radians(azimuth), math.radians(elevation)
        offset = dist * np.array([math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), 0.0])
        offset[2] = dist * math.sin(el)
        views.append(
            CameraSpec(
                name=f"view{k}",
                pos=tuple(target + offset),
                lookat=tuple(target),
                fovy_deg=fovy_deg,
                width=width,
                height=height,
            )
        )
    return views


def world_T_cam(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    camera_name: str,
    convention: Literal["opencv", "mujoco"] = "opencv",
) -> np.ndarray:
    """4x4 pose of a model camera in the world frame, from ``data.cam_xpos/cam_xmat``.

    ``data`` must hold current kinematics (after ``mj_forward``/``mj_step``). With
    ``convention="opencv"`` (default) the camera frame is x right, y down, z forward; with
    ``"mujoco"`` it is MuJoCo's own (x right, y up, looking along -z).
    """
    camera_id = camera_id_of(model, camera_name)
    world_T_mjcam = make_transform(data.cam_xmat[camera_id].reshape(3, 3), data.cam_xpos[camera_id])
    if convention == "mujoco":
        return world_T_mjcam
    if convention != "opencv":
        raise SimgraspError(f"convention must be 'opencv' or 'mujoco', got {convention!r}")
    return world_T_mjcam @ cv_T_mujoco


def camera_id_of(model: mujoco.MjModel, camera_name: str) -> int:
    """Id of the camera named ``camera_name``; a clear error listing the model's cameras."""
    camera_id = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_CAMERA, camera_name)
    if camera_id < 0:
        names = [model.camera(i).name for i in range(model.ncam)]
        raise SimgraspError(f"no camera named {camera_name!r} in the model (cameras: {names})")
    return camera_id


def model_camera_intrinsics(model: mujoco.MjModel, camera_name: str) -> CameraIntrinsics:
    """Intrinsics of a model camera from its ``fovy`` and ``resolution`` (see :func:`add_camera`).

    Cameras defined by ``sensorsize``/``focal`` instead of ``fovy``, or left at MuJoCo's default
    1x1 resolution, are rejected with an error naming the camera.
    """
    camera_id = camera_id_of(model, camera_name)
    if np.any(model.cam_sensorsize[camera_id] > 0):
        raise SimgraspError(
            f"camera {camera_name!r} uses sensorsize/focal intrinsics; only fovy cameras "
            "(as made by add_camera) are supported"
        )
    width, height = (int(x) for x in model.cam_resolution[camera_id])
    if width * height <= 1:
        raise SimgraspError(
            f"camera {camera_name!r} has no image resolution; add it with add_camera or set "
            "its resolution attribute"
        )
    return CameraIntrinsics.from_fovy(width, height, float(model.cam_fovy[camera_id]))

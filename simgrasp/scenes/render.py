"""Depth and segmentation images of MuJoCo scenes, with an automatically chosen backend.

Backends, in order of preference:

- ``"egl"``: ``mujoco.Renderer`` on a headless EGL context (GPU or Mesa).
- ``"osmesa"``: ``mujoco.Renderer`` on Mesa's software OSMesa context.
- ``"raycast"``: no OpenGL at all; one ``mujoco.mj_multiRay`` call per frame casts one ray per
  pixel from the camera center through the pixel center.

Choosing a backend. MuJoCo reads ``MUJOCO_GL`` once, when ``mujoco`` is first imported, so the
GL platform is fixed per process. simgrasp imports mujoco through :mod:`simgrasp._mujoco`,
which picks it before that first import: if ``MUJOCO_GL`` is unset, EGL and then OSMesa are
probed, each in a subprocess rendering a tiny model under a timeout (a broken driver can hang),
and the first that works is written to ``os.environ["MUJOCO_GL"]`` (so worker processes
inherit the choice without probing again). :func:`select_backend` then confirms, once per
process (cached), that the platform mujoco actually loaded renders, and otherwise falls back
to ``"raycast"`` with a warning. ``SIMGRASP_RENDER_BACKEND=egl|osmesa|raycast`` forces a
backend (a GL one must match the platform mujoco loaded, else a clear error). A run's worker
processes and Ray tasks get the backend of the process that starts them, forced
(:func:`worker_environment`), so every worker of a run renders alike.

What the depth camera sees. All backends see exactly the geoms whose ``group`` is in
``geom_groups`` (default :data:`DEPTH_GEOM_GROUPS` = 0, 1, 2: MuJoCo's default visible groups;
Menagerie-style models keep visual meshes in group 2 and collision-only geoms in group 3).
Sites, tendons, flexes, skins and decorations are never drawn. Static (world-body) geoms such
as the table are seen.

Agreement between backends: on pixels where all see a surface, depth differs by float32
quantization of the GL depth buffer (sub-millimeter at tabletop range) and, at silhouette
edges, by rasterization versus exact ray hits; see ``tests/test_render_backends.py``.

Processes: a GL context created before ``fork`` hangs forked children, so a process forked
from one that made a GL context renders with ``"raycast"`` (:mod:`simgrasp.scenes.gl_fork`).
Parallel workers that should render with GL must be started with the ``spawn`` or
``forkserver`` start method (e.g. ``multiprocessing.get_context("spawn")``), and each worker
creates its own :class:`SceneRenderer`.
"""

from __future__ import annotations

import functools
import warnings
from dataclasses import dataclass

import numpy as np

from simgrasp._mujoco import mujoco
from simgrasp.errors import SimgraspError
from simgrasp.gl_platform import BACKENDS, FORCE_ENV, GL_BACKENDS, forced_backend, gl_problem
from simgrasp.perception.camera import CameraIntrinsics
from simgrasp.scenes.camera import (
    camera_id_of,
    model_camera_intrinsics,
    world_T_cam,
)
from simgrasp.scenes.gl_fork import check_gl_allowed, forked_from_gl, note_gl_context

DEPTH_GEOM_GROUPS: tuple[int, ...] = (0, 1, 2)


def loaded_gl_platform() -> str | None:
    """The GL platform mujoco loaded in this process (``"egl"``, ``"osmesa"``, ``"glfw"``...),
    or None if its GL module is disabled."""
    context_cls = getattr(mujoco, "GLContext", None)
    if context_cls is None:
        return None
    return context_cls.__module__.split(".")[1] if "." in context_cls.__module__ else None


def select_backend() -> str:
    """The backend this process renders with (see the module docstring): ``"raycast"`` in a
    process forked from one that had made a GL context (GL would hang there; a forced GL
    backend is an error saying to use ``spawn``)."""
    if forked_from_gl():
        if forced_backend() in GL_BACKENDS:
            check_gl_allowed()
        return "raycast"
    return _process_backend()


def worker_environment() -> dict[str, str]:
    """Variables that make worker processes render as this one would: its backend, forced
    (``SIMGRASP_RENDER_BACKEND``). A worker then never probes GL on its own, so a probe that
    times out on a loaded machine cannot switch one worker to ray casting, whose depth images
    (and so the run's results) differ slightly from GL's. Decided without the fallback's
    warning: the workers may never render (``label-grasps``)."""
    backend = "raycast" if forked_from_gl() else _decided_backend()[0]
    return {FORCE_ENV: backend}


@functools.cache
def _process_backend() -> str:
    """The backend of a process that may use GL (cached), with a warning when it falls back
    to ray casting."""
    backend, problem = _decided_backend()
    if problem is not None:
        warnings.warn(
            f"no working headless GL (mujoco GL platform: {loaded_gl_platform()!r}; "
            f"{problem}); rendering depth by ray casting. Set MUJOCO_GL=egl or osmesa before "
            f"importing mujoco to use OpenGL, or {FORCE_ENV}=egl to make a failure an error.",
            RuntimeWarning,
            stacklevel=3,
        )
    return backend


@functools.cache
def _decided_backend() -> tuple[str, str | None]:
    """(the backend of a process that may use GL, why GL is not used or None), cached."""
    platform = loaded_gl_platform()
    forced = forced_backend()
    if forced is not None:
        if forced in GL_BACKENDS and platform != forced:
            raise RuntimeError(
                f"{FORCE_ENV}={forced} but mujoco was imported with GL platform {platform!r}; "
                f"set MUJOCO_GL={forced} before starting Python (or import "
                "simgrasp._mujoco before mujoco)"
            )
        return forced, None
    if platform not in GL_BACKENDS:
        return "raycast", "no headless GL platform loaded"
    problem = gl_problem(platform)
    return (platform, None) if problem is None else ("raycast", problem)


@dataclass(frozen=True, eq=False)
class DepthFrame:
    """One depth image with its segmentation, camera and pose (arrays are read-only).

    Attributes:
        depth: (H, W) float64 meters along the optical axis; 0 where nothing was hit.
        geom_ids: (H, W) int32 id of the geom seen at each pixel, -1 for none.
        body_ids: (H, W) int32 id of that geom's body, -1 for none.
        intrinsics: the pinhole camera (OpenCV conventions, :mod:`simgrasp.perception.camera`).
        world_T_cam: 4x4 pose of the OpenCV camera frame (x right, y down, z forward) in world.
        camera_name: the model camera that took the frame.
        backend: ``"egl"``, ``"osmesa"`` or ``"raycast"``.
    """

    depth: np.ndarray
    geom_ids: np.ndarray
    body_ids: np.ndarray
    intrinsics: CameraIntrinsics
    world_T_cam: np.ndarray
    camera_name: str
    backend: str

    def __post_init__(self) -> None:
        shape = (self.intrinsics.height, self.intrinsics.width)
        arrays = {
            "depth": (np.float64, shape),
            "geom_ids": (np.int32, shape),
            "body_ids": (np.int32, shape),
            "world_T_cam": (np.float64, (4, 4)),
        }
        for name, (dtype, expected) in arrays.items():
            array = np.array(getattr(self, name), dtype=dtype)
            if array.shape != expected:
                raise SimgraspError(
                    f"DepthFrame {name} has shape {array.shape}, expected {expected}"
                )
            array.flags.writeable = False
            object.__setattr__(self, name, array)

    @property
    def camera_position_world(self) -> np.ndarray:
        """Optical center in world coordinates (meters)."""
        return self.world_T_cam[:3, 3].copy()


class SceneRenderer:
    """Renders depth frames and pictures of one compiled model; owns its GL resources.

    Use as a context manager (or call :meth:`close`). ``data`` passed to the render methods
    must hold current kinematics (``mj_forward`` or ``mj_step`` done).
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        *,
        backend: str | None = None,
        geom_groups: tuple[int, ...] = DEPTH_GEOM_GROUPS,
    ) -> None:
        """``backend`` None selects automatically (:func:`select_backend`); ``geom_groups``
        are the geom groups (0..5) the depth camera sees, identical for every backend."""
        if backend is None:
            backend = select_backend()
        if backend not in BACKENDS:
            raise SimgraspError(f"unknown render backend {backend!r}; use one of {BACKENDS}")
        if backend in GL_BACKENDS and loaded_gl_platform() != backend:
            raise RuntimeError(
                f"render backend {backend!r} requested but mujoco loaded GL platform "
                f"{loaded_gl_platform()!r}; set MUJOCO_GL={backend} before importing mujoco"
            )
        bad = [g for g in geom_groups if not 0 <= g < 6]
        if bad or not geom_groups:
            raise SimgraspError(
                f"geom_groups must be a non-empty subset of 0..5, got {geom_groups}"
            )
        self.model = model
        self.backend = backend
        self.geom_groups = tuple(geom_groups)
        self._geomgroup_mask = np.zeros(6, dtype=np.uint8)
        self._geomgroup_mask[list(self.geom_groups)] = 1
        self._depth_option = self._scene_option()
        self._renderers: dict[tuple[int, int], mujoco.Renderer] = {}
        self._rays: dict[CameraIntrinsics, tuple[np.ndarray, np.ndarray]] = {}
        self._closed = False

    def __enter__(self) -> SceneRenderer:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    def close(self) -> None:
        """Free every GL context this renderer created (idempotent)."""
        for renderer in self._renderers.values():
            renderer.close()
        self._renderers.clear()
        self._closed = True

    @property
    def closed(self) -> bool:
        """True once :meth:`close` freed the GL resources."""
        return self._closed

    @property
    def clip_range(self) -> tuple[float, float]:
        """(near, far) clipping distances in meters, as the GL renderer uses them."""
        extent = self.model.stat.extent
        return self.model.vis.map.znear * extent, self.model.vis.map.zfar * extent

    def depth(self, data: mujoco.MjData, camera: str) -> DepthFrame:
        """Depth and segmentation from the model camera named ``camera``.

        The image size and field of view come from the camera (see
        :func:`simgrasp.scenes.camera.add_camera`).
        """
        if self._closed:
            raise RuntimeError("SceneRenderer is closed")
        intrinsics = model_camera_intrinsics(self.model, camera)
        world_T_cv = world_T_cam(self.model, data, camera)
        if self.backend == "raycast":
            depth, geom_ids = self._raycast(data, intrinsics, world_T_cv)
        else:
            depth, geom_ids = self._gl_depth(data, camera, intrinsics)
        body_ids = np.where(geom_ids >= 0, self.model.geom_bodyid[np.maximum(geom_ids, 0)], -1)
        return DepthFrame(
            depth=depth,
            geom_ids=geom_ids,
            body_ids=body_ids,
            intrinsics=intrinsics,
            world_T_cam=world_T_cv,
            camera_name=camera,
            backend=self.backend,
        )

    def rgb(
        self,
        data: mujoco.MjData,
        camera: str | mujoco.MjvCamera | None = None,
        width: int = 640,
        height: int = 480,
    ) -> np.ndarray:
        """An (height, width, 3) uint8 picture from a model camera (by name), an
        ``mujoco.MjvCamera`` (e.g. a free camera), or MuJoCo's default free camera (None).

        Pictures show every default-visible element (not only the depth geom groups). They need
        a GL backend; the raycast backend raises.
        """
        if self._closed:
            raise RuntimeError("SceneRenderer is closed")
        check_gl_allowed()  # in a child forked after GL: say to use spawn
        if self.backend not in GL_BACKENDS:
            raise RuntimeError(
                "RGB pictures need a GL backend (egl or osmesa); this renderer uses "
                f"{self.backend!r}"
            )
        if isinstance(camera, str):
            camera_id_of(self.model, camera)
        renderer = self._gl_renderer(width, height)
        renderer.update_scene(data, -1 if camera is None else camera)
        renderer.disable_depth_rendering()
        renderer.disable_segmentation_rendering()
        return renderer.render()

    def _scene_option(self) -> mujoco.MjvOption:
        option = mujoco.MjvOption()
        option.geomgroup[:] = self._geomgroup_mask
        for groups in (option.sitegroup, option.tendongroup, option.flexgroup, option.skingroup):
            groups[:] = 0
        for flag in (mujoco.mjtVisFlag.mjVIS_TENDON, mujoco.mjtVisFlag.mjVIS_RANGEFINDER):
            option.flags[flag] = 0
        return option

    def _gl_renderer(self, width: int, height: int) -> mujoco.Renderer:
        key = (width, height)
        if key not in self._renderers:
            global_ = self.model.vis.global_
            if width > global_.offwidth or height > global_.offheight:
                raise SimgraspError(
                    f"image {width}x{height} exceeds the model's offscreen framebuffer "
                    f"{global_.offwidth}x{global_.offheight}; add cameras with add_camera or "
                    "raise visual/global offwidth/offheight"
                )
            note_gl_context()  # a forked child of this process must not render
            self._renderers[key] = mujoco.Renderer(self.model, height=height, width=width)
        return self._renderers[key]

    def _gl_depth(
        self, data: mujoco.MjData, camera: str, intrinsics: CameraIntrinsics
    ) -> tuple[np.ndarray, np.ndarray]:
        renderer = self._gl_renderer(intrinsics.width, intrinsics.height)
        renderer.update_scene(data, camera, self._depth_option)
        renderer.enable_depth_rendering()
        depth = renderer.render().astype(np.float64)
        renderer.enable_segmentation_rendering()
        segmentation = renderer.render()
        renderer.disable_segmentation_rendering()
        # int(): comparing an array with the enum object runs per pixel in Python (~0.3 s).
        is_geom = segmentation[..., 1] == int(mujoco.mjtObj.mjOBJ_GEOM)
        geom_ids = np.where(is_geom, segmentation[..., 0], -1).astype(np.int32)
        near, far = self.clip_range
        hit = (geom_ids >= 0) & (depth >= near) & (depth < far)
        return np.where(hit, depth, 0.0), np.where(hit, geom_ids, -1).astype(np.int32)

    def _unit_rays(self, intrinsics: CameraIntrinsics) -> tuple[np.ndarray, np.ndarray]:
        if intrinsics not in self._rays:
            rays_cam = intrinsics.pixel_rays_cam()
            lengths = np.linalg.norm(rays_cam, axis=1)
            self._rays[intrinsics] = (rays_cam / lengths[:, None], lengths)
        return self._rays[intrinsics]

    def _raycast(
        self, data: mujoco.MjData, intrinsics: CameraIntrinsics, world_T_cv: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        unit_rays_cam, ray_lengths = self._unit_rays(intrinsics)
        dirs_world = unit_rays_cam @ world_T_cv[:3, :3].T
        n_rays = dirs_world.shape[0]
        geom_ids = np.empty(n_rays, dtype=np.int32)
        distances = np.empty(n_rays, dtype=np.float64)
        near, far = self.clip_range
        mujoco.mj_multiRay(
            self.model,
            data,
            np.ascontiguousarray(world_T_cv[:3, 3]),
            np.ascontiguousarray(dirs_world).ravel(),
            self._geomgroup_mask,
            1,
            -1,
            geom_ids,
            distances,
            None,
            n_rays,
            far,
        )
        # Unit ray length d along a pixel ray (x, y, 1) / |(x, y, 1)| is at depth d / |.|.
        depth = distances / ray_lengths
        hit = (geom_ids >= 0) & (depth >= near) & (depth < far)
        shape = (intrinsics.height, intrinsics.width)
        depth_image = np.where(hit, depth, 0.0).reshape(shape)
        return depth_image, np.where(hit, geom_ids, -1).astype(np.int32).reshape(shape)

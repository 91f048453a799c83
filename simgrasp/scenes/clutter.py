"""Cluttered scenes: distractor objects dropped around the target and settled by MuJoCo.

World frame as in :mod:`simgrasp.scenes.scene` (z up, table top at ``table_top_z``). For
``SceneConfig.clutter`` = N > 0 the seed draws N distractors from the pool
(:func:`~simgrasp.scenes.clutter_sets.distractor_pool`, with replacement only when the pool is
smaller than N), each in a seeded stable pose and yaw, on a ring around the target's footprint
(bounding circles may overlap by ``TOUCH_OVERLAP``, so objects touch and lean), dropped from
``DROP_HEIGHT``. A scene of the table and the objects alone is then stepped until everything
rests (``SETTLE_LIMIT`` at most); the settled poses, the target's too, are the scene's initial
state. A target of which no default camera sees ``MIN_VISIBLE`` of what it would see without
the distractors (rays to ``VISIBILITY_POINTS`` seeded surface points) is redrawn, up to
``MAX_DRAWS`` times (the most visible draw is kept). A drop whose simulation goes unstable
(MuJoCo's bad-acceleration warning: it then resets the state to the drop poses, objects in the
air at rest) is no layout and is drawn again. Every choice flows from the scene's seed.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import trimesh
from numpy.typing import NDArray

from simgrasp._mujoco import mujoco
from simgrasp.assets.model import ObjectModel, model_for
from simgrasp.assets.stable import sample_rest_pose
from simgrasp.errors import SimgraspError
from simgrasp.scenes.camera import default_viewpoints
from simgrasp.scenes.clutter_sets import distractor_pool
from simgrasp.scenes.config import SceneConfig
from simgrasp.scenes.table import OBJECT_NAME, table_spec
from simgrasp.seeding import rng_for
from simgrasp.transforms import make_transform

DISTRACTOR_PREFIX = "distractor"
"""Distractor bodies are named ``distractor0``, ``distractor1``, ..."""
DROP_HEIGHT = 0.01
"""Distractors start this far (m) above their rest pose on the table."""
TOUCH_OVERLAP = 0.15
"""Share by which two objects' bounding circles (xy) may overlap when dropped."""
RING_SPREAD = 0.6
"""A distractor's center lies up to this share of the summed radii beyond touching."""
SETTLE_TIMESTEP = 0.002
SETTLE_MIN = 0.2
SETTLE_LIMIT = 1.5
"""The drop is stepped at least SETTLE_MIN and at most SETTLE_LIMIT seconds ..."""
SETTLE_SPEED = 0.02
"""... ending once no generalized velocity exceeds this (m/s, rad/s)."""
FALLEN_DEPTH = 0.05
"""A distractor that settles this far (m) below the table top fell off; it is left out."""
FLUNG_HEIGHT = 0.5
"""A distractor this far (m) above the table top at the end of the settle was flung by an
overlapping drop (crowded scenes of 13+ distractors); it is left out too."""
MIN_VISIBLE = 1 / 3
MAX_DRAWS = 8
VISIBILITY_POINTS = 300
_HIDDEN_GROUP = 1
"""Geom group the distractors' visuals take in the settle model only, so rays can skip them."""


@dataclass(frozen=True, eq=False)
class Distractor:
    """A settled distractor: its body name, object model and pose (4 x 4, world frame)."""

    body: str
    model: ObjectModel
    world_T_object: NDArray[np.float64]

    @property
    def object_name(self) -> str:
        return self.model.asset.name


@dataclass(frozen=True, eq=False)
class ClutterLayout:
    """The settled target pose (4 x 4, world), the distractors, the share of the target the
    best camera sees (of what it sees without them) and the draws it took."""

    world_T_target: NDArray[np.float64]
    distractors: tuple[Distractor, ...]
    visible_share: float
    draws: int


@lru_cache(maxsize=64)
def distractor_model(name: str) -> ObjectModel:
    """The object model of a distractor, built once per process (CoACD hulls from the cache)."""
    return model_for(name)


def clutter_layout(
    target: ObjectModel, world_T_target: NDArray[np.float64], config: SceneConfig, seed: int
) -> ClutterLayout:
    """Draw, drop and settle ``config.clutter`` distractors around the target resting at
    ``world_T_target`` (module docstring)."""
    pool = distractor_pool(config.clutter_objects, target.asset.name)
    best: ClutterLayout | None = None
    for draw in range(MAX_DRAWS):
        rng = rng_for(seed, "scene", "clutter", draw)
        replace = len(pool) < config.clutter
        names = [pool[i] for i in rng.choice(len(pool), config.clutter, replace=replace)]
        models = [distractor_model(name) for name in names]
        dropped = _drop_poses(target, world_T_target, models, rng, config)
        layout = _settled(target, world_T_target, models, dropped, config, seed, draw)
        if layout is None:  # the drop went unstable
            continue
        if layout.visible_share >= MIN_VISIBLE:
            return layout
        if best is None or layout.visible_share > best.visible_share:
            best = layout
    if best is None:
        raise SimgraspError(
            f"clutter of {config.clutter} around {target.asset.name!r}, seed {seed}: every one of "
            f"{MAX_DRAWS} drops went unstable in simulation; try fewer distractors"
        )
    return best


def _radius(model: ObjectModel, world_R_object: NDArray[np.float64]) -> float:
    """Radius (m) of the object's bounding circle in xy about its rotated footprint center."""
    xy = (model.asset.mesh.vertices @ world_R_object.T)[:, :2]
    center = (xy.min(axis=0) + xy.max(axis=0)) / 2
    return float(np.linalg.norm(xy - center, axis=1).max())


def _footprint_center(model: ObjectModel, world_T_object: NDArray[np.float64]) -> NDArray:
    vertices = model.asset.mesh.vertices @ world_T_object[:3, :3].T + world_T_object[:3, 3]
    return (vertices[:, :2].min(axis=0) + vertices[:, :2].max(axis=0)) / 2


def _drop_poses(
    target: ObjectModel,
    world_T_target: NDArray[np.float64],
    models: list[ObjectModel],
    rng: np.random.Generator,
    config: SceneConfig,
) -> list[NDArray[np.float64]]:
    """Seeded start poses (4 x 4, world) of the distractors around the target."""
    circles = [(_footprint_center(target, world_T_target), _radius(target, world_T_target[:3, :3]))]
    poses = []
    for model in models:
        world_T_object = np.asarray(sample_rest_pose(model, rng, "stable")).copy()
        radius = _radius(model, world_T_object[:3, :3])
        center = _free_spot(circles, radius, rng, config.table_half_size[:2])
        circles.append((center, radius))
        world_T_object[:2, 3] += center - _footprint_center(model, world_T_object)
        world_T_object[2, 3] += config.table_top_z + DROP_HEIGHT
        poses.append(world_T_object)
    return poses


def _free_spot(
    circles: list[tuple[NDArray, float]],
    radius: float,
    rng: np.random.Generator,
    table_half: tuple[float, float],
) -> NDArray[np.float64]:
    """A seeded xy center near the target (``circles[0]``) for a circle of ``radius`` on the
    table (half extents ``table_half``, m) that overlaps no placed circle by more than
    ``TOUCH_OVERLAP``; farther out each try."""
    (target_center, target_radius), reach = circles[0], 1.0
    for _ in range(50):
        angle = rng.uniform(-np.pi, np.pi)
        distance = (target_radius + radius) * (
            1 - TOUCH_OVERLAP + reach * rng.uniform(0, RING_SPREAD)
        )
        center = target_center + distance * np.array([np.cos(angle), np.sin(angle)])
        on_table = np.all(np.abs(center) + radius <= np.asarray(table_half))
        if on_table and all(
            np.linalg.norm(center - c) >= (1 - TOUCH_OVERLAP) * (r + radius) for c, r in circles
        ):
            return center
        reach += 0.1
    return np.clip(center, radius - np.asarray(table_half), np.asarray(table_half) - radius)


def _settle_model(
    target: ObjectModel,
    world_T_target: NDArray[np.float64],
    models: list[ObjectModel],
    poses: list[NDArray[np.float64]],
    config: SceneConfig,
) -> tuple[mujoco.MjModel, list[int]]:
    """The table and the objects alone, compiled; the body ids (target first)."""
    spec = table_spec(target.asset.name, config)
    target.add_to(spec, world_T_target, name=OBJECT_NAME)
    for index, (model, pose) in enumerate(zip(models, poses, strict=True)):
        model.add_to(spec, pose, name=f"{DISTRACTOR_PREFIX}{index}")
    model = spec.compile()
    model.opt.timestep = SETTLE_TIMESTEP
    names = [OBJECT_NAME] + [f"{DISTRACTOR_PREFIX}{i}" for i in range(len(models))]
    bodies = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, name) for name in names]
    distractor_geoms = np.isin(model.geom_bodyid, bodies[1:]) & (model.geom_group == 2)
    model.geom_group[distractor_geoms] = _HIDDEN_GROUP
    return model, bodies


def _settled(
    target: ObjectModel,
    world_T_target: NDArray[np.float64],
    models: list[ObjectModel],
    dropped: list[NDArray[np.float64]],
    config: SceneConfig,
    seed: int,
    draw: int,
) -> ClutterLayout | None:
    """Step the drop until everything rests; the settled layout and its target visibility, or
    None when the simulation went unstable (module docstring)."""
    model, bodies = _settle_model(target, world_T_target, models, dropped, config)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    min_steps = int(round(SETTLE_MIN / SETTLE_TIMESTEP))
    for step in range(int(round(SETTLE_LIMIT / SETTLE_TIMESTEP))):
        mujoco.mj_step(model, data)
        if data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number:
            return None
        if step >= min_steps and np.abs(data.qvel).max() < SETTLE_SPEED:
            break
    poses = [make_transform(data.xmat[b].reshape(3, 3), data.xpos[b]) for b in bodies]
    low, high = config.table_top_z - FALLEN_DEPTH, config.table_top_z + FLUNG_HEIGHT
    on_table = [pose for pose in poses[1:] if low < pose[2, 3] < high]
    kept = [(m, p) for m, p in zip(models, poses[1:], strict=True) if any(p is q for q in on_table)]
    distractors = tuple(
        Distractor(f"{DISTRACTOR_PREFIX}{i}", m, pose) for i, (m, pose) in enumerate(kept)
    )
    share = _visible_share(model, data, bodies[0], target, poses[0], config, seed)
    return ClutterLayout(poses[0], distractors, share, draw + 1)


def _visible_share(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    target_body: int,
    target: ObjectModel,
    world_T_target: NDArray[np.float64],
    config: SceneConfig,
    seed: int,
) -> float:
    """The largest share, over the scene's cameras, of the target's sampled surface points a
    camera sees with the distractors of those it sees without them (1 when it sees none)."""
    points_object, _ = trimesh.sample.sample_surface(
        target.asset.mesh,
        VISIBILITY_POINTS,
        seed=int(rng_for(seed, "scene", "visible").integers(2**31)),
    )
    points_world = points_object @ world_T_target[:3, :3].T + world_T_target[:3, 3]
    cameras = config.cameras or tuple(default_viewpoints(world_T_target[:3, 3], n=config.num_views))
    shares = []
    for camera in cameras:
        eye = np.asarray(camera.pos, dtype=np.float64)
        alone = _seen(model, data, eye, points_world, target_body, with_distractors=False)
        among = _seen(model, data, eye, points_world, target_body, with_distractors=True)
        shares.append(float((alone & among).sum() / alone.sum()) if alone.any() else 1.0)
    return max(shares)


def _seen(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    eye: NDArray[np.float64],
    points_world: NDArray[np.float64],
    target_body: int,
    with_distractors: bool,
) -> NDArray[np.bool_]:
    """(N,) whether the first surface a ray from ``eye`` meets toward each point is the
    target's, within 5 mm of the point."""
    rays = points_world - eye
    length = np.linalg.norm(rays, axis=1)
    groups = np.array([1, int(with_distractors), 1, 0, 0, 0], dtype=np.uint8)
    geoms = np.zeros(len(rays), dtype=np.int32)
    dist = np.zeros(len(rays), dtype=np.float64)
    mujoco.mj_multiRay(
        model,
        data,
        eye,
        (rays / length[:, None]).ravel(),
        groups,
        True,
        -1,
        geoms,
        dist,
        None,
        len(rays),
        float(length.max() + 1.0),
    )
    hit_target = (geoms >= 0) & (model.geom_bodyid[np.maximum(geoms, 0)] == target_body)
    return hit_target & (dist >= length - 0.005)

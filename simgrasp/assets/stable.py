"""Stable resting poses of an object on a horizontal plane (trimesh's quasi-static analysis).

A pose is ``rest_T_object`` (4 x 4): it maps object-frame points into a rest frame whose
plane z = 0 is the support plane, the object lying on it (lowest point at z = 0) with its
footprint (x/y bounding box) centered on x = y = 0.
"""

from __future__ import annotations

import hashlib
from typing import NamedTuple

import numpy as np
import trimesh
from numpy.typing import NDArray

from simgrasp.assets.model import ObjectModel, inertial_properties
from simgrasp.assets.object import ObjectAsset
from simgrasp.assets.placement import DEFAULT_PLACEMENT, Placement, check_placement
from simgrasp.errors import SimgraspError

MIN_PROBABILITY = 1e-3  # poses less likely than this (knife-edge balances) are dropped

UPRIGHT_COSINE = 0.9
"""``placement="upright"`` keeps the stable poses whose object +z axis is within
arccos(0.9) = 26 degrees of world up."""


class StablePose(NamedTuple):
    """One resting pose and the probability of landing in it from a random drop."""

    rest_T_object: NDArray[np.float64]
    probability: float


def _support_and_com(
    asset_or_model: ObjectAsset | ObjectModel,
) -> tuple[trimesh.Trimesh, NDArray[np.float64]]:
    """The convex support hull (object frame) and center of mass of an asset or model, kept
    per object in this process (a clutter scene draws a rest pose for each of its objects,
    each draw needing the hull twice, ~30 ms a hull). Callers must not modify them."""
    kept = _SUPPORT.get(id(asset_or_model))
    if kept is None or kept[0] is not asset_or_model:
        kept = (asset_or_model, *_compute_support_and_com(asset_or_model))
        if len(_SUPPORT) >= SUPPORT_KEPT:
            del _SUPPORT[next(iter(_SUPPORT))]  # the oldest
        _SUPPORT[id(asset_or_model)] = kept
    return kept[1], kept[2]


SUPPORT_KEPT = 64
"""At most this many support hulls are kept (a clutter scene's target and distractors)."""
_SUPPORT: dict[int, tuple[object, trimesh.Trimesh, NDArray[np.float64]]] = {}
"""Support hulls by object identity, the object kept beside its hull (so its id stays its
own), oldest first."""


def _compute_support_and_com(
    asset_or_model: ObjectAsset | ObjectModel,
) -> tuple[trimesh.Trimesh, NDArray[np.float64]]:
    if isinstance(asset_or_model, ObjectModel):
        model = asset_or_model
        points = np.concatenate([h.vertices for h in model.hulls] + [model.asset.mesh.vertices])
        return trimesh.convex.convex_hull(points), model.inertial.com_object
    asset = asset_or_model
    hull = asset.mesh.convex_hull
    if asset.mesh.is_watertight and asset.mesh.volume > 0:
        return hull, asset.mesh.center_mass
    return hull, inertial_properties(asset, (hull,)).com_object


def _on_plane_centered(rest_T_object: NDArray[np.float64], points_object: NDArray) -> NDArray:
    points_rest = points_object @ rest_T_object[:3, :3].T + rest_T_object[:3, 3]
    low, high = points_rest.min(axis=0), points_rest.max(axis=0)
    shifted = rest_T_object.copy()
    shifted[:3, 3] -= [(low[0] + high[0]) / 2, (low[1] + high[1]) / 2, low[2]]
    return shifted


def stable_poses(
    asset_or_model: ObjectAsset | ObjectModel, min_probability: float = MIN_PROBABILITY
) -> list[StablePose]:
    """Stable poses, most probable first, probabilities renormalized to sum to 1.

    Computed on the convex hull of the object (and its collision hulls, for a model) with
    the object's center of mass (from the model's inertia, or the watertight mesh).
    """
    support, com_object = _support_and_com(asset_or_model)
    key = hashlib.sha1(
        b"".join(
            (
                np.ascontiguousarray(support.vertices, dtype=np.float64).tobytes(),
                np.ascontiguousarray(support.faces, dtype=np.int64).tobytes(),
                np.ascontiguousarray(com_object, dtype=np.float64).tobytes(),
                repr(min_probability).encode(),
            )
        )
    ).hexdigest()
    if key not in _POSES:
        _POSES[key] = _compute_stable_poses(support, com_object, min_probability)
    return list(_POSES[key])


_POSES: dict[str, list[StablePose]] = {}
"""Stable poses already computed in this process, by content of the support hull and center of
mass (trimesh's analysis takes ~0.5 s for a YCB object; every scene of a sweep needs them)."""


def _compute_stable_poses(
    support: trimesh.Trimesh, com_object: NDArray[np.float64], min_probability: float
) -> list[StablePose]:
    # trimesh's spherical-triangle area takes the square root of a rounding-negative product on
    # sliver facets (a RuntimeWarning, e.g. for gen_hammer). The probabilities it returns stayed
    # finite for every object here; a NaN one would count as a pose never landed in.
    with np.errstate(invalid="ignore"):
        transforms, probabilities = trimesh.poses.compute_stable_poses(
            support, center_mass=com_object, sigma=0.0, n_samples=1, threshold=0.0
        )
    probabilities = np.nan_to_num(np.asarray(probabilities, dtype=float), nan=0.0)
    keep = probabilities >= min_probability
    if not np.any(keep):
        keep = probabilities == np.max(probabilities)
    total = float(np.sum(probabilities[keep]))
    poses = [
        StablePose(
            _on_plane_centered(np.asarray(t, dtype=float), support.vertices), float(p) / total
        )
        for t, p, k in zip(transforms, probabilities, keep, strict=True)
        if k
    ]
    return sorted(poses, key=lambda pose: -pose.probability)


def upright_poses(poses: list[StablePose], object_name: str) -> list[StablePose]:
    """The poses standing the object on its own base: its +z axis (the mesh frame's up; YCB
    objects are scanned standing as they are placed) within 26 degrees of world up,
    probabilities renormalized. ValueError naming the object if none does."""
    upright = [pose for pose in poses if pose.rest_T_object[2, 2] >= UPRIGHT_COSINE]
    if not upright:
        raise SimgraspError(
            f"object {object_name!r} has no stable pose with its +z axis up; "
            "place it with placement='stable'"
        )
    total = sum(pose.probability for pose in upright)
    return [StablePose(pose.rest_T_object, pose.probability / total) for pose in upright]


def sample_rest_pose(
    model: ObjectModel, rng: np.random.Generator, placement: Placement = DEFAULT_PLACEMENT
) -> NDArray[np.float64]:
    """``world_T_object`` (4 x 4): a stable pose drawn by probability, a uniform random yaw
    about world z, the object resting on the plane z = 0 with its footprint centered at
    x = y = 0.

    ``placement="stable"`` draws among all stable poses (where a random drop lands it: a mug
    often ends on its side); ``"upright"`` only among those standing it on its own base, as a
    person sets a mug or a pitcher down (:func:`upright_poses`).
    """
    poses = stable_poses(model)
    if check_placement(placement) == "upright":
        poses = upright_poses(poses, model.asset.name)
    index = int(rng.choice(len(poses), p=[pose.probability for pose in poses]))
    yaw = float(rng.uniform(0.0, 2 * np.pi))
    world_T_rest = trimesh.transformations.rotation_matrix(yaw, [0.0, 0.0, 1.0])
    support, _ = _support_and_com(model)
    return _on_plane_centered(world_T_rest @ poses[index].rest_T_object, support.vertices)

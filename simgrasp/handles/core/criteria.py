"""Handle tests on batches of fitted quadrics: the paper's criteria and its suggested extras.

Every function takes arrays for a batch of B fitted neighborhoods (cloud frame, meters) and
returns a (B,) boolean mask of neighborhoods that pass.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from simgrasp.quadric import QuadricKind

CYLINDER = QuadricKind.REAL_ELLIPTIC_CYLINDER
ELLIPSOID = QuadricKind.REAL_ELLIPSOID
REACH_STEP = 0.005
"""Shell test candidates are queried in groups whose reach (m) rounds up to one multiple."""


def handle_points(
    kinds: NDArray[np.object_],
    quadric_centers: NDArray[np.float64],
    handle_axes: NDArray[np.float64],
    neighborhood_centers: NDArray[np.float64],
) -> NDArray[np.float64]:
    """Where each handle's axis passes nearest its neighborhood (B, 3).

    Ellipsoid and hyperboloid: the quadric center. Cylinder: the neighborhood center projected
    onto the axis line (a cylinder's center is any point of its axis).
    """
    offset = neighborhood_centers - quadric_centers
    along = np.einsum("bi,bi->b", offset, handle_axes)
    on_axis = quadric_centers + along[:, None] * handle_axes
    return np.where((kinds == CYLINDER)[:, None], on_axis, quadric_centers)


def center_near(
    points_on_axis: NDArray[np.float64], neighborhood_centers: NDArray[np.float64], limit: float
) -> NDArray[np.bool_]:
    """Paper criterion (b): the center (cylinder: the axis) within ``limit`` (m)."""
    return np.linalg.norm(points_on_axis - neighborhood_centers, axis=1) <= limit


def fits_gripper(
    transverse_semi_axes: NDArray[np.float64], max_opening: float, which: int
) -> NDArray[np.bool_]:
    """Criterion (c) (``which=0``: smaller transverse semi-axis) or the extra width test on
    the larger one (``which=1``): semi-axis at most half the gripper's maximum opening."""
    return transverse_semi_axes[:, which] <= max_opening / 2


def elongated(
    kinds: NDArray[np.object_], semi_axes: NDArray[np.float64], min_elongation: float
) -> NDArray[np.bool_]:
    """Eccentricity test: ellipsoids must not be sphere-like (others always pass)."""
    finite = np.where(np.isfinite(semi_axes), semi_axes, np.nan)
    ratio = np.nanmax(finite, axis=1) / np.nanmin(finite, axis=1)
    return (kinds != ELLIPSOID) | (ratio >= min_elongation)


def inside_object(
    tree: cKDTree,
    normals: NDArray[np.float64],
    points_on_axis: NDArray[np.float64],
    neighbors: int,
) -> NDArray[np.bool_]:
    """Reject quadrics centered outside the object.

    A point is inside when it lies behind (against the outward normal of) its nearest cloud
    points on average: mean((x - p) . n) < 0 over the ``neighbors`` nearest points p.
    """
    k = min(neighbors, tree.n)
    _, index = tree.query(points_on_axis, k=k)
    index = index.reshape(len(points_on_axis), k)
    offsets = points_on_axis[:, None, :] - tree.data[index]
    signed = np.einsum("bki,bki->bk", offsets, normals[index])
    return signed.mean(axis=1) < 0


def shell_clear(
    tree: cKDTree,
    points_on_axis: NDArray[np.float64],
    axes: NDArray[np.float64],
    outer_radius: NDArray[np.float64],
    *,
    half_length: float,
    gap: float,
    thickness: float,
    max_fraction: float,
) -> NDArray[np.bool_]:
    """ten Pas's shell test: few points in a thin shell just outside the fitted surface.

    For each candidate, the cloud points within ``half_length`` (m) along the axis of the
    handle point are split by their distance ρ from the axis line: the shell is
    ``outer_radius + gap < ρ <= outer_radius + gap + thickness``. The candidate passes when
    the shell holds at most ``max_fraction`` of the points with ρ inside the shell's outer
    radius (i.e. the fingers would close around the handle without hitting other parts).

    The candidates' cloud points come from dual-tree queries against ``tree`` (a ``cKDTree``
    of the cloud), one per group of candidates whose shells reach about as far (to the next
    ``REACH_STEP``): one common reach, the widest candidate's, gathered millions of far points
    for thousands of thin candidates. Only points within ``half_length`` along the axis get
    their ρ computed.
    """
    shell_out = outer_radius + gap + thickness
    groups = np.ceil(np.sqrt(shell_out**2 + half_length**2) / REACH_STEP)
    passed = np.ones(len(points_on_axis), dtype=bool)
    found = []
    for group in np.unique(groups):
        members = np.flatnonzero(groups == group)
        pairs = cKDTree(points_on_axis[members]).sparse_distance_matrix(
            tree, group * REACH_STEP, output_type="ndarray"
        )
        found.append((members[pairs["i"]], pairs["j"]))
    candidate = np.concatenate([c for c, _ in found])
    index = np.concatenate([j for _, j in found])
    if len(candidate) == 0:
        return passed
    offsets = tree.data.take(index, axis=0) - points_on_axis.take(candidate, axis=0)
    pair_axes = axes.take(candidate, axis=0)
    along = np.einsum("ni,ni->n", offsets, pair_axes)
    slab = np.flatnonzero(np.abs(along) <= half_length)
    owner = candidate[slab]
    across = offsets.take(slab, axis=0) - along[slab, None] * pair_axes.take(slab, axis=0)
    radial = np.linalg.norm(across, axis=1)
    within = radial <= shell_out[owner]
    in_shell = within & (radial > (outer_radius + gap)[owner])
    total = np.bincount(owner, weights=within, minlength=len(points_on_axis))
    shell = np.bincount(owner, weights=in_shell, minlength=len(points_on_axis))
    has_points = total > 0
    passed[has_points] = shell[has_points] <= max_fraction * total[has_points]
    return passed
